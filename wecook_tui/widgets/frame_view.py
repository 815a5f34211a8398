"""The current video frame with boxes, labels, hand markers and links, drawn in half-blocks.

The view never decodes on the UI thread: a cached frame is painted at once; a missing one is requested from a
decode worker (the previous picture stays until it arrives), and a prefetch worker keeps the frames ahead of
the cursor (behind it, when stepping back) in the cache.
"""

from __future__ import annotations

import contextlib
import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from textual import work
from textual.events import Click
from textual.filter import ANSIToTruecolor, LineFilter
from textual.geometry import Size
from textual.message import Message
from textual.strip import Strip
from textual.widget import Widget
from textual.worker import get_current_worker

from wecook_tui.frames import Canvas, FrameSource, Label, Overlay, blank, draw, fit, to_strips
from wecook_tui.graphics import Graphics, picture, to_pil
from wecook_tui.messages import FirstFramePainted, FrameDecoded

PREFETCH = 120
"""Frames decoded ahead of the cursor."""


def report_moment(name: str) -> None:
    """Append ``name`` and the wall time to ``$WECOOK_FIRST_FRAME`` (for bench.workbench): ``frame`` when the
    first video frame is painted, ``session`` when the boxes and hands are on screen."""
    path = os.environ.get("WECOOK_FIRST_FRAME")
    if path:
        with contextlib.suppress(OSError), open(path, "a") as out:
            out.write(f"{name} {time.time():.6f}\n")


