"""Hand motion: minimum-jerk reaches, work patterns (sawing, stirring, rolling...), tremor and idle drift,
arms by two-link inverse kinematics, and the 21 hand keypoints OpenPose would report.

Everything works on whole arrays of frames (numpy), so a ten-minute scenario takes milliseconds.
Positions are pixels of the nominal 640x360 image, frames are 0-based indices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

UPPER_ARM = 110.0
"""Shoulder to elbow, pixels."""
FOREARM = 80.0
"""Elbow to wrist, pixels."""
WRIST_TO_HAND = 14.0
"""Wrist to the hand's centre (the mean of its keypoints), pixels."""


def minimum_jerk(s: np.ndarray) -> np.ndarray:
    """The minimum-jerk profile 10s^3 - 15s^4 + 6s^5 on ``s`` in [0, 1]."""
    s = np.clip(s, 0.0, 1.0)
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def rotation(angle: np.ndarray | float) -> np.ndarray:
    """2x2 rotation matrices (``(..., 2, 2)``) turning local x into ``(cos, sin)``."""
    if isinstance(angle, float | int):
        c, s = math.cos(angle), math.sin(angle)
        return np.array([[c, -s], [s, c]])
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)


# ----------------------------------------------------------------------------------------------- phases


@dataclass(frozen=True)
class Move:
    """A reach or a carry from ``p0`` to ``p1`` on frames ``[start, end)`` (minimum jerk, slightly curved)."""

    start: int
    end: int
    p0: tuple[float, float]
    p1: tuple[float, float]
    bulge: float = 0.0
    """Sideways deviation at mid-path, pixels (signed, to the left of the direction of travel)."""
    skew: float = 1.0
    """Time warp exponent: below 1 the hand speeds up early, above 1 late (real reaches are asymmetric)."""


@dataclass(frozen=True)
class Hold:
    """The hand stays at ``p`` on frames ``[start, end)`` (tremor is added everywhere later)."""

    start: int
    end: int
    p: tuple[float, float]


@dataclass(frozen=True)
class Work:
    """A periodic work motion around ``p`` on frames ``[start, end)``, faded in and out so it starts and ends
    at ``p``.

    ``pattern``: ``saw`` (strokes along ``axis``), ``circle`` (stirring), ``roll`` (long strokes along
    ``axis``), ``peel`` (fast-out slow-back strokes along ``axis``), ``shake`` (small fast strokes across
    ``axis``), ``squeeze`` (a tremor with small pulses), ``scoop`` (one small loop)."""

    start: int
    end: int
    p: tuple[float, float]
    pattern: str
    axis: tuple[float, float]
    """Unit vector, the main direction of the strokes."""
    amplitude: float
    """Pixels."""
    frequency: float
    """Cycles per second."""
    phase: float = 0.0
    drift: float = 0.0
    """Slow sideways shift across ``axis`` over the whole phase, pixels (cutting across the tomato)."""


Phase = Move | Hold | Work


