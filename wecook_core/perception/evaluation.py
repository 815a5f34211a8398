"""Tree precision and recall (DESIGN.md, Evaluation), and which trees were missed or spurious.

A predicted tree is correct when it equals a ground-truth tree (structure, hands, actions, objects) and their
frame ranges overlap. Only trees that contain an action or a collaboration count; each ground-truth tree is
matched at most once.

Objects are compared at class level by default: wecook names several instances of a label ``bowl``,
``bowl_2``, ``bowl_3`` (:func:`wecook_core.observations.importer.unique_names`), while a person writing the
ground truth names them by what they are. ``instances=True`` compares the exact names.

:func:`report` adds, for reading the mistakes, the missed and spurious trees and the counts per tree case
(:data:`wecook_core.trees.graph.CASES`: tool, container, hand, held, transfer, holding, handover).

:func:`loose` scores the same trees under looser views besides the strict one (``wecook eval --loose``), so a
reviewer sees which part of a tree is wrong: :func:`without_hands` (every hand the same: a tree wrong only in
which hand or person did it matches) and :func:`verbs_only` (only the actions and collaborations, in order: a
tree wrong only in its objects or hands matches). The strict score is the one the bars are set on; the views
never change it.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cache
from typing import TYPE_CHECKING

from wecook_core.model import Category, Node, Scores, TreeSpan
from wecook_core.trees.notation import has_action

if TYPE_CHECKING:
    from wecook_core.knowledge.categories import CategoryTable

_INSTANCE = re.compile(r"^(.+?)_\d+$")


def class_name(name: str) -> str:
    """The label of an instance name: ``bowl_2`` -> ``bowl`` (names without a number suffix unchanged)."""
    found = _INSTANCE.match(name)
    return found.group(1) if found else name


def class_tree(node: Node) -> Node:
    """The tree with every object named by its class (:func:`class_name`)."""
    if node.label == "O" and node.word is not None:
        return replace(node, word=class_name(node.word))
    if not node.children:
        return node
    return replace(node, children=tuple(class_tree(child) for child in node.children))


def object_names(node: Node) -> set[str]:
    """Every object word of a tree."""
    if node.label == "O" and node.word is not None:
        return {node.word}
    return {name for child in node.children for name in object_names(child)}


HAND = "hand"
"""The one hand word of :func:`without_hands`."""


def without_hands(node: Node) -> Node:
    """The tree with every hand word the same (:data:`HAND`): which hand, and whose, no longer counts."""
    if node.label == "H":
        return replace(node, word=HAND)
    if not node.children:
        return node
    return replace(node, children=tuple(without_hands(child) for child in node.children))


def _preterminals(node: Node) -> list[Node]:
    if not node.children:
        return [node]
    return [leaf for child in node.children for leaf in _preterminals(child)]


def verbs_only(node: Node) -> Node:
    """The tree's actions and collaborations (``A`` and ``C`` words) in order, as the children of one node:
    hands, objects and structure no longer count."""
    return Node("AP", tuple(Node(leaf.label, word=leaf.word) for leaf in _preterminals(node)
                            if leaf.label in ("A", "C")))


View = Callable[[Node], Node]
"""A view of a tree for loose scoring: two trees match when their views are equal."""

LOOSE_VIEWS: dict[str, View] = {"hands ignored": without_hands, "verbs only": verbs_only}
"""The views of :func:`loose`, by the name a reviewer reads."""


def _overlap(a: TreeSpan, b: TreeSpan) -> int:
    return min(a.end, b.end) - max(a.start, b.start)


def _counted(spans: Sequence[TreeSpan], instances: bool, view: View | None = None) -> list[TreeSpan]:
    kept = [s for s in spans if has_action(s.tree)]
    named = kept if instances else [replace(s, tree=class_tree(s.tree)) for s in kept]
    return named if view is None else [replace(s, tree=view(s.tree)) for s in named]


def _pairs(pred: Sequence[TreeSpan], true: Sequence[TreeSpan]) -> list[tuple[int, int]]:
    candidates = sorted(
        ((_overlap(p, t), i, j) for i, p in enumerate(pred) for j, t in enumerate(true)
         if p.tree == t.tree and _overlap(p, t) > 0),
        key=lambda c: (-c[0], c[1], c[2]),
    )
    used_pred: set[int] = set()
    used_true: set[int] = set()
    pairs = []
    for _, i, j in candidates:
        if i in used_pred or j in used_true:
            continue
        used_pred.add(i)
        used_true.add(j)
        pairs.append((i, j))
    return pairs


def match(predicted: Sequence[TreeSpan], truth: Sequence[TreeSpan], *, instances: bool = False,
          ) -> list[tuple[TreeSpan, TreeSpan]]:
    """Correct (predicted, truth) pairs, as given (trees with actions only). Pairs are taken by largest frame
    overlap first, so one long prediction cannot take a ground-truth tree that a better-aligned prediction of
    the same tree covers."""
    pred = [p for p in predicted if has_action(p.tree)]
    true = [t for t in truth if has_action(t.tree)]
    pairs = _pairs(_counted(pred, instances), _counted(true, instances))
    return [(pred[i], true[j]) for i, j in pairs]


def evaluate(predicted: Sequence[TreeSpan], truth: Sequence[TreeSpan], *, instances: bool = False,
             view: View | None = None) -> Scores:
    """Tree precision and recall; with ``view``, trees match when their views are equal (loose scoring; the
    trees counted are the same: those with an action)."""
    n_pred = sum(1 for p in predicted if has_action(p.tree))
    n_true = sum(1 for t in truth if has_action(t.tree))
    if view is None:
        correct = len(match(predicted, truth, instances=instances))
    else:
        correct = len(_pairs(_counted(predicted, instances, view), _counted(truth, instances, view)))
    return Scores(
        precision=correct / n_pred if n_pred else 0.0,
        recall=correct / n_true if n_true else 0.0,
        correct=correct,
        predicted=n_pred,
        truth=n_true,
    )


@dataclass(frozen=True)
class Report:
    """Scores, the trees that were missed and spurious, and counts per tree case."""

    scores: Scores
    missed: tuple[TreeSpan, ...]
    """Ground-truth trees no prediction matched."""
    spurious: tuple[TreeSpan, ...]
    """Predicted trees that match no ground-truth tree."""
    predicted: Mapping[str, int] = field(default_factory=dict)
    """Case -> predicted trees of that case."""
    truth: Mapping[str, int] = field(default_factory=dict)
    """Case -> ground-truth trees of that case."""
    correct: Mapping[str, int] = field(default_factory=dict)
    """Case -> correct pairs of that case (a correct pair has equal trees, so one case)."""

    def cases(self) -> list[str]:
        from wecook_core.trees.graph import CASES

        seen = set(self.truth) | set(self.predicted)
        return [c for c in CASES if c in seen] + sorted(seen - set(CASES))


def case_name(span: TreeSpan, categories: Mapping[str, Category] | None = None) -> str:
    """The tree case of a span (:func:`wecook_core.trees.graph.case_of`); objects are categorised by
    ``categories`` (by name, then class name), else by the shipped category table."""
    from wecook_core.trees.graph import case_of
    from wecook_core.trees.notation import action_of

    action = action_of(span.tree, span.start, span.end)
    names = [action.held, *action.targets]
    if action.partner is not None:
        names += [action.partner.held, *action.partner.targets]
    return case_of(action, {name: _category(name, categories) for name in names if name is not None})


def _category(name: str, categories: Mapping[str, Category] | None) -> Category:
    if categories is not None:
        found = categories.get(name, categories.get(class_name(name)))
        if found is not None:
            return found
    return _shipped().categorize(class_name(name).replace("_", " ")) or Category.INGREDIENT


@cache
def _shipped() -> CategoryTable:
    from wecook_core.knowledge.categories import load_categories

    return load_categories()


def report(predicted: Sequence[TreeSpan], truth: Sequence[TreeSpan], *, instances: bool = False,
           categories: Mapping[str, Category] | None = None) -> Report:
    """Scores, missed and spurious trees, and counts per case (see :class:`Report`)."""
    pred = [p for p in predicted if has_action(p.tree)]
    true = [t for t in truth if has_action(t.tree)]
    pairs = _pairs(_counted(pred, instances), _counted(true, instances))
    hit_pred = {i for i, _ in pairs}
    hit_true = {j for _, j in pairs}
    pred_cases = [case_name(p, categories) for p in pred]
    true_cases = [case_name(t, categories) for t in true]
    return Report(
        scores=evaluate(predicted, truth, instances=instances),
        missed=tuple(t for j, t in enumerate(true) if j not in hit_true),
        spurious=tuple(p for i, p in enumerate(pred) if i not in hit_pred),
        predicted=dict(Counter(pred_cases)),
        truth=dict(Counter(true_cases)),
        correct=dict(Counter(true_cases[j] for _, j in pairs)),
    )


def loose(predicted: Sequence[TreeSpan], truth: Sequence[TreeSpan], *, instances: bool = False,
          ) -> dict[str, Scores]:
    """The scores under each of :data:`LOOSE_VIEWS`, by name (the strict score is :func:`evaluate`'s)."""
    return {name: evaluate(predicted, truth, instances=instances, view=view) for name, view in LOOSE_VIEWS.items()}
