"""The commonsense model at run time: rank actions by P(A | O1..On) ∝ P(A) ∏ P(Ok | A).

The tables come from a corpus of (action, objects) records (:mod:`wecook_core.knowledge`); the shipped
ones are learned from EPIC-KITCHENS, recipe instructions and the Open Recipe Archive
(``wecook_core/assets/knowledge/``), each corpus its own table with every object in its role, P(O | A) their
mean (:mod:`wecook_core.knowledge.mixture`, :attr:`Knowledge.components`), with a uniform P(A). Object labels are
free text: each is matched to a corpus noun (exact, the corpus's own aliases, shorter tails down to the head
noun, singular/plural); labels that match nothing are ignored and reported by :func:`unknown_objects`.

The counts are per group (a video or a recipe that repeats a verb with an object counts once, see
:func:`wecook_core.knowledge.learning.count`). Measured against this model on the same held-out splits
(``wecook knowledge evaluate``, seeds 0-4) and not adopted, as none named held-out verbs better: multinomial
logistic regression over objects and their categories (higher accuracy and precision, lower macro recall;
class-balanced, the reverse), complement naive Bayes, smoothing by back-off to the object's category
(EPIC's or wecook's: it raises the rare verbs for every object of a category, precision falls), and separate
tables for the held object and the targets (EPIC's take context as the held object, a recipe's tool).
Measured again on those splits (macro precision / recall, mean of seeds 0-4; this model, with EPIC's "take"
records among the 2 before as context: 0.401 / 0.507, with the held tool of
:data:`~wecook_core.knowledge.corpus.HELD_S` instead, the shipped tables: 0.416 / 0.519) and not adopted:
Dirichlet smoothing towards the objects' marginal P(O) (Zhai and Lafferty, SIGIR 2001; mu = 300: 0.399 /
0.548, but 0.382 / 0.497 on the held-out recipes, where this model has 0.423 / 0.511; mu picked by
cross-validation on the training groups: 0.386 / 0.526), Witten-Bell (0.372 / 0.543) and Jelinek-Mercer
interpolation (0.36 / 0.53); per-verb decision biases picked by cross-validation on the training groups
(0.41 / 0.55), and even picked on the held-out records themselves, an oracle decision rule (0.46 / 0.57);
logistic regression over objects, their categories, the tool/container/ingredient pattern of the record and
tool x ingredient pairs, class-balanced or not (0.37-0.47 / 0.41-0.55); the verbs of the training records
with exactly the same object set, backed off to this model (0.40-0.43 / 0.46-0.52). What generalises from
one cook (or recipe) to another is the limit: the objects oracle of ``wecook knowledge evaluate``, the
most frequent verb of each object set among the held-out records themselves, names 0.86 / 0.76 of them
(an upper reference, loose: an object set met once there is right by construction), the same model
learned from them 0.63 / 0.61. On the Open Recipe Archive, whose sentences say how each object takes part,
the role-aware model of :mod:`wecook_core.knowledge.relations` does better than this one on the held-out
collections (macro P / R 0.493 / 0.602 with its class and role back-off, 0.474 / 0.605 without, against 0.387 /
0.532, ``bench/recognize.py --held-out``); it is not shipped, as its tables (sentence relations for every
object) ask more of a video than a role per object. The shipped mixture reads the archive's relations only
to count an object where it is in its role (held-out per corpus, seed 0, against the tables pooled from EPIC
and the recipes before the archive: EPIC 0.452 / 0.423 -> 0.447 / 0.609, recipes 0.432 / 0.376 -> 0.449 /
0.471, archive 0.336 / 0.323 -> 0.353 / 0.449; ``bench/recognize.py --corpora``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from wecook_core.errors import InputError, json_error
from wecook_core.knowledge.nouns import match
from wecook_core.resources import ASSETS_DIR

KNOWLEDGE_PATH = ASSETS_DIR / "knowledge" / "commonsense.json"
"""The shipped tables (learned from EPIC-KITCHENS and recipes, see ``wecook_core/assets/knowledge/SOURCE.md``)."""

FORMAT_KEY = "wecook_knowledge"
FORMAT_VERSION = 1

PRIORS: tuple[str, ...] = ("corpus", "uniform")
"""How P(A) is taken (:attr:`Knowledge.prior_kind`)."""

Ranking = tuple[tuple[str, float], ...]
"""(verb, probability) pairs, best first, probabilities summing to 1."""


@dataclass(frozen=True, eq=False)
class Component:
    """One corpus's own counts in tables that mix corpora (:attr:`Knowledge.components`)."""

    source: str
    """The corpus (``epic-kitchens``, ``open-recipe-archive``)."""
    pair_counts: np.ndarray
    """int64 ``(len(verbs), len(objects))``: groups in which an action names an object in the relation of its
    role (:func:`wecook_core.knowledge.roles.role_relation`: a tool as what it is done with, a container as
    where, an ingredient as what it is done to)."""
    totals: np.ndarray
    """int64 ``(len(verbs),)``: the action's (relation, object) features over its groups, every relation
    counted (so ``pair_counts`` over ``totals`` is the share of the action's features that the object in its
    role takes)."""