class FrameView(Widget):
    """Shows frame ``index`` of ``source`` with ``overlay`` on top; a click says which box or hand it hit."""

    @dataclass
    class Clicked(Message):
        """The user clicked the picture of frame ``frame`` at video pixel ``pixel``."""

        frame: int
        pixel: tuple[float, float]
        box: str | None
        """The object whose box (the smallest, where boxes overlap) or label is under the click."""
        hand: str | None
        """The hand whose marker or label is under the click (it wins over a box)."""

    DEFAULT_CSS = """
    FrameView { height: 1fr; min-height: 6; }
    """

    def __init__(self, *, id: str | None = None, graphics: bool = False) -> None:
        """``graphics``: draw through the terminal's graphics protocol when the app chose one
        (``app.graphics``, :mod:`wecook_tui.graphics`); half-blocks otherwise."""
        super().__init__(id=id)
        self.want_graphics = graphics
        self.graphics: Graphics | None = None
        """The protocol in use (set on mount); None: half-blocks."""
        self._graphic: Widget | None = None
        self.source: FrameSource | None = None
        self.video_size: tuple[int, int] = (0, 0)
        """Pixels of the video that overlay coordinates refer to."""
        self.index = 0
        """The frame the cursor is on."""
        self.shown: int | None = None
        """The frame whose picture is on screen (lags ``index`` while decoding)."""
        self.overlay = Overlay()
        self.selected_box: str | None = None
        """The object drawn as selected (white, thicker): the last box clicked."""
        self._labels: list[Label] = []
        """The labels of the picture on screen, in the picture's cells."""
        self.message: str | None = None
        """Printed over the picture when frames cannot be shown (missing or corrupt video)."""
        self._strips: list[Strip] = []
        self._dirty = False
        self._image: np.ndarray | None = None
        self._direction = 1
        self.hold_prefetch = False
        """No decoding ahead (while the session's boxes and hands load, which it would slow down)."""
        self._moves: list[int] = []
        """The last four moves of the cursor (frames)."""
        self._prefetch_until: int | None = None
        self.first_painted = False
        """A decoded video frame has been painted."""
        self.misses = 0
        """Frames asked for that were not in the cache yet (the benchmark reports it)."""
        self.painted: tuple[int, float] | None = None
        """(frame, perf_counter) of the last repaint of the whole picture: the benchmark reads it."""

    # --------------------------------------------------------------------------------- public

    def set_source(self, source: FrameSource | None, video_size: tuple[int, int]) -> None:
        self.source = source
        self.video_size = video_size
        self.message = source.facts.error if source is not None else None
        self._resize_source()
        if source is not None and source.ok and self.index == 0 and self.size.width:
            source.decode(0)  # opening the video already decoded frame 0: this only resizes it
        self.show(self.index, self.overlay)

    def show(self, index: int, overlay: Overlay) -> None:
        """Move to frame ``index``: paint now if cached, else ask a worker and keep the old picture."""
        self._direction = 1 if index >= self.index else -1
        self._moves = [*self._moves[-3:], index - self.index]
        self.index = index
        self.overlay = overlay
        source = self.source
        if source is None or not source.ok or not self.size.width:
            self._image = None
            self._paint()
            return
        frame, at = source.cached(index), index
        stride = self.stride
        if frame is None and stride > 1:  # playback skipping frames: the latest kept frame before this one
            at = next((i for i in range(index - 1, index - stride, -1) if source.cached(i) is not None), index)
            frame = source.cached(at) if at != index else None
        if frame is not None:
            self._image = frame
            self.shown = at
            self._paint()
        else:
            self.misses += 1
            if self._image is not None:
                self._paint()  # new overlay on the old picture while the frame decodes
            self._decode(index)
        self._keep_ahead(index)

    # -------------------------------------------------------------------------------- workers

    @work(thread=True, exclusive=True, group="decode", exit_on_error=False)
    def _decode(self, index: int) -> None:
        source = self.source
        if source is None:
            return
        frame = source.decode(index)
        self.post_message(FrameDecoded(index, frame is not None))

    @work(thread=True, exclusive=True, group="prefetch", exit_on_error=False)
    def _prefetch(self, start: int, stop: int, step: int = 1, back: bool = False) -> None:
        """``back``: the window behind the cursor, read in blocks from ``stop`` down (nearest first)."""
        worker = get_current_worker()
        if self.source is None:
            return
        if back:
            self.source.prefetch_back(stop, stop - start, cancelled=lambda: worker.is_cancelled)
        else:
            self.source.prefetch(start, stop, cancelled=lambda: worker.is_cancelled, step=step)

    @property
    def stride(self) -> int:
        """Frames between the pictures kept ahead: 1, or while the last four moves all went forward by two or
        more (playback that cannot paint every frame, or repeated jumps), the smallest of them (at most 8)."""
        moves = self._moves
        if len(moves) < 4 or min(moves) < 2:
            return 1
        return min(8, min(moves))

    def _keep_ahead(self, index: int) -> None:
        source = self.source
        if source is None or not source.ok or self.hold_prefetch:
            return
        if self._direction > 0:
            probe, start, stop = index + PREFETCH // 2, index + 1, index + PREFETCH
        else:
            probe, start, stop = index - PREFETCH // 2, index - PREFETCH, index
        probe = max(0, probe)
        stride = self.stride if self._direction > 0 else 1
        ahead = any(source.cached(i) is not None for i in range(probe, probe + stride))
        if not ahead and self._prefetch_until != stop:
            self._prefetch_until = stop
            self._prefetch(start, stop, stride, back=self._direction < 0)

    def on_frame_decoded(self, message: FrameDecoded) -> None:
        message.stop()
        if message.index != self.index or self.source is None:
            return
        frame = self.source.cached(message.index)
        if frame is None:
            self.message = f"frame {message.index} does not decode"
            self._image = None
        else:
            self.message = self.source.facts.error
            self._image = frame
            self.shown = message.index
        self._paint()

    # ------------------------------------------------------------------------------- painting

    def on_mount(self) -> None:
        graphics = getattr(self.app, "graphics", None) if self.want_graphics else None
        if graphics is not None:
            self.graphics = graphics
            self._graphic = graphics.widget()
            self._graphic.display = False
            self.mount(self._graphic)

    def _picture_size(self) -> tuple[int, int]:
        """Pixels of the picture: two per cell row for half-blocks, the terminal's cell size with graphics."""
        if self.graphics is not None:
            return self.graphics.picture_size((self.size.width, self.size.height), self.video_size)
        return fit(self.video_size, (self.size.width, self.size.height))

    def _layout(self) -> tuple[int, float, float]:
        """(left pad in cells, the picture's width and height in cells)."""
        width, height = self._picture_size()
        if self.graphics is not None:
            columns, rows = width / self.graphics.cell[0], height / self.graphics.cell[1]
        else:
            columns, rows = float(width), height / 2
        return max(0, (self.size.width - math.ceil(columns)) // 2), columns, rows

    def _resize_source(self) -> None:
        width, height = self._picture_size()
        if self.source is not None:
            if self.graphics is not None:
                self.source.cache_size = min(self.source.cache_size, 120)  # full-size pictures
            self.source.set_size(width, height)
        self._image = None

    def on_resize(self) -> None:
        self._resize_source()
        self.show(self.index, self.overlay)

    def _paint(self) -> None:
        """Ask for a repaint; the picture is built when the compositor asks for lines, so keys that arrive
        faster than the screen refreshes cost no conversions for frames nobody sees."""
        self._dirty = True
        self.refresh()
        if self._graphic is not None:
            self._show_graphic()

    def _show_graphic(self) -> None:
        """Hand the picture with its overlay to the graphics widget (half-blocks show a missing frame)."""
        assert self._graphic is not None and self.graphics is not None
        width, height = self._picture_size()
        image = self._image
        if image is None or image.shape[1] != width or image.shape[0] != height or self.message:
            self._graphic.display = False
            return
        columns, rows = self.graphics.cells_of((width, height))
        self._graphic.styles.width = columns
        self._graphic.styles.height = rows
        self._graphic.styles.margin = (0, 0, 0, max(0, (self.size.width - columns) // 2))
        self._graphic.image = to_pil(picture(image, self._selected_overlay(), self.video_size))  # type: ignore[attr-defined]
        self._graphic.display = True
        self._labels = []

    def _selected_overlay(self) -> Overlay:
        if self.selected_box is None:
            return self.overlay
        return replace(self.overlay, boxes=tuple(replace(mark, selected=mark.name == self.selected_box)
                                                 for mark in self.overlay.boxes))

    def _build(self) -> None:
        self._dirty = False
        width, height = fit(self.video_size, (self.size.width, self.size.height))
        if self._graphic is not None and self._graphic.display:  # the graphics widget shows the picture
            self._strips = [Strip.blank(width)] * (height // 2)
            return
        image = self._image
        if image is None or image.shape[1] != width or image.shape[0] != height:
            image = blank(width, height)
        canvas: Canvas = draw(image, self._selected_overlay(), self.video_size)
        self._labels = list(canvas.labels)
        if self.message:
            canvas.labels.append(Label(1, 0, self.message[: max(0, width - 2)], (255, 200, 80)))
        self._strips = to_strips(canvas)

    def select_box(self, name: str | None) -> None:
        """Draw the box of ``name`` as selected (None: none)."""
        if name != self.selected_box:
            self.selected_box = name
            self._paint()

    # ---------------------------------------------------------------------------------- mouse

    def pixel_at(self, x: int, y: int) -> tuple[float, float] | None:
        """The video pixel at the centre of cell (x, y) of this view, or None outside the picture."""
        vw, vh = self.video_size
        pad, columns, rows = self._layout()
        column = x - pad
        if vw <= 0 or vh <= 0 or not (0 <= column < columns and 0 <= y < rows):
            return None
        return (min(vw, (column + 0.5) / columns * vw), min(vh, (y + 0.5) / rows * vh))

    def hit(self, x: int, y: int) -> tuple[str | None, str | None]:
        """(box, hand) under cell (x, y): a label names its box or hand; else the hand marker within a cell and
        a half, else the smallest box holding the point (its edge within half a cell)."""
        pad, columns, _ = self._layout()
        boxes = {mark.name for mark in self.overlay.boxes}
        hands = {mark.hand for mark in self.overlay.hands}
        for label in self._labels:
            if label.y == y and label.x <= x - pad < label.x + len(label.text):
                if label.text in hands:
                    return None, label.text
                if label.text in boxes:
                    return label.text, None
        point = self.pixel_at(x, y)
        if point is None:
            return None, None
        cell = self.video_size[0] / max(1.0, columns)  # video pixels per cell column
        near = [(math.hypot(mark.xy[0] - point[0], mark.xy[1] - point[1]), mark.hand) for mark in self.overlay.hands]
        near = [item for item in near if item[0] <= 1.5 * cell]
        if near:
            return None, min(near)[1]
        slack = cell / 2
        inside = [((x2 - x1) * (y2 - y1), mark.name) for mark in self.overlay.boxes
                  for x1, y1, x2, y2 in [mark.box]
                  if x1 - slack <= point[0] <= x2 + slack and y1 - slack <= point[1] <= y2 + slack]
        return (min(inside)[1] if inside else None), None

    def on_click(self, event: Click) -> None:
        offset = event.get_content_offset(self)
        if offset is None:
            return
        point = self.pixel_at(offset.x, offset.y)
        if point is None:
            return
        box, hand = self.hit(offset.x, offset.y)
        self.post_message(self.Clicked(self.index, point, box, hand))

    def get_line_filters(self) -> Sequence[LineFilter]:
        """The app's filters but the ANSI-to-truecolour one: every colour here is a truecolour triplet already,
        and that filter rebuilt each of the picture's few thousand segments on every repaint (about a fifth
        of a frame step's time)."""
        return [f for f in super().get_line_filters() if not isinstance(f, ANSIToTruecolor)]

    def get_content_width(self, container: Size, viewport: Size) -> int:
        return container.width

    def render_line(self, y: int) -> Strip:
        if self._dirty:
            self._build()
        strips = self._strips
        width = self.size.width
        if y >= len(strips):
            return Strip.blank(width)
        strip = strips[y]
        pad = max(0, (width - strip.cell_length) // 2)
        line = Strip.join([Strip.blank(pad), strip]) if pad else strip
        if y == len(strips) - 1:
            self.painted = (self.shown if self.shown is not None else -1, time.perf_counter())
            if self._image is not None and not self.first_painted:
                self.first_painted = True
                report_moment("frame")
                self.post_message(FirstFramePainted())
        return line.crop_extend(0, width, None)
