"""A role-aware commonsense model: actions ranked from how each object takes part, not from the object set alone.

The baseline (:mod:`wecook_core.knowledge.recognize`) ranks P(A | O1..On) ∝ P(A) ∏ P(Ok | A) over an unordered
set of objects. A sentence says more: "Dip the fish in the batter" and "Pour the batter over the fish" name the
same two objects, with the roles swapped. Here each object is a feature with its relation to the verb
(:data:`~wecook_core.knowledge.roles.RELATIONS`: ``object:fish``, ``place:batter``, ``means:fork``), and
each pair of such features is one too (``object:egg|means:fork``: what an object is done to depends on what
else takes part, which a product of single-object likelihoods cannot say)::

    score(A) = tau log P(A) + sum_k log P(r_k:O_k | A) + w sum_{j<k} log P(r_j:O_j | r_k:O_k | A)

plus, with object classes (:mod:`wecook_core.knowledge.classes`), two back-off families weighed in the same way,
``c sum_k log P(r_k:class(O_k) | A) + r sum_k log P(r_k:role(O_k) | A)`` (a rarely seen "haddock" as the object
is ranked as fish are, "place:cookware" as pans and stew-pans are); each family a binarised multinomial (a
feature counts once per recipe and verb, as :func:`~wecook_core.knowledge.learning.count`) with additive
smoothing ``alpha`` over its own vocabulary.

The prior is the corpus's P(A) tempered by ``tau`` (0: uniform, 1: the corpus's): what a video shows is not
drawn from how often cookbooks write a verb (they stir six times as often as they peel), so the full prior
buries the rare actions, but a flat one makes the rare verbs the answer of every ambiguous record and their
precision falls (transfer, with 300 of 64,000 training records, to 0.07). ``tau``, ``alpha`` and ``w`` are
picked on validation collections carved out of the training collections (:func:`tune`), never on held-out
ones, and so are the back-off weights ``c`` and ``r``. Measured on the held-out archive collections (``bench/
recognize.py --held-out``, seed 0): macro P / R 0.474 / 0.605 without the back-off families, 0.493 / 0.602 with
them (alpha 0.1, tau 0.5, w 0.5, c 0.5, r 0.5 picked on the validation collections).

The video side can name these relations: a held tool is what the action is done with (``means``), the
ingredient a tool works or the held ingredient is the verb's ``object``, and the container it goes into or lies
in is the ``place`` (:data:`~wecook_core.knowledge.roles.VIDEO_RELATIONS`).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from wecook_core.knowledge.classes import UNKNOWN_ROLE, ObjectClasses, object_classes
from wecook_core.knowledge.corpus import Corpus
from wecook_core.knowledge.evaluation import Metrics
from wecook_core.knowledge.learning import Example
from wecook_core.knowledge.nouns import match
from wecook_core.knowledge.recognize import Ranking, _ordered, _posterior
from wecook_core.knowledge.synonyms import RECOGNISED

FAMILIES: tuple[str, ...] = ("single", "pair", "class", "role")
"""Feature families: each related object, each pair of them, and the two back-offs of each related object, its
class and its role (:mod:`wecook_core.knowledge.classes`: ``place:cookware``, ``means:tool``)."""


def features(objects: Sequence[str], relations: Sequence[str], classes: Mapping[str, str] | None = None,
             roles: Mapping[str, str] | None = None) -> dict[str, list[str]]:
    """The features of one record per family: ``relation:object`` of each object, each pair of them, and with
    ``classes`` and ``roles`` (object -> its class, its role; an object neither names is an ingredient)
    ``relation:class`` and ``relation:role`` of each object."""
    single = sorted({f"{r}:{o}" for o, r in zip(objects, relations, strict=True)})
    pairs = [f"{a}|{b}" for a, b in itertools.combinations(single, 2)]
    found = {"single": single, "pair": pairs}
    for family, kinds in (("class", classes), ("role", roles)):
        if kinds is not None:
            found[family] = sorted({f"{r}:{kinds.get(o, UNKNOWN_ROLE)}"
                                    for o, r in zip(objects, relations, strict=True)})
    return found


@dataclass(frozen=True, eq=False)
class RelationalKnowledge:
    """Counts per feature family and the log tables derived from them (see the module docstring)."""

    verbs: tuple[str, ...]
    action_counts: np.ndarray
    """int64 ``(len(verbs),)``: recipes (groups) per action."""
    vocabularies: Mapping[str, tuple[str, ...]]
    """Family -> its features, in table order."""
    counts: Mapping[str, np.ndarray]
    """Family -> int64 ``(len(features), len(verbs))``: groups in which an action has a feature."""
    objects: tuple[str, ...] = ()
    """Object names the features are made of (for matching free-text labels)."""
    aliases: Mapping[str, str] = field(default_factory=dict)
    alpha: float = 0.3
    tau: float = 0.25
    """Weight of log P(A) (0: uniform prior)."""
    pair_weight: float = 1.0
    classes: Mapping[str, str] = field(default_factory=dict)
    """Object -> its class (:func:`~wecook_core.knowledge.classes.object_classes`), for the ``class`` family."""
    roles: Mapping[str, str] = field(default_factory=dict)
    """Object -> its role (tool, container, ingredient), for the ``role`` family."""
    class_weight: float = 0.0
    role_weight: float = 0.0
    tables: Mapping[str, tuple[Mapping[str, int], np.ndarray]] = field(init=False, repr=False)
    log_prior: np.ndarray = field(init=False, repr=False)
    index: Mapping[str, str] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.alpha <= 0:
            raise ValueError("alpha must be positive")
        tables = {}
        for family, vocabulary in self.vocabularies.items():
            counts = np.asarray(self.counts[family], dtype=np.float64).reshape(len(vocabulary), len(self.verbs))
            log = np.log((counts + self.alpha) / (counts.sum(axis=0, keepdims=True) + self.alpha * len(vocabulary)))
            tables[family] = ({f: i for i, f in enumerate(vocabulary)}, log)
        actions = np.asarray(self.action_counts, dtype=np.float64)
        prior = (actions + 1.0) / (actions.sum() + len(self.verbs))
        index = {a: o for a, o in self.aliases.items()}
        index.update({o: o for o in self.objects})
        object.__setattr__(self, "tables", tables)
        object.__setattr__(self, "log_prior", self.tau * np.log(prior))
        object.__setattr__(self, "index", index)

    def with_settings(self, *, alpha: float | None = None, tau: float | None = None,
                      pair_weight: float | None = None, class_weight: float | None = None,
                      role_weight: float | None = None) -> RelationalKnowledge:
        """The same counts with other smoothing, prior or family weights."""
        return RelationalKnowledge(self.verbs, self.action_counts, self.vocabularies, self.counts, self.objects,
                                   self.aliases, self.alpha if alpha is None else alpha,
                                   self.tau if tau is None else tau,
                                   self.pair_weight if pair_weight is None else pair_weight, self.classes,
                                   self.roles, self.class_weight if class_weight is None else class_weight,
                                   self.role_weight if role_weight is None else role_weight)

    @property
    def weights(self) -> dict[str, float]:
        """Family -> the weight of its log likelihoods in :meth:`scores`."""
        return {"single": 1.0, "pair": self.pair_weight, "class": self.class_weight, "role": self.role_weight}

    def features(self, objects: Sequence[str], relations: Sequence[str]) -> dict[str, list[str]]:
        """:func:`features` of vocabulary objects with this model's classes and roles (the families it has)."""
        found = features(objects, relations, self.classes if "class" in self.tables else None,
                         self.roles if "role" in self.tables else None)
        return found

    def scores(self, objects: Sequence[str], relations: Sequence[str]) -> np.ndarray:
        """Log scores of every verb for vocabulary objects and their relations."""
        total = self.log_prior.copy()
        weights = self.weights
        for family, found in self.features(objects, relations).items():
            if not weights[family]:
                continue
            rows, log = self.tables[family]
            hit = [rows[f] for f in found if f in rows]
            if hit:
                total += weights[family] * log[hit].sum(axis=0)
        return total


