"""Object categories (tool, container, ingredient) from a shipped table that users extend with YAML files.

Layers, later wins: the entries derived from the EPIC-KITCHENS noun categories
(``wecook_core/assets/knowledge/epic_categories.yaml``, written by ``wecook knowledge learn``), the hand-written table
``wecook_core/assets/categories.yaml``, the file ``$WECOOK_CATEGORIES`` names, then files passed in (``extra``).

A file::

    wecook_categories: 1          # optional
    objects:
      rolling pin: tool
      mixing bowl: container

Labels are matched like object names everywhere (:func:`wecook_core.knowledge.nouns.match`): lowercase,
``_`` or spaces, instance suffix (``bowl_2``) and plural stripped, and an unknown label falls back to ever
shorter tails down to its head noun ("big red bowl" -> bowl, "chef's knife" -> knife).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError, yaml_error
from wecook_core.files import read_text
from wecook_core.knowledge.nouns import match, normalise
from wecook_core.model import Category
from wecook_core.resources import ASSETS_DIR

CATEGORIES_PATH = ASSETS_DIR / "categories.yaml"
"""The hand-written table (overrides the derived one)."""
DERIVED_PATH = ASSETS_DIR / "knowledge" / "epic_categories.yaml"
"""Entries derived from the EPIC-KITCHENS noun categories."""
ENV_VAR = "WECOOK_CATEGORIES"

EXTEND_HINT = (
    "add them to a YAML file `objects: {label: tool|container|ingredient}` and pass it with --categories "
    f"or point ${ENV_VAR} at it"
)

EPIC_CATEGORIES: Mapping[str, Category] = {
    "cutlery": Category.TOOL,
    "utensils": Category.TOOL,
    "crockery": Category.CONTAINER,
    "cookware": Category.CONTAINER,
    "containers": Category.CONTAINER,
    "vegetables": Category.INGREDIENT,
    "fruits and nuts": Category.INGREDIENT,
    "meat and substitute": Category.INGREDIENT,
    "dairy and eggs": Category.INGREDIENT,
    "baked goods and grains": Category.INGREDIENT,
    "spices and herbs and sauces": Category.INGREDIENT,
    "prepared food": Category.INGREDIENT,
    "drinks": Category.INGREDIENT,
}
"""EPIC-KITCHENS noun category -> wecook category. Appliances, furniture, materials, cleaning, rubbish and
the rest are left out: the hand-written table names the few of them that matter (foil, lid)."""


@dataclass(frozen=True)
class CategoryTable:
    """Normalised label -> category, with the files it was read from."""

    entries: Mapping[str, Category]
    """Keys are normalised (:func:`~wecook_core.knowledge.nouns.normalise`)."""
    sources: tuple[str, ...] = field(default=())
    """Files merged into the table, in order (later won)."""

    def categorize(self, label: str) -> Category | None:
        """The category of a free-text label, or None when neither it nor its head noun is known."""
        return match(label, self.entries)

    def merged(self, other: CategoryTable) -> CategoryTable:
        """This table with ``other``'s entries on top."""
        return CategoryTable({**self.entries, **other.entries}, self.sources + other.sources)

    def categorize_all(self, labels: Iterable[str], source: str | Path) -> dict[str, Category]:
        """Every label's category; an InputError naming ``source`` lists the labels that have none."""
        found: dict[str, Category] = {}
        missing: list[str] = []
        for label in labels:
            category = self.categorize(label)
            if category is None:
                if label not in missing:
                    missing.append(label)
            else:
                found[label] = category
        if missing:
            raise InputError(source, f"cannot categorise {', '.join(repr(m) for m in missing)} as tool, "
                                     f"container or ingredient; {EXTEND_HINT}")
        return found


def _line(node: yaml.Node) -> str:
    return f"line {node.start_mark.line + 1}"


