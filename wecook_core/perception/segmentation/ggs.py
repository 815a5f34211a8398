"""Greedy Gaussian Segmentation (Hallac, Nystrup, Boyd, "Greedy Gaussian segmentation of multivariate time
series", 2019).

A series ``x_0 .. x_{m-1}`` (rows = samples, columns = features) is cut into segments; each segment of
``c`` samples is modelled as a Gaussian with its empirical mean and the regularised covariance
``Σ = S + (λ / c) I`` (``S`` the biased empirical covariance). The objective maximised is

    objective = Σ_segments [ -c log det Σ + λ tr(Σ⁻¹) ]

which is the reference code's (cvxgrp/GGS) "covariance-regularised log-likelihood", up to constants.
Breakpoints are added one at a time, each where it raises the objective most (over all current segments);
after every addition each breakpoint is moved to its best place between its two neighbours, in the
reference's random order (Python ``random`` seeded with 0), until nothing moves.

Speed: all split points of a segment are scored at once (:class:`.scorer.SplitScorer`),
the best split of every ``[start, end)`` range is cached (the greedy step and the adjustment passes ask for the
same ranges many times), a heap holds every segment's best split, and an adjustment pass visits only the
breakpoints whose neighbours moved.
"""

from __future__ import annotations

import heapq
import itertools
import random
import threading
import time

import numpy as np

from wecook_core.model import GGSResult
from wecook_core.perception.segmentation.scorer import SplitScorer

MAX_SHUFFLES = 250
"""Adjustment passes per added breakpoint at most (the reference's ``maxShuffles``)."""


