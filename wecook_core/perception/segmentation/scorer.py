"""Scoring every split point of a segment at once, for Greedy Gaussian Segmentation.

A segment's cost is ``c log det Σ - λ tr Σ⁻¹`` with ``Σ = S + (λ / c) I`` (``S`` the biased empirical
covariance of its ``c`` samples); the GGS objective is minus the sum of the costs. Costs come from prefix sums
of ``x`` and ``x xᵀ``, with closed-form determinants and inverse traces for 1 to 3 features (batched LAPACK
beyond), so scoring all ``c - 3`` split points of a segment is a handful of vector operations.
"""

from __future__ import annotations

import numpy as np


class SplitScorer:
    """Segment costs and best splits of one series, from prefix sums; caches the best split per range.

    ``prefix[f, t]`` sums, over samples ``[0, t)``, the feature ``f`` for ``f < n`` and then the product of
    each pair of features (upper triangle of ``x xᵀ``), all on data centred on the series mean (less
    cancellation). A segment's split candidates are then contiguous slices. ``quirk``: score splits as the
    reference code does (see :func:`~wecook_core.perception.segmentation.ggs.ggs`).
    """

    def __init__(self, x: np.ndarray, lamb: float, quirk: bool) -> None:
        m, n = x.shape
        self.n = n
        self.lamb = float(lamb)
        self.raw = x
        self.center = x.mean(axis=0)
        xc = (x - self.center).T
        self.pairs = [(i, j) for i in range(n) for j in range(i, n)]
        self.prefix = np.zeros((n + len(self.pairs), m + 1))
        np.cumsum(np.concatenate([xc, np.stack([xc[i] * xc[j] for i, j in self.pairs])]), axis=1,
                  out=self.prefix[:, 1:])
        self.counts = np.arange(m + 1, dtype=np.float64)
        self.quirk = quirk and n > 1
        self.cache: dict[tuple[int, int], tuple[int, float]] = {}

    def cost(self, count: np.ndarray, moments: np.ndarray) -> np.ndarray:
        """``c log det Σ - λ tr Σ⁻¹`` per segment, from its sample count ``c`` ``(k,)`` and its sums (rows of
        ``moments``, ``(n + pairs, k)``, laid out like ``prefix``; overwritten)."""
        inv = 1.0 / count
        moments *= inv
        mean, cov = moments[: self.n], moments[self.n :]
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
        return self.cost(self.counts[ends - starts], self.prefix[:, ends] - self.prefix[:, starts])

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

    def _split_costs(self, start: int, end: int, lo: int, hi: int) -> tuple[np.ndarray, float]:
        """Cost of ``[start, t)`` plus ``[t, end)`` for every cut ``t`` in ``[lo, hi]``, and of ``[start, end)``.

        One batched evaluation: columns ``[0, k)`` are the left parts, column ``k`` the whole segment,
        columns ``k + 1 ..`` the right parts."""
        k = hi - lo + 1
        prefix = self.prefix
        moments = np.empty((len(prefix), 2 * k + 1))
        np.subtract(prefix[:, lo : hi + 1], prefix[:, start : start + 1], out=moments[:, :k])
        np.subtract(prefix[:, end : end + 1], prefix[:, start : start + 1], out=moments[:, k : k + 1])
        np.subtract(prefix[:, end : end + 1], prefix[:, lo : hi + 1], out=moments[:, k + 1 :])
        left_n = self.counts[lo - start : hi - start + 1]
        count = np.concatenate([left_n, self.counts[end - start : end - start + 1], (end - start) - left_n])
        costs = self._quirk_costs(start, k, count, moments) if self.quirk else self.cost(count, moments)
        return costs[:k] + costs[k + 1 :], float(costs[k])

    def best_cuts(self, starts: np.ndarray, ends: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """For each row, the cut ``t`` in ``[lo, hi]`` minimising the cost of ``[start, t)`` plus
        ``[t, end)`` (first on ties); all rows in one batched evaluation."""
        rows, width = len(starts), int((hi - lo).max()) + 1
        cuts = np.minimum(lo[:, None] + np.arange(width), hi[:, None])  # (rows, width), padded with hi
        prefix = self.prefix
        left = prefix[:, cuts] - prefix[:, starts][:, :, None]
        right = prefix[:, ends][:, :, None] - prefix[:, cuts]
        moments = np.concatenate([left.reshape(len(prefix), -1), right.reshape(len(prefix), -1)], axis=1)
        count = np.concatenate([(cuts - starts[:, None]).ravel(), (ends[:, None] - cuts).ravel()])
        costs = self.cost(count.astype(np.float64), moments)
        total = costs[: rows * width].reshape(rows, width) + costs[rows * width :].reshape(rows, width)
        return cuts[np.arange(rows), np.argmin(total, axis=1)]

    def _quirk_costs(self, start: int, k: int, count: np.ndarray, moments: np.ndarray) -> np.ndarray:
        """Costs as the reference scores split points: each left part's mean biased by
        ``-x_start (1 - 1/n) / count`` (its running mean starts from ``x_start / n``)."""
        inv = 1.0 / count
        moments *= inv
        mean, cov = moments[: self.n], moments[self.n :]
        raw_mean = mean + self.center[:, None]
        bias = np.zeros_like(mean)
        bias[:, :k] = self.raw[start][:, None] * (1 - 1 / self.n) * inv[:k]
        for p, (i, j) in enumerate(self.pairs):
            cov[p] += -mean[i] * mean[j] + raw_mean[i] * bias[j] + bias[i] * raw_mean[j] - bias[i] * bias[j]
        return self._cost_of_cov(count, inv, cov)
