"""The kitchen's things: what each object looks like from above, how big it is and where a hand holds it.

Sizes are pixels of the nominal 640x360 table image. Every object has a local frame: its angle turns the
local x axis (the long axis of a tool, handle at the negative end) into the image. ``size`` is ``(w, h)``
along local x and y; the drawn shape stays inside that rectangle, so the box is its rotated extent.
"""

from __future__ import annotations

from dataclasses import dataclass

from wecook_core.model import Category


@dataclass(frozen=True)
class Kind:
    """One sort of object."""

    label: str
    """The label written to the box file (``"chopping board"``)."""
    style: str
    """Which drawing routine of :mod:`wecook_core.synth.render` draws it."""
    size: tuple[float, float]
    """``(w, h)`` pixels along the local x and y axes."""
    colour: tuple[int, int, int]
    """Main colour, BGR."""
    round: bool = False
    """Drawn as an ellipse: the box of a turned ellipse is tighter than a turned rectangle's."""
    grip: float = 0.0
    """Where a hand holds it, on the local x axis (pixels from the centre; negative: towards the handle)."""


KINDS: dict[str, Kind] = {k.label: k for k in (
    Kind("knife", "knife", (86, 12), (200, 200, 205), grip=-36),
    Kind("spoon", "spoon", (60, 12), (170, 175, 180), grip=-22),
    Kind("peeler", "peeler", (50, 12), (60, 140, 60), grip=-24),
    Kind("rolling pin", "rolling_pin", (88, 16), (120, 180, 215), grip=-34),
    Kind("chopping board", "board", (76, 112), (90, 150, 200)),
    Kind("pot", "pot", (84, 108), (70, 70, 75)),
    Kind("bowl", "bowl", (62, 62), (230, 225, 215), round=True),
    Kind("jar", "jar", (48, 48), (215, 200, 170), round=True),
    Kind("cup", "jar", (46, 46), (60, 120, 220), round=True),
    Kind("tomato", "tomato", (26, 26), (40, 40, 215), round=True),
    Kind("lemon", "lemon", (30, 22), (40, 220, 240), round=True),
    Kind("dough", "dough", (58, 42), (170, 215, 235), round=True),
    Kind("potato", "potato", (36, 26), (80, 140, 180), round=True),
    Kind("oil", "bottle", (20, 42), (60, 200, 230)),
    Kind("salt", "shaker", (20, 26), (245, 245, 245)),
    Kind("sugar", "heap", (18, 14), (250, 250, 250), round=True),
    Kind("rice", "heap", (18, 14), (225, 240, 245), round=True),
    Kind("peas", "peas", (18, 14), (60, 180, 70), round=True),
    Kind("cheese", "cheese", (22, 18), (80, 200, 250)),
    Kind("onion", "heap", (22, 18), (150, 90, 160), round=True),
    Kind("carrot", "carrot", (24, 14), (40, 130, 240)),
)}
"""Every kind the script uses, by label."""

TRANSFER_SOURCES = ("jar", "cup")
"""Containers a spoon scoops from (chosen by seed)."""
SCOOPED = ("sugar", "rice", "peas")
"""Ingredients a spoon carries from its source container to the pot (chosen by seed)."""
TIPPED = ("cheese", "onion", "carrot")
"""Ingredients tipped from the bowl into the pot (chosen by seed)."""
HANDED_OVER = ("lemon", "salt", "oil")
"""Objects one person passes to the other (chosen per handover)."""

MAX_DOUGH = (76.0, 50.0)
"""The dough grows while it is rolled, up to this size."""

FALLBACK_CATEGORIES: dict[str, Category] = {
    "knife": Category.TOOL, "spoon": Category.TOOL, "peeler": Category.TOOL, "rolling pin": Category.TOOL,
    "chopping board": Category.CONTAINER, "pot": Category.CONTAINER, "bowl": Category.CONTAINER,
    "jar": Category.CONTAINER, "cup": Category.CONTAINER,
}
"""Used only for labels the shipped category table does not know (everything else: ingredient)."""


def category_of(label: str) -> Category:
    """The shipped table's category of a label (:mod:`wecook_core.knowledge.categories`), else the fallback."""
    from wecook_core.knowledge.categories import load_categories

    found = load_categories().categorize(label)
    if found is not None:
        return found
    return FALLBACK_CATEGORIES.get(label, Category.INGREDIENT)
