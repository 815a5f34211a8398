"""The timeline: a ruler with the cursor, one lane per hand coloured by action, and each segment's status."""

from __future__ import annotations

from collections.abc import Mapping

from rich.style import Style
from rich.text import Text
from textual.reactive import reactive
from textual.widget import Widget

from wecook_core.model import Segment, SegmentStatus
from wecook_tui.review import ACTION_COLOURS, STATUS_GLYPHS, Lane

LABEL_WIDTH = 8
IDLE = "#303030"


class Timeline(Widget):
    """Whole video mapped onto the width; the current segment is underlined, the cursor is a bright column."""

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

    def set_data(self, frame_count: int, lanes: tuple[Lane, ...], segments: tuple[Segment, ...],
                 status: Mapping[int, SegmentStatus]) -> None:
        self.frame_count = max(1, frame_count)
        self.lanes = lanes
        self.segments = segments
        self.status = status
        self.styles.height = len(lanes) + 4  # ruler, lanes, status, legend, border
        self.refresh()

    def _column_frames(self, width: int) -> list[int]:
        """The frame each column of the track area stands for (its first frame)."""
        return [column * self.frame_count // width for column in range(width)]

    def render(self) -> Text:
        width = max(1, self.size.width - LABEL_WIDTH)
        frames = self._column_frames(width)
        cursor_col = min(width - 1, self.cursor * width // self.frame_count)
        current = next((s for s in self.segments if s.start <= self.cursor < s.end), None)
        text = Text(no_wrap=True, overflow="crop")
        # ruler
        text.append(f"{'frame':<{LABEL_WIDTH}}", style="dim")
        ruler = [" "] * width
        label = f"{self.cursor}"
        start = min(max(0, cursor_col - len(label) // 2), max(0, width - len(label)))
        ruler[start:start + len(label)] = list(label)
        text.append("".join(ruler), style="bold")
        text.append("\n")
        for lane in self.lanes:
            marker = "▶" if lane.hand == self.selected_hand else " "
            text.append(f"{marker}{lane.hand:<{LABEL_WIDTH - 1}}", style="bold" if marker != " " else "")
            spans = lane.spans
            span_index = 0
            for column, frame in enumerate(frames):
                while span_index < len(spans) - 1 and spans[span_index][1] <= frame:
                    span_index += 1
                span = spans[span_index] if spans else None
                label_ = span[2] if span and span[0] <= frame < span[1] else None
                colour = ACTION_COLOURS.get(label_ or "", "#9e9e9e") if label_ else IDLE
                in_current = current is not None and current.start <= frame < current.end
                boundary = column > 0 and span is not None and frames[column - 1] < span[0] <= frame
                char = "┃" if column == cursor_col else ("▎" if boundary else ("▆" if in_current else "▄"))
                fg = "#ffffff" if column == cursor_col else colour
                text.append(char, style=Style(color=fg, bgcolor=None))
            text.append("\n")
        text.append(f"{'status':<{LABEL_WIDTH}}", style="dim")
        status_row: list[tuple[str, str]] = [(" ", IDLE)] * width
        for seg in self.segments:
            glyph, colour = STATUS_GLYPHS[SegmentStatus(self.status.get(seg.start, SegmentStatus.UNREVIEWED))]
            first = seg.start * width // self.frame_count
            last = max(first, (seg.end * width // self.frame_count) - 1)
            for column in range(first, min(last + 1, width)):
                status_row[column] = ("─" if column != first else glyph, colour)
        for column, (char, colour) in enumerate(status_row):
            text.append(char, style=Style(color=colour, reverse=column == cursor_col))
        text.append("\n")
        text.append(" " * LABEL_WIDTH)
        for name, colour in ACTION_COLOURS.items():
            text.append("■", style=colour)
            text.append(f"{name} ", style="dim")
        return text
