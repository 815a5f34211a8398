"""How well the commonsense model names held-out actions from their objects.

Deterministic split by group (EPIC: video), seeded: learn on the train groups, predict the verb of every
held-out record from its objects (argmax of the posterior), and compare with always predicting the most
frequent training verb, and with the same model learned from the held-out records themselves (the ceiling:
what the objects of these records can tell of their verbs at all, for this model), and with the best any
predictor that sees only the objects could do on them (:func:`object_oracle`: the most frequent verb of each
distinct object set among the held-out records).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from wecook_core.knowledge.corpus import Corpus
from wecook_core.knowledge.learning import Example, fold, from_examples
from wecook_core.knowledge.recognize import Knowledge
from wecook_core.knowledge.synonyms import RECOGNISED, VerbFolder


@dataclass(frozen=True)
class VerbScore:
    verb: str
    precision: float
    """Correct / predicted as this verb; 0 when never predicted."""
    recall: float
    """Correct / held-out records of this verb; 0 when it has none."""
    support: int
    """Held-out records of this verb."""
    predicted: int
    """Held-out records predicted as this verb."""


@dataclass(frozen=True)
class Metrics:
    accuracy: float
    """Fraction of held-out records whose verb is predicted exactly."""
    macro_precision: float
    """Mean of the per-verb precisions over the verbs with held-out records (a verb never predicted
    counts 0)."""
    macro_recall: float
    """Mean of the per-verb recalls over the verbs with held-out records."""
    per_verb: tuple[VerbScore, ...]


@dataclass(frozen=True)
class Evaluation:
    model: Metrics
    baseline: Metrics
    """Always predicting ``majority``."""
    majority: str
    """The most frequent verb of the training records."""
    train_records: int
    test_records: int
    test_groups: int
    """Groups (videos) held out."""
    seed: int
    fraction: float
    """Fraction of groups held out."""
    by_source: tuple[tuple[str, Metrics], ...] = ()
    """The model's figures on the held-out records of each corpus (``epic-kitchens``, ``recipes``, ...),
    in order of first appearance; empty when the records come from one corpus only."""
    ceiling: Metrics | None = None
    """The same model learned from the held-out records and scored on them (resubstitution): not a
    generalisation figure but an upper reference. Records with the same objects and different verbs
    (``pour`` and ``stir`` of salt over a pot) cannot all be right, whatever is learned from them."""
    ceiling_by_source: tuple[tuple[str, Metrics], ...] = ()
    """The ceiling's figures on the held-out records of each corpus, as :attr:`by_source`."""
    oracle: Metrics | None = None
    """:func:`object_oracle` on the held-out records: what any predictor from the objects alone, whatever
    its model, could at most name right of these records (in accuracy; near it in the macro figures)."""
    oracle_by_source: tuple[tuple[str, Metrics], ...] = ()
    """The oracle's figures on the held-out records of each corpus, as :attr:`by_source`."""


def split(examples: Sequence[Example], *, seed: int = 0,
          fraction: float = 0.2) -> tuple[tuple[Example, ...], tuple[Example, ...], int]:
    """Train and held-out examples, by split unit (:func:`unit`), corpus by corpus: per corpus (in name order)
    a seeded permutation of its sorted units, the first ``round(fraction * units)`` (at least one, when it has
    two units or more) held out, so every corpus is tested on its own share (six of the archive's 31
    collections, a fifth of EPIC's videos); the count returned is the units held out."""
    if not 0 < fraction < 1:
        raise ValueError("fraction must be between 0 and 1")
    rng = np.random.default_rng(seed)
    held: set[tuple[str, str]] = set()
    for source in sorted({e.source for e in examples}):
        groups = sorted({unit(e.group) for e in examples if e.source == source})
        count = max(1, round(fraction * len(groups))) if len(groups) > 1 else 0
        order = rng.permutation(len(groups))
        held.update((source, groups[i]) for i in order[:count].tolist())
    train = tuple(e for e in examples if (e.source, unit(e.group)) not in held)
    test = tuple(e for e in examples if (e.source, unit(e.group)) in held)
    return train, test, len(held)


def unit(group: str) -> str:
    """What is held out whole: a group named ``collection/recipe`` (the recipe archive: ``victorian-britain/
    toad-in-the-hole``) goes with its collection, so no book is both learned from and tested on (its phrasing,
    its dishes); any other group (an EPIC video, a recipe of a folder) is its own unit."""
    return group.split("/", 1)[0]


def predict(knowledge: Knowledge, examples: Sequence[Example]) -> list[str]:
    """The argmax verb of each example's objects (vectorised; objects are vocabulary names)."""
    rows = {o: i for i, o in enumerate(knowledge.objects)}
    counts = np.zeros((len(examples), len(knowledge.objects)))
    for i, example in enumerate(examples):
        for obj in example.objects:
            if obj in rows:
                counts[i, rows[obj]] += 1
    best = np.argmax(counts @ knowledge.log_likelihood + knowledge.log_prior, axis=1)
    return [knowledge.verbs[j] for j in best.tolist()]


