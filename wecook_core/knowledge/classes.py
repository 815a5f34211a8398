"""Object classes for backing off: what a noun the corpus names a few times is a kind of.

The role-aware model (:mod:`wecook_core.knowledge.relations`) learns ``relation:object`` features; an object
seen a few times ("cayenne", "stew-pan", "haddock") says little by itself, its class more ("a spice over the
fish", "a fish into the pan"). Two levels:

- the **class**: the EPIC-KITCHENS noun category of the object (``spices and herbs and sauces``, ``vegetables``,
  ``meat and substitute``, ``cookware``...), found through the class's instances like every EPIC noun
  (``pepper:cayenne`` makes "cayenne" a spice: the last word of an instance names the class's kind as well);
  an object EPIC does not know takes its role;
- the **role**: wecook's category of the object (tool, container, ingredient; the shipped category tables), an
  object they do not know being an ingredient (the recipe's own ingredient list named it,
  :func:`wecook_core.knowledge.archive.ingredient_nouns`).

Only the category words are read from EPIC's noun classes (``../shared/data/epic-kitchens``, CC BY-NC 4.0, read
in place as the shipped ``epic_categories.yaml`` is derived); without the folder every class is the role.
"""

from __future__ import annotations

import ast
import csv
from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from wecook_core.knowledge.categories import CategoryTable, load_categories
from wecook_core.knowledge.nouns import epic_name, match

NOUN_CLASSES = Path("epic100") / "EPIC_100_noun_classes.csv"
UNKNOWN_ROLE = "ingredient"


@dataclass(frozen=True)
class ObjectClasses:
    """Object name -> its class and its role (see the module docstring)."""

    classes: Mapping[str, str]
    roles: Mapping[str, str]


def epic_noun_categories(root: Path) -> dict[str, str]:
    """Normalised EPIC noun (class key, instance, an instance's last word when all its instances agree) -> the
    class's category word, ``_`` for spaces; empty when the folder has no noun classes."""
    file = root / NOUN_CLASSES
    if not file.is_file():
        return {}
    found: dict[str, str] = {}
    heads: dict[str, Counter[str]] = {}
    with file.open(newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            category = row.get("category", "").strip().replace(" ", "_")
            if not category:
                continue
            found.setdefault(epic_name(row["key"]), category)
            try:
                instances = ast.literal_eval(row.get("instances") or "[]")
            except (ValueError, SyntaxError):
                instances = []
            for instance in instances:
                found.setdefault(epic_name(str(instance)), category)
                parts = [p for p in str(instance).split(":") if p]
                if len(parts) > 1:
                    heads.setdefault(epic_name(parts[-1]), Counter())[category] += 1
    for word, counts in heads.items():
        if len(counts) == 1:
            found.setdefault(word, next(iter(counts)))
    return found


def object_classes(objects: Iterable[str], epic_root: Path | None = None,
                   table: CategoryTable | None = None) -> ObjectClasses:
    """The class and role of every object name (``epic_root``: the EPIC-KITCHENS folder, default the team's
    copy; ``table``: the category table, default the shipped one)."""
    if epic_root is None:
        from wecook_core.knowledge.build import default_corpus

        epic_root = default_corpus()
    categories = epic_noun_categories(epic_root)
    table = table if table is not None else load_categories()
    classes: dict[str, str] = {}
    roles: dict[str, str] = {}
    for name in objects:
        category = table.categorize(name)
        roles[name] = category.value if category is not None else UNKNOWN_ROLE
        classes[name] = match(name, categories) or roles[name]
    return ObjectClasses(classes, roles)
