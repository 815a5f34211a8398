"""Helpers for Pilot tests: wait for the workers or a condition, read the journal, pick in a picker."""

from __future__ import annotations

import asyncio
import contextlib
import functools
import json
from collections.abc import Callable, Coroutine
from pathlib import Path
from typing import Any

from textual.pilot import Pilot
from textual.worker import WorkerCancelled

from wecook_tui.app import WecookApp
from wecook_tui.screens.picker import PickerScreen


async def settle(pilot: Pilot, app: WecookApp) -> None:
    """Until no worker runs and the analysis matches the journal."""
    for _ in range(200):
        with contextlib.suppress(WorkerCancelled):
            await app.workers.wait_for_complete()
        await pilot.pause()
        if app.analysis is not None and not app.pending and not any(w.is_running for w in app.workers):
            return
        await pilot.pause(0.02)
    raise AssertionError("the workbench never settled")


async def wait_for(pilot: Pilot, predicate: Callable[[], bool], tries: int = 300) -> bool:
    """Pause until ``predicate()`` holds, at most ``tries`` pauses of 20 ms; whether it held."""
    for _ in range(tries):
        if predicate():
            return True
        await pilot.pause(0.02)
    return bool(predicate())


def journal(session: Path) -> list[dict]:
    lines = (session / "journal.jsonl").read_text().splitlines()
    return [json.loads(line) for line in lines if line.strip()]


async def pick(pilot: Pilot, app: WecookApp, value: str) -> None:
    """Choose ``value`` in the open picker with the keyboard (down arrows, then enter)."""
    screen = app.screen
    assert isinstance(screen, PickerScreen), f"expected a picker, got {screen!r}"
    values = [v for v, _ in screen.options]
    assert value in values, f"{value!r} not offered: {values}"
    await pilot.press("home", *(["down"] * values.index(value)), "enter")
    await pilot.pause()


def pilot_test(test: Callable[..., Coroutine[Any, Any, None]]) -> Callable[..., None]:
    """Run an async Pilot test with ``asyncio.run`` (no async plugin needed); fixtures pass through."""

    @functools.wraps(test)
    def run(*args: Any, **kwargs: Any) -> None:
        asyncio.run(test(*args, **kwargs))

    return run