def _fade(length: int, ramp: int) -> np.ndarray:
    t = np.arange(length, dtype=float)
    ramp = max(1, min(ramp, length // 2))
    return np.clip(np.minimum(t / ramp, (length - 1 - t) / ramp), 0.0, 1.0)


def phase_positions(phase: Phase, fps: float) -> np.ndarray:
    """``(end - start, 2)`` hand positions of one phase."""
    length = phase.end - phase.start
    if isinstance(phase, Hold):
        return np.tile(np.asarray(phase.p, dtype=float), (length, 1))
    if isinstance(phase, Move):
        p0, p1 = np.asarray(phase.p0, dtype=float), np.asarray(phase.p1, dtype=float)
        s = np.arange(length, dtype=float) / max(length, 1)
        profile = minimum_jerk(s ** phase.skew)
        d = p1 - p0
        norm = float(np.hypot(*d))
        side = np.array([d[1], -d[0]]) / norm if norm > 1e-9 else np.zeros(2)
        return p0 + profile[:, None] * d + (phase.bulge * np.sin(np.pi * profile))[:, None] * side
    t = np.arange(length, dtype=float) / fps
    axis = np.asarray(phase.axis, dtype=float)
    across = np.array([-axis[1], axis[0]])
    w = 2 * np.pi * phase.frequency * t + phase.phase
    amp = phase.amplitude
    fade = _fade(length, int(0.25 * fps))
    if phase.pattern == "saw":
        along, side = amp * np.sin(w), 0.15 * amp * np.sin(2 * w)
    elif phase.pattern == "circle":
        along, side = amp * np.cos(w) - amp, amp * np.sin(w)
        fade = _fade(length, int(0.4 * fps))
    elif phase.pattern == "roll":
        along, side = amp * np.sin(w), 0.1 * amp * np.sin(0.5 * w)
    elif phase.pattern == "peel":
        saw = (w / (2 * np.pi)) % 1.0
        stroke = np.where(saw < 0.35, saw / 0.35, 1.0 - (saw - 0.35) / 0.65)
        along, side = amp * (minimum_jerk(stroke) - 0.5) * 2, 0.2 * amp * np.sin(0.3 * w)
    elif phase.pattern == "shake":
        along, side = 0.3 * amp * np.sin(0.5 * w), amp * np.sin(w)
    elif phase.pattern == "squeeze":
        along, side = 0.5 * amp * np.sin(w), 0.3 * amp * np.sin(1.7 * w + 1.0)
    elif phase.pattern == "scoop":
        along, side = amp * (1 - np.cos(w)) * 0.5, amp * np.sin(w) * 0.5
    else:
        raise ValueError(f"unknown work pattern {phase.pattern!r}")
    drift = phase.drift * (np.arange(length) / max(length - 1, 1) - 0.5)
    along, side = along * fade, (side + drift) * fade
    base = np.asarray(phase.p, dtype=float)
    return base + along[:, None] * axis + side[:, None] * across


def hand_path(
    phases: list[Phase], rest: np.ndarray, frames: int, fps: float, rng: np.random.Generator
) -> np.ndarray:
    """``(frames, 2)`` positions of one hand: its phases, rest (with a slow drift) everywhere else, and a small
    tremor on top."""
    xy = np.full((frames, 2), np.nan)
    for phase in phases:
        if phase.end > frames:
            raise ValueError("phase beyond the scenario's end")
        xy[phase.start : phase.end] = phase_positions(phase, fps)
    idle = np.isnan(xy[:, 0])
    drift = gaussian_filter1d(rng.normal(0.0, 1.0, (frames, 2)), sigma=fps, axis=0, mode="nearest")
    drift *= 2.5 / max(float(np.std(drift)), 1e-9)
    taper = gaussian_filter1d(idle.astype(float), sigma=0.2 * fps, mode="nearest") * idle
    xy[idle] = rest
    xy += drift * taper[:, None]
    tremor = gaussian_filter1d(rng.normal(0.0, 1.0, (frames, 2)), sigma=2.0, axis=0, mode="nearest")
    tremor *= 0.45 / max(float(np.std(tremor)), 1e-9)
    return xy + tremor


# ------------------------------------------------------------------------------------------------ arms


def elbows(shoulder: np.ndarray, hand: np.ndarray, outward: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Elbow and wrist positions ``(n, 2)`` for hands ``(n, 2)`` and shoulders ``(n, 2)`` as seen from above.

    The upper arm is foreshortened when the hand is near the body (it hangs down), so the elbow lies a
    little past the middle of shoulder-wrist, pushed towards ``outward`` (a unit vector away from the body's
    midline) by how much the arm is bent; out of reach, the arm is straight."""
    towards = hand - shoulder
    distance = np.maximum(np.linalg.norm(towards, axis=1), 1e-6)
    unit = towards / distance[:, None]
    wrist_distance = np.maximum(distance - WRIST_TO_HAND, 1.0)
    half = (UPPER_ARM + FOREARM) / 2
    bend = np.minimum(0.35 * np.sqrt(np.maximum(half**2 - (wrist_distance / 2) ** 2, 0.0)), 30.0)
    side = np.stack([-unit[:, 1], unit[:, 0]], axis=1)
    sign = np.where(side @ outward >= 0, 1.0, -1.0)
    elbow = shoulder + (0.55 * wrist_distance)[:, None] * unit + (sign * bend)[:, None] * side
    forearm = hand - elbow
    forearm /= np.maximum(np.linalg.norm(forearm, axis=1), 1e-6)[:, None]
    wrist = hand - WRIST_TO_HAND * forearm
    return elbow, wrist


_HAND_TEMPLATE = np.array([
    (-14, 0),                                    # wrist
    (-8, 6), (-3, 10), (2, 12), (6, 13),         # thumb
    (0, 5), (6, 6), (10, 6), (14, 6),            # index
    (0, 1.5), (7, 2), (11, 2), (15, 2),          # middle
    (0, -2), (6, -2.5), (10, -3), (13, -3),      # ring
    (-1, -5.5), (4, -6.5), (7, -7), (10, -7),    # little finger
], dtype=float)
"""OpenPose's 21 hand keypoints of a flat right hand, palm down, fingers along +x, thumb on +y (pixels)."""


def hand_keypoints(centre: np.ndarray, elbow: np.ndarray, left: bool, rng: np.random.Generator) -> np.ndarray:
    """``(n, 21, 2)`` hand keypoints whose mean is ``centre`` (up to a little noise), fingers pointing away
    from the elbow; a left hand mirrors the thumb."""
    template = _HAND_TEMPLATE.copy()
    if left:
        template[:, 1] *= -1
    template -= template.mean(axis=0)
    direction = centre - elbow
    direction /= np.maximum(np.linalg.norm(direction, axis=1), 1e-6)[:, None]
    normal = np.stack([-direction[:, 1], direction[:, 0]], axis=1)
    points = (centre[:, None, :] + template[None, :, 0, None] * direction[:, None, :]
              + template[None, :, 1, None] * normal[:, None, :])
    noise = rng.normal(0.0, 0.6, points.shape)
    return points + noise - noise.mean(axis=1, keepdims=True)


def hand_boxes(keypoints: np.ndarray, wrist: np.ndarray, elbow: np.ndarray) -> np.ndarray:
    """Boxes ``(n, 4)`` from keypoints as wecook's OpenPose importer computes them: the keypoints' extent
    grown by 20% about its centre, at least a quarter of a hand length (0.8 forearm) each side."""
    low, high = keypoints.min(axis=1), keypoints.max(axis=1)
    mid = (low + high) / 2
    size = np.maximum(0.8 * np.linalg.norm(wrist - elbow, axis=1), 8.0)
    half = np.maximum((high - low) * 0.6, (size / 4)[:, None])
    return np.concatenate([mid - half, mid + half], axis=1)
