"""Frames through a terminal graphics protocol (textual-image) where the terminal has one, half-blocks otherwise."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from tui_driving import pilot_test, settle
from tui_fake import fake_workspace

from wecook_tui import graphics
from wecook_tui.app import WecookApp
from wecook_tui.frames import BoxMark, HandMark, Overlay
from wecook_tui.widgets.frame_view import FrameView


def test_the_protocol_comes_from_the_environment() -> None:
    def choose(**env: str) -> str | None:
        return graphics.choose(env, available=True)

    assert choose(TERM="xterm-256color") is None  # an ordinary terminal: half-blocks
    assert choose(TERM="xterm-kitty") == "kitty" and choose(TERM="xterm-256color", KITTY_WINDOW_ID="1") == "kitty"
    assert choose(TERM="xterm-256color", TERM_PROGRAM="WezTerm") == "sixel" and choose(TERM="foot") == "sixel"
    assert choose(TERM="xterm-kitty", TMUX="/tmp/tmux-0/default,1,0") is None  # tmux does not pass images
    assert choose(TERM="screen-256color", TERM_PROGRAM="WezTerm") is None
    assert choose(TERM="xterm-256color", WECOOK_GRAPHICS="sixel") == "sixel"  # asked for: used anywhere
    assert choose(TERM="xterm-kitty", WECOOK_GRAPHICS="halfblocks") is None
    assert graphics.choose({"TERM": "xterm-kitty"}, available=False) is None  # textual-image missing


def test_the_picture_has_the_terminal_s_pixels_and_written_labels() -> None:
    chosen = graphics.Graphics("kitty", object, (10, 20))
    assert chosen.picture_size((100, 30), (1280, 720)) == (1000, 562)  # the columns limit it: 100 x 10 px
    assert chosen.cells_of((1000, 562)) == (100, 29) and chosen.picture_size((200, 30), (1280, 720)) == (1066, 600)
    image = np.zeros((360, 640, 3), np.uint8)
    overlay = Overlay(boxes=(BoxMark("bowl", (200, 200, 600, 500), (0, 255, 0)),),
                      hands=(HandMark("RH_P1", (900, 300), (255, 0, 0)),))
    out = graphics.picture(image, overlay, (1280, 720))
    assert tuple(out[100, 200]) == (0, 255, 0)  # the box edge, scaled by a half (BGR)
    tag = out[80:99, 100:140]
    assert (tag == (0, 255, 0)).all(axis=2).any() and (tag == 0).all(axis=2).any()  # black text on the box colour
    assert out[140:152, 450:500].any()  # the hand's name
    assert not graphics.picture(image, Overlay(boxes=overlay.boxes, labels=False), (1280, 720))[80:99, 100:140].any()
    assert graphics.to_pil(out).size == (640, 360)


@pilot_test
@pytest.mark.slow
async def test_a_graphics_terminal_gets_the_picture_at_its_pixel_size(tmp_path: Path) -> None:
    opener, analyzer = fake_workspace(tmp_path)
    app = WecookApp(tmp_path / "kitchen", opener=opener, analyzer=analyzer)
    assert app.graphics is None  # not a graphics terminal: half-blocks
    app.graphics = graphics.load("kitty")
    assert app.graphics is not None
    async with app.run_test(size=(120, 40)) as pilot:
        await settle(pilot, app)
        view = app.main.query_one(FrameView)
        widget = view._graphic
        assert view.graphics is app.graphics and widget is not None and widget.display
        width, height = app.graphics.picture_size((view.size.width, view.size.height), (320, 180))
        assert widget.image.size == (width, height) and width > 2 * view.size.width  # sharper than half-blocks
        first = np.asarray(widget.image).copy()
        await pilot.press("L")
        await pilot.pause(0.2)
        assert view.shown == 10 and not np.array_equal(np.asarray(widget.image), first)
        before = app.main.selected_hand
        await pilot.press("t")
        assert app.main.selected_hand != before
        pad, columns, rows = view._layout()
        await pilot.click(FrameView, offset=(pad + int(165 / 320 * columns), int(95 / 180 * rows)))  # the tomato
        await pilot.pause()
        assert view.selected_box == "tomato"
