"""A run served live (issue 15): `wecook execute --jsonl --live` says its address in its run_start event, and
the workbench's run screen (v on the review screen) shows it while the run goes."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from rich.text import Text
from tui_driving import pilot_test, settle, wait_for

from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_tui.app import WecookApp
from wecook_tui.screens.run import RunScreen

SIZE = (150, 45)

FAKE_LIVE = r"""
import json, signal, sys, time, yaml
plan, mcap = sys.argv[1], sys.argv[2]
port = sys.argv[sys.argv.index("--port") + 1] if "--live" in sys.argv else None
actions = yaml.safe_load(open(plan))["actions"]
def say(**event):
    print(json.dumps(event), flush=True)
def stop(signum, frame):
    sys.exit(130)
signal.signal(signal.SIGTERM, stop)
live = {"live": f"ws://127.0.0.1:{port}"} if port else {}
say(t=0.0, kind="run_start", actions=len(actions), seed=0, **live)
say(t=0.5, kind="action_start", action_id=actions[0]["id"], agent="P1")
time.sleep(60)
"""


def fake_live(plan: Path, mcap: Path) -> list[str]:
    return [sys.executable, "-c", FAKE_LIVE, str(plan), str(mcap)]


def summary(screen: RunScreen) -> str:
    rendered = screen.query_one("#run-summary").render()
    return rendered.plain if isinstance(rendered, Text) else str(rendered)


@pilot_test
@pytest.mark.slow
async def test_the_run_screen_says_the_live_address_from_the_run_events(session_path: Path) -> None:
    app = WecookApp(session_path)
    app.run_command = fake_live
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("v")
        assert await wait_for(pilot, lambda: isinstance(app.screen, RunScreen))
        screen = app.screen
        assert isinstance(screen, RunScreen) and screen.live_port == 8765
        assert await wait_for(pilot, lambda: "live: ws://127.0.0.1:8765" in summary(screen), 500)
        assert screen.live_url == "ws://127.0.0.1:8765"
        assert await wait_for(pilot, lambda: "running" in screen.states.values())
        await pilot.press("ctrl+k")
        assert await wait_for(pilot, lambda: screen.result is not None, 500)
        assert "live view was ws://127.0.0.1:8765" in summary(screen)
        await pilot.press("escape")
        # The past run keeps its address (R lists past runs; the newest is shown).
        await pilot.press("R")
        assert await wait_for(pilot, lambda: isinstance(app.screen, RunScreen) and app.screen.analysis is None)
        past = app.screen
        assert isinstance(past, RunScreen)
        assert await wait_for(pilot, lambda: "served live on ws://127.0.0.1:8765" in summary(past))
        await pilot.press("escape")
        # r runs without serving: no address is said.
        await pilot.press("r")
        assert await wait_for(pilot, lambda: isinstance(app.screen, RunScreen) and app.screen is not screen)
        plain = app.screen
        assert isinstance(plain, RunScreen) and plain.live_port is None and plain is not past
        assert await wait_for(pilot, lambda: "running" in plain.states.values(), 500)
        assert "live" not in summary(plain) and plain.live_url is None
        await pilot.press("ctrl+k")
        assert await wait_for(pilot, lambda: plain.result is not None, 500)


@pytest.mark.sim
def test_execute_jsonl_live_says_its_address_in_run_start(tmp_path: Path) -> None:
    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM_CUTS)
    child = subprocess.Popen([sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--no-record", "--jsonl",
                              "--live", "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout is not None
        first = json.loads(child.stdout.readline())
    finally:
        child.send_signal(signal.SIGTERM)
        child.communicate(timeout=60)
    assert first["kind"] == "run_start"
    host, port = first["live"].removeprefix("ws://").split(":")
    assert host == "127.0.0.1" and int(port) > 0  # port 0 asked for any free one: the real one is said
