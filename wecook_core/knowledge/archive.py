"""The Open Recipe Archive as a corpus: one (verb, objects) record per clause of its direction steps.

The archive (``../shared/data/recipes/open-recipe-archive.jsonl.gz``, the Unlicense) is one JSON object a
line: ``id`` (``collection/slug``), ``collection``, ``source`` (the book), ``ingredients`` (lines) and ``steps``
(the numbered directions). Each step is read by :func:`wecook_core.knowledge.instructions.extract_relations` with the
recipe's ingredient list, so "add them" takes the ingredients named last. A record's group is the recipe's id,
whose ``collection/`` prefix is the unit of held-out splits (:func:`wecook_core.knowledge.evaluation.split`:
a whole collection is held out, never a sentence or a recipe of a book learned from).

The old books hyphenate what is one word now ("sauce-pan", "stew-pan"): the noun lookup tries the words
joined (``saucepan``), and :data:`OLD_SPELLINGS` names the object classes of the old words the category
tables do not know.

No NLP library parses the steps: none that is well kept installs from PyPI with its English model inside.
spaCy's models (en_core_web_sm) are published on GitHub, not PyPI (the PyPI copies are third-party re-uploads);
NLTK's tagger, TextBlob's corpora and Stanza's models are downloaded at run time; lemminflect and simplemma
ship their data but only lemmatise, which the verb list and its gerunds already cover. The clause reader of
:mod:`wecook_core.knowledge.instructions` is extended instead.
"""

from __future__ import annotations

import gzip
import json
import re
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError
from wecook_core.knowledge.corpus import Corpus, Record
from wecook_core.knowledge.instructions import extract_relations
from wecook_core.knowledge.nouns import singular, variants

ARCHIVE_SOURCE = "open-recipe-archive"
ARCHIVE_FILE = "open-recipe-archive.jsonl.gz"
ARCHIVE_LICENCE = "Unlicense (public domain dedication)"

OLD_SPELLINGS: Mapping[str, str] = {
    "stewpan": "pan", "stew_pan": "pan", "fryingpan": "frying_pan", "frying_pan": "frying_pan",
    "spider": "frying_pan", "skillet": "frying_pan", "griddle": "pan", "kettle": "pot", "stewpot": "pot",
    "porringer": "bowl", "basin": "bowl", "pipkin": "pot", "dripping_pan": "tray", "baking_pan": "tray",
    "baking_dish": "dish", "pie_dish": "dish", "gravy_boat": "jug", "sauceboat": "jug", "tureen": "bowl",
    "cloth": "towel", "napkin": "towel", "muslin": "towel", "rolling_pin": "rolling_pin", "paste_board": "board",
    "pasteboard": "board", "skimmer": "ladle", "egg_beater": "whisk", "eggbeater": "whisk",
    "egg_plant": "aubergine", "eggplant": "aubergine",
}
"""Old cookbook words -> the object class they are (a stew-pan is a pan, a spider a frying pan, a basin a bowl),
added to the noun table where it does not know the word; only classes the table has are kept."""


def is_archive(path: Path) -> bool:
    """Whether ``path`` is the archive's JSON lines (``*.jsonl`` or ``*.jsonl.gz``) or a folder holding it."""
    if path.is_dir():
        return (path / ARCHIVE_FILE).is_file()
    return path.is_file() and path.name.endswith((".jsonl", ".jsonl.gz"))


def archive_file(path: Path) -> Path:
    return path / ARCHIVE_FILE if path.is_dir() else path


def with_old_spellings(nouns: Mapping[str, str]) -> dict[str, str]:
    """The noun table with :data:`OLD_SPELLINGS` whose class it has (a table entry wins)."""
    table = dict(nouns)
    for word, name in OLD_SPELLINGS.items():
        if name in table.values() or name in table:
            table.setdefault(word, table.get(name, name))
    return table


