"""Recipe instructions as (verb, objects) records: clause verbs, noun phrases, Markdown recipes."""

from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.knowledge.corpus import RECIPES_SOURCE, read_corpus
from wecook_core.knowledge.instructions import clause_records, directions, extract, noun_table, sentences

NOUNS = noun_table(["ball", "apple", "knife", "bowl", "egg", "flour", "sugar", "salt", "pepper", "bell pepper", "water",
                    "spoon", "rice", "jar", "pot", "pan", "oil", "olive oil", "plastic wrap", "dough", "bread",
                    "butter", "foil"])


@pytest.mark.parametrize(("sentence", "records"), [
    ("Peel and cut the apples", [("peel", ("apple",)), ("cut", ("apple",))]),
    ("In a large bowl, whisk the eggs with the sugar", [("whisk", ("bowl", "egg", "sugar"))]),
    ("Using a spoon, transfer the rice into the jars", [("transfer", ("spoon", "rice", "jar"))]),
    ("Spoon the rice into the jars", [("spoon", ("spoon", "rice", "jar"))]),  # done with a spoon
    ("Salt and pepper to taste", []),  # nouns, not verbs
    ("Salt the water", [("salt", ("salt", "water"))]),
    ("Season with salt and pepper", [("season", ("salt", "pepper"))]),
    ("Cut the bell peppers, then add olive oil to the pan", [("cut", ("bell_pepper",)), ("add", ("olive_oil", "pan"))]),
    ("Begin by cutting the apples in half", [("cut", ("apple",))]),
    ("Heat the oil and gently stir in the flour", [("heat", ("oil",)), ("stir", ("flour",))]),
    ("Wrap the dough in plastic wrap", [("wrap", ("dough", "plastic_wrap"))]),
    ("The foil keeps it warm", []),  # no clause-opening verb
    ("Roll the balls in sugar", [("roll-in", ("ball", "sugar"))]),  # coating: folded into dip
    ("Roll out the dough", [("roll-out", ("dough",))]),  # with a pin
    ("Roll the dough, in a bowl or on the table", [("roll", ("dough", "bowl"))]),  # a comma ends the search
])
def test_clause_records(sentence: str, records: list[tuple[str, tuple[str, ...]]]) -> None:
    assert clause_records(sentence, NOUNS) == records


def test_nouns_match_whole_words_only() -> None:
    assert clause_records("Boil the potatoes in a pot", NOUNS) == [("boil", ("pot",))]  # potato is unknown
    assert clause_records("Stir the spoonful of sugar", NOUNS) == [("stir", ("sugar",))]  # not "spoon"


def test_sentences_drop_markup_and_asides() -> None:
    assert sentences("Cut the [apples](/apple) (about 4). Stir; serve!") == ["Cut the apples", "Stir", "serve"]
    assert extract(["Peel the apples. Put the butter in a bowl"], NOUNS) == [
        ("peel", ("apple",)), ("put", ("butter", "bowl"))]


RECIPE = """---
title: "Apple bowl"
---

Intro text, not a step: cut nothing.

## Ingredients

- 2 apples, cut in half

## Directions

1. Peel the apples
   and cut them.
2. Butter the bread.

## Notes

- Stir the pot.
"""


def test_directions_of_a_markdown_recipe() -> None:
    assert directions(RECIPE) == ["Peel the apples and cut them.", "Butter the bread."]


def test_a_folder_of_recipes_is_a_corpus(tmp_path: Path) -> None:
    content = tmp_path / "site" / "content"
    content.mkdir(parents=True)
    (content / "apple-bowl.md").write_text(RECIPE)
    (content / "_index.md").write_text("## Directions\n\n1. Stir the pot.\n")
    corpus = read_corpus(tmp_path / "site", nouns=NOUNS)
    assert [(r.action, r.objects, r.group, r.source) for r in corpus.records] == [
        ("peel", ("apple",), "apple-bowl", RECIPES_SOURCE), ("cut", (), "apple-bowl", RECIPES_SOURCE),
        ("butter", ("butter", "bread"), "apple-bowl", RECIPES_SOURCE)]
