"""The commonsense model at run time: exact probabilities from known counts, matching, batch, shipped tables."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.knowledge.recognize import (
    Knowledge,
    knowledge_from_json,
    load_knowledge,
    match_object,
    rank,
    rank_batch,
    save_knowledge,
    unknown_objects,
)
from wecook_core.model import VERBS as VERBS_OF_THE_GRAMMAR

# Three verbs, four objects. cut: 3 records, stir: 1, pour: 0.
VERBS = ("cut", "stir", "pour")
OBJECTS = ("knife", "tomato", "spoon", "chopping_board")
COUNTS = np.array([[3, 2, 0, 1],
                   [0, 0, 1, 0],
                   [0, 0, 0, 0]])
ACTIONS = np.array([3, 1, 0])


@pytest.fixture
def small() -> Knowledge:
    return Knowledge(VERBS, OBJECTS, ACTIONS, COUNTS, alpha=1.0, aliases={"cherry_tomato": "tomato"})


def test_smoothed_tables_match_the_formulas(small: Knowledge) -> None:
    # P(A) = (n_A + 1) / (4 + 3)
    assert small.prior() == pytest.approx({"cut": 4 / 7, "stir": 2 / 7, "pour": 1 / 7})
    # P(O | cut) = (n + 1) / (6 + 4); P(O | pour) uniform over the 4 objects
    assert small.likelihood("knife", "cut") == pytest.approx(4 / 10)
    assert small.likelihood("spoon", "cut") == pytest.approx(1 / 10)
    assert small.likelihood("spoon", "stir") == pytest.approx(2 / 5)
    assert small.likelihood("tomato", "pour") == pytest.approx(1 / 4)


def test_uniform_prior_ranks_by_the_likelihood_alone() -> None:
    uniform = Knowledge(VERBS, OBJECTS, ACTIONS, COUNTS, alpha=1.0, prior_kind="uniform")
    assert uniform.prior() == pytest.approx({"cut": 1 / 3, "stir": 1 / 3, "pour": 1 / 3})
    # spoon: P(spoon | cut) = 1/10, P(spoon | stir) = 2/5, P(spoon | pour) = 1/4
    assert dict(rank(uniform, ["spoon"])) == pytest.approx({"cut": 0.1 / 0.75, "stir": 0.4 / 0.75,
                                                            "pour": 0.25 / 0.75})
    with pytest.raises(ValueError, match="prior"):
        Knowledge(VERBS, OBJECTS, ACTIONS, COUNTS, prior_kind="flat")


def test_rank_is_the_normalised_posterior(small: Knowledge) -> None:
    ranking = rank(small, ["knife", "tomato"])
    cut = 4 / 7 * (4 / 10) * (3 / 10)
    stir = 2 / 7 * (1 / 5) * (1 / 5)
    pour = 1 / 7 * (1 / 4) * (1 / 4)
    total = cut + stir + pour
    assert [v for v, _ in ranking] == ["cut", "stir", "pour"]
    assert dict(ranking) == pytest.approx({"cut": cut / total, "stir": stir / total, "pour": pour / total})
    assert sum(p for _, p in ranking) == pytest.approx(1.0)


def test_candidates_restrict_and_renormalise(small: Knowledge) -> None:
    ranking = rank(small, ["spoon"], candidates=["pour", "stir"])
    stir, pour = 2 / 7 * 2 / 5, 1 / 7 * 1 / 4
    assert ranking == (("stir", pytest.approx(stir / (stir + pour))), ("pour", pytest.approx(pour / (stir + pour))))
    with pytest.raises(ValueError, match="dance"):
        rank(small, ["spoon"], candidates=["dance"])


def test_unknown_objects_are_ignored_and_reported(small: Knowledge) -> None:
    assert rank(small, ["knife", "spaceship"]) == rank(small, ["knife"])
    assert unknown_objects(small, ["knife", "spaceship", "Tomatoes"]) == ("spaceship",)
    prior = rank(small, [])
    assert dict(prior) == pytest.approx(small.prior())
    assert rank(small, ["spaceship"]) == prior


def test_free_text_labels_match_vocabulary_nouns(small: Knowledge) -> None:
    assert match_object(small, "Chopping Board") == "chopping_board"
    assert match_object(small, "chopping-board_2") == "chopping_board"
    assert match_object(small, "cherry_tomato") == "tomato"  # the corpus's alias
    assert match_object(small, "Cherry Tomatoes") == "tomato"
    assert match_object(small, "big ripe tomato") == "tomato"  # head noun
    assert match_object(small, "knives") == "knife"
    assert match_object(small, "bowl") is None


def test_each_occurrence_counts(small: Knowledge) -> None:
    once = dict(rank(small, ["tomato"]))
    twice = dict(rank(small, ["tomato", "tomato_2"]))
    assert twice["cut"] > once["cut"]


def test_log_space_survives_many_objects(small: Knowledge) -> None:
    ranking = rank(small, ["spoon"] * 2000)  # products underflow to 0 in linear space
    assert ranking[0] == ("stir", pytest.approx(1.0))
    assert all(math.isfinite(p) for _, p in ranking)


def test_batch_equals_rank_line_by_line(small: Knowledge) -> None:
    lines = [["knife", "tomato"], [], ["spoon", "nothing"], ["chopping board"], ["spoon"]]
    items = list(rank_batch(small, lines, chunk=2))
    assert len(items) == len(lines)
    assert items[1].ranking == ()
    assert items[2].unknown == ("nothing",)
    for labels, item in zip(lines, items, strict=True):
        if labels:
            expected = rank(small, labels)
            assert [v for v, _ in item.ranking] == [v for v, _ in expected]
            assert [p for _, p in item.ranking] == pytest.approx([p for _, p in expected])
    restricted = next(rank_batch(small, [["knife"]], ["stir", "pour"]))
    assert dict(restricted.ranking) == pytest.approx(dict(rank(small, ["knife"], ["stir", "pour"])))


def test_save_load_round_trip(tmp_path: Path, small: Knowledge) -> None:
    path = tmp_path / "k.json"
    save_knowledge(small, path)
    loaded = load_knowledge(path)
    assert loaded.verbs == VERBS and loaded.objects == OBJECTS
    assert (loaded.pair_counts == COUNTS).all() and (loaded.action_counts == ACTIONS).all()
    assert dict(rank(loaded, ["cherry tomato"])) == pytest.approx(dict(rank(small, ["tomato"])))
    assert load_knowledge(path) is loaded  # cached
    assert loaded.prior_kind == "corpus"
    uniform = Knowledge(VERBS, OBJECTS, ACTIONS, COUNTS, prior_kind="uniform")
    save_knowledge(uniform, tmp_path / "u.json")
    assert load_knowledge(tmp_path / "u.json").prior_kind == "uniform"


@pytest.mark.parametrize(("text", "fragment"), [
    ("{", "invalid JSON"),
    ('{"verbs": []}', "not a wecook knowledge file"),
    ('{"wecook_knowledge": 1, "verbs": ["cut"], "objects": ["a", "b"], "action_counts": [1], '
     '"pair_counts": [[1]]}', "shape"),
    ('{"wecook_knowledge": 1, "verbs": ["cut"], "objects": ["a"], "action_counts": [1], '
     '"pair_counts": [[-1]]}', "non-negative"),
])
def test_bad_knowledge_files_name_the_file(tmp_path: Path, text: str, fragment: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(InputError, match=fragment) as error:
        load_knowledge(path)
    assert str(path) in str(error.value)


def test_missing_knowledge_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="cannot read"):
        load_knowledge(tmp_path / "none.json")


# ------------------------------------------------------------------------------------ the shipped tables


def test_shipped_tables_load_fast() -> None:
    from wecook_core.knowledge.recognize import KNOWLEDGE_PATH

    data = json.loads(KNOWLEDGE_PATH.read_text())
    best = math.inf
    for _ in range(5):
        started = time.perf_counter()
        knowledge_from_json(json.loads(KNOWLEDGE_PATH.read_text()), KNOWLEDGE_PATH)
        best = min(best, time.perf_counter() - started)
    assert best < 0.05
    knowledge = load_knowledge()
    assert knowledge.verbs == tuple(data["verbs"]) == VERBS_OF_THE_GRAMMAR  # transfer, dip, wrap too
    assert load_knowledge() is knowledge


@pytest.mark.parametrize(("objects", "verb"), [
    (["knife", "tomato"], "cut"),
    (["knife", "onion", "chopping board"], "cut"),
    (["cherry_tomato", "Chopping-Board"], "cut"),
    (["spatula", "pan"], "stir"),
    (["rolling pin", "dough"], "roll"),
    (["peeler", "potato"], "peel"),
    (["hand", "lemon"], "squeeze"),
    (["lemon", "juicer"], "squeeze"),
    (["oil", "pan"], "pour"),
    (["butter", "knife", "bread"], "spread"),
    (["lemon"], "squeeze"),
    (["foil"], "wrap"),
    (["tortilla"], "wrap"),
    (["chicken", "flour"], "dip"),
    (["pepper", "pot"], "sprinkle"),
    (["spoon", "rice", "bowl"], "transfer"),
])
def test_shipped_tables_rank_what_the_corpus_supports(objects: list[str], verb: str) -> None:
    knowledge = load_knowledge()
    assert unknown_objects(knowledge, objects) == ()
    assert rank(knowledge, objects)[0][0] == verb


def test_bread_and_hummus_is_spread_or_dipped() -> None:
    """Bread with hummus is spread or dipped, and the corpora do both: EPIC's cooks and the recipes spread it,
    the old books dip bread (in egg, in milk) far more often than they spread it. Both lead, nothing else near."""
    ranking = rank(load_knowledge(), ["bread", "hummus"])
    assert {verb for verb, _ in ranking[:2]} == {"spread", "dip"} and ranking[2][1] < 0.1


def test_a_held_spoon_over_a_pot_stirs_among_the_tool_verbs() -> None:
    """Asked as the pipeline asks for a held tool (the tool verbs, :data:`TOOL_VERBS`), a spoon over a pot
    stirs. Over all verbs transfer, pour and stir lead: the books spoon things into pots ("spoon", a transfer
    with the spoon), EPIC's cooks hold a spoon in one hand while they pour with the other, and a held tool
    joins the records of both hands (``corpus.HELD_S``)."""
    from wecook_core.perception.recognition.actions import TOOL_VERBS

    knowledge = load_knowledge()
    assert rank(knowledge, ["spoon", "pot"], list(TOOL_VERBS))[0][0] == "stir"
    assert {verb for verb, _ in rank(knowledge, ["spoon", "pot"])[:3]} == {"transfer", "stir", "pour"}
