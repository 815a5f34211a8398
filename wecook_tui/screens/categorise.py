"""Asking what the labels nothing categorises are: each is taken as an ingredient until the user says tool,
container or ingredient; each answer is a ``set_category`` correction (journaled, undoable) and the analysis
re-runs."""

from __future__ import annotations

from typing import Any

from wecook_core.model import Category
from wecook_core.session.boxes import SetCategory
from wecook_tui import review
from wecook_tui.screens.picker import PickerScreen
from wecook_tui.workbench_state import workbench

CATEGORY_OPTIONS = [("tool", "tool         acts on others: knife, spoon, whisk"),
                    ("container", "container    holds others: bowl, pan, board"),
                    ("ingredient", "ingredient   is held, cut or poured: tomato, salt")]


def ask_categories(app: Any) -> None:
    """Ask about one unknown label (with several, the label is picked first), then the next, until none is left
    or the user cancels."""
    wb = workbench(app)
    labels = review.unknown_labels(wb.opened)
    if not labels:
        app.notify("Every object label has a category.")
        return

    def category_chosen(label: str, value: str | None) -> None:
        if value and wb.correct(SetCategory(label, Category(value))) and review.unknown_labels(wb.opened):
            ask_categories(app)  # the next one

    def label_chosen(label: str | None) -> None:
        if label:
            app.push_screen(PickerScreen(f"What is {label!r}? (taken as an ingredient until you say)",
                                         CATEGORY_OPTIONS, "ingredient"),
                            lambda value: category_chosen(label, value))

    if len(labels) == 1:
        label_chosen(labels[0])
    else:
        app.push_screen(PickerScreen(f"{len(labels)} labels nothing categorises: pick one",
                                     [(label, label) for label in labels]), label_chosen)
