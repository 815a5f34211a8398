"""Snapshots of the workbench (update with `pytest --snapshot-update`).

They run on the fake workspace of ``tui_fake`` (a video, boxes and an analysis made in the test) so that they
show the widgets, and do not change whenever the pipeline's numbers improve."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import settle
from tui_fake import fake_workspace

from wecook_tui.app import WecookApp

SIZE = (140, 42)
SIZES = [pytest.param((80, 24), id="80x24"), pytest.param((200, 55), id="200x55")]
"""The smallest terminal the workbench supports and a large one: nothing needed is cut at either."""


@pytest.fixture
def fixed_key_path(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("WECOOK_KEYS", "/nonexistent/wecook/keys.toml")  # shown on the help screen


def fake_app(folder: Path) -> WecookApp:
    opener, analyzer = fake_workspace(folder)
    return WecookApp(folder / "kitchen", opener=opener, analyzer=analyzer)


def ready(app: WecookApp):  # type: ignore[no-untyped-def]
    async def run_before(pilot) -> None:  # type: ignore[no-untyped-def]
        await settle(pilot, app)

    return run_before


@pytest.mark.parametrize("size", SIZES)
@pytest.mark.slow
def test_main_screen(snap_compare, tmp_path: Path, size: tuple[int, int]) -> None:  # type: ignore[no-untyped-def]
    app = fake_app(tmp_path)
    assert snap_compare(app, terminal_size=size, run_before=ready(app))


@pytest.mark.parametrize("size", SIZES)
@pytest.mark.slow
def test_main_screen_after_review(snap_compare, tmp_path: Path,  # type: ignore[no-untyped-def]
                                  size: tuple[int, int]) -> None:
    app = fake_app(tmp_path)

    async def run_before(pilot) -> None:  # type: ignore[no-untyped-def]
        await settle(pilot, app)
        await pilot.press("a", "down", "x", "down", "L", "L")
        await settle(pilot, app)

    assert snap_compare(app, terminal_size=size, run_before=run_before)


@pytest.mark.parametrize("size", SIZES)
@pytest.mark.slow
def test_help_screen(snap_compare, tmp_path: Path, fixed_key_path: None,  # type: ignore[no-untyped-def]
                     size: tuple[int, int]) -> None:
    app = fake_app(tmp_path)

    async def run_before(pilot) -> None:  # type: ignore[no-untyped-def]
        await settle(pilot, app)
        await pilot.press("question_mark")

    assert snap_compare(app, terminal_size=size, run_before=run_before)


@pytest.mark.slow
def test_action_picker(snap_compare, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    app = fake_app(tmp_path)

    async def run_before(pilot) -> None:  # type: ignore[no-untyped-def]
        await settle(pilot, app)
        await pilot.press("c")

    assert snap_compare(app, terminal_size=SIZE, run_before=run_before)
