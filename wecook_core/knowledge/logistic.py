"""Multinomial logistic regression over binary features, for the role-aware ensemble.

Naive Bayes (:mod:`wecook_core.knowledge.relations`) multiplies each feature's likelihood as if the features
were independent; they are not (a pair feature repeats its two singles, a class repeats its object). A
discriminative model weighs them jointly. Here the softmax of ``x W + b`` over the verbs, ``x`` the binary
features of a record, fitted by L-BFGS (:func:`scipy.optimize.minimize`) from zero weights (deterministic:
no random start) on the L2-penalised, class-weighted log loss: a record of verb ``A`` weighs
``(n / (|verbs| n_A)) ** balance`` (``balance`` 0: every record alike, 1: every verb alike).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.optimize
import scipy.sparse

LAMBDA = 1e-4
"""L2 penalty per weight (the loss is a mean over records)."""
BALANCE = 0.5
ITERATIONS = 300


@dataclass(frozen=True, eq=False)
class LogisticModel:
    """Weights per feature and verb (``(len(index), len(verbs))``) and a bias per verb."""

    verbs: tuple[str, ...]
    index: Mapping[str, int]
    """Feature -> row of :attr:`weights`."""
    weights: np.ndarray
    bias: np.ndarray

    def log_posterior(self, found: Iterable[str]) -> np.ndarray:
        """Log P(A | features) of one record's features (unknown ones ignored)."""
        rows = [r for f in found if (r := self.index.get(f)) is not None]
        scores = self.bias + (self.weights[rows].sum(axis=0) if rows else 0.0)
        return _log_softmax(scores[None, :])[0]

    def log_posteriors(self, records: Sequence[Iterable[str]]) -> np.ndarray:
        """``(len(records), len(verbs))`` log posteriors."""
        matrix = design(records, self.index)
        return _log_softmax(np.asarray(matrix @ self.weights) + self.bias)


def _log_softmax(scores: np.ndarray) -> np.ndarray:
    shifted = scores - scores.max(axis=1, keepdims=True)
    result: np.ndarray = shifted - np.log(np.exp(shifted).sum(axis=1, keepdims=True))
    return result


def design(records: Sequence[Iterable[str]], index: Mapping[str, int]) -> scipy.sparse.csr_matrix:
    """The binary ``(len(records), len(index))`` matrix of the records' known features."""
    rows: list[int] = []
    columns: list[int] = []
    for i, found in enumerate(records):
        for column in sorted({c for f in found if (c := index.get(f)) is not None}):
            rows.append(i)
            columns.append(column)
    return scipy.sparse.csr_matrix((np.ones(len(rows)), (rows, columns)), shape=(len(records), len(index)))


def fit_logistic(records: Sequence[Iterable[str]], labels: Sequence[int], verbs: Sequence[str], *,
                 penalty: float = LAMBDA, balance: float = BALANCE,
                 iterations: int = ITERATIONS) -> LogisticModel:
    """The model of records' features and their verbs (indices into ``verbs``), see the module docstring."""
    index: dict[str, int] = {}
    for found in records:
        for f in found:
            index.setdefault(f, len(index))
    matrix = design(records, index)
    transposed = matrix.T.tocsr()
    y = np.asarray(labels, dtype=np.int64)
    n, d, v = len(y), len(index), len(verbs)
    counts = np.bincount(y, minlength=v).astype(np.float64)
    weight = ((n / (v * np.maximum(counts, 1.0))) ** balance)[y]
    weight = weight / weight.mean() / max(n, 1)
    onehot = np.zeros((n, v))
    onehot[np.arange(n), y] = 1.0

    def loss(theta: np.ndarray) -> tuple[float, np.ndarray]:
        w = theta[:d * v].reshape(d, v)
        logp = _log_softmax(np.asarray(matrix @ w) + theta[d * v:])
        value = -float((weight * logp[np.arange(n), y]).sum()) + penalty / 2 * float((w * w).sum())
        residual = (np.exp(logp) - onehot) * weight[:, None]
        grad_w = np.asarray(transposed @ residual) + penalty * w
        return value, np.concatenate([grad_w.ravel(), residual.sum(axis=0)])

    result = scipy.optimize.minimize(loss, np.zeros(d * v + v), jac=True, method="L-BFGS-B",
                                     options={"maxiter": iterations})
    return LogisticModel(tuple(verbs), index, result.x[:d * v].reshape(d, v), result.x[d * v:])
