"""What a held object's own motion says about the verb: circles are stirring, tipping is pouring.

Commonsense (P(A | objects)) cannot tell a whisk stirring a pot from one poured into it, and it knows
nothing of a spoon whose hand the detector lost. The object's track can: each verb has its actuation pattern
(stirring goes round in circles, sawing and rolling go back and forth, pouring tips the bottle). Two cues are
read from the held object's box over a segment, each robust to box jitter and to the frame rate:

- **turns**: the winding number of the box centre around its own running mean (the signed angle it sweeps,
  over 2 pi), counted only while the centre is farther from the mean than :data:`JITTER_TIMES` times the
  track's own jitter (estimated from its second differences, so a still box jittering in place winds
  nowhere). Circling at least :data:`CIRCLE_TURNS` times, mostly one way round (:data:`ROUND`), is
  stirring; sawing, rolling and shaking reverse and wind back to about zero.
- **tilt**: the ratio between the largest and smallest width-to-height ratio of the box, each a running
  median over :data:`TILT_SMOOTH_S` (jitter out). Tipping a bottle or a glass over a pan by 45 degrees or more
  turns a box twice as tall as wide into one about as wide as tall: a ratio of :data:`TILT_RATIO` or more
  is pouring; shaking salt or dipping bread, which move the box about (**active**: its centre strays from
  its running mean by more than :data:`ACTIVE_FRACTION` of its size on a typical frame), turn it far less.
  Read only for an ingredient held over a container (on a knife's thin box, sawing changes the ratio as
  much: it says nothing there).
- **stroke**: how far the box centre, smoothed over :data:`STROKE_SMOOTH_S` (detector jitter out), strays
  from its running mean over a second, on a typical frame, as a fraction of the box's diagonal. Read for an
  ingredient the bare hand works: peeling pulls strips off with strokes that move the ingredient by a good
  part of its size (:data:`STROKE_FRACTION` or more: peel, wrap); squeezing closes the grip where it is and
  the ingredient stays put (squeeze). Jitter of a few pixels, smoothed, is well under it.

:func:`verbs_of` turns them into the verbs the motion allows (None: the motion does not say), which the
recogniser intersects with the commonsense candidates (never leaving none).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from wecook_core.perception.params import DEFAULT_FPS

Role = Literal["tool", "held", "hand"]
"""What the object whose motion is read does: a held ``tool``; an ingredient ``held`` over a container (poured,
sprinkled, dipped); an ingredient worked by the ``hand`` itself (squeezed, peeled)."""

JITTER_TIMES = 3.0
"""The centre counts as away from its mean (winding) only beyond this many times the track's jitter."""
CIRCLE_TURNS = 1.5
"""Winding at least this many turns is circling (sawing and carrying wind back and forth by up to about one
turn, jitter counted out)."""
ROUND = 0.5
"""Circling also turns one way: the net angle swept is at least this fraction of all the angle swept (a
saw's strokes flip the centre from one side of its mean to the other, sweeping half turns either way)."""
ACTIVE_FRACTION = 0.05
"""A box whose centre strays from its running mean by more than this fraction of its diagonal on a typical
frame is being moved about (shaken, dipped), beyond a detector's jitter of a few pixels."""
TILT_RATIO = 2.0
"""An ingredient's box changing its proportions by at least this factor is tipped: poured."""
TILT_SMOOTH_S = 0.3
"""Seconds of running median over the box's proportions before the tilt is read."""
STROKE_FRACTION = 0.05
"""A hand-worked ingredient whose smoothed centre strays from its running mean by this fraction of its
diagonal or more on a typical frame is stroked (peeled); below, it is gripped in place (squeezed). Half a
typical peeling stroke, twice what a box's jitter leaves after smoothing."""
STROKE_SMOOTH_S = 0.2
"""Seconds of running mean over the centre before the stroke is read (box jitter out, strokes kept)."""
DRIFT_S = 0.5
"""Half-width, in seconds, of the running mean taken as a stroke's drifting centre (about a second in all: a
stir goes round at least once a second, the pot it is in does not wander that fast)."""
MIN_JITTER_PX = 0.5
"""Pixels: the jitter is never taken below half a pixel, the rounding of boxes drawn or stored in whole pixels
(a box tracked without noise would otherwise count every sub-pixel wobble as winding)."""
MIN_SEEN = 4
"""Frames a box must be seen on for its motion to be read: the second differences behind the jitter need
three, and one more makes their median mean something."""
CIRCLE_VERBS = frozenset({"stir"})
TIPPED_VERBS = frozenset({"pour"})
UNTIPPED_VERBS = frozenset({"sprinkle", "dip"})
STROKED_VERBS = frozenset({"peel", "wrap"})
GRIPPED_VERBS = frozenset({"squeeze"})


