"""What a playback or a run of segment changes costs besides the frames: the resume position is written at most
once a second (and on quitting), and the inspector's tree is rebuilt only when the segment's trees change."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import pytest
from tui_driving import pilot_test, settle

from wecook_tui import review
from wecook_tui.app import WecookApp
from wecook_tui.resume import PositionKeeper, load_position
from wecook_tui.widgets.inspector import Inspector

SIZE = (150, 45)


def test_the_keeper_writes_at_most_once_an_interval_and_the_last_frame_on_flush(tmp_path: Path) -> None:
    (tmp_path / "s").mkdir()
    now = [0.0]
    keeper = PositionKeeper(tmp_path / "s", interval=1.0, clock=lambda: now[0])
    assert keeper.note(10) and load_position(tmp_path / "s") == 10  # the first change at once
    for frame in (20, 30, 40):
        now[0] += 0.2
        assert not keeper.note(frame)
    assert keeper.pending and load_position(tmp_path / "s") == 10 and keeper.writes == 1
    assert keeper.due() == pytest.approx(0.4)
    now[0] += 0.4
    assert keeper.note(50) and load_position(tmp_path / "s") == 50 and not keeper.pending
    now[0] += 0.1
    keeper.note(60)
    keeper.flush()  # quitting
    assert load_position(tmp_path / "s") == 60 and keeper.writes == 3


@pilot_test
@pytest.mark.slow
async def test_segment_changes_write_the_position_once_and_quitting_writes_the_last(
        session_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(PositionKeeper, "INTERVAL", 3600.0)  # every change below falls in one interval
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        assert len(segs) >= 4
        for _ in range(3):
            await pilot.press("n")
        keeper = app.main._keeper
        assert keeper is not None and keeper.writes == 1 and keeper.pending
        assert load_position(session_path) != app.main.frame
        await pilot.press("right")
        left = app.main.frame
        await pilot.press("q")
    assert keeper.writes == 2 and load_position(session_path) == left


@pilot_test
@pytest.mark.slow
async def test_the_pending_position_is_written_once_the_interval_is_over(session_path: Path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(PositionKeeper, "INTERVAL", 0.3)
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("n", "n")
        at = app.main.frame
        await pilot.pause(0.6)  # no key since: the timer wrote it
        assert load_position(session_path) == at


@pilot_test
@pytest.mark.slow
async def test_the_tree_is_rebuilt_only_when_the_segment_s_trees_change(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        inspector = app.main.query_one(Inspector)
        segs = app.analysis.segmentation.segments
        shown = [review.trees_of(app.analysis, segs[0])]
        before = inspector.rebuilds
        for seg in segs[1:]:
            await pilot.press("n")
            assert app.main.frame == seg.start
            shown.append(review.trees_of(app.analysis, seg))
        changes = sum(a != b for a, b in pairwise(shown))
        assert changes < len(segs) - 1  # some neighbours share their trees (one action over several segments)
        assert inspector.rebuilds - before == changes
        await pilot.press("right")  # inside the segment: nothing rebuilt
        assert inspector.rebuilds - before == changes


@pilot_test
@pytest.mark.slow
async def test_leaving_without_q_writes_the_pending_position_too(session_path: Path,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(PositionKeeper, "INTERVAL", 3600.0)
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("n", "n")
        at = app.main.frame
        assert load_position(session_path) != at
        app.exit()  # ctrl+q, ctrl+c: the app quits, not the screen's q
        await pilot.pause()
    assert load_position(session_path) == at
