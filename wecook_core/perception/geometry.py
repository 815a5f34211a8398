"""Box geometry, one place for it: boxes are ``x1 y1 x2 y2`` pixels in arrays ``(..., 4)``, NaN where absent.

Sizes are box diagonals (:func:`box_diagonal`), and lengths in :class:`~wecook_core.perception.params.Params`
are fractions of a box's or of the image's diagonal (:func:`video_diagonal`), so a close-up and a wide shot are
judged alike."""

from __future__ import annotations

import numpy as np

from wecook_core.model import Observations


def box_diagonal(boxes: np.ndarray) -> np.ndarray:
    """Diagonals ``(...)`` of boxes ``(..., 4)`` (NaN where absent)."""
    return np.hypot(boxes[..., 2] - boxes[..., 0], boxes[..., 3] - boxes[..., 1])


def box_area(boxes: np.ndarray) -> np.ndarray:
    return np.clip(boxes[..., 2] - boxes[..., 0], 0, None) * np.clip(boxes[..., 3] - boxes[..., 1], 0, None)


def box_intersection(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Intersection areas of broadcast box arrays ``a[..., 4]`` and ``b[..., 4]`` (NaN where either is absent)."""
    width = np.minimum(a[..., 2], b[..., 2]) - np.maximum(a[..., 0], b[..., 0])
    height = np.minimum(a[..., 3], b[..., 3]) - np.maximum(a[..., 1], b[..., 1])
    return np.clip(width, 0, None) * np.clip(height, 0, None)


def box_gap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance between two boxes' closest points (0 when they overlap); NaN where absent."""
    dx = np.clip(np.maximum(a[..., 0], b[..., 0]) - np.minimum(a[..., 2], b[..., 2]), 0, None)
    dy = np.clip(np.maximum(a[..., 1], b[..., 1]) - np.minimum(a[..., 3], b[..., 3]), 0, None)
    return np.hypot(dx, dy)


def video_diagonal(obs: Observations) -> float:
    """Image diagonal in pixels (from the video's size, else from the boxes' extent)."""
    if obs.video.width > 0 and obs.video.height > 0:
        return float(np.hypot(obs.video.width, obs.video.height))
    width, height = 1.0, 1.0
    for boxes in [t.boxes for t in obs.objects] + [t.boxes for t in obs.hands]:
        if len(boxes):
            width = max(width, float(np.max(boxes[:, 2])))
            height = max(height, float(np.max(boxes[:, 3])))
    return float(np.hypot(width, height))


def box_centres(boxes: np.ndarray) -> np.ndarray:
    """Centres ``(..., 2)`` of boxes ``(..., 4)`` given as x1, y1, x2, y2."""
    return np.stack([(boxes[..., 0] + boxes[..., 2]) / 2, (boxes[..., 1] + boxes[..., 3]) / 2], axis=-1)
