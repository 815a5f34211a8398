"""Object classes for backing off: EPIC's noun categories through their instances, wecook's roles, and the
role-aware model's class and role families."""

from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.knowledge.classes import ObjectClasses, epic_noun_categories, object_classes
from wecook_core.knowledge.learning import Example
from wecook_core.knowledge.relations import features, learn_relational, rank_relational

CSV = '''id,key,instances,category
1,chilli,"['chilli', 'pepper:cayenne', 'powder:chilli']",spices and herbs and sauces
2,pan,"['pan', 'pan:frying', 'pan:stew']",cookware
3,fish,"['fish', 'fillet:fish']",meat and substitute
'''


def _epic(tmp_path: Path) -> Path:
    (tmp_path / "epic100").mkdir()
    (tmp_path / "epic100" / "EPIC_100_noun_classes.csv").write_text(CSV)
    return tmp_path


def test_a_noun_is_the_kind_of_its_epic_class(tmp_path: Path) -> None:
    categories = epic_noun_categories(_epic(tmp_path))
    assert categories["cayenne_pepper"] == categories["chilli"] == "spices_and_herbs_and_sauces"
    assert categories["cayenne"] == "spices_and_herbs_and_sauces"  # the last word of an instance of one class
    assert categories["stew_pan"] == "cookware"
    assert epic_noun_categories(tmp_path / "nowhere") == {}


def test_every_object_has_a_class_and_a_role(tmp_path: Path) -> None:
    found = object_classes(["cayenne", "stew pan", "knife", "haddock"], _epic(tmp_path))
    assert found.classes["cayenne"] == "spices_and_herbs_and_sauces"
    assert found.classes["stew pan"] == "cookware"
    assert found.roles["knife"] == "tool" and found.classes["knife"] == "tool"  # EPIC has no knife here: its role
    assert found.roles["haddock"] == "ingredient" and found.classes["haddock"] == "ingredient"
    assert object_classes(["cayenne"], tmp_path / "nowhere").classes["cayenne"] == "ingredient"


def test_features_back_off_to_class_and_role() -> None:
    found = features(["cod", "pan"], ["object", "place"], {"cod": "fish"}, {"pan": "container"})
    assert found["class"] == ["object:fish", "place:ingredient"]
    assert found["role"] == ["object:ingredient", "place:container"]
    assert set(features(["cod"], ["object"])) == {"single", "pair"}


def test_an_object_seen_rarely_is_ranked_by_its_class() -> None:
    """Fish are dipped in batter far more often than batter is poured over them; a haddock, met once in a pour,
    is dipped like a fish when the class family weighs in, poured without it."""
    kinds = ObjectClasses({"cod": "fish", "sole": "fish", "haddock": "fish", "batter": "sauce"},
                          {"cod": "ingredient", "sole": "ingredient", "haddock": "ingredient", "batter": "ingredient"})
    examples = [Example("dip", (fish, "batter"), f"a/{fish}{i}", "t", ("object", "place"))
                for fish in ("cod", "sole") for i in range(10)]
    examples += [Example("pour", ("batter", fish), f"b/{fish}{i}", "t", ("object", "place"))
                 for fish in ("cod", "sole") for i in range(5)]
    examples += [Example("pour", ("haddock",), "c/1", "t", ("object",))]
    plain = learn_relational(examples, alpha=1.0, tau=0.0)
    backed = learn_relational(examples, alpha=1.0, tau=0.0, classes=kinds, class_weight=1.0)
    query = (["haddock"], ["object"])
    assert rank_relational(plain, *query, candidates=["dip", "pour"])[0][0] == "pour"
    assert rank_relational(backed, *query, candidates=["dip", "pour"])[0][0] == "dip"
    assert backed.with_settings(class_weight=0.0).scores(*query) == pytest.approx(plain.scores(*query))