def ggs(
    data: np.ndarray,
    k_max: int,
    lamb: float,
    *,
    min_gain: float | None = None,
    patience: int = 3,
    reference_quirk: bool = False,
) -> GGSResult:
    """Segment ``data`` (``(m,)`` or ``(m, n)``, rows = samples) with 0..``k_max`` interior breakpoints.

    ``lamb`` (> 0) is the covariance regularisation λ, in squared units of the data. Stops early (fewer
    entries in the result) when no split of any segment raises the objective, or, given ``min_gain``, once
    ``patience`` breakpoints in a row each raised the objective by less than ``min_gain`` (the price of a
    breakpoint in :func:`~wecook_core.perception.segmentation.choose.choose_k`: saves time when ``k_max`` is generous).

    ``reference_quirk`` reproduces a slip of the reference code: when it scores split points its running
    left-segment mean starts from ``x_0 / n`` instead of ``x_0``. That only matters for ``n > 1``; it exists
    to check this implementation sample-for-sample against the reference's answers.
    """
    started = time.perf_counter()
    x = np.asarray(data, dtype=np.float64)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] == 0 or x.shape[1] == 0:
        raise ValueError(f"ggs needs a non-empty (samples, features) array, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("ggs needs finite data")
    if lamb <= 0:
        raise ValueError(f"lamb must be > 0, got {lamb}")
    if k_max < 0:
        raise ValueError(f"k_max must be >= 0, got {k_max}")

    scorer = SplitScorer(x, lamb, reference_quirk)
    m = x.shape[0]
    breaks = [0, m]
    breakpoints_by_k: list[tuple[int, ...]] = [()]
    objective_by_k = [scorer.objective(breaks)]
    # best split of every current segment, smallest gain (= largest rise) first, then earliest segment:
    # the reference's choice; entries of segments that no longer exist are skipped when they surface
    candidates: list[tuple[float, int, int, int]] = []
    current: set[tuple[int, int]] = set()
    for _ in range(k_max):
        for segment in set(itertools.pairwise(breaks)) - current:
            at, gain = scorer.best_split(*segment)
            heapq.heappush(candidates, (gain, *segment, at))
        current = set(itertools.pairwise(breaks))
        while (candidates[0][1], candidates[0][2]) not in current:
            heapq.heappop(candidates)
        best_gain, _, _, best_at = candidates[0]
        if best_gain == 0:
            break
        breaks = _adjust(sorted([*breaks, best_at]), best_at, scorer)
        breakpoints_by_k.append(tuple(breaks[1:-1]))
        objective_by_k.append(scorer.objective(breaks))
        if min_gain is not None and len(objective_by_k) > patience:
            gains = np.diff(objective_by_k[-patience - 1 :])
            if np.all(gains < min_gain):
                break
    return GGSResult(
        breakpoints_by_k=tuple(breakpoints_by_k),
        objective_by_k=tuple(objective_by_k),
        seconds=time.perf_counter() - started,
    )


def segment_objective(data: np.ndarray, breakpoints: tuple[int, ...] | list[int], lamb: float) -> float:
    """The GGS objective of ``data`` cut at the given interior ``breakpoints`` (sorted sample indices)."""
    x = np.asarray(data, dtype=np.float64)
    if x.ndim == 1:
        x = x[:, None]
    return SplitScorer(x, lamb, False).objective([0, *breakpoints, x.shape[0]])


def refine_breakpoints(data: np.ndarray, breakpoints: tuple[int, ...], lamb: float, radius: int) -> tuple[int, ...]:
    """Move each breakpoint, within ``± radius`` samples of where it is, to its best place between its
    neighbours (the objective of :func:`ggs`), until none moves: used after segmenting a decimated series, to
    place the breakpoints at full resolution. Keeps every segment at least 2 samples long.

    Coordinate ascent in two alternating half-passes (odd-numbered breakpoints, then even-numbered ones), each
    a single batched evaluation: within a half-pass no breakpoint is the neighbour of another."""
    x = np.asarray(data, dtype=np.float64)
    if x.ndim == 1:
        x = x[:, None]
    scorer = SplitScorer(x, lamb, False)
    bp = np.array([0, *breakpoints, x.shape[0]], dtype=np.int64)
    origin = bp.copy()
    count = len(bp) - 2
    for _ in range(MAX_SHUFFLES):
        moved = False
        for first in (1, 2):
            index = np.arange(first, count + 1, 2)
            lo = np.maximum(bp[index - 1] + 2, origin[index] - radius)
            hi = np.minimum(bp[index + 1] - 2, origin[index] + radius)
            index, lo, hi = index[lo <= hi], lo[lo <= hi], hi[lo <= hi]
            if len(index) == 0:
                continue
            best = scorer.best_cuts(bp[index - 1], bp[index + 1], lo, hi)
            if np.any(best != bp[index]):
                bp[index], moved = best, True
        if not moved:
            break
    return tuple(int(b) for b in bp[1:-1])


def _adjust(breaks: list[int], new: int, scorer: SplitScorer) -> list[int]:
    """Move each breakpoint to the best place between its neighbours until none moves.

    Follows the reference's schedule exactly (it decides the result when two places score the same):
    passes over the interior breakpoints in an order shuffled by ``random.Random(0)`` (re-seeded for every
    adjustment); a breakpoint is re-placed only if a neighbour moved in the previous pass or earlier in this
    pass. Only those breakpoints are visited, in pass order, so a pass costs what moves, not ``k``.
    """
    bp = list(breaks)
    count = len(bp) - 2
    if count == 1:
        return bp
    moved = [bp.index(new)]  # by index: a breakpoint keeps its index when it moves
    for z in range(MAX_SHUFFLES):
        order, position = _pass_order(count, z)
        due = sorted({position[i] for m in moved for i in (m - 1, m + 1) if 1 <= i <= count})
        moved = []
        visited: set[int] = set()
        while due:
            turn = heapq.heappop(due)
            i = order[turn]
            if i in visited:
                continue
            visited.add(i)
            at, gain = scorer.best_split(bp[i - 1], bp[i + 1])
            if at != bp[i] and gain != 0:
                bp[i] = at
                moved.append(i)
                for neighbour in (i - 1, i + 1):  # due later in this pass, now that i moved
                    if 1 <= neighbour <= count and position[neighbour] > turn:
                        heapq.heappush(due, position[neighbour])
        if not moved:
            break
    return bp


_ORDERS: dict[int, tuple[random.Random, list[tuple[list[int], list[int]]]]] = {}
_ORDERS_LOCK = threading.Lock()


def _pass_order(count: int, z: int) -> tuple[list[int], list[int]]:
    """Visiting order of pass ``z`` when adjusting ``count`` breakpoints (indices 1..count), as the reference's
    ``random.seed(0)`` then one ``random.shuffle`` per pass produce it, and each index's place in it.

    Depends only on ``(count, z)``, so it is computed once per process (shuffling is ``O(count)`` Python
    work per pass: the main cost of the adjustment otherwise)."""
    with _ORDERS_LOCK:
        rng, orders = _ORDERS.setdefault(count, (random.Random(0), []))
        while len(orders) <= z:
            order = list(range(1, count + 1))
            _shuffle(order, rng)
            position = [0] * (count + 2)
            for turn, i in enumerate(order):
                position[i] = turn
            orders.append((order, position))
        return orders[z]


def _shuffle(items: list[int], rng: random.Random) -> None:
    """``rng.shuffle(items)``, the same permutation from the same state, without a method call per item
    (CPython 3.11's ``shuffle`` and ``_randbelow_with_getrandbits``, inlined)."""
    getrandbits = rng.getrandbits
    for i in reversed(range(1, len(items))):
        n = i + 1
        bits = n.bit_length()
        j = getrandbits(bits)
        while j >= n:
            j = getrandbits(bits)
        items[i], items[j] = items[j], items[i]
