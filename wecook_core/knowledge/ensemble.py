"""The role-aware ensemble: the naive Bayes of :mod:`.relations` and a logistic regression over the same
features (:mod:`.logistic`), their log posteriors mixed::

    score(A) = m log P_nb(A | x) + (1 - m) log P_lr(A | x) + s log (n_A + 1)

``m`` (1: naive Bayes alone) and ``s`` (a last shift of the prior, the logistic model having learned the
corpus's own) are picked on the validation collections carved from the training ones, after naive Bayes's own
settings (:func:`~wecook_core.knowledge.relations.tune`), never on the held-out collections. The logistic
model sees each record's ``relation:object`` features, their pairs, classes and roles (the naive Bayes
families) and its bare objects.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from wecook_core.knowledge.classes import ObjectClasses
from wecook_core.knowledge.corpus import Corpus
from wecook_core.knowledge.evaluation import Metrics
from wecook_core.knowledge.learning import Example
from wecook_core.knowledge.logistic import LogisticModel, fit_logistic
from wecook_core.knowledge.nouns import match
from wecook_core.knowledge.recognize import Ranking, _ordered, _posterior
from wecook_core.knowledge.relations import (
    RelationalKnowledge,
    Tuning,
    family_scores,
    goal,
    learn_tuned,
    relational_split,
)
from wecook_core.knowledge.synonyms import RECOGNISED

MIXES: tuple[float, ...] = (0.0, 0.25, 0.5, 0.75, 1.0)
SHIFTS: tuple[float, ...] = (-0.5, -0.25, 0.0, 0.25)


def record_features(knowledge: RelationalKnowledge, objects: Sequence[str], relations: Sequence[str]) -> list[str]:
    """The logistic model's features of one record: the naive Bayes families' and the bare objects."""
    found = [f"{family}/{f}" for family, fs in knowledge.features(objects, relations).items() for f in fs]
    return found + [f"bag/{o}" for o in sorted(set(objects))]


def _log_normalised(scores: np.ndarray) -> np.ndarray:
    top = scores.max(axis=-1, keepdims=True)
    result: np.ndarray = scores - top - np.log(np.exp(scores - top).sum(axis=-1, keepdims=True))
    return result


@dataclass(frozen=True, eq=False)
class Ensemble:
    bayes: RelationalKnowledge
    logistic: LogisticModel
    mix: float
    """Weight of naive Bayes's log posterior (1: it alone)."""
    shift: float
    """Weight of log (n_A + 1), the training records' action counts."""

    @property
    def log_counts(self) -> np.ndarray:
        return np.log(np.asarray(self.bayes.action_counts, dtype=np.float64) + 1.0)

    def scores(self, objects: Sequence[str], relations: Sequence[str]) -> np.ndarray:
        """Log scores of every verb for vocabulary objects and their relations."""
        bayes = _log_normalised(self.bayes.scores(objects, relations))
        logistic = self.logistic.log_posterior(record_features(self.bayes, objects, relations))
        result: np.ndarray = self.mix * bayes + (1 - self.mix) * logistic + self.shift * self.log_counts
        return result


def rank_ensemble(model: Ensemble, objects: Sequence[str], relations: Sequence[str],
                  candidates: Sequence[str] | None = None) -> Ranking:
    """Verbs ranked for free-text labels and their relations, as
    :func:`~wecook_core.knowledge.relations.rank_relational`."""
    if isinstance(objects, str):
        raise TypeError("objects must be a sequence of labels, not one string")
    if len(objects) != len(relations):
        raise ValueError("one relation per object")
    pairs = [(name, r) for label, r in zip(objects, relations, strict=True)
             if (name := match(label, model.bayes.index)) is not None]
    scores = model.scores([o for o, _ in pairs], [r for _, r in pairs])
    verbs = model.bayes.verbs
    columns = list(range(len(verbs))) if candidates is None else [verbs.index(c) for c in candidates]
    if not columns:
        return ()
    return _ordered([verbs[c] for c in columns], _posterior(scores[columns]).tolist())


