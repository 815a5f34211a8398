"""Box mode through the frame view's own mapping: a click selects the box under it, a drag draws in video pixels,
with half-blocks and with a graphics protocol's picture alike."""

from __future__ import annotations

from pathlib import Path

import pytest
from textual.app import App
from tui_driving import pilot_test, wait_for

from tests.square_video import moving_square
from wecook_tui import graphics
from wecook_tui.screens.boxes import BoxScreen, BoxVideo
from wecook_tui.widgets.frame_view import FrameView

SIZE = (100, 40)
VIDEO = (320, 240)


class BoxApp(App[None]):
    def __init__(self, screen: BoxScreen, protocol: graphics.Graphics | None) -> None:
        super().__init__()
        self.box_screen = screen
        self.graphics = protocol

    def on_mount(self) -> None:
        self.push_screen(self.box_screen)


def cell_of(view: FrameView, x: float, y: float) -> tuple[int, int]:
    """The view's cell showing video pixel (x, y), from the picture's layout (half-blocks or graphics)."""
    pad, columns, rows = view._layout()
    return pad + int(x / VIDEO[0] * columns), int(y / VIDEO[1] * rows)


@pytest.mark.parametrize("protocol", [None, "kitty"])
@pilot_test
@pytest.mark.slow
async def test_a_click_selects_the_box_under_it_and_a_drag_draws_where_it_went(tmp_path: Path,
                                                                              protocol: str | None) -> None:
    video = tmp_path / "square.avi"
    moving_square(video)
    screen = BoxScreen(BoxVideo(str(video), VIDEO, 10.0, 40), tmp_path / "out", labels=lambda: ["bowl"])
    chosen = graphics.load(protocol) if protocol else None
    assert (chosen is not None) == (protocol is not None)
    app = BoxApp(screen, chosen)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.pause()
        view = screen.query_one(FrameView)
        assert (view.graphics is not None) == (protocol is not None)
        screen.add_box((20.0, 20.0, 100.0, 100.0), "bowl")
        screen.add_box((200.0, 120.0, 300.0, 220.0), "knife")
        await pilot.pause()
        assert [t.label for t in screen.tracks] == ["bowl", "knife"] and screen.selected == 1
        await pilot.click(FrameView, offset=cell_of(view, 60, 60))  # inside the bowl's box
        assert await wait_for(pilot, lambda: screen.selected == 0)
        await pilot.click(FrameView, offset=cell_of(view, 160, 30))  # on no box: the selection stays
        await pilot.pause()
        assert screen.selected == 0
        await pilot.click(FrameView, offset=cell_of(view, 250, 170))
        assert await wait_for(pilot, lambda: screen.selected == 1)
        # A drag sets the selected box's keyframe where it went, in video pixels (a cell's precision).
        start, end = cell_of(view, 210, 130), cell_of(view, 290, 200)
        await pilot.mouse_down(FrameView, offset=start)
        await pilot.mouse_up(FrameView, offset=end)
        await pilot.pause()
        x1, y1, x2, y2 = screen.tracks[1].keyframes[0]
        cell = VIDEO[0] / view._layout()[1], VIDEO[1] / view._layout()[2]
        assert abs(x1 - 210) <= cell[0] and abs(x2 - 290) <= cell[0]
        assert abs(y1 - 130) <= cell[1] and abs(y2 - 200) <= cell[1]