@dataclass(frozen=True, eq=False)
class Knowledge:
    """Counts learned from a corpus and the smoothed log-probability tables derived from them.

    Holds arrays, so it compares by identity (``eq=False``); :func:`load_knowledge` returns one shared
    instance per file.

    P(A) = (n_A + alpha) / (N + alpha |verbs|) and P(O | A) = (n_{A,O} + alpha) / (Σ_O n_{A,O} + alpha |objects|):
    additive smoothing over the whole object vocabulary, so an object never seen with an action only
    lowers that action's score, it never rules it out.

    With ``prior_kind="uniform"`` P(A) is 1 / |verbs|: the ranking is then the likelihood of the objects under
    each action. How often a corpus names an action (cooks stir far more often than they wrap) says little
    about what one segment of a video shows once its objects are known, and the corpus prior buries the
    rare actions (wrap, dip, sprinkle) under the frequent ones whatever the objects; the shipped tables
    use the uniform prior (see ``wecook_core/assets/knowledge/SOURCE.md`` for the held-out figures of both).
    """

    verbs: tuple[str, ...]
    """The actions ranked, in table order."""
    objects: tuple[str, ...]
    """The object vocabulary (wecook names, ``chopping_board``), in table order."""
    action_counts: np.ndarray
    """int64 ``(len(verbs),)``: groups (or records, see :func:`~wecook_core.knowledge.learning.count`) per
    action."""
    pair_counts: np.ndarray
    """int64 ``(len(verbs), len(objects))``: groups (or records) in which an action names an object."""
    alpha: float = 1.0
    """Additive smoothing constant (pseudo-count), for the prior and the likelihoods."""
    aliases: Mapping[str, str] = field(default_factory=dict)
    """Alias -> object name (EPIC class instances: ``cherry_tomato -> tomato``). Keys are normalised
    (:func:`wecook_core.knowledge.nouns.normalise`); aliases of objects outside the vocabulary are ignored."""
    source: str = ""
    """Where the counts come from, one line."""
    prior_kind: str = "corpus"
    """``"corpus"``: P(A) from the action counts; ``"uniform"``: every action equally likely a priori."""
    components: tuple[Component, ...] = ()
    """Per corpus, its own counts: when given, P(O | A) is the mean over the corpora of each one's
    (n_{s,A,O} + alpha) / (T_{s,A} + alpha F) (every corpus one vote, however many records it has; F:
    :attr:`features`), and :attr:`pair_counts` is their sum, for showing."""
    features: int = 0
    """With components: the number of distinct (relation, object) features of all corpora (the smoothing's
    vocabulary)."""
    log_prior: np.ndarray = field(init=False, repr=False)
    """float64 ``(len(verbs),)``: natural log of P(A)."""
    log_likelihood: np.ndarray = field(init=False, repr=False)
    """float64 ``(len(objects), len(verbs))``: natural log of P(O | A); one row per object, so a ranking
    sums rows."""
    index: Mapping[str, int] = field(init=False, repr=False)
    """Normalised name or alias -> row of ``log_likelihood``."""

    def __post_init__(self) -> None:
        counts = np.asarray(self.pair_counts, dtype=np.int64).reshape(len(self.verbs), len(self.objects))
        actions = np.asarray(self.action_counts, dtype=np.int64).reshape(len(self.verbs))
        if self.alpha <= 0:
            raise ValueError("alpha must be positive")
        if (counts < 0).any() or (actions < 0).any():
            raise ValueError("counts must be non-negative")
        if self.prior_kind not in PRIORS:
            raise ValueError(f"prior must be one of {', '.join(PRIORS)}, not {self.prior_kind!r}")
        if self.prior_kind == "uniform":
            prior = np.full(len(self.verbs), 1.0 / max(1, len(self.verbs)))
        else:
            prior = (actions + self.alpha) / (actions.sum() + self.alpha * len(self.verbs))
        if self.components:
            likelihood = self._mixed()
        else:
            likelihood = (counts + self.alpha) / (counts.sum(axis=1, keepdims=True) + self.alpha * len(self.objects))
        rows = {name: i for i, name in enumerate(self.objects)}
        index = {alias: rows[name] for alias, name in self.aliases.items() if name in rows}
        index.update(rows)
        object.__setattr__(self, "action_counts", actions)
        object.__setattr__(self, "pair_counts", counts)
        object.__setattr__(self, "log_prior", np.log(prior))
        object.__setattr__(self, "log_likelihood", np.ascontiguousarray(np.log(likelihood).T))
        object.__setattr__(self, "index", index)

    def _mixed(self) -> np.ndarray:
        """The mean of the components' smoothed P(O | A), ``(len(verbs), len(objects))``."""
        shape = (len(self.verbs), len(self.objects))
        if self.features < len(self.objects):
            raise ValueError("features must count at least every object")
        total = np.zeros(shape)
        for component in self.components:
            counts = np.asarray(component.pair_counts, dtype=np.int64)
            totals = np.asarray(component.totals, dtype=np.int64)
            if counts.shape != shape or totals.shape != (len(self.verbs),):
                raise ValueError(f"component {component.source!r}: expected counts of shape {shape[0]}x{shape[1]} "
                                 f"and {shape[0]} totals")
            if (counts < 0).any() or (counts.sum(axis=1) > totals).any():
                raise ValueError(f"component {component.source!r}: counts must be non-negative and within the "
                                 "totals")
            total += (counts + self.alpha) / (totals[:, None] + self.alpha * self.features)
        result: np.ndarray = total / len(self.components)
        return result

    def prior(self) -> dict[str, float]:
        """P(A) for every verb."""
        return dict(zip(self.verbs, np.exp(self.log_prior).tolist(), strict=True))

    def likelihood(self, obj: str, verb: str) -> float:
        """P(O | A) for a vocabulary object (wecook name) and a verb."""
        return math.exp(self.log_likelihood[self.objects.index(obj), self.verbs.index(verb)])


