"""Segmenting a video: GGS on each hand's trajectory, then the union of all hands' breakpoints."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence

import numpy as np

from wecook_core.model import HandTrack, Observations, Segment, Segmentation
from wecook_core.perception.filters import running_median
from wecook_core.perception.params import Params, frames
from wecook_core.perception.segmentation.choose import breakpoint_penalty, choose_k
from wecook_core.perception.segmentation.ggs import ggs, refine_breakpoints

SAMPLE_HZ = 10.0
"""GGS runs on each trajectory sampled at about this rate (every ``round(fps / SAMPLE_HZ)``-th frame), then
the chosen breakpoints are placed at full frame rate. Hand phases last half a second or more, so 10 Hz loses
little, and it makes GGS 3 to 5 times faster at 30 fps and its choices nearly independent of the frame rate."""


GLITCH_FRAMES = 5
"""Frames of the running median over a hand's centre before GGS (or the sampling step if longer): a detector's
wrong detections last one or two frames (a hand found on the other hand, or on a face), which a median over
five removes, while a real phase change lasts far longer. Frames, not seconds: the glitches are the
detector's, one per frame it runs on, whatever the frame rate."""
REFINE_STEPS = 1.5
"""Each breakpoint found on the sampled series is moved to its best frame within this many sampling steps
of where it was found: the sample stands for ``step`` frames, so the true cut lies within about one step of
it, and half a step more covers a cut that the median smoothed across two samples."""


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

    For each hand track:

    1. its centre over all frames, scaled to the unit square, gaps interpolated (:func:`hand_series`);
    2. a running median over 5 frames (or ``step`` if longer; :func:`~wecook_core.perception.filters.running_median`)
       removes the tracker's one- and two-frame jumps;
    3. :func:`ggs` (``params.lamb``, ``params.k_max``) runs on every ``step``-th frame, ``step =
       round(fps / sample_hz)`` (3 at 30 fps), with λ divided by ``step`` so a span of frames keeps the same
       covariance floor; it stops once 3 breakpoints in a row gain less than the BIC price;
    4. the number of breakpoints is ``params.k[hand]`` when given (not capped by ``k_max``; fewer only if no
       split helps), else :func:`choose_k` (BIC);
    5. each breakpoint is moved to its best frame within ``± 1.5 step`` frames at full rate.

    A track with no detection in the video contributes no breakpoints (``per_hand[hand] == ()``, no
    ``interpolated`` entry). ``segments`` cut ``[0, frame_count)`` at the union of every hand's breakpoints.
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
    min_frames = frames(params.min_segment_s, video.fps)  # one rule for every duration (the default rate at fps 0)
    cuts = union_breakpoints(per_hand.values(), frame_count, min_frames)
    edges = [0, *cuts, frame_count]
    segments = tuple(Segment(a, b) for a, b in itertools.pairwise(edges)) if frame_count > 0 else ()
    return Segmentation(per_hand=per_hand, segments=segments, interpolated=interpolated)


def union_breakpoints(breaks: Iterable[Sequence[int]], frame_count: int, min_frames: int) -> list[int]:
    """The interior cuts of the whole video: every hand's breakpoints, no two closer than ``min_frames``.

    Two hands rarely change phase on the same frame; the plain union then cuts a sliver of a frame or two
    between them, a segment no action fits in and no reviewer wants to step through. Cuts that follow each
    other by less than ``min_frames`` form a group, replaced by its median; a group's median that still lands
    within ``min_frames`` of the previous cut is dropped, and so are cuts within ``min_frames`` of the ends.
    Every segment of the result is at least ``min_frames`` long.
    """
    cuts = sorted({b for hand in breaks for b in hand if min_frames <= b <= frame_count - min_frames})
    groups: list[list[int]] = []
    for cut in cuts:
        if groups and cut - groups[-1][-1] < min_frames:
            groups[-1].append(cut)
        else:
            groups.append([cut])
    merged: list[int] = []
    for group in groups:
        cut = int(np.median(group))
        if not merged or cut - merged[-1] >= min_frames:
            merged.append(cut)
    return merged


def _segment_series(series: np.ndarray, params: Params, step: int, forced_k: int | None) -> tuple[int, ...]:
    """Breakpoints (frames) of one hand's full-rate series: GGS on every ``step``-th frame of the
    median-filtered series (sample ``j`` stands for frames ``[j step, (j + 1) step)``), then refinement."""
    smooth = running_median(series, max(GLITCH_FRAMES, step + 1 - step % 2))
    sampled = smooth[step // 2 :: step]
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
    return refine_breakpoints(smooth, coarse, params.lamb, radius=math.ceil(REFINE_STEPS * step))
