"""Plan review, export and the run screen (with a stand-in for `wecook execute` that prints its line format)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import yaml
from tui_driving import pilot_test, settle, wait_for

from wecook_tui.app import WecookApp
from wecook_tui.screens.plan_review import PlanReviewScreen, plan_file
from wecook_tui.screens.run import RunScreen, action_state, past_runs

SIZE = (150, 45)

FAKE_EXECUTE = r"""
import sys, yaml
plan, mcap = sys.argv[1], sys.argv[2]
actions = yaml.safe_load(open(plan))["actions"]
print(f"run started: {len(actions)} actions, seed 0", flush=True)
for i, a in enumerate(actions):
    print(f"[{i:7.2f}s] {a['id']} P1 {a['verb']}: started", flush=True)
    mark = "done" if i == 0 else "FAILED: no grasp found"
    print(f"[{i + 0.5:7.2f}s] {a['id']} P1 {a['verb']}: {mark}", flush=True)
open(mcap, "wb").write(b"\x89MCAP0\r\n")
print(f"recording: {mcap}")
print(f"1/{len(actions)} actions done in 2.0 s simulated, 0.1 s wall")
sys.exit(1)
"""


def fake_execute(plan: Path, mcap: Path) -> list[str]:
    return [sys.executable, "-c", FAKE_EXECUTE, str(plan), str(mcap)]


@pilot_test
async def test_plan_review_and_export(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("e")
        screen = app.screen
        assert isinstance(screen, PlanReviewScreen)
        assert await wait_for(pilot, lambda: screen.plan is not None)
        nodes = {node.id: node for node in app.analysis.graph.nodes}
        ids = [a.id for a in screen.plan.actions]
        assert ids and set(ids) <= set(nodes)  # grasp-only nodes are not robot actions
        assert all(a.frames == (nodes[a.id].span.start, nodes[a.id].span.end) for a in screen.plan.actions)
        await pilot.press("w")
        assert await wait_for(pilot, lambda: screen.exported is not None)
        assert screen.exported == plan_file(session_path)
        data = yaml.safe_load(screen.exported.read_text())
        assert data["wecook_plan"] == 1 and [a["id"] for a in data["actions"]] == ids
        await pilot.press("escape")
        assert app.screen is app.main


@pilot_test
async def test_export_follows_corrections(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        node = min((n for n in app.analysis.graph.nodes if n.action.verb), key=lambda n: n.span.end - n.span.start)
        start, end = node.span.start, node.span.end
        inside = [i for i, seg in enumerate(segs) if seg.start < end and start < seg.end]
        app.main.frame = segs[inside[0]].start
        for _ in inside:  # reject every segment of that action: it leaves the plan
            await pilot.press("x", "down")
        await settle(pilot, app)
        await pilot.press("e")
        screen = app.screen
        assert isinstance(screen, PlanReviewScreen)
        assert await wait_for(pilot, lambda: screen.plan is not None)
        assert not [a for a in screen.plan.actions if a.frames and a.frames[0] < end and start < a.frames[1]]


@pilot_test
async def test_run_screen_shows_progress_summary_and_past_runs(session_path: Path) -> None:
    app = WecookApp(session_path)
    app.run_command = fake_execute
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("r")
        screen = app.screen
        assert isinstance(screen, RunScreen)
        assert await wait_for(pilot, lambda: screen.result is not None)
        ids = [a["id"] for a in yaml.safe_load(plan_file(session_path).read_text())["actions"]]
        assert ids
        assert screen.states == {aid: ("done" if i == 0 else "failed") for i, aid in enumerate(ids)}
        assert screen.result.returncode == 1 and screen.result.mcap.exists()
        assert screen.result.mcap.parent == session_path / "runs"
        record = json.loads(screen.result.mcap.with_suffix(".json").read_text())
        assert record["returncode"] == 1 and record["actions"] == screen.states
        assert plan_file(session_path).exists()  # the run executes the exported current plan
        await pilot.press("escape")
        await pilot.press("R")  # past runs, without starting one
        listing = app.screen
        assert isinstance(listing, RunScreen) and listing.analysis is None
        runs = past_runs(session_path)
        assert [r["name"] for r in runs] == [screen.result.mcap.stem]
        assert runs[0]["returncode"] == 1


def test_action_state_parses_the_execute_line_format() -> None:
    ids = {"a1", "a12"}
    assert action_state("[   1.20s] a12 P1 cut: started", ids) == ("a12", "running")
    assert action_state("[   2.00s] a1 P1,P2 handover: done", ids) == ("a1", "done")
    assert action_state("[   2.00s] a1 P1 cut: FAILED: no IK solution", ids) == ("a1", "failed")
    assert action_state("a1\tP1\tcut\tdone\t", ids) == ("a1", "done")
    skipped = "[  10.33s] a12 P2,P1 holding: skipped: needs a1 (cut), which failed"
    assert action_state(skipped, ids) == ("a12", "skipped")
    assert action_state("a1\tP1\ttransfer\tskipped\tneeds a12 (transfer), which failed", ids) == ("a1", "skipped")
    assert action_state("recording: runs/a1.mcap", set()) is None
    assert action_state("[   2.00s] a3 P1 cut: done", ids) is None  # not an action of this plan
