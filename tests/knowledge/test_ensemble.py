"""The logistic model and the role-aware ensemble: deterministic fits, the mixing picked without the held-out
collections, naive Bayes alone when the mix says so."""

from __future__ import annotations

import numpy as np
import pytest

from wecook_core.knowledge.classes import ObjectClasses
from wecook_core.knowledge.ensemble import Ensemble, Mixing, learn_ensemble, rank_ensemble, record_features
from wecook_core.knowledge.learning import Example
from wecook_core.knowledge.logistic import fit_logistic
from wecook_core.knowledge.relations import Tuning, learn_relational, rank_relational

KINDS = ObjectClasses({"fish": "fish", "batter": "sauce", "knife": "tool"}, {"knife": "tool"})
TUNING = Tuning(alpha=0.3, tau=0.0, pair_weight=1.0, precision=0.0, recall=0.0, class_weight=0.5,
                role_weight=0.5)


def _examples() -> list[Example]:
    found = [Example("dip", ("fish", "batter"), f"a/{i}", "t", ("object", "place")) for i in range(6)]
    found += [Example("pour", ("batter", "fish"), f"b/{i}", "t", ("object", "place")) for i in range(6)]
    found += [Example("cut", ("fish", "knife"), f"c/{i}", "t", ("object", "means")) for i in range(6)]
    return found


def test_the_logistic_model_learns_its_features_deterministically() -> None:
    records = [["x"], ["x", "z"], ["y"], ["y", "z"]] * 5
    labels = [0, 0, 1, 1] * 5
    one = fit_logistic(records, labels, ("cut", "stir"))
    two = fit_logistic(records, labels, ("cut", "stir"))
    assert np.array_equal(one.weights, two.weights) and np.array_equal(one.bias, two.bias)
    assert np.argmax(one.log_posterior(["x"])) == 0 and np.argmax(one.log_posterior(["y", "z"])) == 1
    assert np.exp(one.log_posterior(["unknown"])).sum() == pytest.approx(1.0)
    assert one.log_posteriors([["x"], ["y"]]).argmax(axis=1).tolist() == [0, 1]


def test_the_ensemble_tells_the_roles_apart_and_mix_one_is_naive_bayes() -> None:
    unrelated = Example("cut", ("fish",), "d/1", "t")  # no relations (EPIC, a CSV): skipped, as naive Bayes does
    model = learn_ensemble([*_examples(), unrelated], TUNING, Mixing(0.5, 0.0, 0.0, 0.0), KINDS)
    assert rank_ensemble(model, ["fish", "batter"], ["object", "place"])[0][0] == "dip"
    assert rank_ensemble(model, ["batter", "fish"], ["object", "place"])[0][0] == "pour"
    assert rank_ensemble(model, ["knife", "fish"], ["means", "object"])[0][0] == "cut"
    ranking = rank_ensemble(model, ["fish"], ["object"], candidates=["dip", "pour"])
    assert [v for v, _ in ranking] in (["dip", "pour"], ["pour", "dip"]) and sum(p for _, p in ranking) == \
        pytest.approx(1.0)
    bayes = learn_relational(_examples(), alpha=0.3, tau=0.0, pair_weight=1.0, classes=KINDS, class_weight=0.5,
                             role_weight=0.5)
    alone = Ensemble(model.bayes, model.logistic, 1.0, 0.0)
    for query in ((["fish", "batter"], ["object", "place"]), (["knife"], ["means"])):
        assert [v for v, _ in rank_ensemble(alone, *query)] == [v for v, _ in rank_relational(bayes, *query)]
    with pytest.raises(ValueError, match="one relation per object"):
        rank_ensemble(model, ["fish"], [])
    with pytest.raises(TypeError):
        rank_ensemble(model, "fish", ["object"])


def test_record_features_are_the_families_and_the_bare_objects() -> None:
    bayes = learn_relational(_examples(), classes=KINDS)
    found = record_features(bayes, ["knife", "fish"], ["means", "object"])
    assert "single/means:knife" in found and "pair/means:knife|object:fish" in found
    assert "class/means:tool" in found and "role/object:ingredient" in found and "bag/fish" in found