def learn_relational(examples: Sequence[Example], verbs: Sequence[str] = RECOGNISED, *, alpha: float = 0.3,
                     tau: float = 0.25, pair_weight: float = 1.0, aliases: Mapping[str, str] | None = None,
                     classes: ObjectClasses | None = None, class_weight: float = 0.0,
                     role_weight: float = 0.0) -> RelationalKnowledge:
    """The role-aware tables of examples that carry relations (others are skipped), counted once per group;
    with ``classes`` (every object's class and role) the back-off families ``class`` and ``role`` too."""
    verb_index = {v: i for i, v in enumerate(verbs)}
    actions = np.zeros(len(verbs), dtype=np.int64)
    seen: set[tuple[str, ...]] = set()
    families = FAMILIES if classes is not None else FAMILIES[:2]
    tallies: dict[str, dict[tuple[str, int], int]] = {f: {} for f in families}
    objects: dict[str, None] = {}
    kinds = (classes.classes, classes.roles) if classes is not None else (None, None)
    for example in examples:
        if len(example.relations) != len(example.objects) or example.action not in verb_index:
            continue
        a = verb_index[example.action]
        key = (example.source, example.group, example.action)
        if key not in seen:
            seen.add(key)
            actions[a] += 1
        objects.update(dict.fromkeys(example.objects))
        for family, found in features(example.objects, example.relations, *kinds).items():
            tally = tallies[family]
            for f in found:
                if (*key, family, f) not in seen:
                    seen.add((*key, family, f))
                    tally[(f, a)] = tally.get((f, a), 0) + 1
    vocabularies = {f: tuple(sorted({feature for feature, _ in tallies[f]})) for f in families}
    counts = {}
    for family, vocabulary in vocabularies.items():
        rows = {f: i for i, f in enumerate(vocabulary)}
        table = np.zeros((len(vocabulary), len(verbs)), dtype=np.int64)
        for (f, a), n in tallies[family].items():
            table[rows[f], a] = n
        counts[family] = table
    known = set(objects)
    kept = {k: v for k, v in (aliases or {}).items() if v in known}
    known_kinds = ({o: classes.classes.get(o, UNKNOWN_ROLE) for o in objects},
                   {o: classes.roles.get(o, UNKNOWN_ROLE) for o in objects}) if classes is not None else ({}, {})
    return RelationalKnowledge(tuple(verbs), actions, vocabularies, counts, tuple(objects), kept, alpha, tau,
                               pair_weight, *known_kinds, class_weight, role_weight)


