"""The Open Recipe Archive as a corpus: JSON lines, ingredient pronouns, old spellings, split by collection."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.knowledge.archive import ARCHIVE_SOURCE, is_archive, read_archive, with_old_spellings
from wecook_core.knowledge.evaluation import split, unit
from wecook_core.knowledge.instructions import clause_records, extract, noun_table
from wecook_core.knowledge.learning import Example
from wecook_core.knowledge.synonyms import load_synonyms

NOUNS = noun_table(["saucepan", "sauce", "pan", "gooseberry", "water", "sieve", "flour", "egg", "sugar", "dish",
                    "bowl", "fork"])

RECIPES = [
    {"id": "victorian-britain/gooseberry-fool", "collection": "victorian-britain", "source": "Beeton",
     "ingredients": ["1 quart of gooseberries", "a little water"],
     "steps": ["Put the gooseberries into a sauce-pan with a little water.",
               "When they are soft, stir them through a sieve."]},
    {"id": "ye-old-american/batter", "collection": "ye-old-american", "source": "Boston",
     "ingredients": ["2 eggs", "flour"], "steps": ["Beat the eggs with a fork in a basin", "Dredge with flour"]},
]


def _write(path: Path, recipes: list[dict[str, object]]) -> Path:
    with gzip.open(path, "wt", encoding="utf-8") as f:
        f.writelines(json.dumps(r) + "\n" for r in recipes)
    return path


def test_old_hyphenated_spellings_are_the_one_word_noun() -> None:
    assert clause_records("Put the sugar in a sauce-pan", NOUNS) == [("put", ("sugar", "saucepan"))]
    # the word is tried joined only when the hyphenated phrase is not a noun itself: "stew-pan" is a pan
    assert clause_records("Stir the sugar in the stew-pan", NOUNS) == [("stir", ("sugar", "pan"))]
    assert with_old_spellings(NOUNS)["basin"] == "bowl"
    assert "spider" not in with_old_spellings(NOUNS)  # frying_pan is not a class of this table


def test_an_egg_plant_is_no_egg() -> None:
    # the books' "egg-plant" (and the American "eggplant") is the aubergine: its peeling is not an egg's
    nouns = with_old_spellings(noun_table(["egg", "aubergine", "knife"]))
    for text in ("Peel the egg-plant", "Peel the egg plants", "Peel the eggplant"):
        assert clause_records(text, nouns) == [("peel", ("aubergine",))]
    assert clause_records("Peel the eggs", nouns) == [("peel", ("egg",))]


def test_pronouns_take_the_ingredients_named_last() -> None:
    steps = ["Put the gooseberries into a saucepan with water.", "When soft, stir them through a sieve."]
    assert extract(steps, NOUNS, ["gooseberries", "water"]) == [
        ("put", ("gooseberry", "saucepan", "water")), ("stir", ("gooseberry", "water", "sieve"))]
    assert extract(steps, NOUNS) == [("put", ("gooseberry", "saucepan", "water")), ("stir", ("sieve",))]
    # a clause that names an ingredient of the list keeps its own
    assert extract(["Add the flour.", "Beat the eggs and add them"], NOUNS, ["flour", "eggs"])[-1] == ("add", ("egg",))


def test_the_archive_is_a_corpus_grouped_by_recipe(tmp_path: Path) -> None:
    path = _write(tmp_path / "open-recipe-archive.jsonl.gz", RECIPES)
    assert is_archive(path) and is_archive(tmp_path) and not is_archive(tmp_path / "nothing")
    corpus = read_archive(tmp_path, NOUNS)
    assert [(r.action, r.objects, r.group) for r in corpus.records] == [
        ("put", ("gooseberry", "saucepan", "water"), "victorian-britain/gooseberry-fool"),
        ("stir", ("gooseberry", "water", "sieve"), "victorian-britain/gooseberry-fool"),
        ("beat", ("egg", "fork", "bowl"), "ye-old-american/batter"),
        ("dredge", ("flour",), "ye-old-american/batter")]
    assert {r.source for r in corpus.records} == {ARCHIVE_SOURCE}
    assert corpus.licences and "Unlicense" in corpus.licences[0]


def test_a_malformed_archive_line_is_named(tmp_path: Path) -> None:
    path = tmp_path / "a.jsonl"
    path.write_text(json.dumps(RECIPES[0]) + "\n{not json\n")
    with pytest.raises(InputError, match="line 2"):
        read_archive(path, NOUNS)


def test_split_holds_out_whole_collections_per_corpus() -> None:
    examples = [Example("cut", ("knife",), f"book{b}/recipe{r}", "archive") for b in range(10) for r in range(5)]
    examples += [Example("stir", ("spoon",), f"P{v:02d}_01", "epic") for v in range(10)]
    train, test, held = split(examples, seed=0, fraction=0.2)
    assert held == 4  # two books of ten, two videos of ten
    books = {unit(e.group) for e in test if e.source == "archive"}
    assert len(books) == 2 and not books & {unit(e.group) for e in train}
    assert sum(e.source == "epic" for e in test) == 2
    assert unit("victorian-britain/toad") == "victorian-britain" and unit("P01_01") == "P01_01"


def test_wrapping_in_egg_is_a_coating() -> None:
    # the books' "wrap them in beaten egg" (before frying) coats; "wrap the fish in paper" wraps
    nouns = noun_table(["egg", "fish", "paper", "batter"])
    assert clause_records("Wrap them in beaten egg", nouns) == [("wrap-coat", ("egg",))]
    assert clause_records("Wrap the fish in batter", nouns) == [("wrap-coat", ("fish", "batter"))]
    assert clause_records("Wrap the fish in paper", nouns) == [("wrap", ("fish", "paper"))]
    assert clause_records("Wrap the egg in paper", nouns) == [("wrap", ("egg", "paper"))]  # the egg is wrapped
    assert load_synonyms().fold("wrap-coat") == "dip"
