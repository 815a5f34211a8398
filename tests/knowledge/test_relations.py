"""Each object's relation to its verb: extracted from the sentence, kept through the CSV, learned and ranked."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.knowledge.archive import read_archive
from wecook_core.knowledge.build import extract_archive, recipe_nouns
from wecook_core.knowledge.classes import ObjectClasses
from wecook_core.knowledge.corpus import Corpus, Record, read_csv
from wecook_core.knowledge.ensemble import evaluate_ensemble
from wecook_core.knowledge.evaluation import split
from wecook_core.knowledge.instructions import extract_relations, noun_table
from wecook_core.knowledge.learning import Example, fold, from_examples
from wecook_core.knowledge.recognize import rank
from wecook_core.knowledge.relations import (
    evaluate_relational,
    features,
    learn_relational,
    rank_relational,
)
from wecook_core.knowledge.roles import VIDEO_RELATIONS

NOUNS = noun_table(["fish", "batter", "pan", "salt", "bowl", "egg", "fork", "spoon", "rice", "jar", "sugar",
                    "gooseberry", "saucepan", "sieve", "water", "dough"])


@pytest.mark.parametrize(("sentence", "records"), [
    ("Dip the fish in the batter", [("dip", ("fish", "batter"), ("object", "place"))]),
    ("Pour the batter over the fish", [("pour", ("batter", "fish"), ("object", "place"))]),
    ("Sprinkle the fish with salt", [("sprinkle", ("fish", "salt"), ("object", "means"))]),
    ("In a bowl, whisk the eggs with a fork", [("whisk", ("bowl", "egg", "fork"), ("place", "object", "means"))]),
    ("Using a spoon, transfer the rice to the jars",
     [("transfer", ("spoon", "rice", "jar"), ("means", "object", "place"))]),
    ("Take the fish out of the pan", [("take", ("fish", "pan"), ("object", "source"))]),
    ("Stir the eggs until the sugar is dissolved", [("stir", ("egg", "sugar"), ("object", "aside"))]),
    ("Put a pinch of salt over the fish", [("put", ("salt", "fish"), ("object", "place"))]),
    # a preposition that is the verb's particle names its object: stir in, roll out, cut off, not "roll in"
    ("Stir in the sugar and the eggs", [("stir", ("sugar", "egg"), ("object", "object"))]),
    ("Pour in the batter", [("pour", ("batter",), ("object",))]),
    ("Roll out the dough", [("roll-out", ("dough",), ("object",))]),
    ("Cut off the fish", [("cut", ("fish",), ("object",))]),
    ("Roll the fish in the batter", [("roll-in", ("fish", "batter"), ("object", "place"))]),
    ("Roll in the batter", [("roll-in", ("batter",), ("place",))]),
    ("Pour out of the pan", [("pour", ("pan",), ("source",))]),
    ("Take off the pan", [("take", ("pan",), ("source",))]),
])
def test_each_noun_gets_its_relation_to_the_verb(sentence: str,
                                                 records: list[tuple[str, tuple[str, ...], tuple[str, ...]]]) -> None:
    assert extract_relations([sentence], NOUNS) == records


def test_ingredients_named_by_a_pronoun_are_the_object() -> None:
    steps = ["Put the gooseberries into a saucepan with a little water.",
             "When they are soft, stir them through a sieve."]
    found = extract_relations(steps, NOUNS, ["1 quart of gooseberries", "water"])
    assert found[0] == ("put", ("gooseberry", "saucepan", "water"), ("object", "place", "means"))
    assert found[1] == ("stir", ("gooseberry", "water", "sieve"), ("object", "object", "place"))


def _archive(path: Path) -> Path:
    recipe = {"id": "victorian-britain/fried-fish", "collection": "victorian-britain", "source": "Beeton",
              "ingredients": ["2 eggs", "1 fish"],
              "steps": ["Beat the eggs with a fork in a basin", "Dip the fish in the eggs, and fry it in a stew-pan"]}
    with gzip.open(path, "wt", encoding="utf-8") as f:
        f.write(json.dumps(recipe) + "\n")
    return path


def test_archive_records_and_their_csv_carry_the_relations(tmp_path: Path) -> None:
    archive = _archive(tmp_path / "open-recipe-archive.jsonl.gz")
    records = read_archive(archive, recipe_nouns()).records
    dip = next(r for r in records if r.action == "dip")
    assert dict(zip(dip.objects, dip.relations, strict=True)) == {"fish": "object", "egg": "place"}
    beat = next(r for r in records if r.action == "beat")
    assert dict(zip(beat.objects, beat.relations, strict=True)) == {"egg": "object", "fork": "means", "bowl": "place"}
    out = tmp_path / "archive.csv"
    assert extract_archive(archive, out) == 2  # beat and dip fold into wecook's verbs; fry does not
    again = {r.action: r for r in read_csv(out).records}
    assert again["dip"].relations == dip.relations and again["dip"].objects == dip.objects
    assert again["beat"].relations == beat.relations and again["beat"].group == "victorian-britain/fried-fish"


@pytest.mark.parametrize(("row", "message"), [
    ("dip,fish;batter,g,,object", "one relation per object"),
    ("dip,fish;batter,g,,object;inside", "unknown relation 'inside'"),
])
def test_a_bad_relations_column_names_the_line(tmp_path: Path, row: str, message: str) -> None:
    path = tmp_path / "c.csv"
    path.write_text(f"action,objects,group,context,relations\ndip,fish,g,,object\n{row}\n")
    with pytest.raises(InputError) as error:
        read_csv(path)
    assert message in str(error.value) and "line 3" in str(error.value)


def test_folding_keeps_the_relations_and_the_whisk_is_the_means() -> None:
    corpus = Corpus(records=(Record("whisk", ("egg", "bowl"), "c/r", relations=("object", "place")),
                             Record("cut", ("bread",), "c/r")))
    examples, _ = fold(corpus)
    assert examples[0].action == "stir"
    assert examples[0].objects == ("egg", "bowl", "whisk")
    assert examples[0].relations == ("object", "place", "means")
    assert examples[1].relations == ()  # a record that says nothing of relations


def _examples(per: int = 5) -> list[Example]:
    dip = [Example("dip", ("fish", "batter"), f"a/{i}", "t", ("object", "place")) for i in range(per)]
    pour = [Example("pour", ("batter", "fish"), f"b/{i}", "t", ("object", "place")) for i in range(per)]
    return dip + pour


def test_roles_tell_apart_what_the_object_set_cannot() -> None:
    examples = _examples()
    model = learn_relational(examples, tau=0.0)
    assert rank_relational(model, ["Fish_1", "batter"], ["object", "place"])[0][0] == "dip"
    assert rank_relational(model, ["batter", "fish"], ["object", "place"])[0][0] == "pour"
    flat = from_examples(examples, ("fish", "batter"), Corpus(records=()), prior="uniform")
    assert rank(flat, ["fish", "batter"]) == rank(flat, ["batter", "fish"])  # the same set: the same ranking
    # the video's roles: a held ingredient is the object, the container it goes into the place
    assert VIDEO_RELATIONS == {"tool": "means", "ingredient": "object", "container": "place"}


def test_features_are_each_related_object_and_each_pair() -> None:
    found = features(("egg", "fork", "bowl"), ("object", "means", "place"))
    assert found["single"] == ["means:fork", "object:egg", "place:bowl"]
    assert found["pair"] == ["means:fork|object:egg", "means:fork|place:bowl", "object:egg|place:bowl"]


def test_the_prior_is_tempered_by_tau() -> None:
    examples = _examples() + [Example("dip", ("egg",), f"c/{i}", "t", ("object",)) for i in range(10)]
    uniform = learn_relational(examples, tau=0.0)
    flat = rank_relational(uniform, ["gizmo"], ["object"])  # an unknown label: the prior alone
    assert len(flat) == 11 and all(p == pytest.approx(1 / 11) for _, p in flat)
    corpus = uniform.with_settings(tau=1.0)
    ranking = rank_relational(corpus, [], [])
    assert ranking[0][0] == "dip" and ranking[1][0] == "pour"
    half = uniform.with_settings(tau=0.5)
    share = dict(rank_relational(half, [], []))["dip"]
    assert 1 / 11 < share < dict(ranking)["dip"]


def test_ranking_checks_its_input_and_restricts_the_candidates() -> None:
    model = learn_relational(_examples())
    with pytest.raises(ValueError, match="one relation per object"):
        rank_relational(model, ["fish"], [])
    with pytest.raises(TypeError):
        rank_relational(model, "fish", ["object"])  # type: ignore[arg-type]
    ranking = rank_relational(model, ["fish", "batter"], ["object", "place"], ["pour", "dip"])
    assert [v for v, _ in ranking] == ["dip", "pour"]
    assert sum(p for _, p in ranking) == pytest.approx(1.0)


def _collections(flip: frozenset[str] = frozenset()) -> Corpus:
    """Ten collections of dip and pour records, told apart only by which object goes where; ``flip``: the
    collections whose verbs are swapped."""
    records = []
    for c in range(10):
        name = f"c{c}"
        for i in range(6):
            verbs = ("pour", "dip") if name in flip else ("dip", "pour")
            records.append(Record(verbs[0], ("fish", "batter"), f"{name}/{i}", relations=("object", "place"),
                                  source="archive"))
            records.append(Record(verbs[1], ("batter", "fish"), f"{name}/{i}", relations=("object", "place"),
                                  source="archive"))
            records.append(Record("cut", ("bread", "knife"), f"{name}/{i}", relations=("object", "means"),
                                  source="archive"))
    return Corpus(records=tuple(records))


def test_the_settings_are_tuned_without_the_held_out_collections() -> None:
    result = evaluate_relational(_collections())
    assert result.model.macro_recall == pytest.approx(1.0) and result.model.macro_precision == pytest.approx(1.0)
    assert result.baseline.macro_recall < 1.0  # the object set cannot tell dip from pour
    assert result.validation_groups == 2
    examples, _ = fold(_collections())
    _, test, _ = split(examples)
    held = {e.group.split("/")[0] for e in test}
    flipped = evaluate_relational(_collections(frozenset(held)))
    assert flipped.tuning == result.tuning  # what the held-out records say changes nothing of the tuning
    assert flipped.model.macro_recall < result.model.macro_recall


def test_the_back_off_weights_are_tuned_without_the_held_out_collections_too() -> None:
    kinds = ObjectClasses({"fish": "fish", "batter": "sauce", "bread": "bread"}, {"knife": "tool"})
    result = evaluate_relational(_collections(), classes=kinds)
    assert result.plain is not None and result.plain_tuning is not None
    assert result.plain_tuning.class_weight == result.plain_tuning.role_weight == 0.0
    assert result.model.macro_recall == pytest.approx(1.0)
    examples, _ = fold(_collections())
    _, test, _ = split(examples)
    held = {e.group.split("/")[0] for e in test}
    assert evaluate_relational(_collections(frozenset(held)), classes=kinds).tuning == result.tuning


def test_the_ensemble_mixing_is_tuned_without_the_held_out_collections() -> None:
    kinds = ObjectClasses({"fish": "fish", "batter": "sauce", "bread": "bread"}, {"knife": "tool"})
    tuning = evaluate_relational(_collections(), classes=kinds).tuning
    result = evaluate_ensemble(_collections(), tuning, kinds)
    assert result.model.macro_recall == pytest.approx(1.0)
    examples, _ = fold(_collections())
    _, test, _ = split(examples)
    held = {e.group.split("/")[0] for e in test}
    flipped = evaluate_ensemble(_collections(frozenset(held)), tuning, kinds)
    assert flipped.mixing == result.mixing
    assert flipped.model.macro_recall < result.model.macro_recall


def test_learning_counts_a_feature_once_per_recipe_and_verb() -> None:
    twice = [Example("dip", ("fish",), "a/1", "t", ("object",))] * 2 + [Example("dip", ("fish",), "a/2", "t",
                                                                                   ("object",))]
    model = learn_relational(twice)
    rows, _ = model.tables["single"]
    assert model.counts["single"][rows["object:fish"], model.verbs.index("dip")] == 2
    assert int(np.sum(model.action_counts)) == 2


@pytest.mark.slow
def test_the_archive_teaches_the_roles_a_video_shows(shared: Path) -> None:
    """Learned from the whole archive with the settings picked on validation collections, the role-aware model
    names what a cook would for the roles a video gives (a held tool is the means, the container the place)."""
    examples, _ = fold(read_archive(shared / "data" / "recipes", recipe_nouns()))
    model = learn_relational(examples, alpha=0.1, tau=0.25)
    for objects, relations, verb in [
        (("knife", "tomato", "chopping board"), ("means", "object", "place"), "cut"),
        (("rolling pin", "dough"), ("means", "object"), "roll"),
        (("whisk", "egg", "bowl"), ("means", "object", "place"), "stir"),
        (("peeler", "potato"), ("means", "object"), "peel"),
        (("oil", "pan"), ("object", "place"), "pour"),
        (("lemon",), ("object",), "squeeze"),
    ]:
        assert rank_relational(model, objects, relations)[0][0] == verb, objects
    # the same objects, the roles swapped: the fish goes into the batter, or the batter over the fish
    assert rank_relational(model, ["fish", "batter"], ["object", "place"])[0][0] == "dip"
    assert rank_relational(model, ["batter", "fish"], ["object", "place"])[0][0] == "pour"
