"""Every key binding of the workbench with its id (for `keys.toml`) and what it does."""

from __future__ import annotations

from collections.abc import Iterable
from typing import ClassVar

from rich.table import Table
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import ModalScreen
from textual.widgets import Static

from wecook_tui.keymap import keymap_path


def binding_table(bindings: Iterable[Binding], keymap: dict[str, str], title: str = "Keys") -> Table:
    table = Table(title=title, expand=True, show_lines=False, title_justify="left")
    table.add_column("keys", style="bold cyan", no_wrap=True)
    table.add_column("does")
    table.add_column("id (keys.toml)", style="dim")
    for binding in bindings:
        keys = keymap.get(binding.id or "", binding.key)
        table.add_row(keys.replace(",", "  "), binding.description, binding.id or "")
    return table


class HelpScreen(ModalScreen[None]):
    BINDINGS: ClassVar = [Binding("escape,q,question_mark,f1", "close", "Close", id="help-close")]

    def __init__(self, bindings: list[Binding], keymap: dict[str, str],
                 more: dict[str, list[Binding]] | None = None) -> None:
        super().__init__()
        self.bindings_ = bindings
        """The review screen's bindings."""
        self.more = more or {}
        """Other screens' bindings, by screen title."""
        self.keymap = keymap

    def compose(self) -> ComposeResult:
        with VerticalScroll(id="help"):
            yield Static("up/down, page up/down scroll; escape closes", id="help-hint")
            yield Static(binding_table(self.bindings_, self.keymap, "Review screen"), id="help-table")
            for title, bindings in self.more.items():
                yield Static(binding_table(bindings, self.keymap, title), classes="help-more")
            yield Static(f"Remap any key in {keymap_path()} (or $WECOOK_KEYS), e.g.\n"
                         "  [keys]\n  accept = \"enter,a\"\n"
                         "All commands are also in the command palette (ctrl+p).", id="help-footer")

    def on_mount(self) -> None:
        self.query_one("#help", VerticalScroll).focus()  # the arrows and page keys scroll it

    def action_close(self) -> None:
        self.dismiss(None)
