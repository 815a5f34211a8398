"""The timeline: a ruler with the cursor, one lane per hand coloured by action, and each segment's status.

Drawn with the line API: the lanes' cells are computed once per analysis (or resize) and each cursor move only
swaps the cursor column, so stepping through frames costs a few hundred microseconds here.
"""

from __future__ import annotations

import bisect
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from functools import cache

from rich.segment import Segment as RichSegment
from rich.style import Style
from textual.events import Click
from textual.message import Message
from textual.reactive import reactive
from textual.strip import Strip
from textual.widget import Widget

from wecook_core.model import Segment, SegmentStatus
from wecook_tui.review import ACTION_COLOURS, STATUS_GLYPHS, UNSURE_GLYPH, Lane

LABEL_WIDTH = 8
IDLE = "#303030"
Cell = tuple[str, str]
"""(character, colour)."""


@cache
def _style(colour: str, bold: bool = False, reverse: bool = False, dim: bool = False) -> Style:
    return Style(color=colour, bold=bold, reverse=reverse, dim=dim)


def _strip(cells: list[tuple[str, Style]], width: int) -> Strip:
    """Run-length join cells of equal style into segments."""
    segments: list[RichSegment] = []
    text, style = "", None
    for char, cell_style in cells:
        if cell_style is style:
            text += char
            continue
        if text:
            segments.append(RichSegment(text, style))
        text, style = char, cell_style
    if text:
        segments.append(RichSegment(text, style))
    return Strip(segments).crop_extend(0, width, None)


