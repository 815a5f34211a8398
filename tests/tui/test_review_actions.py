"""Corrections act on the whole action; every edit, undo and redo answers and shows what it changed."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import journal, pick, pilot_test, settle

from wecook_core.model import ActionKind, SegmentStatus
from wecook_tui import review
from wecook_tui.app import WecookApp
from wecook_tui.widgets.status_line import StatusLine

SIZE = (150, 45)


def longest_verb(app: WecookApp) -> tuple[str, tuple[int, int], list[int]]:
    """(hand, span, indices of its segments) of the verb that spans the most segments."""
    segs = app.analysis.segmentation.segments
    best: tuple[str, tuple[int, int], list[int]] | None = None
    for index, seg in enumerate(segs):
        for hand, action in review.actions_of(app.analysis, seg, index).items():
            if action.kind in (ActionKind.TRANSFER, ActionKind.HANDOVER):
                continue  # the pipeline names these itself, whatever verb is chosen
            span = review.verb_span(app.analysis, seg, hand)
            if span is None:
                continue
            inside = [i for i, s in enumerate(segs) if span[0] <= s.start < span[1]]
            if best is None or len(inside) > len(best[2]):
                best = (hand, span, inside)
    assert best is not None
    return best


@pilot_test
@pytest.mark.slow
async def test_a_verb_correction_acts_on_the_whole_action_or_on_one_segment(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        hand, span, inside = longest_verb(app)
        if len(inside) == 1:  # make it a two-segment action: split it in the middle
            app.main.frame = (span[0] + span[1]) // 2
            await pilot.press("s")
            await settle(pilot, app)
            hand, span, inside = longest_verb(app)
        assert len(inside) >= 2
        segs = app.analysis.segmentation.segments
        middle = segs[inside[-1]]
        app.main.frame = middle.start
        await pilot.pause()
        assert app.main.selected_hand in review.actions_of(app.analysis, middle, inside[-1])  # an acting hand
        while app.main.selected_hand != hand:
            await pilot.press("t")
        before = review.actions_of(app.analysis, middle, inside[-1])[hand].verb
        verb = next(v for v in ("stir", "peel", "cut") if v != before)
        count = len(journal(session_path))
        await pilot.press("c")
        await pick(pilot, app, verb)
        entries = journal(session_path)
        assert len(entries) == count + 1  # one correction for the whole action
        assert (entries[-1]["segment"], entries[-1]["end"]) == span
        assert ("recomputing" in app.main.query_one(StatusLine).plain) == app.pending  # until the screen matches
        await settle(pilot, app)
        assert "recomputing" not in app.main.query_one(StatusLine).plain
        for i in inside:
            assert review.actions_of(app.analysis, segs[i], i)[hand].verb == verb
            assert review.status_of(app.corrections, segs[i].start) is SegmentStatus.CORRECTED
        assert sum(1 for a in app.analysis.actions if a.hand == hand and a.verb == verb and a.start < span[1]
                   and span[0] < a.end) == 1  # one action, not split by the correction
        assert app.last_message.startswith(f"✎ verb of {hand} -> {verb}")
        # C: this segment only
        other = next(v for v in ("roll", "spread", "dip") if v != verb)
        await pilot.press("C")
        await pick(pilot, app, other)
        entry = journal(session_path)[-1]
        assert entry["segment"] == middle.start and "end" not in entry
        await settle(pilot, app)
        index = review.segment_index(app.analysis.segmentation.segments, middle.start)
        assert review.actions_of(app.analysis, middle, index)[hand].verb == other
        assert review.actions_of(app.analysis, segs[inside[0]], inside[0])[hand].verb == verb


@pilot_test
@pytest.mark.slow
async def test_undo_and_redo_answer_and_jump_to_what_they_changed(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        app.main.frame = segs[2].start
        await pilot.press("x")  # reject segment 3
        assert app.last_message == f"✎ segment rejected at [{segs[2].start}, {segs[2].end})"
        app.main.frame = 0
        await pilot.press("z")
        assert app.last_message.startswith("Undone: segment rejected")
        assert app.main.frame == segs[2].start  # jumped to what the undo changed
        assert app.last_message in app.main.query_one(StatusLine).plain
        app.main.frame = 0
        await pilot.press("y")
        assert app.last_message.startswith("Redone: segment rejected") and app.main.frame == segs[2].start
        await settle(pilot, app)
        await pilot.press("y")
        assert app.last_message == "Nothing to redo."
