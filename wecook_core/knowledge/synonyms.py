"""Folding corpus verbs into wecook's action vocabulary (chop, slice, dice -> cut; whisk -> stir).

The rules are data (``wecook_core/assets/knowledge/synonyms.yaml``): a table of verb words and a table of corpus verb
classes; the corpus supplies its own class lists (EPIC's "cut" class lists chop, slice, dice, ...).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from wecook_core.errors import InputError
from wecook_core.model import VERBS
from wecook_core.resources import ASSETS_DIR

SYNONYMS_PATH = ASSETS_DIR / "knowledge" / "synonyms.yaml"

RECOGNISED: tuple[str, ...] = VERBS
"""The verbs the commonsense model ranks: the whole vocabulary. ``transfer`` is ranked too (spoon + rice +
jar + pot), though the pipeline detects transfers from container changes and leaves it out of the
candidates of an individual action."""


@dataclass(frozen=True)
class VerbFolder:
    """Folds a raw corpus verb into a wecook verb, or None when it is not one of wecook's actions."""

    words: Mapping[str, str | None]
    """Verb or first word of a verb -> wecook verb; None drops it."""
    classes: Mapping[str, str]
    """Corpus verb class key -> wecook verb."""
    verb_classes: Mapping[str, str] = field(default_factory=dict)
    """The corpus's raw verb -> class key."""

    def fold(self, verb: str) -> str | None:
        verb = verb.strip().lower()
        if verb in self.words:
            return self.words[verb]
        first = verb.split("-", 1)[0]
        if first in self.words:
            return self.words[first]
        key = self.verb_classes.get(verb)
        if key is None:
            key = self.verb_classes.get(first)
        if key is not None:
            return self.classes.get(key)
        return self.classes.get(verb)

    def with_classes(self, verb_classes: Mapping[str, str]) -> VerbFolder:
        return VerbFolder(self.words, self.classes, verb_classes)


def load_synonyms(path: Path | None = None, vocabulary: tuple[str, ...] = RECOGNISED) -> VerbFolder:
    """The folding rules of a synonyms YAML file (default: the shipped one); targets must be in ``vocabulary``."""
    path = path or SYNONYMS_PATH
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as error:
        raise InputError(path, f"cannot read the synonym table: {error}") from None
    if not isinstance(data, dict):
        raise InputError(path, "expected a mapping with `words` and `classes`")
    tables: dict[str, dict[str, str | None]] = {}
    for section in ("words", "classes"):
        table = data.get(section) or {}
        if not isinstance(table, dict):
            raise InputError(path, f"`{section}` must map verbs to wecook verbs", place=section)
        for key, value in table.items():
            if value is not None and value not in vocabulary:
                raise InputError(path, f"{value!r} is not a recognised verb (expected one of "
                                       f"{', '.join(vocabulary)} or null)", place=f"{section}.{key}")
        tables[section] = {str(k).strip().lower(): v for k, v in table.items()}
    classes = {k: v for k, v in tables["classes"].items() if v is not None}
    return VerbFolder(words=tables["words"], classes=classes)
