"""Boxes with the detector's frame-to-frame noise taken out, before any motion is read from them (R0).

Every motion cue of the pipeline compares a box's position a few tenths of a second apart (a hand carries what
moves with it, an object moving with no hand near is held by one the detector missed). A detector's or a
tracker's boxes jitter from frame to frame by a few pixels, independently on every frame; read as motion, that
noise makes a still onion "move by itself" and a still hand "move over" what it rests on. Real motion lasts
longer than a frame or two. So each track's boxes (and a hand's centre) are replaced by their running median over
``Params.smooth_s``, within runs of consecutive frames (never across a gap in the track): the standard filter for
impulsive and frame-independent noise, which keeps steps (a grasp, a cut) where a mean would blur them.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from wecook_core.model import Observations
from wecook_core.perception.filters import running_median


def _median_runs(frames: np.ndarray, values: np.ndarray, half: int) -> np.ndarray:
    """``values`` (rows by ``frames``) median-filtered over ``2 half + 1`` rows within each run of consecutive
    frames (runs shorter than three frames as they are), the ends padded with the run's end values, as the
    segmentation's hand series are (:func:`~wecook_core.perception.filters.running_median`)."""
    out = values.astype(np.float64, copy=True)
    if half <= 0 or len(frames) < 3:
        return out
    breaks = np.flatnonzero(np.diff(frames) != 1) + 1
    for start, end in zip(np.concatenate([[0], breaks]), np.concatenate([breaks, [len(frames)]]), strict=True):
        if end - start >= 3:
            out[start:end] = running_median(out[start:end], 2 * half + 1)
    return out


def smoothed(obs: Observations, half: int) -> Observations:
    """``obs`` with every object's and hand's boxes (and the hands' centres) median-filtered over ``2 half + 1``
    frames (module docstring); ``obs`` itself when ``half`` is 0."""
    if half <= 0:
        return obs
    objects = tuple(replace(t, boxes=_median_runs(t.frames, t.boxes, half)) for t in obs.objects)
    hands = tuple(replace(t, boxes=_median_runs(t.frames, t.boxes, half), xy=_median_runs(t.frames, t.xy, half))
                  for t in obs.hands)
    return replace(obs, objects=objects, hands=hands)