@dataclass(frozen=True)
class Motion:
    """Cues of one object's box over a stretch of frames."""

    turns: float
    """Net winding of the centre around its running mean, in turns (unsigned)."""
    tilt: float
    """Largest over smallest width-to-height ratio of the box (1: no change)."""
    roundness: float = 1.0
    """Net angle swept over all the angle swept, around the running mean (1: always the same way round)."""
    active: bool = True
    """The centre strays from its running mean by more than :data:`ACTIVE_FRACTION` of the box's diagonal on
    a typical frame: the object is being worked, not held frozen."""
    stroke: float = 0.0
    """Median distance of the smoothed centre from its running mean, over the box's diagonal."""


def median_of(values: np.ndarray) -> float:
    """``np.median`` of the 1-D ``values``, bit for bit (NaN when any is NaN), without its general machinery
    (called on short stretches, where that machinery is most of the cost)."""
    n = len(values)
    if n == 0 or np.isnan(values).any():
        return float(np.median(values))
    half = n // 2
    if n % 2:
        return float(np.partition(values, half)[half])
    part = np.partition(values, (half - 1, half))
    return float((part[half - 1] + part[half]) / 2)


def _running_mean(values: np.ndarray, half: int) -> np.ndarray:
    """Mean of ``values`` ``(n, 2)`` over ``2 half + 1`` rows around each (edges repeated)."""
    padded = np.concatenate([np.repeat(values[:1], half + 1, axis=0), values, np.repeat(values[-1:], half, axis=0)])
    running = np.cumsum(padded, axis=0)
    return (running[2 * half + 1 :] - running[: -2 * half - 1]) / (2 * half + 1)


def motion_of(boxes: np.ndarray, fps: float) -> Motion | None:
    """The cues of boxes ``(frames, 4)`` (NaN rows where unseen); None when too few frames are seen."""
    seen = np.isfinite(boxes).all(axis=1)
    if seen.sum() < MIN_SEEN:
        return None
    box = boxes[seen]
    centre = np.stack([(box[:, 0] + box[:, 2]) / 2, (box[:, 1] + box[:, 3]) / 2], axis=1)
    width = np.clip(box[:, 2] - box[:, 0], 1e-6, None)
    height = np.clip(box[:, 3] - box[:, 1], 1e-6, None)
    aspect = width / height
    k = max(1, round(TILT_SMOOTH_S * (fps if fps > 0 else DEFAULT_FPS) / 2))
    if len(aspect) > 2 * k:
        padded = np.concatenate([np.full(k, aspect[0]), aspect, np.full(k, aspect[-1])])  # np.pad "edge", cheaper
        windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * k + 1)
        aspect = np.median(windows, axis=1)
    tilt = float(np.max(aspect) / np.min(aspect))
    # jitter: a box that sits still changes by noise alone from one frame to the next; second differences
    # of a smooth path are small, so their median over the stretch is the noise level (times sqrt(6))
    second = np.linalg.norm(centre[2:] - 2 * centre[1:-1] + centre[:-2], axis=1)
    jitter = median_of(second) / np.sqrt(6.0) if len(second) else 0.0
    # running mean over about a second removes the drift of the stroke's centre
    rate = fps if fps > 0 else DEFAULT_FPS
    mean = _running_mean(centre, max(1, round(DRIFT_S * rate)))
    offset = centre - mean
    radius = np.linalg.norm(offset, axis=1)
    angle = np.arctan2(offset[:, 1], offset[:, 0])
    step = np.angle(np.exp(1j * np.diff(angle)))
    floor = JITTER_TIMES * max(jitter, MIN_JITTER_PX)
    counted = (radius[1:] > floor) & (radius[:-1] > floor)
    diagonal = median_of(np.hypot(width, height))
    active = bool(median_of(radius) > ACTIVE_FRACTION * diagonal)
    swept = step[counted]
    turns = float(abs(swept.sum()) / (2 * np.pi))
    total = float(np.abs(swept).sum())
    roundness = float(abs(swept.sum()) / total) if total > 0 else 1.0
    smooth = _running_mean(centre, round(STROKE_SMOOTH_S * rate / 2))
    stroke = median_of(np.linalg.norm(smooth - mean, axis=1)) / max(diagonal, 1e-6)
    return Motion(turns=turns, tilt=tilt, roundness=roundness, active=active, stroke=stroke)


def verbs_of(motion: Motion | None, role: Role = "tool") -> frozenset[str] | None:
    """The verbs ``motion`` allows, None when it says nothing (too little seen, or no telling pattern).
    ``role``: a ``held`` ingredient over a container (its tilt tells a pour from a sprinkle or a dip), an
    ingredient worked by the ``hand`` (its stroke tells a peel from a squeeze), a ``tool`` (circles stir)."""
    if motion is None:
        return None
    if role == "hand":
        return STROKED_VERBS if motion.stroke >= STROKE_FRACTION else GRIPPED_VERBS
    if role == "held":
        if motion.tilt >= TILT_RATIO:
            return TIPPED_VERBS
        return UNTIPPED_VERBS if motion.active else None  # held frozen, it may pour without tipping far
    if motion.turns >= CIRCLE_TURNS and motion.roundness >= ROUND:
        return CIRCLE_VERBS
    return None
