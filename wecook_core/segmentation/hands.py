"""Segmenting a video: GGS on each hand's trajectory, then the union of all hands' breakpoints."""

from __future__ import annotations

import itertools
import math
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HandTrack, Observations, Segment, Segmentation
from wecook_core.segmentation.choose import breakpoint_penalty, choose_k
from wecook_core.segmentation.ggs import ggs, refine_breakpoints

if TYPE_CHECKING:  # pipeline imports the stages: no import cycle at run time
    from wecook_core.pipeline import Params

SAMPLE_HZ = 10.0
"""GGS runs on each trajectory sampled at about this rate (every ``round(fps / SAMPLE_HZ)``-th frame), then
the chosen breakpoints are placed at full frame rate. Hand phases last half a second or more, so 10 Hz loses
nothing, and it keeps GGS fast and its results independent of the video's frame rate."""


def hand_series(track: HandTrack, frame_count: int, width: float, height: float) -> tuple[np.ndarray, int]:
    """The hand's centre for every frame of ``[0, frame_count)``, scaled to the unit square.

    Returns ``(xy, interpolated)``: float64 ``(frame_count, 2)`` with x divided by ``width`` and y by
    ``height`` (pixels; the series' own extent when the video size is unknown), and the number of frames
    filled in: linearly between detections, held constant before the first and after the last one.
    Detections outside ``[0, frame_count)`` are ignored. The track must have at least one detection there.
    """
    inside = (track.frames >= 0) & (track.frames < frame_count)
    frames = track.frames[inside]
    xy = track.xy[inside]
    if len(frames) == 0:
        raise ValueError(f"hand {track.hand} has no detection in [0, {frame_count})")
    every = np.arange(frame_count)
    series = np.stack([np.interp(every, frames, xy[:, 0]), np.interp(every, frames, xy[:, 1])], axis=1)
    scale = np.array([width, height], dtype=np.float64)
    if not np.all(scale > 0):
        extent = float(np.ptp(series, axis=0).max())
        scale = np.array([extent, extent]) if extent > 0 else np.ones(2)
    return series / scale, frame_count - len(frames)


def segment_hands(obs: Observations, params: Params, *, sample_hz: float = SAMPLE_HZ) -> Segmentation:
    """Cut the video ``[0, obs.video.frame_count)`` into segments from the hands' trajectories.

    For each hand track: its trajectory over all frames (gaps interpolated, see :func:`hand_series`) is
    segmented by :func:`ggs` with ``params.lamb`` and ``params.k_max`` on a ~``sample_hz`` sampling; the number
    of breakpoints is ``params.k[hand]`` when given (clipped to what GGS found), else :func:`choose_k` (BIC);
    the breakpoints are then placed at full frame rate. A track with no detection contributes no
    breakpoints (``per_hand[hand] == ()``, no ``interpolated`` entry). ``segments`` cut ``[0, frame_count)``
    at the union of every hand's breakpoints.
    """
    video = obs.video
    frame_count = int(video.frame_count)
    step = max(1, round(video.fps / sample_hz)) if video.fps > 0 and sample_hz > 0 else 1
    per_hand: dict[str, tuple[int, ...]] = {}
    interpolated: dict[str, int] = {}
    for track in obs.hands:
        inside = (track.frames >= 0) & (track.frames < frame_count)
        if not np.any(inside):
            per_hand[track.hand] = ()
            continue
        series, filled = hand_series(track, frame_count, video.width, video.height)
        interpolated[track.hand] = filled
        per_hand[track.hand] = _segment_series(series, params, step, params.k.get(track.hand))
    cuts = sorted({b for breaks in per_hand.values() for b in breaks if 0 < b < frame_count})
    edges = [0, *cuts, frame_count]
    segments = tuple(Segment(a, b) for a, b in itertools.pairwise(edges)) if frame_count > 0 else ()
    return Segmentation(per_hand=per_hand, segments=segments, interpolated=interpolated)


def _segment_series(series: np.ndarray, params: Params, step: int, forced_k: int | None) -> tuple[int, ...]:
    """Breakpoints (frames) of one hand's full-rate series: GGS every ``step``-th frame, then refinement."""
    sampled = series[::step]
    if len(sampled) < 4:
        return ()
    # λ / step keeps the covariance floor λ / count of a span of frames the same as at full rate
    lamb = params.lamb / step
    if forced_k is not None:
        result = ggs(sampled, max(forced_k, 0), lamb)
        k = len(result.breakpoints_by_k) - 1
    else:
        price = breakpoint_penalty(len(sampled), sampled.shape[1])
        result = ggs(sampled, params.k_max, lamb, min_gain=price)
        k = choose_k(result, samples=len(sampled), features=sampled.shape[1])
    coarse = tuple(b * step for b in result.breakpoints_by_k[k])
    if step == 1 or not coarse:
        return coarse
    return refine_breakpoints(series, coarse, params.lamb, radius=math.ceil(1.5 * step))