# ------------------------------------------------------------------------------------ loading / saving


def knowledge_to_json(knowledge: Knowledge) -> str:
    """The tables as JSON text: counts (not probabilities) so the file stays small, exact and diffable."""
    head = {
        FORMAT_KEY: FORMAT_VERSION,
        "source": knowledge.source,
        "alpha": knowledge.alpha,
        "prior": knowledge.prior_kind,
        "verbs": list(knowledge.verbs),
        "action_counts": knowledge.action_counts.tolist(),
        "objects": list(knowledge.objects),
    }
    lines = ["{"]
    lines += [f" {json.dumps(k)}: {json.dumps(v)}," for k, v in head.items()]
    lines.append(' "pair_counts": [')
    rows = [f"  {json.dumps(row)}" for row in knowledge.pair_counts.tolist()]
    lines.append(",\n".join(rows))
    lines.append(" ],")
    if knowledge.components:
        lines.append(f' "features": {knowledge.features},')
        lines.append(' "components": [')
        parts = []
        for component in knowledge.components:
            table = ",\n".join(f"    {json.dumps(row)}" for row in component.pair_counts.tolist())
            parts.append(f'  {{"source": {json.dumps(component.source)}, "totals": '
                         f'{json.dumps(component.totals.tolist())}, "pair_counts": [\n{table}\n  ]}}')
        lines.append(",\n".join(parts))
        lines.append(" ],")
    lines.append(f' "aliases": {json.dumps(dict(sorted(knowledge.aliases.items())), indent=None)}')
    lines.append("}")
    return "\n".join(lines) + "\n"


def save_knowledge(knowledge: Knowledge, path: Path) -> None:
    from wecook_core.files import write_atomic

    write_atomic(path, knowledge_to_json(knowledge), replace=True, what="knowledge file")


