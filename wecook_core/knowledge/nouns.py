"""Object names: normalising free text and matching it to a vocabulary of known nouns.

One matching rule serves the commonsense model (labels -> corpus nouns) and the category table
(labels -> categories), so "Rolling-Pin", "rolling pin" and "rolling_pins_2" mean the same everywhere.
Only the standard library: the runtime imports this.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from typing import TypeVar

T = TypeVar("T")

_SEPARATORS = re.compile(r"[\s\-_/.,;]+")
_DROP = re.compile(r"[^a-z0-9_]")
_INSTANCE_SUFFIX = re.compile(r"(?:_\d+)+$")


def normalise(label: str) -> str:
    """Lowercase, words joined by ``_``, punctuation dropped, instance suffix stripped.

    ``"Rolling-Pin" -> "rolling_pin"``, ``"bowl_2" -> "bowl"``, ``"chef's knife" -> "chefs_knife"``.
    A label made only of digits keeps them (``"7"`` stays ``"7"``).
    """
    text = label.strip().lower().replace("'", "")
    text = _SEPARATORS.sub("_", text).strip("_")
    text = _DROP.sub("", text)
    stripped = _INSTANCE_SUFFIX.sub("", text)
    return stripped or text


def epic_name(noun: str) -> str:
    """An EPIC-KITCHENS noun (``"board:chopping"``, head first, modifiers after ``:``) as a wecook name
    (``"chopping_board"``)."""
    parts = [p for p in noun.strip().lower().split(":") if p]
    if not parts:
        return ""
    return normalise(" ".join([*reversed(parts[1:]), parts[0]]))


def singular(word: str) -> str:
    """A simple English singular of the last word: tomatoes -> tomato, knives -> knife, berries -> berry."""
    if len(word) <= 3 or word.endswith(("ss", "us", "is")):
        return word
    if word.endswith("ies"):
        return word[:-3] + "y"
    if word.endswith("ves"):
        return word[:-3] + "f"
    if word.endswith(("oes", "ches", "shes", "xes", "sses", "zes")):
        return word[:-2]
    if word.endswith("s"):
        return word[:-1]
    return word


def variants(name: str) -> Iterator[str]:
    """``name`` and its number variants, most likely first: as given, singular, ``-fe`` form, plural."""
    yield name
    one = singular(name)
    if one != name:
        yield one
        if one.endswith("f"):
            yield one[:-1] + "fe"  # knives -> knife
        if name.endswith("es"):
            yield name[:-1]  # "sauces" -> "sauce", singular() gave "sauc"
    else:
        yield name + "s"
        yield name + "es"


def suffixes(name: str) -> Iterator[str]:
    """The name, then ever shorter tails down to the head noun: big_red_bowl, red_bowl, bowl."""
    words = name.split("_")
    for i in range(len(words)):
        yield "_".join(words[i:])


def match(label: str, names: Mapping[str, T]) -> T | None:
    """The entry of ``names`` (normalised name -> value) that ``label`` means, or None.

    Tries, in order: the full normalised label, its singular/plural, then ever shorter tails of it (the
    head noun last), each with its number variants. ``names`` keys must be normalised.
    """
    name = normalise(label)
    if not name:
        return None
    for tail in suffixes(name):
        for candidate in variants(tail):
            found = names.get(candidate)
            if found is not None:
                return found
    return None