def rank_relational(knowledge: RelationalKnowledge, objects: Sequence[str], relations: Sequence[str],
                    candidates: Sequence[str] | None = None) -> Ranking:
    """Verbs ranked for free-text labels and their relations (``object``, ``place``, ``means``, ``source``),
    normalised over ``candidates`` (default: every verb), best first; unknown labels are ignored."""
    if isinstance(objects, str):
        raise TypeError("objects must be a sequence of labels, not one string")
    if len(objects) != len(relations):
        raise ValueError("one relation per object")
    pairs = [(name, r) for label, r in zip(objects, relations, strict=True)
             if (name := match(label, knowledge.index)) is not None]
    scores = knowledge.scores([o for o, _ in pairs], [r for _, r in pairs])
    columns = list(range(len(knowledge.verbs))) if candidates is None else [knowledge.verbs.index(c)
                                                                            for c in candidates]
    if not columns:
        return ()
    chosen = scores[columns]
    return _ordered([knowledge.verbs[c] for c in columns], _posterior(chosen).tolist())


def family_scores(knowledge: RelationalKnowledge, examples: Sequence[Example]) -> dict[str, np.ndarray]:
    """Family -> ``(len(examples), len(verbs))`` sums of its log likelihoods, for scoring many examples at
    once under several weights."""
    result = {f: np.zeros((len(examples), len(knowledge.verbs))) for f in knowledge.tables}
    for i, example in enumerate(examples):
        relations = example.relations or ("object",) * len(example.objects)
        for family, found in knowledge.features(example.objects, relations).items():
            rows, log = knowledge.tables[family]
            hit = [rows[f] for f in found if f in rows]
            if hit:
                result[family][i] = log[hit].sum(axis=0)
    return result


