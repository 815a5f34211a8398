"""Tree precision and recall (DESIGN.md, Evaluation).

A predicted tree is correct when it equals a ground-truth tree (structure, hands, actions, objects) and their
frame ranges overlap. Only trees that contain an action or a collaboration count; each ground-truth tree is
matched at most once.
"""

from __future__ import annotations

from collections.abc import Sequence

from wecook_core.model import Scores, TreeSpan
from wecook_core.trees.notation import has_action


def _overlap(a: TreeSpan, b: TreeSpan) -> int:
    return min(a.end, b.end) - max(a.start, b.start)


def match(predicted: Sequence[TreeSpan], truth: Sequence[TreeSpan]) -> list[tuple[TreeSpan, TreeSpan]]:
    """Correct (predicted, truth) pairs. Pairs are taken by largest frame overlap first, so one long
    prediction cannot take a ground-truth tree that a better-aligned prediction of the same tree covers."""
    pred = [p for p in predicted if has_action(p.tree)]
    true = [t for t in truth if has_action(t.tree)]
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
        pairs.append((pred[i], true[j]))
    return pairs


def evaluate(predicted: Sequence[TreeSpan], truth: Sequence[TreeSpan]) -> Scores:
    n_pred = sum(1 for p in predicted if has_action(p.tree))
    n_true = sum(1 for t in truth if has_action(t.tree))
    correct = len(match(predicted, truth))
    return Scores(
        precision=correct / n_pred if n_pred else 0.0,
        recall=correct / n_true if n_true else 0.0,
        correct=correct,
        predicted=n_pred,
        truth=n_true,
    )