_CUT = re.compile(r"[,(;:]| or | to | for | and | with | if ")
_WORD = re.compile(r"[a-z]+")
MEASURES: frozenset[str] = frozenset({
    "bunch", "cup", "dash", "dessertspoon", "dessertspoonful", "doz", "dozen", "drop", "gallon", "gill", "glass",
    "glassful", "gram", "handful", "half", "kilo", "liter", "litre", "lb", "little", "ounce", "oz", "piece", "pinch",
    "pint", "pound", "quantity", "quart", "quarter", "saltspoon", "saltspoonful", "slice", "spoon", "spoonful",
    "sprig", "stick", "tablespoon", "tablespoonful", "taste", "teacup", "teacupful", "teaspoon", "teaspoonful",
    "tbsp", "tsp", "wineglass", "wineglassful", "whole", "some", "each", "more", "other", "same", "any",
})
"""Words that end an ingredient line without being its ingredient ("a pinch", "1 teacupful")."""


def ingredient_nouns(lines: Iterable[str], nouns: Mapping[str, str]) -> dict[str, str]:
    """The head nouns of a recipe's ingredient lines that ``nouns`` does not know, each to itself: the last word
    before a comma, a parenthesis or "or", "to", "and"... ("1 oz. Butter or Dripping" -> butter, "a little grated
    nutmeg" -> nutmeg, "whites of four eggs" -> egg), singular, measures (:data:`MEASURES`) left out. A
    sentence of the recipe that names one ("Sprinkle with nutmeg") then has an object where the category tables
    alone gave it none."""
    found: dict[str, str] = {}
    for line in lines:
        words = _WORD.findall(_CUT.split(" " + line.lower() + " ", maxsplit=1)[0])
        if not words:
            continue
        head = singular(words[-1])
        if len(head) < 3 or head in MEASURES or words[-1] in MEASURES:
            continue
        if not any(v in nouns for v in variants(head)):
            found.setdefault(head, head)
    return found


def recipes(path: Path) -> Iterator[dict[str, Any]]:
    """The archive's recipes, in file order; InputError naming the line of a malformed one."""
    file = archive_file(path)
    opener = gzip.open if file.name.endswith(".gz") else open
    try:
        with opener(file, "rt", encoding="utf-8") as lines:
            for number, line in enumerate(lines, start=1):
                if not line.strip():
                    continue
                try:
                    recipe = json.loads(line)
                except json.JSONDecodeError as error:
                    raise InputError(file, f"invalid JSON: {error.msg}", place=f"line {number}") from None
                if not isinstance(recipe, dict) or not isinstance(recipe.get("id"), str) \
                        or not isinstance(recipe.get("steps"), list):
                    raise InputError(file, "expected an object with an `id` and a list of `steps`",
                                     place=f"line {number}")
                yield recipe
    except (OSError, EOFError, UnicodeDecodeError) as error:
        raise InputError(file, f"cannot read the recipe archive: {error}") from None


def read_archive(path: Path, nouns: Mapping[str, str], *, own_nouns: bool = True) -> Corpus:
    """The archive as a corpus: every clause of every recipe's steps, grouped by recipe id. ``own_nouns``: a
    recipe's steps are read with the nouns of its own ingredient list too (:func:`ingredient_nouns`)."""
    table = with_old_spellings(nouns)
    found: list[Record] = []
    count = 0
    for recipe in recipes(path):
        count += 1
        steps = [str(s) for s in recipe["steps"]]
        ingredients = [str(i) for i in recipe.get("ingredients") or ()]
        extra = ingredient_nouns(ingredients, table) if own_nouns else {}
        for verb, objects, relations in extract_relations(steps, {**table, **extra} if extra else table,
                                                          ingredients):
            found.append(Record(verb, objects, recipe["id"], source=ARCHIVE_SOURCE, relations=relations))
    if not found:
        raise InputError(archive_file(path), "no recipe steps found")
    return Corpus(records=tuple(found), sources=(f"{archive_file(path).name} ({count} recipes, {len(found)} clauses)",),
                  licences=(ARCHIVE_LICENCE,))