class Timeline(Widget):
    """Whole video mapped onto the width; the current segment is raised, the cursor is a bright column."""

    DEFAULT_CSS = """
    Timeline { height: auto; }
    """

    cursor: reactive[int] = reactive(0)
    """Frame under the cursor."""
    selected_hand: reactive[str | None] = reactive(None)
    """The lane the hand-specific keys act on (marked ▶)."""

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.frame_count = 1
        self.lanes: tuple[Lane, ...] = ()
        self.segments: tuple[Segment, ...] = ()
        self.status: Mapping[int, SegmentStatus] = {}
        self.unsure: frozenset[int] = frozenset()
        self._rows: list[list[Cell]] = []
        """Lane rows then the status row, without cursor or current-segment marks; for the current width."""
        self._row_width = -1
        self._frames: list[int] = []
        """First frame of each track column."""
        self._lines: dict[tuple[int, int, int, int, str | None], Strip] = {}
        """Lane and status lines by (row, cursor column, current segment's columns, selected hand): stepping
        a frame moves the cursor a column every few frames, so most repaints reuse every line but the ruler."""

    def set_data(self, frame_count: int, lanes: tuple[Lane, ...], segments: tuple[Segment, ...],
                 status: Mapping[int, SegmentStatus], unsure: Collection[int] = ()) -> None:
        """``unsure``: starts of the segments still to review whose evidence is too thin (marked ?)."""
        self.unsure = frozenset(unsure)
        self.frame_count = max(1, frame_count)
        self.lanes = lanes
        self.segments = segments
        self.status = status
        self.styles.height = len(lanes) + 4  # ruler, lanes, status, legend, border
        self._row_width = -1
        self.refresh()

    @dataclass
    class Seek(Message):
        """The user clicked the timeline at ``frame``."""

        frame: int

    def on_click(self, event: Click) -> None:
        """A click on the track moves the cursor to the first frame of that column."""
        column = event.x - LABEL_WIDTH
        if self._row_width != self.track_width:
            self._build_rows()
        if 0 <= column < len(self._frames):
            self.post_message(self.Seek(int(self._frames[column])))

    @property
    def track_width(self) -> int:
        return max(1, self.size.width - LABEL_WIDTH)

    def column_of(self, frame: int) -> int:
        """The column whose frames include ``frame``."""
        if self._row_width != self.track_width:
            self._build_rows()
        return max(0, bisect.bisect_right(self._frames, frame) - 1)

    def _columns_of(self, seg: Segment) -> tuple[int, int]:
        """First and last column whose first frame lies in ``seg`` (last < first when none does)."""
        return bisect.bisect_left(self._frames, seg.start), bisect.bisect_left(self._frames, seg.end) - 1

    def _build_rows(self) -> None:
        width = self.track_width
        frames = [column * self.frame_count // width for column in range(width)]
        self._frames = frames
        rows: list[list[Cell]] = []
        for lane in self.lanes:
            row: list[Cell] = []
            spans = lane.spans
            index = 0
            for frame in frames:
                while index < len(spans) - 1 and spans[index][1] <= frame:
                    index += 1
                span = spans[index] if spans else None
                label = span[2] if span and span[0] <= frame < span[1] else None
                colour = ACTION_COLOURS.get(label, "#9e9e9e") if label else IDLE
                boundary = bool(row) and label is not None and row[-1][1] != colour  # the action changes
                row.append(("▎" if boundary else "▄", colour))
            rows.append(row)
        status_row: list[Cell] = [(" ", IDLE)] * width
        for seg in self.segments:
            glyph, colour = STATUS_GLYPHS[SegmentStatus(self.status.get(seg.start, SegmentStatus.UNREVIEWED))]
            if seg.start in self.unsure:
                glyph, colour = UNSURE_GLYPH
            first, last = self._columns_of(seg)
            for column in range(first, min(max(first, last) + 1, width)):
                status_row[column] = (glyph if column == first else "─", colour)
        rows.append(status_row)
        self._rows = rows
        self._row_width = width
        self._lines = {}

    def watch_cursor(self) -> None:
        self.refresh()

    def watch_selected_hand(self) -> None:
        self.refresh()

    def render_line(self, y: int) -> Strip:
        width = self.size.width
        if self._row_width != self.track_width:
            self._build_rows()
        cursor = self.column_of(self.cursor)
        if y == 0:  # ruler
            label = str(self.cursor)
            start = min(max(0, cursor - len(label) // 2), max(0, self.track_width - len(label)))
            return Strip([RichSegment(f"{'frame':<{LABEL_WIDTH}}", _style("#808080")),
                          RichSegment(" " * start + label, _style("#ffffff", bold=True))]).crop_extend(0, width, None)
        lanes = len(self.lanes)
        if 1 <= y <= lanes + 1 and self._rows:
            row = self._rows[y - 1]
            current = next((s for s in self.segments if s.start <= self.cursor < s.end), None)
            first, last = self._columns_of(current) if current else (-1, -2)
            key = (y, cursor, first, last, self.selected_hand if y <= lanes else None)
            cached = self._lines.get(key)
            if cached is not None and cached.cell_length == width:
                return cached
            if len(self._lines) > 4096:
                self._lines = {}
            if y <= lanes:
                hand = self.lanes[y - 1].hand
                marker = "▶" if hand == self.selected_hand else " "
                head = [(char, _style("#e0e0e0", bold=marker != " ")) for char in f"{marker}{hand:<{LABEL_WIDTH - 1}}"]
                cells = [("┃", _style("#ffffff")) if column == cursor else
                         ("▆" if first <= column <= last and char == "▄" else char, _style(colour))
                         for column, (char, colour) in enumerate(row)]
            else:
                head = [(char, _style("#808080")) for char in f"{'status':<{LABEL_WIDTH}}"]
                cells = [(char, _style(colour, reverse=column == cursor)) for column, (char, colour) in enumerate(row)]
            line = self._lines[key] = _strip(head + cells, width)
            return line
        if y == lanes + 2:  # legend
            segments = [RichSegment(" " * LABEL_WIDTH)]
            for name, colour in ACTION_COLOURS.items():
                segments += [RichSegment("■", _style(colour)), RichSegment(f"{name} ", _style("#808080"))]
            return Strip(segments).crop_extend(0, width, None)
        return Strip.blank(width)