def object_oracle(examples: Sequence[Example], verbs: Sequence[str]) -> list[str]:
    """For each example, the verb the most examples with exactly its set of objects have (ties: ``verbs``
    order): the predictions of highest accuracy that a function of the object set can make on these
    examples. Learned from the examples it is scored on, so an upper reference, not a model: it shows how
    much of a held-out figure any recogniser fed the same objects could still gain."""
    order = {v: i for i, v in enumerate(verbs)}
    tally: dict[frozenset[str], dict[str, int]] = {}
    for example in examples:
        counts = tally.setdefault(frozenset(example.objects), {})
        counts[example.action] = counts.get(example.action, 0) + 1
    best = {key: min(counts, key=lambda v: (-counts[v], order.get(v, len(order)))) for key, counts in tally.items()}
    return [best[frozenset(e.objects)] for e in examples]


def score(truth: Sequence[str], predicted: Sequence[str], verbs: Sequence[str]) -> Metrics:
    per_verb = []
    for verb in verbs:
        support = sum(t == verb for t in truth)
        made = sum(p == verb for p in predicted)
        correct = sum(t == p == verb for t, p in zip(truth, predicted, strict=True))
        per_verb.append(VerbScore(verb, correct / made if made else 0.0, correct / support if support else 0.0,
                                  support, made))
    with_support = [s for s in per_verb if s.support]
    accuracy = sum(t == p for t, p in zip(truth, predicted, strict=True)) / len(truth) if truth else 0.0
    return Metrics(
        accuracy=accuracy,
        macro_precision=float(np.mean([s.precision for s in with_support])) if with_support else 0.0,
        macro_recall=float(np.mean([s.recall for s in with_support])) if with_support else 0.0,
        per_verb=tuple(per_verb),
    )


def evaluate(corpus: Corpus, *, seed: int = 0, fraction: float = 0.2, alpha: float = 1.0,
             folder: VerbFolder | None = None, verbs: Sequence[str] = RECOGNISED,
             prior: str = "corpus", per_group: bool = True, mixed: bool = False) -> Evaluation:
    """Learn on the train groups of ``corpus``, score verb prediction on the held-out groups (``per_group``:
    see :func:`~wecook_core.knowledge.learning.count`; the held-out records are scored one by one). ``mixed``:
    the tables of :mod:`~wecook_core.knowledge.mixture` (one per corpus, objects in their roles, uniform prior;
    ``prior`` and ``per_group`` do not apply), as shipped."""
    examples, vocabulary = fold(corpus, folder, verbs)
    train, test, groups = split(examples, seed=seed, fraction=fraction)
    if not train or not test:
        raise ValueError("the corpus has too few groups to hold some out")
    if mixed:
        from wecook_core.knowledge.mixture import mixed_from_examples, object_roles

        roles = object_roles(vocabulary)
        knowledge = mixed_from_examples(train, vocabulary, corpus, alpha=alpha, verbs=verbs, roles=roles)
        resubstituted = mixed_from_examples(test, vocabulary, corpus, alpha=alpha, verbs=verbs, roles=roles)
    else:
        knowledge = from_examples(train, vocabulary, corpus, alpha=alpha, verbs=verbs, prior=prior,
                                  per_group=per_group)
        resubstituted = from_examples(test, vocabulary, corpus, alpha=alpha, verbs=verbs, prior=prior,
                                      per_group=per_group)
    truth = [e.action for e in test]
    predicted = predict(knowledge, test)
    ceiling = predict(resubstituted, test)
    oracle = object_oracle(test, verbs)
    majority = knowledge.verbs[int(np.argmax(knowledge.action_counts))]
    sources = list(dict.fromkeys(e.source for e in examples)) if len({e.source for e in examples}) > 1 else []

    def of(source: str, values: Sequence[str]) -> list[str]:
        return [v for v, e in zip(values, test, strict=True) if e.source == source]

    by_source = tuple((s, score(of(s, truth), of(s, predicted), verbs)) for s in sources)
    ceiling_by_source = tuple((s, score(of(s, truth), of(s, ceiling), verbs)) for s in sources)
    oracle_by_source = tuple((s, score(of(s, truth), of(s, oracle), verbs)) for s in sources)
    return Evaluation(
        model=score(truth, predicted, verbs),
        baseline=score(truth, [majority] * len(test), verbs),
        majority=majority,
        train_records=len(train),
        test_records=len(test),
        test_groups=groups,
        seed=seed,
        fraction=fraction,
        by_source=by_source,
        ceiling=score(truth, ceiling, verbs),
        ceiling_by_source=ceiling_by_source,
        oracle=score(truth, oracle, verbs),
        oracle_by_source=oracle_by_source,
    )
