"""A modal list to choose what a held object acts on: several targets, closest first; space toggles,
enter confirms, escape cancels."""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Label, SelectionList


class LinkPickerScreen(ModalScreen[tuple[str, ...] | None]):
    """Dismisses with the chosen targets in the order offered (closest first), or None when cancelled."""

    BINDINGS: ClassVar = [
        Binding("enter", "confirm", "Confirm", priority=True, id="links-confirm"),
        Binding("escape", "cancel", "Cancel", id="links-cancel"),
    ]

    def __init__(self, title: str, options: Sequence[tuple[str, str]], current: Sequence[str] = ()) -> None:
        super().__init__()
        self.title_text = title
        self.options = list(options)
        """(value, label) pairs, closest first."""
        self.current = tuple(current)

    def compose(self) -> ComposeResult:
        with Vertical(id="picker"):
            yield Label(f"{self.title_text}  (space toggles, enter confirms)", id="picker-title")
            yield SelectionList[str](*((label, value, value in self.current) for value, label in self.options),
                                     id="picker-options")

    def on_mount(self) -> None:
        self.query_one(SelectionList).focus()

    def action_confirm(self) -> None:
        chosen = set(self.query_one(SelectionList).selected)
        self.dismiss(tuple(value for value, _ in self.options if value in chosen))

    def action_cancel(self) -> None:
        self.dismiss(None)
