"""Segments whose evidence is too thin (issue 16): the workbench marks them unsure with the reason, in the
inspector and on the timeline, and next-unreviewed visits them until they are accepted or rejected."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import pilot_test, settle, wait_for
from tui_scenario import write_inputs

from wecook_core.model import SegmentStatus
from wecook_core.session.corrections import SetHandObject
from wecook_core.session.store import create_session
from wecook_tui import review
from wecook_tui.app import WecookApp
from wecook_tui.widgets.timeline import Timeline

SIZE = (150, 45)


def hands_missing(tmp_path: Path) -> Path:
    """The kitchen scenario with the hands undetected on frames 35-69, while the knife is sawing."""
    video, objects, hands = write_inputs(tmp_path / "inputs")
    lines = hands.read_text().splitlines()
    hands.write_text("\n".join([lines[0], *(r for r in lines[1:] if not 35 <= int(r.split(",")[0]) < 70)]) + "\n")
    return Path(create_session(tmp_path / "sessions", "gaps", video, objects, hands))


def header(app: WecookApp) -> str:
    return str(app.main.query_one("#segment-header").render())


def status_row(app: WecookApp) -> str:
    timeline = app.main.query_one(Timeline)
    return "".join(char for char, _ in timeline._rows[-1])


@pilot_test
@pytest.mark.slow
async def test_unsure_segments_are_marked_with_their_reason_and_visited_until_reviewed(tmp_path: Path) -> None:
    app = WecookApp(hands_missing(tmp_path))
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        unsure = app.analysis.unsure
        assert unsure, "the pipeline found nothing unsure where the hands are missing"
        (start, reason), = unsure.items()
        assert "hands seen on" in reason
        index = next(i for i, s in enumerate(segs) if s.start == start)
        # On the timeline: its status mark is ? (the others ·); in the inspector: unsure and why.
        await pilot.pause()
        row = status_row(app)
        timeline = app.main.query_one(Timeline)
        assert row[timeline.column_of(start)] == "?" and row.count("?") == 1
        assert "unsure" not in header(app)
        await pilot.press("u")  # from segment 1, the next to review
        assert app.main.frame == segs[1].start
        app.go_to(start + 1)
        await pilot.pause()
        assert f"unsure: {reason}" in header(app)
        # A correction there does not settle it (the rest of the segment is still thin): u still stops there.
        app.correct(SetHandObject(start, "RH_P1", "knife"))
        await settle(pilot, app)
        assert review.status_of(app.corrections, start) is SegmentStatus.CORRECTED
        for i, seg in enumerate(segs):
            if i != index:
                app.go_to(seg.start)
                await pilot.press("a")
        await settle(pilot, app)
        app.go_to(segs[0].start)
        await pilot.press("u")
        assert app.main.frame == start and "unsure" in header(app)
        assert status_row(app)[timeline.column_of(start)] == "?"
        # Accepted, it is settled: no mark, no reason, nothing left to visit.
        await pilot.press("a")
        await settle(pilot, app)
        assert "unsure" not in header(app) and "?" not in status_row(app)
        app.go_to(segs[0].start)
        await pilot.press("u")
        assert await wait_for(pilot, lambda: any("Every segment is reviewed" in str(n.message)
                                                 for n in app._notifications))
        assert app.main.frame == segs[0].start
