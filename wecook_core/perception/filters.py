"""The running median over time, shared by the segmentation's hand series and the boxes' smoothing (R0)."""

from __future__ import annotations

import numpy as np


def _median3(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    return np.maximum(np.minimum(x, y), np.minimum(np.maximum(x, y), z))


def running_median(series: np.ndarray, window: int) -> np.ndarray:
    """Median of each sample's ``window`` (odd) neighbours along axis 0, the ends padded with the end values.

    Equal to ``np.median`` over the sliding windows, value for value: windows of three and five by min/max
    networks (the median of five is the median of the middle value, the larger of the two pairs' minima and the
    smaller of their maxima), a few NumPy calls; longer ones by a partial sort."""
    half = window // 2
    if half == 0 or len(series) == 0:
        return series
    padded = np.concatenate([np.repeat(series[:1], half, axis=0), series, np.repeat(series[-1:], half, axis=0)])
    n = len(series)
    rows = [padded[i : i + n] for i in range(2 * half + 1)]
    if half == 1:
        return _median3(*rows)
    if half == 2:
        a, b, c, d, e = rows
        return _median3(c, np.maximum(np.minimum(a, b), np.minimum(d, e)), np.minimum(np.maximum(a, b),
                                                                                    np.maximum(d, e)))
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1, axis=0)
    return np.partition(windows, half, axis=-1)[..., half]
