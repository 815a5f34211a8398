"""Tables that mix corpora: each corpus its own P(O | A), read with the relation the object has in a video.

Pooling the corpora's counts lets the biggest speak for all: the Open Recipe Archive's 95,000 records
outweigh EPIC's videos ten to one, and its text, which hardly names tools, took the tools' verbs over
(``knife + meat + board`` ranked roll). Here each corpus keeps its own table and P(O | A) is their mean
(:attr:`~wecook_core.knowledge.recognize.Knowledge.components`): every corpus one vote.

A sentence also says how each object takes part ("spread the butter over the turkey": the turkey is where,
not what is spread; "wrap in beaten egg": the egg is what the meat is wrapped in). What a video shows, and what
``wecook recognize`` is asked, is objects in their roles: the held tool is what the action is done with, the
container where it happens, an ingredient what it is done to (:func:`~wecook_core.knowledge.roles.role_relation`).
So an object counts for an action only where the record names it in its role's relation (the archive says
so; EPIC and the recipe files, which do not, are read as a video is, by role), over all of the action's
(relation, object) features: P(O | A) is the share of the action's features that the object in its role
takes. The turkey of "spread ... over the turkey" then says nothing of spreading turkey, and the eggs the
old books wrap things in nothing of wrapping eggs.

Measured on each corpus's held-out units (``python -m bench.recognize --corpora``, seed 0), against the
tables pooled from EPIC and the recipe files: see that bench's docstring and ``assets/knowledge/SOURCE.md``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from wecook_core.knowledge.corpus import Corpus
from wecook_core.knowledge.learning import Example, count, fold
from wecook_core.knowledge.recognize import Component, Knowledge
from wecook_core.knowledge.roles import role_relation
from wecook_core.knowledge.synonyms import RECOGNISED, VerbFolder

ALPHA = 0.03
"""Additive smoothing of each component, picked on validation units carved from the training units of the
held-out split (``bench.recognize --corpora``: of 0.01, 0.03, 0.1, 0.3 and 1, the best of
:func:`~wecook_core.knowledge.relations.goal`)."""


def object_roles(objects: Sequence[str]) -> dict[str, str]:
    """Object -> its role in the shipped category tables (tool, container; an object they do not know is an
    ingredient, as the recipe's ingredient list named it)."""
    from wecook_core.knowledge.categories import load_categories

    table = load_categories()
    roles = {}
    for name in objects:
        category = table.categorize(name)
        roles[name] = category.value if category is not None else "ingredient"
    return roles


def components(examples: Sequence[Example], verbs: Sequence[str], vocabulary: Sequence[str],
               roles: Mapping[str, str]) -> tuple[tuple[Component, ...], int]:
    """Per corpus (in order of first appearance) its :class:`~wecook_core.knowledge.recognize.Component`, and
    the number of distinct (relation, object) features of all of them. Counted once per group, as
    :func:`~wecook_core.knowledge.learning.count`; a record without relations is read by role."""
    verb_index = {v: i for i, v in enumerate(verbs)}
    object_index = {o: i for i, o in enumerate(vocabulary)}
    sources = list(dict.fromkeys(e.source for e in examples))
    pairs = {s: np.zeros((len(verbs), len(vocabulary)), dtype=np.int64) for s in sources}
    totals = {s: np.zeros(len(verbs), dtype=np.int64) for s in sources}
    features: set[tuple[str, str]] = set()
    seen: set[tuple[str, str, str, str, str]] = set()
    for example in examples:
        a = verb_index.get(example.action)
        if a is None:
            continue
        said = example.relations if len(example.relations) == len(example.objects) else ()
        for i, obj in enumerate(example.objects):
            own = role_relation(roles.get(obj, "ingredient"))
            relation = said[i] if said else own
            key = (example.source, example.group, example.action, relation, obj)
            if key in seen:
                continue
            seen.add(key)
            features.add((relation, obj))
            totals[example.source][a] += 1
            if relation == own:
                pairs[example.source][a, object_index[obj]] += 1
    return tuple(Component(s, pairs[s], totals[s]) for s in sources), max(len(features), len(vocabulary))


def mixed_from_examples(examples: Sequence[Example], vocabulary: Sequence[str], corpus: Corpus, *,
                        alpha: float = ALPHA, verbs: Sequence[str] = RECOGNISED, source: str = "",
                        roles: Mapping[str, str] | None = None) -> Knowledge:
    """Mixed tables of folded examples (uniform prior; ``roles``: default :func:`object_roles`)."""
    roles = roles if roles is not None else object_roles(vocabulary)
    parts, features = components(examples, verbs, vocabulary, roles)
    actions, _ = count(examples, verbs, vocabulary)
    summed = sum((c.pair_counts for c in parts), np.zeros((len(verbs), len(vocabulary)), dtype=np.int64))
    known = set(vocabulary)
    aliases = {a: o for a, o in corpus.nouns.items() if o in known and a != o}
    return Knowledge(tuple(verbs), tuple(vocabulary), actions, summed, alpha=alpha, aliases=aliases,
                     source=source or "; ".join(corpus.sources), prior_kind="uniform", components=parts,
                     features=features)


def learn_mixed(corpus: Corpus, *, alpha: float = ALPHA, folder: VerbFolder | None = None,
                verbs: Sequence[str] = RECOGNISED, source: str = "") -> Knowledge:
    """The mixed tables of a corpus's records (see the module docstring)."""
    examples, vocabulary = fold(corpus, folder, verbs)
    return mixed_from_examples(examples, vocabulary, corpus, alpha=alpha, verbs=verbs, source=source)
