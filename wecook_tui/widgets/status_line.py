"""One line under the timeline: session, frame and time, segment, selected hand, what is running.

A line-API widget: updating it repaints one row and never triggers a layout pass (``Static.update`` would).
"""

from __future__ import annotations

from rich.text import Text
from textual.strip import Strip
from textual.widget import Widget


class StatusLine(Widget):
    DEFAULT_CSS = """
    StatusLine { height: 1; }
    """

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.text = Text()

    def show(self, text: Text) -> None:
        if text != self.text:
            self.text = text
            self.refresh()

    @property
    def plain(self) -> str:
        return self.text.plain

    def render_line(self, y: int) -> Strip:
        width = self.size.width
        if y != 0:
            return Strip.blank(width, self.rich_style)
        segments = list(self.text.render(self.app.console))
        return Strip(segments).apply_style(self.rich_style).crop_extend(0, width, self.rich_style)