def knowledge_from_json(data: Any, path: Path) -> Knowledge:
    """Tables from the parsed JSON of a knowledge file; InputError naming ``path`` when malformed."""
    if not isinstance(data, dict) or data.get(FORMAT_KEY) != FORMAT_VERSION:
        raise InputError(path, f"not a wecook knowledge file (expected {FORMAT_KEY}: {FORMAT_VERSION})")
    for key, kind in (("verbs", list), ("objects", list), ("action_counts", list), ("pair_counts", list)):
        if not isinstance(data.get(key), kind):
            raise InputError(path, f"expected a list under {key!r}", place=key)
    verbs, objects = tuple(map(str, data["verbs"])), tuple(map(str, data["objects"]))
    try:
        counts = np.asarray(data["pair_counts"], dtype=np.int64)
        actions = np.asarray(data["action_counts"], dtype=np.int64)
    except (ValueError, TypeError):
        raise InputError(path, "counts must be integers", place="pair_counts") from None
    if counts.shape != (len(verbs), len(objects)) or actions.shape != (len(verbs),):
        raise InputError(path, f"expected pair_counts of shape {len(verbs)}x{len(objects)} and "
                               f"{len(verbs)} action_counts", place="pair_counts")
    aliases = data.get("aliases") or {}
    if not isinstance(aliases, dict):
        raise InputError(path, "expected a mapping alias -> object", place="aliases")
    components = _components(data.get("components"), path)
    try:
        return Knowledge(verbs, objects, actions, counts, alpha=float(data.get("alpha", 1.0)),
                         aliases={str(k): str(v) for k, v in aliases.items()}, source=str(data.get("source", "")),
                         prior_kind=str(data.get("prior", "corpus")), components=components,
                         features=int(data.get("features", 0)))
    except (ValueError, TypeError) as error:
        raise InputError(path, str(error), place="components" if components else None) from None


def _components(data: Any, path: Path) -> tuple[Component, ...]:
    """The ``components`` of a knowledge file (absent: none); InputError naming the entry when malformed."""
    if data is None:
        return ()
    if not isinstance(data, list):
        raise InputError(path, "expected a list of components", place="components")
    found = []
    for i, entry in enumerate(data):
        if not isinstance(entry, dict) or not isinstance(entry.get("pair_counts"), list) or not isinstance(
                entry.get("totals"), list):
            raise InputError(path, "expected source, totals and pair_counts", place=f"components[{i}]")
        try:
            found.append(Component(str(entry.get("source", "")), np.asarray(entry["pair_counts"], dtype=np.int64),
                                   np.asarray(entry["totals"], dtype=np.int64)))
        except (ValueError, TypeError):
            raise InputError(path, "counts must be integers", place=f"components[{i}]") from None
    return tuple(found)


_CACHE: dict[tuple[str, int], Knowledge] = {}


def load_knowledge(path: Path | None = None) -> Knowledge:
    """The tables of a knowledge file (default: the shipped ones), cached until the file changes."""
    path = Path(path) if path is not None else KNOWLEDGE_PATH
    try:
        key = (str(path.resolve()), path.stat().st_mtime_ns)
    except OSError as error:
        raise InputError(path, f"cannot read the knowledge tables: {error.strerror or error}") from None
    cached = _CACHE.get(key)
    if cached is not None:
        return cached
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(path, f"cannot read the knowledge tables: {error}") from None
    except json.JSONDecodeError as error:
        raise json_error(path, error, "invalid JSON") from None
    knowledge = knowledge_from_json(data, path)
    _CACHE[key] = knowledge
    return knowledge


# --------------------------------------------------------------------------------------------- ranking


def match_object(knowledge: Knowledge, label: str) -> str | None:
    """The vocabulary object a free-text label means (``"Cherry_Tomatoes_2" -> "tomato"``), or None."""
    row = match(label, knowledge.index)
    return None if row is None else knowledge.objects[row]


def unknown_objects(knowledge: Knowledge, objects: Iterable[str]) -> tuple[str, ...]:
    """The labels :func:`rank` ignores because they match no object of the vocabulary, in input order."""
    return tuple(label for label in objects if match(label, knowledge.index) is None)


def _columns(knowledge: Knowledge, candidates: Sequence[str] | None) -> np.ndarray:
    if candidates is None:
        return np.arange(len(knowledge.verbs))
    try:
        return np.array([knowledge.verbs.index(c) for c in candidates], dtype=np.int64)
    except ValueError:
        unknown = [c for c in candidates if c not in knowledge.verbs]
        raise ValueError(f"not verbs of the knowledge tables: {', '.join(unknown)}") from None


