"""`wecook export --format {wecook,wecook-ros,pddl}`: of a session (the demo's) and of a plan file; bad input is
one line and exit code 2."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from exports_helpers import check_message, platform_checks, run_dispatch, simulate

from wecook_core.plan import dump_plan, read_plan
from wecook_core.plan.ros import ros_task
from wecook_tui.cli import main

SMALL = Path(__file__).parent / "golden" / "small.yaml"


@pytest.mark.slow
def test_the_demo_session_exports_to_every_format(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    from wecook_core.session.store import create_session
    from wecook_core.synth import demo_dir
    from wecook_core.workflows import demo_plan

    root = tmp_path / "sessions"
    folder = demo_dir()
    create_session(root, "demo", folder / "video.mp4", folder / "objects.csv", folder / "hands.csv")
    plans = root / "demo" / "plans"
    assert main(["export", "demo", "--root", str(root)]) == 0
    plan = read_plan(plans / "plan.yaml")
    assert dump_plan(plan) == dump_plan(demo_plan())  # a new demo session's plan is the demo's plan
    capsys.readouterr()

    assert main(["export", "demo", "--root", str(root), "--format", "wecook-ros"]) == 0
    out, err = capsys.readouterr()
    script = plans / "dispatch.py"
    export = ros_task(plan)
    assert f"wrote {script}: a TaskMsg of {len(export.task.actions)} actions" in out
    assert "wecook: warning: jar: no URDF of its own on the platform, stands in as" in err
    assert "wecook: warning: a2 left out: squeeze" in err  # what is not dispatched, and why
    assert os.access(script, os.X_OK)
    run = run_dispatch(script.read_text(), monkeypatch)
    platform_checks(plan, export, run.task)
    check_message(run.msg, run.task)

    assert main(["export", "demo", "--root", str(root), "--format", "pddl", "-o", str(tmp_path / "pddl")]) == 0
    assert "wrote" in capsys.readouterr().out
    steps = [tuple(line.strip("()").split()) for line in (tmp_path / "pddl" / "plan.pddl").read_text().splitlines()
             if not line.startswith(";")]
    simulate(tmp_path / "pddl" / "domain.pddl", tmp_path / "pddl" / "problem.pddl", steps)


def test_a_plan_file_exports_beside_itself(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    plan_file = tmp_path / "small.yaml"
    plan_file.write_text(SMALL.read_text())
    assert main(["export", "--plan", str(plan_file), "--format", "wecook-ros", "--real"]) == 0
    assert "for WeCookDispatch (real arms)" in capsys.readouterr().out
    run = run_dispatch((tmp_path / "small-dispatch.py").read_text(), monkeypatch)
    assert run.task.ifSim is False
    assert main(["export", "--plan", str(plan_file), "--format", "pddl"]) == 0
    assert sorted(p.name for p in (tmp_path / "small-pddl").iterdir()) == ["domain.pddl", "plan.pddl", "problem.pddl"]
    assert main(["export", "--plan", str(plan_file), "-o", str(tmp_path / "again.yaml")]) == 0
    assert dump_plan(read_plan(tmp_path / "again.yaml")) == dump_plan(read_plan(plan_file))
    urdfs = tmp_path / "urdfs.yaml"
    urdfs.write_text("wecook_ros_objects: 1\nobjects: {whisk: objects/whisk.urdf}\n")
    capsys.readouterr()
    assert main(["export", "--plan", str(plan_file), "--format", "wecook-ros", "--urdfs", str(urdfs)]) == 0
    assert "whisk" not in capsys.readouterr().err


def test_bad_exports_are_one_line_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan_file = tmp_path / "small.yaml"
    text = SMALL.read_text()
    plan_file.write_text(text)
    assert main(["export", "--plan", str(plan_file)]) == 2  # would write over the plan itself
    assert "is the plan being exported" in capsys.readouterr().err
    assert plan_file.read_text() == text
    (tmp_path / "taken").write_text("mine")
    assert main(["export", "--plan", str(plan_file), "--format", "pddl", "-o", str(tmp_path / "taken")]) == 2
    assert (tmp_path / "taken").read_text() == "mine"
    assert "taken: is a file: pddl writes a folder" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("verb: cut", "verb: slice"))
    assert main(["export", "--plan", str(bad), "--format", "pddl"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bad.yaml:actions[0] (a1).verb: expected one of cut" in err
    assert not (tmp_path / "bad-pddl").exists()
    with pytest.raises(SystemExit) as exit_:
        main(["export"])
    assert exit_.value.code == 2
    assert "give a session NAME or --plan FILE" in capsys.readouterr().err
