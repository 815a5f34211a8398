"""Mouse clicks on the picture: a box selects its object (and the hand holding it), a hand marker its hand."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import pilot_test, settle
from tui_fake import fake_workspace

from wecook_tui.app import WecookApp
from wecook_tui.frames import fit
from wecook_tui.widgets.frame_view import FrameView


def cell_of(view: FrameView, x: float, y: float) -> tuple[int, int]:
    """The view's cell showing video pixel (x, y)."""
    width, height = fit(view.video_size, (view.size.width, view.size.height))
    pad = (view.size.width - width) // 2
    return pad + int(x / view.video_size[0] * width), int(y / view.video_size[1] * height / 2)


@pilot_test
@pytest.mark.slow
async def test_clicks_on_boxes_and_hands_select_them(tmp_path: Path) -> None:
    opener, analyzer = fake_workspace(tmp_path)
    app = WecookApp(tmp_path / "kitchen", opener=opener, analyzer=analyzer)
    async with app.run_test(size=(120, 40)) as pilot:
        await settle(pilot, app)
        view = app.main.query_one(FrameView)
        assert view.hit(*cell_of(view, 165, 95)) == ("tomato", None)
        x, y = view.pixel_at(*cell_of(view, 165, 95)) or (0.0, 0.0)
        assert abs(x - 165) < 6 and abs(y - 95) < 6
        await pilot.click(FrameView, offset=cell_of(view, 165, 95))  # the tomato lies on the board
        await pilot.pause()
        assert view.selected_box == "tomato" and "tomato: no hand holds it" in app.last_message

        await pilot.click(FrameView, offset=cell_of(view, 220, 140))  # the board, away from the tomato
        await pilot.pause()
        assert view.selected_box == "chopping_board"

        await pilot.press("t")  # the other hand
        assert app.main.selected_hand == "LH_P1"
        await pilot.click(FrameView, offset=cell_of(view, 86, 44))  # the knife, which RH_P1 holds
        await pilot.pause()
        assert view.selected_box == "knife" and app.main.selected_hand == "RH_P1"
        assert "knife: held by RH_P1" in app.last_message

        left = app.obs.hand("LH_P1").xy[0]
        await pilot.click(FrameView, offset=cell_of(view, float(left[0]), float(left[1])))  # LH_P1's marker
        await pilot.pause()
        assert app.main.selected_hand == "LH_P1" and "Hand LH_P1 selected" in app.last_message

        await pilot.click(FrameView, offset=cell_of(view, 10, 170))  # nothing there
        await pilot.pause()
        assert view.hit(*cell_of(view, 10, 170)) == (None, None) and view.selected_box is None
        assert view.pixel_at(0, view.size.height + 5) is None  # below the picture
