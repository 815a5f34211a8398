"""`wecook export`, `wecook execute` (validation before the run), `wecook runs check` and `runs recover`."""

from __future__ import annotations

import datetime as dt
from pathlib import Path

import cv2
import numpy as np
import pytest

from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_core.plan import dump_plan, read_plan
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import McapRecorder
from wecook_tui.cli import main
from wecook_tui.commands.execute import default_record_path

PLAN = """\
wecook_plan: 1
agents:
- {pid: P1, robot: franka_panda/panda.urdf, base: {position: [-0.5, 0.0, 0.0], yaw: 0.0}}
scene:
  table: {size: [1.0, 0.8], height: 0.0}
  objects:
  - {name: knife, category: tool, shape: box, size: [0.2, 0.03, 0.025], pose: {x: 0.0, y: 0.15, yaw: 0.0}}
  - {name: tomato, category: ingredient, shape: sphere, size: [0.05, 0.05, 0.05], pose: {x: 0.0, y: 0.0}}
  containing: []
actions:
- {id: a1, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], location: null, after: []}
- {id: a2, pid: [P1], verb: stir, tool: spoon, ingredients: [], location: null, after: [a1]}
"""


def test_execute_rejects_a_bad_plan_before_running(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.yaml"
    plan.write_text(PLAN)
    assert main(["execute", str(plan)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"wecook: error: {plan}:actions[1] (a2).tool: object 'spoon' is not in the scene"
    assert not (tmp_path / "runs").exists()  # nothing was recorded
    plan.write_text(PLAN.replace("after: [a1]", "after: [a3]").replace("tool: spoon", "tool: knife"))
    assert main(["execute", str(plan), "--no-record"]) == 2
    assert "(a2).after: unknown action id 'a3'" in capsys.readouterr().err
    assert main(["execute", str(tmp_path / "none.yaml")]) == 2
    assert "cannot read the plan" in capsys.readouterr().err


def test_default_record_path(tmp_path: Path) -> None:
    now = dt.datetime(2026, 11, 24, 3, 4, 5)
    session = tmp_path / "sessions" / "demo"
    (session / "plans").mkdir(parents=True)
    (session / "session.yaml").write_text("inputs: {}\n")
    assert default_record_path(session / "plans" / "plan.yaml", now) == \
        session.resolve() / "runs" / "plan-20261124-030405.mcap"
    assert default_record_path(tmp_path / "my.yaml", now) == tmp_path.resolve() / "runs" / "my-20261124-030405.mcap"


@pytest.mark.slow
def test_runs_check_and_recover(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    good = tmp_path / "good.mcap"
    synthetic_run(McapRecorder(good), actions=2, seconds_per_action=0.3)
    assert main(["runs", "check", str(good)]) == 0
    out = capsys.readouterr().out
    assert out.strip().endswith("ok") and "actions: 2 done" in out
    killed = tmp_path / "killed.mcap"
    rec = McapRecorder(killed)
    synthetic_run(rec, actions=2, seconds_per_action=0.3, end=False)
    rec.flush()  # the process "dies" here: no summary, no footer
    assert main(["runs", "check", str(killed)]) == 1
    assert "problem: no footer" in capsys.readouterr().out
    assert main(["runs", "recover", str(killed)]) == 0
    out = capsys.readouterr().out
    recovered = tmp_path / "killed.recovered.mcap"
    assert f"wrote {recovered}" in out and "the run had not finished" in out
    assert main(["runs", "check", str(recovered)]) == 0
    capsys.readouterr()
    assert main(["runs", "check", str(tmp_path / "none.mcap")]) == 2
    assert "no such recording" in capsys.readouterr().err


def _write_inputs(folder: Path) -> tuple[Path, Path, Path]:
    """A 60-frame 320x240 video where the right hand of P1 takes a knife to a tomato on a board."""
    folder.mkdir(parents=True, exist_ok=True)
    video = folder / "v.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 30.0, (320, 240))
    for _ in range(60):
        writer.write(np.full((240, 320, 3), 40, np.uint8))
    writer.release()
    objects = ["frame,track_id,label,x1,y1,x2,y2"]
    hands = ["frame,hand,x,y,x1,y1,x2,y2"]
    for f in range(60):
        k = min(f, 20) / 20  # the hand reaches the knife by frame 20, then carries it to the tomato
        knife_x = 60 + (max(f - 20, 0) / 40) * 60
        objects += [f"{f},1,knife,{knife_x:.1f},150,{knife_x + 50:.1f},160",
                    f"{f},2,tomato,130,120,150,140", f"{f},3,chopping board,100,100,220,180",
                    f"{f},4,bowl,250,60,300,100"]
        hx = 20 + k * 60 if f < 20 else knife_x + 10
        hands.append(f"{f},RH_P1,{hx:.1f},155,{hx - 10:.1f},145,{hx + 10:.1f},165")
        hands.append(f"{f},LH_P2,280,{120 + (f % 10)},270,{110 + (f % 10)},290,{130 + (f % 10)}")
    (folder / "objects.csv").write_text("\n".join(objects) + "\n")
    (folder / "hands.csv").write_text("\n".join(hands) + "\n")
    return video, folder / "objects.csv", folder / "hands.csv"


@pytest.mark.slow
def test_export_writes_a_valid_plan_into_the_session(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from wecook_core.session.store import create_session

    root = tmp_path / "sessions"
    video, objects, hands = _write_inputs(tmp_path / "inputs")
    create_session(root, "kitchen", video, objects, hands)
    assert main(["export", "kitchen", "--root", str(root)]) == 0
    path = root / "kitchen" / "plans" / "plan.yaml"
    assert f"wrote {path}" in capsys.readouterr().out
    plan = read_plan(path)  # validates
    assert {o.name for o in plan.scene.objects} == {"knife", "tomato", "chopping_board", "bowl"}
    assert {a.pid for a in plan.agents} <= {"P1", "P2"} and plan.agents
    other = tmp_path / "elsewhere.yaml"
    assert main(["export", "kitchen", "--root", str(root), "-o", str(other)]) == 0
    assert dump_plan(read_plan(other)) == dump_plan(plan)  # the analysis is deterministic
    assert main(["export", "nobody", "--root", str(root)]) == 2
    assert "no such session" in capsys.readouterr().err


ONE_ARM = ONE_ARM_CUTS


@pytest.mark.sim
def test_execute_records_a_run_and_reports_every_action(tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    from wecook_core.recording.check import check_recording

    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM)
    record = tmp_path / "run.mcap"
    code = main(["execute", str(plan), "--record", str(record), "--seed", "3"])
    out = capsys.readouterr().out
    rows = [line.split("\t") for line in out.splitlines() if line.startswith("a")]  # plain lines: not a tty
    assert [r[0] for r in rows] == ["a1", "a2"] and all(r[2] == "cut" for r in rows)
    statuses = [r[3] for r in rows]
    assert set(statuses) <= {"done", "failed", "skipped"}
    assert code == (0 if statuses == ["done", "done"] else 1)
    report = check_recording(record)
    assert report.ok, report.problems
    assert {k: v.split(":")[0] for k, v in report.actions.items()} == \
        {r[0]: ("done" if r[3] == "done" else "failed") for r in rows}
    assert report.metadata["wecook"]["seed"] == "3"


@pytest.mark.sim
def test_killed_execute_leaves_a_recoverable_recording(tmp_path: Path) -> None:
    import os
    import signal
    import subprocess
    import sys
    import time

    from wecook_core.recording.check import check_recording, recover_recording

    plan = tmp_path / "plan.yaml"
    more = "".join(f"- {{id: a{k}, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], "
                   f"location: chopping_board, after: [a{k - 1}]}}\n" for k in range(3, 9))
    plan.write_text(ONE_ARM + more)  # eight cuts: long enough to be killed midway
    record = tmp_path / "run.mcap"
    child = subprocess.Popen([sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--record",
                              str(record)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    sizes = {0}
    while time.monotonic() < deadline and len(sizes) < 4 and child.poll() is None:  # three flushes seen
        sizes.add(record.stat().st_size if record.exists() else 0)
        time.sleep(0.05)
    assert child.poll() is None, "the run ended before it could be killed"
    os.kill(child.pid, signal.SIGKILL)
    child.wait()
    report = recover_recording(record, tmp_path / "recovered.mcap")
    assert not report.complete and report.messages.get("/tf", 0) > 0
    check = check_recording(tmp_path / "recovered.mcap")
    assert check.ok, check.problems
    assert "a1" in check.actions


@pytest.mark.sim
def test_sigterm_stops_the_run_with_a_closed_recording(tmp_path: Path) -> None:
    import json
    import signal
    import subprocess
    import sys

    from wecook_core.recording.check import check_recording

    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM)
    record = tmp_path / "run.mcap"
    child = subprocess.Popen([sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--record", str(record),
                              "--jsonl"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    assert child.stdout is not None
    lines = []
    for line in child.stdout:
        lines.append(json.loads(line))
        if lines[-1]["kind"] == "primitive_start":  # well inside the first action
            child.send_signal(signal.SIGTERM)
            break
    assert child.wait(timeout=60) == 130
    assert lines[0]["kind"] == "run_start" and lines[0]["actions"] == 2
    report = check_recording(record)  # finished properly: summary, footer, a story that ends
    assert report.ok, report.problems
    assert report.actions["a1"] == "failed: interrupted"


@pytest.mark.sim
def test_ctrl_c_on_a_forced_replacement_keeps_the_previous_recording(tmp_path: Path) -> None:
    """Ctrl-C during ``execute --record F --force`` replaced the finished recording F with the interrupted run
    (issue 28): F stays as it was, and no hidden ``.F.*.part.mcap`` is left."""
    import json
    import signal
    import subprocess
    import sys

    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM)
    record = tmp_path / "run.mcap"
    old = b"the finished recording, not to be lost\n"
    record.write_bytes(old)
    child = subprocess.Popen([sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--record", str(record),
                              "--force", "--jsonl"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert child.stdout is not None and child.stderr is not None
    for line in child.stdout:
        if json.loads(line)["kind"] == "primitive_start":  # well inside the first action
            child.send_signal(signal.SIGINT)
            break
    assert child.wait(timeout=60) == 130
    said = "".join((child.stdout.read() + child.stderr.read()).split())  # rich wraps its lines, long paths too
    assert "".join(f"no recording: {record} left as it was".split()) in said
    assert record.read_bytes() == old
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.yaml", "run.mcap"]


def test_plan_check_says_which_action_cannot_be_reached(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.yaml"
    good = PLAN.replace("tool: spoon", "tool: knife")
    plan.write_text(good)
    assert main(["plan", "check", str(plan)]) == 0
    assert "ok: 2 actions, 1 arms" in capsys.readouterr().out
    # the knife at the far end of the table, beyond P1's reach (P1 stands at x = -0.5)
    plan.write_text(good.replace("pose: {x: 0.0, y: 0.15, yaw: 0.0}", "pose: {x: 0.15, y: 0.3, yaw: 0.0}"))
    assert main(["plan", "check", str(plan)]) == 1
    out = capsys.readouterr().out
    assert "a1 (cut by P1): the knife at (0.15, 0.30) is 0.72 m from P1's base, beyond its reach" in out
    assert "a2 (stir by P1): the knife" in out
    plan.write_text(PLAN)  # an invalid plan: one line, exit 2
    assert main(["plan", "check", str(plan)]) == 2
    assert "(a2).tool: object 'spoon' is not in the scene" in capsys.readouterr().err


@pytest.mark.sim
def test_execute_force_keeps_the_old_recording_whole_until_the_new_one_replaces_it(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import wecook_core.execution.run as executor
    from wecook_core.recording.check import check_recording
    from wecook_core.recording.writer import layout_path

    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM)
    record = tmp_path / "run.mcap"
    old = b"the user's recording, not to be lost\n"
    record.write_bytes(old)
    real = executor.execute_plan
    seen: list[bytes] = []

    def watched(*args: object, **kwargs: object) -> object:
        seen.append(record.read_bytes())  # the run is about to start: the old file is untouched
        result = real(*args, **kwargs)  # type: ignore[arg-type]
        seen.append(record.read_bytes())  # the run is over, the recording not yet closed: still the old file
        return result

    monkeypatch.setattr(executor, "execute_plan", watched)
    assert main(["execute", str(plan), "--record", str(record)]) == 2  # no --force: refused
    assert record.read_bytes() == old
    assert main(["execute", str(plan), "--record", str(record), "--force"]) in (0, 1)
    assert seen == [old, old]
    assert check_recording(record).ok
    assert layout_path(record).is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.yaml", "run.layout.json", "run.mcap"]
    assert "recording: " in capsys.readouterr().out


def test_a_robot_urdf_with_missing_meshes_is_one_line_and_exit_2(tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    import pybullet_data

    robot = tmp_path / "robot" / "panda.urdf"  # the Panda's URDF without its meshes folder
    robot.parent.mkdir()
    robot.write_text((Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf").read_text())
    plan = tmp_path / "plan.yaml"
    plan.write_text(PLAN.replace("franka_panda/panda.urdf", str(robot)).replace("tool: spoon", "tool: knife"))
    for command in (["execute", str(plan), "--record", str(tmp_path / "run.mcap")], ["plan", "check", str(plan)]):
        assert main(command) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and "Traceback" not in err
        assert err.startswith(f"wecook: error: {plan}:agents[0].robot: ")
        assert "names a mesh that is not a file: 'package://meshes/" in err
    assert not (tmp_path / "run.mcap").exists()


@pytest.mark.sim
def test_a_robot_pybullet_cannot_load_is_an_input_error_not_a_traceback(tmp_path: Path) -> None:
    import pybullet as p

    from wecook_core.errors import InputError
    from wecook_core.execution.bullet.bodies import build_scene
    from wecook_core.plan import Agent, Plan, Scene

    robot = tmp_path / "robot.urdf"  # well-formed XML, every mesh there (none), yet no robot PyBullet can load
    robot.write_text('<robot name="r"><link name="a"/><joint name="j" type="fixed"><parent link="a"/>'
                     '<child link="missing"/></joint></robot>')
    plan = Plan(agents=(Agent("P1", str(robot), (-0.5, 0.0, 0.0), 0.0),), scene=Scene(), actions=())
    client = p.connect(p.DIRECT)
    try:
        with pytest.raises(InputError, match=r"agents \(P1\)\.robot.*PyBullet cannot load the robot URDF"):
            build_scene(client, plan)
    finally:
        p.disconnect(client)
