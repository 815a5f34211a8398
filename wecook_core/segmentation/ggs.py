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

Speed: all split points of a segment are scored at once from prefix sums of ``x`` and ``x xᵀ`` (closed-form
determinants and inverse traces for 1 to 3 features, batched LAPACK beyond), and the best split of every
``[start, end)`` range is cached: the greedy step and the adjustment passes ask for the same ranges many times.
"""

from __future__ import annotations

import heapq
import itertools
import random
import threading
import time

import numpy as np

from wecook_core.model import GGSResult

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
    breakpoint in :func:`~wecook_core.segmentation.choose.choose_k`: saves time when ``k_max`` is generous).

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

    scorer = _SplitScorer(x, lamb, reference_quirk)
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
    return _SplitScorer(x, lamb, False).objective([0, *breakpoints, x.shape[0]])


def refine_breakpoints(data: np.ndarray, breakpoints: tuple[int, ...], lamb: float, radius: int) -> tuple[int, ...]:
    """Move each breakpoint, within ``± radius`` samples of where it is, to its best place between its
    neighbours (the objective of :func:`ggs`), until none moves: used after segmenting a decimated series, to
    place the breakpoints at full resolution. Keeps every segment at least 2 samples long."""
    x = np.asarray(data, dtype=np.float64)
    if x.ndim == 1:
        x = x[:, None]
    scorer = _SplitScorer(x, lamb, False)
    bp = [0, *breakpoints, x.shape[0]]
    origin = list(bp)
    for _ in range(MAX_SHUFFLES):
        moved = False
        for i in range(1, len(bp) - 1):
            lo, hi = max(bp[i - 1] + 2, origin[i] - radius), min(bp[i + 1] - 2, origin[i] + radius)
            if lo > hi:
                continue
            at = scorer.best_cut_within(bp[i - 1], bp[i + 1], lo, hi)
            if at != bp[i]:
                bp[i], moved = at, True
        if not moved:
            break
    return tuple(bp[1:-1])


def _adjust(breaks: list[int], new: int, scorer: _SplitScorer) -> list[int]:
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
    this_pass = [False] * (count + 2)  # by index: a breakpoint keeps its index when it moves
    this_pass[bp.index(new)] = True
    for z in range(MAX_SHUFFLES):
        last_pass, this_pass = this_pass, [False] * (count + 2)
        order, position = _pass_order(count, z)
        due = [position[i] for i in range(1, count + 1) if last_pass[i - 1] or last_pass[i + 1]]
        heapq.heapify(due)
        visited: set[int] = set()
        moved_any = False
        while due:
            turn = heapq.heappop(due)
            i = order[turn]
            if i in visited:
                continue
            visited.add(i)
            at, gain = scorer.best_split(bp[i - 1], bp[i + 1])
            if at != bp[i] and gain != 0:
                bp[i] = at
                this_pass[i] = moved_any = True
                for neighbour in (i - 1, i + 1):  # due later in this pass, now that i moved
                    if 1 <= neighbour <= count and position[neighbour] > turn:
                        heapq.heappush(due, position[neighbour])
        if not moved_any:
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
            rng.shuffle(order)
            position = [0] * (count + 2)
            for turn, i in enumerate(order):
                position[i] = turn
            orders.append((order, position))
        return orders[z]


class _SplitScorer:
    """Segment costs and best splits of one series, from prefix sums; caches the best split per range.

    Prefix sums are stored feature-major: ``s1[j, t]`` sums feature ``j`` of samples ``[0, t)`` (centred on
    the series mean: less cancellation), ``s2[p, t]`` the products of the ``p``-th pair of features (upper
    triangle of ``x xᵀ``). A segment's split candidates are then contiguous slices.
    """

    def __init__(self, x: np.ndarray, lamb: float, quirk: bool) -> None:
        m, n = x.shape
        self.n = n
        self.lamb = float(lamb)
        self.raw = x
        self.center = x.mean(axis=0)
        xc = (x - self.center).T
        self.pairs = [(i, j) for i in range(n) for j in range(i, n)]
        self.s1 = np.zeros((n, m + 1))
        np.cumsum(xc, axis=1, out=self.s1[:, 1:])
        self.s2 = np.zeros((len(self.pairs), m + 1))
        np.cumsum(np.stack([xc[i] * xc[j] for i, j in self.pairs]), axis=1, out=self.s2[:, 1:])
        self.counts = np.arange(m + 1, dtype=np.float64)
        self.quirk = quirk and n > 1
        self.cache: dict[tuple[int, int], tuple[int, float]] = {}

    def cost(self, count: np.ndarray, sums: np.ndarray, squares: np.ndarray) -> np.ndarray:
        """``c log det Σ - λ tr Σ⁻¹`` per segment, from its sample count ``c`` ``(k,)``, sums of x ``(n, k)``
        and sums of the feature pairs' products ``(pairs, k)`` (centred data)."""
        inv = 1.0 / count
        mean = sums * inv
        cov = squares * inv
        for p, (i, j) in enumerate(self.pairs):
            cov[p] -= mean[i] * mean[j]
        return self._cost_of_cov(count, inv, cov)

    def _cost_of_cov(self, count: np.ndarray, inv: np.ndarray, cov: np.ndarray) -> np.ndarray:
        n, lamb = self.n, self.lamb
        reg = lamb * inv
        if n == 1:
            det = cov[0] + reg
            trace_inv = 1.0 / det
        elif n == 2:
            a, b, d = cov[0] + reg, cov[1], cov[2] + reg
            det = a * d - b * b
            trace_inv = (a + d) / det
        elif n == 3:
            a, b, c, d, e, f = cov[0] + reg, cov[1], cov[2], cov[3] + reg, cov[4], cov[5] + reg
            minor_a, minor_d, minor_f = d * f - e * e, a * f - c * c, a * d - b * b
            det = a * minor_a - b * (b * f - c * e) + c * (b * e - c * d)
            trace_inv = (minor_a + minor_d + minor_f) / det
        else:
            sigma = np.empty((len(count), n, n))
            for p, (i, j) in enumerate(self.pairs):
                sigma[:, i, j] = sigma[:, j, i] = cov[p]
            sigma += reg[:, None, None] * np.eye(n)
            sign, logdet = np.linalg.slogdet(sigma)
            trace_inv = np.trace(np.linalg.inv(sigma), axis1=1, axis2=2)
            return np.where(sign > 0, count * logdet - lamb * trace_inv, np.inf)
        if np.all(det > 0):
            return count * np.log(det) - lamb * trace_inv
        with np.errstate(divide="ignore", invalid="ignore"):  # only from rounding when λ is tiny
            return np.where(det > 0, count * np.log(det) - lamb * trace_inv, np.inf)

    def segment_costs(self, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
        """Cost of each segment ``[starts[i], ends[i])``."""
        return self.cost(self.counts[ends - starts], self.s1[:, ends] - self.s1[:, starts],
                         self.s2[:, ends] - self.s2[:, starts])

    def objective(self, breaks: list[int]) -> float:
        edges = np.asarray(breaks)
        return -float(self.segment_costs(edges[:-1], edges[1:]).sum())

    def best_split(self, start: int, end: int) -> tuple[int, float]:
        """Best place to cut ``[start, end)`` (both parts >= 2 samples) and the change of the segments'
        cost (negative = better); ``(start, 0.0)`` when no cut improves."""
        key = (start, end)
        if key in self.cache:
            return self.cache[key]
        result = (start, 0.0)
        if end - start >= 4:
            total, whole = self._split_costs(start, end, start + 2, end - 2)
            best = int(np.argmin(total))  # first of equal minima, like the reference's strict `<`
            if total[best] < whole:
                result = (start + 2 + best, float(total[best] - whole))
        self.cache[key] = result
        return result

    def best_cut_within(self, start: int, end: int, lo: int, hi: int) -> int:
        """The cut ``t`` in ``[lo, hi]`` minimising the cost of ``[start, t)`` plus ``[t, end)`` (first on ties)."""
        total, _ = self._split_costs(start, end, lo, hi)
        return lo + int(np.argmin(total))

    def _split_costs(self, start: int, end: int, lo: int, hi: int) -> tuple[np.ndarray, float]:
        """Cost of ``[start, t)`` plus ``[t, end)`` for every cut ``t`` in ``[lo, hi]``, and of ``[start, end)``.

        One batched evaluation: rows ``[0, k)`` are the left parts, row ``k`` the whole segment, rows
        ``k + 1 ..`` the right parts."""
        k = hi - lo + 1
        s1, s2 = self.s1, self.s2
        sums = np.empty((self.n, 2 * k + 1))
        squares = np.empty((len(self.pairs), 2 * k + 1))
        np.subtract(s1[:, lo : hi + 1], s1[:, start : start + 1], out=sums[:, :k])
        np.subtract(s2[:, lo : hi + 1], s2[:, start : start + 1], out=squares[:, :k])
        sums[:, k] = s1[:, end] - s1[:, start]
        squares[:, k] = s2[:, end] - s2[:, start]
        np.subtract(s1[:, end : end + 1], s1[:, lo : hi + 1], out=sums[:, k + 1 :])
        np.subtract(s2[:, end : end + 1], s2[:, lo : hi + 1], out=squares[:, k + 1 :])
        left_n = self.counts[lo - start : hi - start + 1]
        count = np.concatenate([left_n, self.counts[end - start : end - start + 1], (end - start) - left_n])
        costs = self._quirk_costs(start, k, count, sums, squares) if self.quirk else self.cost(count, sums, squares)
        return costs[:k] + costs[k + 1 :], float(costs[k])

    def _quirk_costs(self, start: int, k: int, count: np.ndarray, sums: np.ndarray, squares: np.ndarray) -> np.ndarray:
        """Costs as the reference scores split points: each left part's mean biased by
        ``-x_start (1 - 1/n) / count`` (its running mean starts from ``x_start / n``)."""
        inv = 1.0 / count
        mean = sums * inv
        raw_mean = mean + self.center[:, None]
        bias = np.zeros_like(mean)
        bias[:, :k] = self.raw[start][:, None] * (1 - 1 / self.n) * inv[:k]
        cov = squares * inv
        for p, (i, j) in enumerate(self.pairs):
            cov[p] += -mean[i] * mean[j] + raw_mean[i] * bias[j] + bias[i] * raw_mean[j] - bias[i] * bias[j]
        return self._cost_of_cov(count, inv, cov)
