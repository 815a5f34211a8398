"""Plan review, export and the run screen (with a stand-in for `wecook execute` that prints its line format)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
import yaml
from tui_driving import pilot_test, settle, wait_for

from wecook_tui.app import WecookApp
from wecook_tui.screens.plan_review import PlanReviewScreen, plan_file
from wecook_tui.screens.run import RunScreen, apply_event, past_runs

SIZE = (150, 45)

FAKE_EXECUTE = r"""
import json, signal, sys, time, yaml
plan, mcap, mode = sys.argv[1], sys.argv[2], sys.argv[3]
actions = yaml.safe_load(open(plan))["actions"]
def say(**event):
    print(json.dumps(event), flush=True)
say(t=0.0, kind="run_start", actions=len(actions), seed=0)
print("a message on stderr, not an event", file=sys.stderr, flush=True)
if mode == "hang":
    def stop(signum, frame):
        say(t=1.0, kind="action_failed", action_id=actions[0]["id"], agent="P1", detail="interrupted")
        print("wecook: interrupted", file=sys.stderr, flush=True)
        sys.exit(130)
    signal.signal(signal.SIGTERM, stop)
    say(t=0.5, kind="action_start", action_id=actions[0]["id"], agent="P1")
    time.sleep(60)
for i, a in enumerate(actions):
    say(t=float(i), kind="action_start", action_id=a["id"], agent="P1", primitive=None, detail="")
    if i == 0:
        say(t=i + 0.5, kind="action_end", action_id=a["id"], agent="P1", primitive=None, detail="")
    else:
        say(t=i + 0.5, kind="action_failed", action_id=a["id"], agent="P1", primitive=None,
            detail="failed: no grasp found")
open(mcap, "wb").write(b"\x89MCAP0\r\n")
print(f"recording: {mcap}", file=sys.stderr)
sys.exit(1)
"""


def fake_execute(plan: Path, mcap: Path) -> list[str]:
    return [sys.executable, "-c", FAKE_EXECUTE, str(plan), str(mcap), "run"]


def hanging_execute(plan: Path, mcap: Path) -> list[str]:
    return [sys.executable, "-c", FAKE_EXECUTE, str(plan), str(mcap), "hang"]


@pilot_test
@pytest.mark.slow
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
        segs = app.analysis.segmentation.segments
        assert screen.review.unreviewed == screen.review.segments == len(segs)
        assert f"{len(segs)} of {len(segs)} segments unreviewed" in str(screen.query_one("#plan-review").render())
        await pilot.press("w")  # asks first: nothing is reviewed
        await pilot.pause(0.2)
        assert screen.exported is None and "still unreviewed" in str(screen.query_one("#plan-status").render())
        await pilot.press("w")
        assert await wait_for(pilot, lambda: screen.exported is not None)
        assert screen.exported == plan_file(session_path)
        data = yaml.safe_load(screen.exported.read_text())
        assert data["wecook_plan"] == 1 and [a["id"] for a in data["actions"]] == ids
        await pilot.press("escape")
        assert app.screen is app.main


@pilot_test
@pytest.mark.slow
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
        assert screen.review.rejected == len(inside)
        assert screen.review.unreviewed == len(segs) - len(inside)
        assert await wait_for(pilot, lambda: screen.plan is not None)
        assert not [a for a in screen.plan.actions if a.frames and a.frames[0] < end and start < a.frames[1]]


@pilot_test
@pytest.mark.slow
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


def test_run_events_fold_into_action_states() -> None:
    states = {"a1": "waiting", "a2": "waiting", "a3": "waiting"}
    assert apply_event(states, {"kind": "action_start", "action_id": "a1"}) == "a1"
    assert states["a1"] == "running"
    apply_event(states, {"kind": "action_failed", "action_id": "a1", "detail": "no IK"})
    apply_event(states, {"kind": "action_failed", "action_id": "a2", "detail": "skipped: needs a1"})
    apply_event(states, {"kind": "action_start", "action_id": "a3"})
    apply_event(states, {"kind": "action_failed", "action_id": "a3", "detail": "interrupted"})
    assert states == {"a1": "failed", "a2": "skipped", "a3": "stopped"}
    assert apply_event(states, {"kind": "action_start", "action_id": "a9"}) is None  # not of this plan
    apply_event(states, {"kind": "summary", "actions": [{"id": "a1", "status": "done"}]})
    assert states["a1"] == "done"


@pilot_test
@pytest.mark.slow
async def test_stopping_a_run_is_clean_and_says_stopped(session_path: Path) -> None:
    app = WecookApp(session_path)
    app.run_command = hanging_execute
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("r")
        screen = app.screen
        assert isinstance(screen, RunScreen)
        assert await wait_for(pilot, lambda: "running" in screen.states.values())
        await pilot.press("ctrl+k")
        assert await wait_for(pilot, lambda: screen.result is not None)
        assert screen.result.returncode == 130
        assert "stopped" in screen.states.values() and "failed" not in screen.states.values()
        summary = str(screen.query_one("#run-summary").render())
        assert summary.startswith("Run stopped")
        log = "\n".join(str(line.text) for line in screen.query_one("#run-log").lines)
        assert "Traceback" not in log and "Run stopped." in log


@pilot_test
@pytest.mark.slow
async def test_past_runs_show_their_table_and_log_and_enter_opens_one(session_path: Path) -> None:
    app = WecookApp(session_path)
    app.run_command = fake_execute
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        for _ in range(2):
            await pilot.press("r")
            screen = app.screen
            assert await wait_for(pilot, lambda screen=screen: screen.result is not None)
            await pilot.press("escape")
            await pilot.pause(1.05)  # run names are stamped to the second
        await pilot.press("R")
        listing = app.screen
        assert isinstance(listing, RunScreen) and listing.analysis is None
        runs = past_runs(session_path)
        assert len(runs) == 2 and listing.shown_run == runs[0]["name"]  # the newest, at once
        table = listing.query_one("#run-actions")
        assert table.row_count == len(runs[0]["actions"]) > 0
        assert not listing.query_one("#run-progress").display  # no bar animating without a run
        await pilot.press("down", "enter")
        assert listing.shown_run == runs[1]["name"]
        log = "\n".join(str(line.text) for line in listing.query_one("#run-log").lines)
        assert "run started" in log and "stderr" in log
