"""The box mode's name prompt: type any label, or pick one of the known labels (the commonsense corpus's objects,
most often seen first)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Input, OptionList, Static
from textual.widgets.option_list import Option


class NameScreen(ModalScreen[str | None]):
    """Type a label (any new one is allowed) or pick one of the known labels, best first."""

    BINDINGS: ClassVar = [Binding("escape", "cancel", "Cancel", id="name-cancel")]

    def __init__(self, labels: Sequence[str], current: str = "") -> None:
        super().__init__()
        self.labels = list(labels)
        self.current = current

    def compose(self) -> ComposeResult:
        with Vertical(id="picker"):
            yield Static("Name the box: type a label, or pick one (enter)", id="picker-title")
            yield Input(value=self.current, placeholder="label", id="name-input")
            yield OptionList(*(Option(label, id=label) for label in self.labels[:200]), id="picker-options")

    def on_mount(self) -> None:
        self.query_one(Input).focus()

    def on_input_changed(self, event: Input.Changed) -> None:
        text = event.value.strip().lower()
        options = self.query_one(OptionList)
        options.clear_options()
        matching = [label for label in self.labels if text in label.lower()] if text else self.labels
        options.add_options([Option(label, id=label) for label in matching[:200]])

    def on_input_submitted(self, event: Input.Submitted) -> None:
        event.stop()
        value = event.value.strip()
        self.dismiss(value or None)

    def on_option_list_option_selected(self, event: OptionList.OptionSelected) -> None:
        event.stop()
        self.dismiss(event.option.id)

    def action_cancel(self) -> None:
        self.dismiss(None)


def known_labels() -> list[str]:
    """Labels to name a box from: the commonsense corpus's objects, most often seen first, then the rest of
    the category table, alphabetically."""
    from wecook_core.knowledge.categories import load_categories
    from wecook_core.knowledge.recognize import load_knowledge

    knowledge = load_knowledge()
    counts = knowledge.pair_counts.sum(axis=0)
    ranked = [knowledge.objects[i].replace("_", " ") for i in sorted(range(len(knowledge.objects)),
                                                                      key=lambda i: (-int(counts[i]), i))]
    seen = set(ranked)
    rest = sorted(name.replace("_", " ") for name in load_categories().entries if name.replace("_", " ") not in seen)
    return ranked + rest
