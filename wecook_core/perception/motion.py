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
- **tilt**: the ratio between the largest and smallest width-to-height ratio of the box (a bottle or a bowl
  tipped over a pan turns in the image plane). Measured and reported, not yet used: on thin boxes (knives,
  spoons) a few pixels of jitter change the ratio as much as a tilt does.

:func:`verbs_of` turns them into the verbs the motion allows (None: the motion does not say), which the
recogniser intersects with the commonsense candidates (never leaving none).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

JITTER_TIMES = 3.0
"""The centre counts as away from its mean (winding) only beyond this many times the track's jitter."""
CIRCLE_TURNS = 1.5
"""Winding at least this many turns is circling (sawing and carrying wind back and forth by up to about one
turn, jitter counted out)."""
ROUND = 0.5
"""Circling also turns one way: the net angle swept is at least this fraction of all the angle swept (a
saw's strokes flip the centre from one side of its mean to the other, sweeping half turns either way)."""
CIRCLE_VERBS = frozenset({"stir"})


@dataclass(frozen=True)
class Motion:
    """Cues of one object's box over a stretch of frames."""

    turns: float
    """Net winding of the centre around its running mean, in turns (unsigned)."""
    tilt: float
    """Largest over smallest width-to-height ratio of the box (1: no change)."""
    roundness: float = 1.0
    """Net angle swept over all the angle swept, around the running mean (1: always the same way round)."""


def motion_of(boxes: np.ndarray, fps: float) -> Motion | None:
    """The cues of boxes ``(frames, 4)`` (NaN rows where unseen); None when too few frames are seen."""
    seen = np.isfinite(boxes).all(axis=1)
    if seen.sum() < 4:
        return None
    box = boxes[seen]
    centre = np.stack([(box[:, 0] + box[:, 2]) / 2, (box[:, 1] + box[:, 3]) / 2], axis=1)
    width = np.clip(box[:, 2] - box[:, 0], 1e-6, None)
    height = np.clip(box[:, 3] - box[:, 1], 1e-6, None)
    aspect = width / height
    tilt = float(np.max(aspect) / np.min(aspect))
    # jitter: a box that sits still changes by noise alone from one frame to the next; second differences
    # of a smooth path are small, so their median over the stretch is the noise level (times sqrt(6))
    second = np.linalg.norm(centre[2:] - 2 * centre[1:-1] + centre[:-2], axis=1)
    jitter = float(np.median(second)) / np.sqrt(6.0) if len(second) else 0.0
    # running mean over about a second removes the drift of the stroke's centre
    half = max(1, round(0.5 * (fps if fps > 0 else 30.0)))
    padded = np.pad(centre, ((half + 1, half), (0, 0)), mode="edge")
    running = np.cumsum(padded, axis=0)
    mean = (running[2 * half + 1 :] - running[: -2 * half - 1]) / (2 * half + 1)
    offset = centre - mean
    radius = np.linalg.norm(offset, axis=1)
    angle = np.arctan2(offset[:, 1], offset[:, 0])
    step = np.angle(np.exp(1j * np.diff(angle)))
    counted = (radius[1:] > JITTER_TIMES * max(jitter, 0.5)) & (radius[:-1] > JITTER_TIMES * max(jitter, 0.5))
    swept = step[counted]
    turns = float(abs(swept.sum()) / (2 * np.pi))
    total = float(np.abs(swept).sum())
    roundness = float(abs(swept.sum()) / total) if total > 0 else 1.0
    return Motion(turns=turns, tilt=tilt, roundness=roundness)


def verbs_of(motion: Motion | None) -> frozenset[str] | None:
    """The verbs ``motion`` allows, None when it says nothing (too little seen, or no telling pattern)."""
    if motion is None:
        return None
    if motion.turns >= CIRCLE_TURNS and motion.roundness >= ROUND:
        return CIRCLE_VERBS
    return None