def parse_categories(text: str, path: str | Path) -> CategoryTable:
    """A table from YAML text: ``objects:`` mapping label -> category (or the mapping at top level)."""
    try:
        root = yaml.compose(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except yaml.YAMLError as error:
        raise yaml_error(path, error, "invalid YAML") from None
    if root is None:
        return CategoryTable({}, (str(path),))
    if not isinstance(root, yaml.MappingNode):
        raise InputError(path, "expected a mapping `objects: {label: category}`", place=_line(root))
    table = root
    for key, value in root.value:
        if isinstance(key, yaml.ScalarNode) and key.value == "objects":
            if not isinstance(value, yaml.MappingNode):
                raise InputError(path, "`objects` must map labels to categories", place=_line(value))
            table = value
    entries: dict[str, Category] = {}
    allowed = ", ".join(c.value for c in Category)
    for key, value in table.value:
        if table is root and isinstance(key, yaml.ScalarNode) and key.value in ("wecook_categories", "source"):
            continue
        if not isinstance(key, yaml.ScalarNode) or not isinstance(value, yaml.ScalarNode):
            raise InputError(path, f"expected `label: category` with category one of {allowed}", place=_line(key))
        name = normalise(key.value)
        if not name:
            raise InputError(path, f"empty object label {key.value!r}", place=_line(key))
        try:
            entries[name] = Category(value.value.strip().lower())
        except ValueError:
            raise InputError(path, f"{value.value!r} is not a category (expected one of {allowed})",
                             place=_line(value)) from None
    return CategoryTable(entries, (str(path),))


def read_categories(path: Path) -> CategoryTable:
    try:
        text = read_text(path, "category table")
    except InputError as error:
        raise InputError(path, f"cannot read the category table: {error.message}") from None
    return parse_categories(text, path)


_SHIPPED: dict[tuple[tuple[str, int], ...], CategoryTable] = {}


def _shipped() -> CategoryTable:
    paths = [p for p in (DERIVED_PATH, CATEGORIES_PATH) if p.is_file()]
    key = tuple((str(p), p.stat().st_mtime_ns) for p in paths)
    if key not in _SHIPPED:
        table = CategoryTable({})
        for path in paths:
            table = table.merged(read_categories(path))
        _SHIPPED.clear()
        _SHIPPED[key] = table
    return _SHIPPED[key]


def load_categories(extra: Sequence[Path] = ()) -> CategoryTable:
    """The shipped table, then ``$WECOOK_CATEGORIES``, then ``extra`` files, each overriding the ones before."""
    table = _shipped()
    env = os.environ.get(ENV_VAR)
    for path in ([Path(env)] if env else []) + [Path(p) for p in extra]:
        table = table.merged(read_categories(path))
    return table


def categorize_all(labels: Iterable[str], source: str | Path,
                   table: CategoryTable | None = None) -> dict[str, Category]:
    """Every label's category (default table: :func:`load_categories`); InputError naming ``source`` and
    listing the labels that have none, with a hint how to extend the table."""
    return (table or load_categories()).categorize_all(labels, source)


# --------------------------------------------------------------------------------- derived from a corpus


def derive_categories(noun_categories: Mapping[str, str], aliases: Mapping[str, str] | None = None,
                      overrides: Mapping[str, Category] | None = None) -> dict[str, Category]:
    """Object -> category from a corpus's own noun categories (EPIC: "cutlery" -> tool, ...).

    ``overrides`` (the hand-written table) decide an object's category first, so that its one-word
    aliases (EPIC instances such as ``saucepan`` or ``mug``), which inherit it, agree with the table:
    ``board`` (an alias of the chopping board, EPIC "utensils") is a container. Aliases that are objects
    themselves keep their own category. Overridden entries are not repeated in the result.
    """
    overrides = overrides or {}
    derived: dict[str, Category] = {}
    for name, word in noun_categories.items():
        category = overrides.get(name) or EPIC_CATEGORIES.get(word.strip().lower())
        if category is not None:
            derived[name] = category
    for alias, name in (aliases or {}).items():
        if "_" not in alias and alias not in noun_categories and name in derived:
            derived.setdefault(alias, derived[name])
    return {name: category for name, category in sorted(derived.items()) if name not in overrides}


def format_categories(entries: Mapping[str, Category], header: str = "") -> str:
    """A category file's text: the header as comments, then ``objects:`` sorted by label."""
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    lines += ["wecook_categories: 1", "objects:"]
    lines += [f"  {name}: {category.value}" for name, category in sorted(entries.items())]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------ labels the table lacks

DEFAULT_CATEGORY = Category.INGREDIENT
"""What a label nothing knows is taken as until the user says: the category that claims least (it neither acts
on other objects, as a tool does, nor holds them, as a container does)."""

_OF = " of "


@dataclass(frozen=True)
class Categorised:
    """Every label's category and how it was found."""

    categories: Mapping[str, Category]
    """Label (as given) -> category, for every label; unknown ones have :data:`DEFAULT_CATEGORY`."""
    how: Mapping[str, str]
    """Label -> how its category was found, for a person: ``table``, ``head noun 'bowl'``, ``corpus noun
    'colander'`` or ``unknown``."""
    unknown: tuple[str, ...]
    """Labels nothing categorised, in first-seen order."""


def _phrases(label: str) -> list[str]:
    """The label, then for ``X of Y`` its head ``X`` and then ``Y`` ("bowl of rice" is a bowl; "slice of
    bread", whose head is no object, is bread)."""
    text = " ".join(label.replace("_", " ").split())
    lower = f" {text.lower()} "
    if _OF not in lower:
        return [label]
    head, _, rest = lower.strip().partition(_OF.strip() + " ")
    return [head.strip(), rest.strip(), label]


def categorise_labels(labels: Iterable[str], table: CategoryTable | None = None,
                      knowledge: Any | None = None) -> Categorised:
    """Every label's category, never an error: from the table (the label, its head noun, ``X of Y``'s head),
    else from the commonsense corpus (the corpus noun that the label or its head names through the corpus's
    aliases, "sieve" -> colander, and that noun's category), else :data:`DEFAULT_CATEGORY`, listed in
    :attr:`Categorised.unknown`. (Guessing from the actions a corpus noun is used with was tried and dropped:
    leaving each categorised noun out in turn, its five most alike nouns' majority was right for 67%, below
    the 73% of always answering the most common category.)

    ``knowledge`` is a :class:`~wecook_core.knowledge.recognize.Knowledge` (default: the shipped one)."""
    table = table if table is not None else load_categories()
    categories: dict[str, Category] = {}
    how: dict[str, str] = {}
    unknown: list[str] = []
    corpus = None
    for label in labels:
        if label in categories:
            continue
        found = _from_table(label, table)
        if found is None:
            if corpus is None:
                corpus = _Corpus(table, knowledge)
            found = corpus.categorise(label)
        if found is None:
            categories[label], how[label] = DEFAULT_CATEGORY, "unknown"
            unknown.append(label)
        else:
            categories[label], how[label] = found
    return Categorised(categories, how, tuple(unknown))


def _from_table(label: str, table: CategoryTable) -> tuple[Category, str] | None:
    phrases = _phrases(label)
    for phrase in phrases:
        category = table.categorize(phrase)
        if category is not None:
            exact = normalise(phrase) in table.entries and phrase == label
            return category, "table" if exact else f"head noun {_head(phrase, table)!r}"
    return None


def _head(phrase: str, table: CategoryTable) -> str:
    """The tail of ``phrase`` that the table knows (for saying how a label was categorised)."""
    from wecook_core.knowledge.nouns import suffixes, variants

    for tail in suffixes(normalise(phrase)):
        for candidate in variants(tail):
            if candidate in table.entries:
                return candidate.replace("_", " ")
    return normalise(phrase).replace("_", " ")


class _Corpus:
    """The commonsense corpus's nouns, for labels the table does not know."""

    def __init__(self, table: CategoryTable, knowledge: Any | None) -> None:
        if knowledge is None:
            from wecook_core.knowledge.recognize import load_knowledge

            knowledge = load_knowledge()
        self.table = table
        self.knowledge = knowledge
        self.names = {name: name for name in knowledge.objects}
        self.names.update({alias: name for alias, name in knowledge.aliases.items() if name in self.names})

    def categorise(self, label: str) -> tuple[Category, str] | None:
        for phrase in _phrases(label):
            noun = match(phrase, self.names)
            if noun is None:
                continue
            category = self.table.categorize(noun)
            if category is not None:
                return category, f"corpus noun {noun.replace('_', ' ')!r}"
        return None