def _argmax(knowledge: RelationalKnowledge, scores: Mapping[str, np.ndarray]) -> list[str]:
    weights = knowledge.weights
    total = knowledge.log_prior + sum(weights[f] * part for f, part in scores.items() if weights[f])
    return [knowledge.verbs[j] for j in np.argmax(total, axis=1).tolist()]


def predict_relational(knowledge: RelationalKnowledge, examples: Sequence[Example]) -> list[str]:
    """The argmax verb of each example (objects are vocabulary names; no relations: all ``object``)."""
    return _argmax(knowledge, family_scores(knowledge, examples))


def goal(precision: float, recall: float, bars: tuple[float, float] = (0.55, 0.69)) -> float:
    """How far macro figures are towards both bars: the smaller of precision / its bar and recall / its bar."""
    return min(precision / bars[0], recall / bars[1])


ALPHAS: tuple[float, ...] = (0.1, 0.3, 1.0)
TAUS: tuple[float, ...] = (0.0, 0.25, 0.5, 0.75, 1.0)
PAIR_WEIGHTS: tuple[float, ...] = (0.0, 0.5, 1.0)
CLASS_WEIGHTS: tuple[float, ...] = (0.0, 0.5, 1.0)
ROLE_WEIGHTS: tuple[float, ...] = (0.0, 0.5)


@dataclass(frozen=True)
class Tuning:
    alpha: float
    tau: float
    pair_weight: float
    precision: float
    """Macro precision on the validation records with these settings."""
    recall: float
    class_weight: float = 0.0
    role_weight: float = 0.0


def tune(fit: Sequence[Example], validation: Sequence[Example], verbs: Sequence[str] = RECOGNISED,
         classes: ObjectClasses | None = None) -> Tuning:
    """The ``alpha``, ``tau`` and family weights of the best :func:`goal` on ``validation`` when learning from
    ``fit`` (both carved from the training collections: the held-out ones are never looked at); the class and
    role weights only with ``classes`` (else 0)."""
    from wecook_core.knowledge.evaluation import score

    best: Tuning | None = None
    truth = [e.action for e in validation]
    counted = learn_relational(fit, verbs, classes=classes)
    back_off = itertools.product(CLASS_WEIGHTS, ROLE_WEIGHTS) if classes is not None else [(0.0, 0.0)]
    grid = list(itertools.product(TAUS, PAIR_WEIGHTS, back_off))
    for alpha in ALPHAS:
        smoothed = counted.with_settings(alpha=alpha)
        scores = family_scores(smoothed, validation)
        for tau, weight, (class_weight, role_weight) in grid:
            setting = smoothed.with_settings(tau=tau, pair_weight=weight, class_weight=class_weight,
                                             role_weight=role_weight)
            metrics = score(truth, _argmax(setting, scores), verbs)
            found = Tuning(alpha, tau, weight, metrics.macro_precision, metrics.macro_recall, class_weight,
                           role_weight)
            if best is None or goal(found.precision, found.recall) > goal(best.precision, best.recall) + 1e-12:
                best = found
    assert best is not None
    return best


def learn_tuned(examples: Sequence[Example], tuning: Tuning, verbs: Sequence[str] = RECOGNISED,
                classes: ObjectClasses | None = None) -> RelationalKnowledge:
    """The role-aware tables of ``examples`` with the settings of ``tuning`` (back-off families with
    ``classes``)."""
    return learn_relational(examples, verbs, alpha=tuning.alpha, tau=tuning.tau, pair_weight=tuning.pair_weight,
                            classes=classes, class_weight=tuning.class_weight, role_weight=tuning.role_weight)


