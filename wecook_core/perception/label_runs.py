"""Runs in per-frame label arrays (one object index per frame, :data:`NONE` for none): the runs, the longest,
those long enough to count, the label that dominates."""

from __future__ import annotations

import numpy as np

NONE = -1
"""Index meaning "no object" in the per-frame label arrays."""


def longest_runs(mask: np.ndarray) -> np.ndarray:
    """Longest run of consecutive True along axis 0 of a boolean ``(frames, k...)`` array, per column."""
    if mask.shape[0] == 0:
        return np.zeros(mask.shape[1:], dtype=np.int64)
    flat = mask.reshape(mask.shape[0], -1).astype(np.int8)
    padded = np.zeros((flat.shape[0] + 2, flat.shape[1]), dtype=np.int8)
    padded[1:-1] = flat
    change = np.diff(padded, axis=0)
    out = np.zeros(flat.shape[1], dtype=np.int64)
    columns_start, rows_start = np.nonzero(change.T == 1)
    _, rows_end = np.nonzero(change.T == -1)
    if len(rows_start):
        np.maximum.at(out, columns_start, rows_end - rows_start)
    return out.reshape(mask.shape[1:])


def runs(labels: np.ndarray) -> list[tuple[int, int, int]]:
    """``(start, end, value)`` runs of equal values of a 1-D label array (rows, end exclusive)."""
    if len(labels) == 0:
        return []
    cuts = np.flatnonzero(np.diff(labels)) + 1
    starts = np.concatenate([[0], cuts])
    ends = np.concatenate([cuts, [len(labels)]])
    return [(int(s), int(e), int(labels[s])) for s, e in zip(starts, ends, strict=True)]


def kept_runs(labels: np.ndarray, min_frames: int) -> list[tuple[int, int, int]]:
    """Runs of a label array that name an object and last at least ``min_frames`` rows."""
    return [r for r in runs(labels) if r[2] != NONE and r[1] - r[0] >= min_frames]


def dominant(labels: np.ndarray, min_frames: int) -> int:
    """The label with the most rows in kept runs (ties: the earliest), :data:`NONE` if no run is kept."""
    if len(labels) and labels[0] == labels[-1] and (labels == labels[0]).all():  # the common case, fast
        return int(labels[0]) if len(labels) >= min_frames else NONE
    totals: dict[int, int] = {}
    for start, end, value in kept_runs(labels, min_frames):
        totals[value] = totals.get(value, 0) + end - start
    if not totals:
        return NONE
    return max(totals, key=lambda value: totals[value])
