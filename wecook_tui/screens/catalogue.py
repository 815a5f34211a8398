"""Every screen's key bindings in one place: the help lists them and the key file may remap them by id.

A new screen adds its bindings to :func:`other_screens`.
"""

from __future__ import annotations

from collections.abc import Iterable

from textual.binding import Binding


def _bindings(items: Iterable[object]) -> list[Binding]:
    return [b for b in items if isinstance(b, Binding)]


def other_screens() -> dict[str, list[Binding]]:
    """Screen title -> its bindings, for every screen but the review screen."""
    from wecook_tui.screens.boxes import BOX_BINDINGS
    from wecook_tui.screens.goto import GoToScreen
    from wecook_tui.screens.links import LinkPickerScreen
    from wecook_tui.screens.picker import PickerScreen
    from wecook_tui.screens.plan_review import PLAN_BINDINGS
    from wecook_tui.screens.run import RUN_BINDINGS

    return {"Plan review": PLAN_BINDINGS, "Run screen": RUN_BINDINGS,
            "Pickers (enter chooses)": _bindings(PickerScreen.BINDINGS),
            "Link picker (space toggles)": _bindings(LinkPickerScreen.BINDINGS),
            "Go to (enter goes)": _bindings(GoToScreen.BINDINGS),
            "Box mode (B on the review screen)": BOX_BINDINGS}


def binding_ids() -> set[str]:
    """The id of every binding of every screen (what a key file may name)."""
    from wecook_tui.screens.help import HelpScreen
    from wecook_tui.screens.main import MAIN_BINDINGS

    everything = [*MAIN_BINDINGS, *_bindings(HelpScreen.BINDINGS)]
    for bindings in other_screens().values():
        everything += bindings
    return {b.id for b in everything if b.id}
