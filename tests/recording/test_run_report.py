"""`wecook runs show` (a run's summary from its recording alone) and `wecook runs export --csv`."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.execution.schedule.observer import RunEvent
from wecook_core.recording.report import export_csv, summarize_recording
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import McapRecorder
from wecook_tui.cli import main

PLAN = """\
wecook_plan: 1
agents:
- {pid: P1, robot: franka_panda/panda.urdf, base: {position: [-0.5, 0.0, 0.0], yaw: 0.0}}
- {pid: P2, robot: franka_panda/panda.urdf, base: {position: [0.5, 0.0, 0.0], yaw: 3.1416}}
scene:
  table: {size: [1.0, 0.8], height: 0.0}
  objects:
  - {name: knife, category: tool, shape: box, size: [0.2, 0.03, 0.025], pose: {x: -0.1, y: 0.15, yaw: 0.0}}
  containing: []
actions:
- {id: a1, pid: [P1], verb: cut, tool: knife, ingredients: [], location: null, after: []}
- {id: a2, pid: [P2], verb: stir, tool: knife, ingredients: [], location: null, after: [a1]}
- {id: a3, pid: [P1], verb: pour, tool: knife, ingredients: [], location: null, after: [a2]}
- {id: a4, pid: [P2], verb: wipe, tool: knife, ingredients: [], location: null, after: [a3]}
"""


@pytest.fixture(autouse=True)
def mesh_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "cache"))


def recorded(path: Path, end: bool = True) -> Path:
    rec = McapRecorder(path, time_origin_ns=1_000_000_000_000)
    synthetic_run(rec, actions=3, seconds_per_action=0.5, fail=("a2",), plan_yaml=PLAN, seed=4, end=end)
    rec.close()
    return path


def test_show_prints_plan_results_duration_and_topics(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = recorded(tmp_path / "run.mcap")
    summary = summarize_recording(path)
    assert [(a.id, a.verb, a.status) for a in summary.actions] == \
        [("a1", "cut", "done"), ("a2", "stir", "failed"), ("a3", "pour", "done"), ("a4", "wipe", "not run")]
    a2 = summary.actions[1]
    assert a2.reason == "synthetic failure" and a2.agents == "P2"
    assert a2.start == pytest.approx(0.5, abs=0.05) and a2.end == pytest.approx(1.0, abs=0.05)
    assert summary.duration_s == pytest.approx(1.5, abs=0.05) and summary.finished
    assert summary.topics["/joint_states"][0] == "sensor_msgs/msg/JointState"
    assert summary.topics["/tf"][1] == summary.topics["/joint_states"][1] > 0
    assert summary.metadata["seed"] == "4" and summary.objects == 1 and len(summary.agents) == 2
    assert main(["runs", "show", str(path)]) == 0
    out = capsys.readouterr().out
    assert "1.5 s simulated; 2/4 actions done" in out
    assert "plan: 4 actions, 2 arms (P1 franka_panda/panda.urdf; P2 franka_panda/panda.urdf), 1 objects" in out
    row = next(line for line in out.splitlines() if line.startswith("a2 "))
    assert row.split()[:4] == ["a2", "P2", "stir", "failed"] and row.endswith("synthetic failure")
    assert any(line.split()[:2] == ["/camera", "foxglove.CompressedImage"] for line in out.splitlines())


def test_show_reads_a_killed_run_and_rejects_what_is_not_a_recording(tmp_path: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "killed.mcap"
    rec = McapRecorder(path, flush_every_s=0.0)
    stats = synthetic_run(rec, actions=2, seconds_per_action=0.5, plan_yaml=PLAN, end=False)
    rec.on_event(stats.sim_seconds, RunEvent("action_start", "a3", agent="P1"))
    rec.flush()  # never closed: no summary, no footer
    summary = summarize_recording(path)
    assert not summary.finished
    assert [a.status for a in summary.actions] == ["done", "done", "unfinished", "not run"]
    assert main(["runs", "show", str(path)]) == 0
    assert "the run did not finish" in capsys.readouterr().out
    rec.close()
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not an mcap file at all")
    assert main(["runs", "show", str(junk)]) == 2
    assert main(["runs", "show", str(tmp_path / "none.mcap")]) == 2
    assert str(junk) in capsys.readouterr().err


def test_export_writes_joint_states_and_events_as_csv(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = recorded(tmp_path / "run.mcap")
    out = tmp_path / "csv"
    assert main(["runs", "export", str(path), "--csv", str(out)]) == 0
    assert f"wrote {out / 'joint_states.csv'}" in capsys.readouterr().out
    with open(out / "joint_states.csv") as f:
        rows = list(csv.DictReader(f))
    summary = summarize_recording(path)
    assert len(rows) == summary.topics["/joint_states"][1]
    assert list(rows[0])[:3] == ["t_s", "P1/joint1.position", "P1/joint2.position"]
    assert "P2/joint7.velocity" in rows[0]
    assert float(rows[0]["t_s"]) == 0.0 and float(rows[-1]["t_s"]) == pytest.approx(1.5, abs=0.05)
    dt = float(rows[3]["t_s"]) - float(rows[2]["t_s"])
    velocity = (float(rows[3]["P1/joint1.position"]) - float(rows[2]["P1/joint1.position"])) / dt
    assert float(rows[3]["P1/joint1.velocity"]) == pytest.approx(velocity, rel=1e-3, abs=1e-4)
    with open(out / "events.csv") as f:
        events = list(csv.DictReader(f))
    assert [e["kind"] for e in events if e["kind"].startswith("action")][:3] == \
        ["action_start", "action_end", "action_start"]
    failed = next(e for e in events if e["kind"] == "action_failed")
    assert failed["action_id"] == "a2" and failed["detail"] == "synthetic failure"
    assert events[-1]["kind"] == "run_end"
    before = (out / "events.csv").read_bytes()
    with pytest.raises(InputError, match="not overwritten"):
        export_csv(path, out)
    assert main(["runs", "export", str(path), "--csv", str(out)]) == 2
    assert (out / "events.csv").read_bytes() == before


def test_show_says_how_long_each_arm_waited_and_for_what(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 25: P2 stood still 52 s at the start of a squeeze and nothing said why. The run's wait events and
    its run_end totals become the table's waited column and a line per arm."""
    path = tmp_path / "waits.mcap"
    rec = McapRecorder(path, time_origin_ns=1_000_000_000_000)
    stats = synthetic_run(rec, actions=2, seconds_per_action=0.5, plan_yaml=PLAN, end=False)
    t = stats.sim_seconds
    why = "the other arm's region: a1 works where a2 would"
    rec.on_event(t, RunEvent("wait", "a2", agent="P2", detail=f"waits for {why}", data={"for": why, "since": t}))
    rec.on_event(t + 52.0, RunEvent("wait", "a2", agent="P2", detail=f"waited 52.0 s for {why}",
                                    data={"for": why, "since": t, "seconds": 52.0}))
    rec.on_event(t + 52.0, RunEvent("run_end", detail="2/4 actions done",
                                    data={"done": 2, "total": 4, "waited_s": {"P1": 0.4, "P2": 52.3}}))
    rec.on_end(t + 52.0)
    rec.close()
    summary = summarize_recording(path)
    assert summary.waited == {"P1": 0.4, "P2": 52.3}
    assert next(a for a in summary.actions if a.id == "a2").waited == pytest.approx(52.0)
    assert main(["runs", "show", str(path)]) == 0
    out = capsys.readouterr().out
    assert "waited: P1 0.4 s, P2 52.3 s" in out
    assert f"  longest: P2 52.0 s from {t:.1f} s for {why}" in out
    header = next(line for line in out.splitlines() if line.startswith("action "))
    assert header.split()[:7] == ["action", "agents", "verb", "status", "start", "end", "waited"]
    assert next(line for line in out.splitlines() if line.startswith("a2 ")).split()[6] == "52.0"