@dataclass(frozen=True)
class RelationalEvaluation:
    tuning: Tuning
    """Settings picked on the validation collections (carved from the training ones)."""
    model: Metrics
    """The role-aware model learned from all training collections with :attr:`tuning`, on the held-out ones."""
    baseline: Metrics
    """The object-set model (:class:`~wecook_core.knowledge.recognize.Knowledge`, uniform prior, alpha 1) on the
    same held-out records."""
    validation_groups: int
    oracle: Metrics
    """:func:`~wecook_core.knowledge.evaluation.object_oracle` over the held-out records' sets of
    ``relation:object`` features: the most frequent verb of each such set among the held-out records themselves
    (an upper reference, learned from what it is scored on)."""
    plain: Metrics | None = None
    """With classes: the role-aware model without the back-off families, tuned the same way, on the same
    records (what the classes add)."""
    plain_tuning: Tuning | None = None


def relational_split(corpus: Corpus, seed: int, fraction: float, verbs: Sequence[str]) -> tuple[
        tuple[Example, ...], tuple[Example, ...], tuple[Example, ...], tuple[Example, ...], int, tuple[str, ...]]:
    """``(train, test, fit, validation, units held out for validation, vocabulary)`` of the corpus's records that carry
    relations: ``test`` a ``fraction`` of the collections (:func:`~wecook_core.knowledge.evaluation.split` with
    ``seed``), ``fit`` and ``validation`` the training ones split again with ``seed + 1`` (where settings are
    picked). ValueError when too few groups are left to hold some out."""
    from wecook_core.knowledge.evaluation import split
    from wecook_core.knowledge.learning import fold

    examples, vocabulary = fold(corpus, verbs=verbs)
    examples = tuple(e for e in examples if len(e.relations) == len(e.objects))
    train, test, _ = split(examples, seed=seed, fraction=fraction)
    fit, validation, groups = split(train, seed=seed + 1, fraction=fraction)
    if not test or not validation:
        raise ValueError("the corpus has too few groups with relations to hold some out")
    return train, test, fit, validation, groups, vocabulary


def evaluate_relational(corpus: Corpus, *, seed: int = 0, fraction: float = 0.2,
                        verbs: Sequence[str] = RECOGNISED, classes: ObjectClasses | None = None,
                        back_off: bool = False) -> RelationalEvaluation:
    """Held-out figures of the role-aware model on the split of :func:`~wecook_core.knowledge.evaluation.split`
    (the records of the corpus that carry relations): tuned on a ``fraction`` of the training collections
    (split again with ``seed + 1``), then learned from all training collections. ``back_off`` (or ``classes``
    given): with the class and role families (:func:`~wecook_core.knowledge.classes.object_classes` of the
    vocabulary unless ``classes``), and the model without them reported as :attr:`RelationalEvaluation.plain`."""
    from wecook_core.knowledge.evaluation import object_oracle, predict, score
    from wecook_core.knowledge.learning import from_examples

    train, test, fit, validation, groups, vocabulary = relational_split(corpus, seed, fraction, verbs)
    if classes is None and back_off:
        classes = object_classes(vocabulary)
    truth = [e.action for e in test]
    tuning = tune(fit, validation, verbs, classes)
    model = learn_tuned(train, tuning, verbs, classes)
    plain = plain_tuning = None
    if classes is not None:
        plain_tuning = tune(fit, validation, verbs)
        plain = score(truth, predict_relational(learn_tuned(train, plain_tuning, verbs), test), verbs)
    flat = from_examples(train, vocabulary, corpus, verbs=verbs, prior="uniform")
    related = [replace(e, objects=tuple(features(e.objects, e.relations)["single"])) for e in test]
    return RelationalEvaluation(tuning, score(truth, predict_relational(model, test), verbs),
                                score(truth, predict(flat, test), verbs), groups,
                                score(truth, object_oracle(related, verbs), verbs), plain, plain_tuning)