def _parts(bayes: RelationalKnowledge, logistic: LogisticModel,
           examples: Sequence[Example]) -> tuple[np.ndarray, np.ndarray]:
    """Naive Bayes's and the logistic model's log posteriors of many examples."""
    weights = bayes.weights
    scores = family_scores(bayes, examples)
    total = bayes.log_prior + sum(weights[f] * part for f, part in scores.items() if weights[f])
    records = [record_features(bayes, e.objects, e.relations) for e in examples]
    return _log_normalised(np.asarray(total)), logistic.log_posteriors(records)


def _logistic(bayes: RelationalKnowledge, examples: Sequence[Example], verbs: Sequence[str]) -> LogisticModel:
    index = {v: i for i, v in enumerate(verbs)}
    records = [record_features(bayes, e.objects, e.relations) for e in examples]
    return fit_logistic(records, [index[e.action] for e in examples], verbs)


@dataclass(frozen=True)
class Mixing:
    mix: float
    shift: float
    precision: float
    """Macro precision on the validation records with these settings."""
    recall: float


def learn_ensemble(examples: Sequence[Example], tuning: Tuning, mixing: Mixing, classes: ObjectClasses | None,
                   verbs: Sequence[str] = RECOGNISED) -> Ensemble:
    """Both models of the ``examples`` that carry relations (naive Bayes with ``tuning``), mixed by ``mixing``."""
    examples = [e for e in examples if len(e.relations) == len(e.objects) and e.action in verbs]
    bayes = learn_tuned(examples, tuning, verbs, classes)
    return Ensemble(bayes, _logistic(bayes, examples, verbs), mixing.mix, mixing.shift)


def tune_mixing(fit: Sequence[Example], validation: Sequence[Example], tuning: Tuning,
                classes: ObjectClasses | None, verbs: Sequence[str] = RECOGNISED) -> Mixing:
    """The ``m`` and ``s`` of the best :func:`~wecook_core.knowledge.relations.goal` on ``validation`` when both
    models learn from ``fit``."""
    from wecook_core.knowledge.evaluation import score

    model = learn_ensemble(fit, tuning, Mixing(1.0, 0.0, 0.0, 0.0), classes, verbs)
    bayes, logistic = _parts(model.bayes, model.logistic, validation)
    truth = [e.action for e in validation]
    best: Mixing | None = None
    for mix, shift in itertools.product(MIXES, SHIFTS):
        total = mix * bayes + (1 - mix) * logistic + shift * model.log_counts
        metrics = score(truth, [verbs[j] for j in np.argmax(total, axis=1).tolist()], verbs)
        found = Mixing(mix, shift, metrics.macro_precision, metrics.macro_recall)
        if best is None or goal(found.precision, found.recall) > goal(best.precision, best.recall) + 1e-12:
            best = found
    assert best is not None
    return best


def predict_ensemble(model: Ensemble, examples: Sequence[Example]) -> list[str]:
    bayes, logistic = _parts(model.bayes, model.logistic, examples)
    total = model.mix * bayes + (1 - model.mix) * logistic + model.shift * model.log_counts
    return [model.bayes.verbs[j] for j in np.argmax(total, axis=1).tolist()]


@dataclass(frozen=True)
class EnsembleEvaluation:
    mixing: Mixing
    """Picked on the validation collections."""
    model: Metrics
    """The ensemble learned from all training collections, on the held-out ones."""


def evaluate_ensemble(corpus: Corpus, tuning: Tuning, classes: ObjectClasses | None, *, seed: int = 0,
                      fraction: float = 0.2, verbs: Sequence[str] = RECOGNISED) -> EnsembleEvaluation:
    """Held-out figures of the ensemble on the split of
    :func:`~wecook_core.knowledge.relations.evaluate_relational` (same records, same validation collections),
    naive Bayes with ``tuning`` (picked there on the validation collections)."""
    from wecook_core.knowledge.evaluation import score

    train, test, fit, validation, _, _ = relational_split(corpus, seed, fraction, verbs)
    mixing = tune_mixing(fit, validation, tuning, classes, verbs)
    model = learn_ensemble(train, tuning, mixing, classes, verbs)
    return EnsembleEvaluation(mixing, score([e.action for e in test], predict_ensemble(model, test), verbs))
