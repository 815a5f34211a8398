"""Go to a frame, a time or a segment: a one-line modal input; Escape cancels.

``120`` is frame 120, ``4.5s`` or ``1:05`` a time, ``#12`` (or ``s12``) the 12th segment.
"""

from __future__ import annotations

import re
from typing import ClassVar

from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Input, Label

_TIME = re.compile(r"^(?:(\d+):)?(\d+(?:\.\d*)?)\s*s?$")


def parse_target(text: str, fps: float, segment_starts: tuple[int, ...]) -> int | None:
    """The frame ``text`` names (see the module), or None when it names nothing."""
    text = text.strip().lower()
    if not text:
        return None
    if text[0] in "#s" and text[1:].strip().isdigit():
        number = int(text[1:])
        if 1 <= number <= len(segment_starts):
            return segment_starts[number - 1]
        return None
    if text.isdigit():
        return int(text)
    match = _TIME.match(text)
    if match and (match.group(1) is not None or text.endswith("s")):
        seconds = float(match.group(2)) + 60 * int(match.group(1) or 0)
        return round(seconds * fps)
    return None


class GoToScreen(ModalScreen[str | None]):
    """Dismisses with the text typed, or None when cancelled."""

    BINDINGS: ClassVar[list[BindingType]] = [Binding("escape", "cancel", "Cancel", id="goto-cancel")]

    def compose(self) -> ComposeResult:
        with Vertical(id="picker"):
            yield Label("Go to: frame (120), time (4.5s, 1:05) or segment (#12)", id="picker-title")
            yield Input(placeholder="120, 4.5s, 1:05, #12", id="goto-input")

    def on_mount(self) -> None:
        self.query_one(Input).focus()

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        self.dismiss(event.value)

    def action_cancel(self) -> None:
        self.dismiss(None)
