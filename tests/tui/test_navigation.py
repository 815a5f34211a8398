"""Navigation: go to a frame, time or segment; previous and next unreviewed; search; resume on reopening."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import pilot_test, settle, wait_for

from wecook_tui.app import WecookApp
from wecook_tui.screens.goto import GoToScreen, parse_target
from wecook_tui.search import targets

SIZE = (150, 45)


def test_go_to_reads_frames_times_and_segments() -> None:
    starts = (0, 30, 66)
    assert parse_target("45", 30.0, starts) == 45
    assert parse_target("1.5s", 30.0, starts) == 45
    assert parse_target("0:02", 30.0, starts) == 60
    assert parse_target("#2", 30.0, starts) == 30
    assert parse_target("s3", 30.0, starts) == 66
    assert parse_target("#4", 30.0, starts) is None  # no 4th segment
    assert parse_target("soon", 30.0, starts) is None


@pilot_test
@pytest.mark.slow
async def test_go_to_key(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        await pilot.press("g")
        assert isinstance(app.screen, GoToScreen)
        await pilot.press(*"#3", "enter")
        assert app.main.frame == segs[2].start
        await pilot.press("g", *"1s", "enter")
        assert app.main.frame == round(app.fps)
        await pilot.press("g", *"17", "enter")
        assert app.main.frame == 17
        await pilot.press("g", *"later", "enter")
        assert app.main.frame == 17 and app.screen is app.main  # refused with a notice


@pilot_test
@pytest.mark.slow
async def test_previous_unreviewed(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        app.main.frame = segs[2].start
        await pilot.press("up", "a", "down")  # segment 2 accepted, back at segment 3
        await pilot.press("U")
        assert app.main.frame == segs[0].start  # segment 2 is reviewed: segment 1 is the previous unreviewed
        await pilot.press("U")
        assert app.main.frame == segs[-1].start  # wraps round


@pilot_test
@pytest.mark.slow
async def test_search_actions_and_objects_from_the_palette(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        found = list(targets(app))
        action = app.analysis.actions[-1]
        assert any(text.startswith("action ") and frame == action.start for text, frame, _ in found)
        knife = next((frame, text) for text, frame, _ in found if text == "object knife")
        assert knife[0] == int(app.obs.object("knife").frames[0])
        app.main.frame = app.frame_count - 1
        await pilot.press("ctrl+p")
        await pilot.pause(0.2)
        await pilot.press(*"object knife")
        await pilot.pause(0.5)
        await pilot.press("enter")
        assert await wait_for(pilot, lambda: app.main.frame == knife[0])


@pilot_test
@pytest.mark.slow
async def test_reopening_resumes_where_the_user_left_off(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        await pilot.press("n", "n", "right", "right")
        left = app.main.frame
        assert left == segs[2].start + 2
        await pilot.press("q")
    again = WecookApp(session_path)
    async with again.run_test(size=SIZE) as pilot:
        await settle(pilot, again)
        assert again.main.frame == left


@pilot_test
@pytest.mark.slow
async def test_a_click_on_the_timeline_moves_the_cursor(session_path: Path) -> None:
    from wecook_tui.widgets.timeline import LABEL_WIDTH, Timeline

    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        timeline = app.main.query_one(Timeline)
        column = timeline.track_width // 2
        await pilot.click(Timeline, offset=(LABEL_WIDTH + column, 2))
        assert app.main.frame == timeline._frames[column]
        assert timeline._frames[timeline.column_of(app.main.frame)] == app.main.frame  # the cursor is drawn there