def _posterior(scores: np.ndarray) -> np.ndarray:
    """Normalised probabilities from log scores (last axis), stable for very negative logs."""
    shifted = np.exp(scores - scores.max(axis=-1, keepdims=True))
    result: np.ndarray = shifted / shifted.sum(axis=-1, keepdims=True)
    return result


def _ordered(verbs: Sequence[str], probabilities: Sequence[float]) -> Ranking:
    order = sorted(range(len(verbs)), key=lambda i: -probabilities[i])  # stable: ties keep table order
    return tuple((verbs[i], float(probabilities[i])) for i in order)


def rank(knowledge: Knowledge, objects: Sequence[str], candidates: Sequence[str] | None = None) -> Ranking:
    """Verbs ranked by P(A | O1..On) ∝ P(A) ∏ P(Ok | A), normalised over the candidates, best first.

    ``objects`` are free-text labels; each known one counts once per occurrence, unknown ones are ignored
    (see :func:`unknown_objects`); with no known object the ranking is the prior. ``candidates``
    restricts the verbs (default: every verb of the tables); an unknown candidate is a ValueError.
    """
    if isinstance(objects, str):
        raise TypeError("objects must be a sequence of labels, not one string")
    columns = _columns(knowledge, candidates)
    if len(columns) == 0:
        return ()
    rows = [r for r in (match(label, knowledge.index) for label in objects) if r is not None]
    scores = knowledge.log_prior[columns] + knowledge.log_likelihood[rows][:, columns].sum(axis=0)
    verbs = [knowledge.verbs[c] for c in columns]
    return _ordered(verbs, _posterior(scores).tolist())


@dataclass(frozen=True)
class BatchItem:
    """One line of a batch ranking."""

    ranking: Ranking
    """Empty for an empty object list."""
    unknown: tuple[str, ...]
    """Labels of the line that matched nothing (ignored)."""


def rank_batch(knowledge: Knowledge, lines: Iterable[Sequence[str]], candidates: Sequence[str] | None = None, *,
               chunk: int = 4096) -> Iterator[BatchItem]:
    """Rank many object lists, streaming, in order: one :class:`BatchItem` per list.

    Vectorised per chunk of lists: labels are matched once each (cached), the chunk becomes a count
    matrix (lists x objects) and one matrix product with the log-likelihood table gives every score.
    An empty list gives an empty ranking (not the prior), so that a blank input line stays visible.
    ``candidates`` restricts the verbs as in :func:`rank`. Chunks are ranked when full, so a slow stream
    sees results by the chunk.
    """
    columns = _columns(knowledge, candidates)
    matched: dict[str, int | None] = {}
    table, prior = knowledge.log_likelihood[:, columns], knowledge.log_prior[columns]
    verbs = [knowledge.verbs[c] for c in columns]
    n_objects = len(knowledge.objects)

    names = np.array(verbs, dtype=object)

    def flush(pending: list[tuple[list[int], tuple[str, ...], bool]]) -> Iterator[BatchItem]:
        lines = np.repeat(np.arange(len(pending)), [len(rows) for rows, _, _ in pending])
        objects = np.fromiter((r for rows, _, _ in pending for r in rows), dtype=np.int64, count=len(lines))
        counts = np.bincount(lines * n_objects + objects, minlength=len(pending) * n_objects)
        probabilities = _posterior(counts.reshape(len(pending), n_objects) @ table + prior)
        order = np.argsort(-probabilities, axis=1, kind="stable")
        ranked_names = names[order].tolist()
        ranked_p = np.take_along_axis(probabilities, order, axis=1).tolist()
        for i, (_, unknown, empty) in enumerate(pending):
            ranking = () if empty else tuple(zip(ranked_names[i], ranked_p[i], strict=True))
            yield BatchItem(ranking, unknown)

    pending: list[tuple[list[int], tuple[str, ...], bool]] = []
    for labels in lines:
        rows: list[int] = []
        unknown: list[str] = []
        for label in labels:
            if label not in matched:
                matched[label] = match(label, knowledge.index)
            row = matched[label]
            if row is None:
                unknown.append(label)
            else:
                rows.append(row)
        pending.append((rows, tuple(unknown), not labels))
        if len(pending) >= chunk:
            yield from flush(pending)
            pending = []
    if pending:
        yield from flush(pending)
