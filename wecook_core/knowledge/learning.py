"""Learning the commonsense tables P(A) and P(O | A) from a corpus of (action, objects) records."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from wecook_core.knowledge.corpus import Corpus, Record
from wecook_core.knowledge.nouns import match, variants
from wecook_core.knowledge.recognize import Knowledge
from wecook_core.knowledge.synonyms import RECOGNISED, VerbFolder, load_synonyms

INSTRUMENTS: Mapping[str, str] = {"whisk": "whisk"}
"""Corpus verbs named after the tool they are done with -> that tool, an object of every record of the verb
(and of its particle forms, ``whisk-in``). Neither narrators nor recipes name the whisk they whisk with
("whisk egg", "Whisk the eggs with the sugar"), so per record the whisk hardly ever met stir, and a held
whisk over a pot was ranked pour. (Spoon and ladle, the other tools that are verbs, are named by the recipe
reader already, :data:`~wecook_core.knowledge.instructions.NAMING_VERBS`; EPIC's "spoon" and "ladle" moves
are transfers, which a held spoon in a pot is not.)"""


@dataclass(frozen=True)
class Example:
    """A record folded into wecook's words: an action of the vocabulary and object names."""

    action: str
    """A wecook verb."""
    objects: tuple[str, ...]
    """Object names, each once: the record's objects then its context (vocabulary names after matching)."""
    group: str
    source: str = ""
    """The corpus of the record (see :attr:`~wecook_core.knowledge.corpus.Record.source`)."""
    relations: tuple[str, ...] = ()
    """How the record's sentence names each object (:attr:`~wecook_core.knowledge.corpus.Record.relations`),
    one per object; empty when the corpus does not say."""


def fold(corpus: Corpus, folder: VerbFolder | None = None,
         verbs: Sequence[str] = RECOGNISED) -> tuple[tuple[Example, ...], tuple[str, ...]]:
    """The corpus's records whose verb folds into ``verbs`` and that name an object, and the object
    vocabulary.

    Objects are matched to the corpus's nouns (aliases, head noun, plural); an object the corpus does
    not define becomes a vocabulary entry of its own (a user's CSV defines its vocabulary by use), unless
    it is the singular or plural of one already seen.
    The vocabulary is the corpus's defined objects, in order, then new ones in order of appearance.
    """
    folder = (folder or load_synonyms()).with_classes(corpus.verb_classes)
    wanted = set(verbs)
    vocabulary: dict[str, None] = dict.fromkeys(corpus.vocabulary)
    cache: dict[str, str] = {}
    examples = []
    for record in corpus.records:
        action = folder.fold(record.action)
        named = (*record.objects, *record.context)
        tool = INSTRUMENTS.get(record.action.strip().lower().split("-", 1)[0])
        if tool is not None:
            named = (*named, tool)
        if action is None or action not in wanted or not named:
            continue  # a record naming no object says nothing of P(O | A), and is never asked
        names = [_object(o, corpus, cache, vocabulary) for o in named]
        objects = tuple(dict.fromkeys(names))
        relations: tuple[str, ...] = ()
        if record.relations and len(record.relations) == len(record.objects):
            # the context has no relation; a folded tool (the whisk of "whisk") is what the verb is done with
            said = (*record.relations, *(["object"] * len(record.context)), *(["means"] * (tool is not None)))
            first = dict(reversed(list(zip(names, said, strict=True))))
            relations = tuple(first[o] for o in objects)
        vocabulary.update(dict.fromkeys(objects))
        examples.append(Example(action, objects, record.group, record.source, relations))
    return tuple(examples), tuple(vocabulary)


def _object(name: str, corpus: Corpus, cache: dict[str, str], seen: dict[str, None]) -> str:
    """The vocabulary name of a record's object: the corpus's noun it matches, else an object already
    seen under another number (tomatoes / tomato), else itself."""
    found = cache.get(name)
    if found is None:
        found = match(name, corpus.nouns) if corpus.nouns else None
        if found is None:
            found = next((v for v in variants(name) if v in seen), name)
        cache[name] = found
    return found


def count(examples: Sequence[Example], verbs: Sequence[str], vocabulary: Sequence[str], *,
          per_group: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Counts per verb ``(len(verbs),)`` and per (verb, object) ``(len(verbs), len(vocabulary))``.

    ``per_group`` (the default): a verb, or a verb with an object, counts once per group (EPIC: video; recipes:
    recipe), however often the group repeats it. Narrations and recipes are bursty: one participant of EPIC
    rolls an egg eight times in one video (P04_02, "roll egg"), and per record that one video made egg the
    second object of roll. Counting the groups that do a verb with an object is the binarised multinomial
    model of text classification (a word counts once per document: Rennie et al., "Tackling the Poor
    Assumptions of Naive Bayes Text Classifiers", ICML 2003; Wang and Manning, ACL 2012), the document being
    the video or the recipe. ``per_group=False`` counts records.
    """
    verb_index = {v: i for i, v in enumerate(verbs)}
    object_index = {o: i for i, o in enumerate(vocabulary)}
    actions = np.zeros(len(verbs), dtype=np.int64)
    pairs = np.zeros((len(verbs), len(vocabulary)), dtype=np.int64)
    seen: set[tuple[str, ...]] = set()
    for example in examples:
        a = verb_index[example.action]
        key = (example.source, example.group, example.action)
        if not per_group or key not in seen:
            seen.add(key)
            actions[a] += 1
        for obj in example.objects:
            if per_group:
                if (*key, obj) in seen:
                    continue
                seen.add((*key, obj))
            pairs[a, object_index[obj]] += 1
    return actions, pairs


def learn(corpus: Corpus, *, alpha: float = 1.0, folder: VerbFolder | None = None,
          verbs: Sequence[str] = RECOGNISED, source: str = "", prior: str = "corpus",
          per_group: bool = True) -> Knowledge:
    """The commonsense tables of a corpus: counts of the records whose verb folds into ``verbs``.

    ``alpha`` is the additive smoothing pseudo-count and ``prior`` how P(A) is taken (see
    :class:`~wecook_core.knowledge.recognize.Knowledge`); ``per_group``: see :func:`count`.
    The corpus's aliases are kept so that run-time labels find their nouns.
    """
    examples, vocabulary = fold(corpus, folder, verbs)
    return from_examples(examples, vocabulary, corpus, alpha=alpha, verbs=verbs, source=source, prior=prior,
                         per_group=per_group)


def from_examples(examples: Sequence[Example], vocabulary: Sequence[str], corpus: Corpus, *, alpha: float = 1.0,
                  verbs: Sequence[str] = RECOGNISED, source: str = "", prior: str = "corpus",
                  per_group: bool = True) -> Knowledge:
    actions, pairs = count(examples, verbs, vocabulary, per_group=per_group)
    known = set(vocabulary)
    aliases = {a: o for a, o in corpus.nouns.items() if o in known and a != o}
    source = source or "; ".join(corpus.sources)
    return Knowledge(tuple(verbs), tuple(vocabulary), actions, pairs, alpha=alpha, aliases=aliases, source=source,
                     prior_kind=prior)


def records(examples: Sequence[Example]) -> tuple[Record, ...]:
    """Examples back as plain records (for writing a folded corpus as CSV)."""
    return tuple(Record(e.action, e.objects, e.group, source=e.source) for e in examples)
