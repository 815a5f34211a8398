"""The actuation motions of the skills (``motion:`` in ``skills.yaml``): each a function from its parameters and
the engage pose to effector waypoints, picked by name from :data:`MOTION_PATHS`. Pure numpy: nothing here touches
the simulator.

Every motion starts at the engage pose ``E`` (4x4, world); ``Rw`` is the engage frame's rotation (its x, y, z give
the motion's axes; z is up for every shipped skill); distances are metres, angles degrees in the parameters.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

AXIS_NAMES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True, eq=False)
class Waypoint:
    pose: np.ndarray
    """4x4 world pose of the effector."""
    fingers: float | None = None
    """Finger opening to command at this waypoint (metres per finger), None to keep."""
    hold: float = 0.0
    """Seconds to stay at this waypoint."""
    lets_go: bool = False
    """What the step releases riding on the carried object is let go here (at a tilt: it falls out), not at the
    end of the motion."""


@dataclass(frozen=True)
class Start:
    """Where a motion starts: the engage pose ``E``, the engage frame's rotation ``Rw``, the finger opening
    ``grip`` and the gripper's world position ``hand`` (tilts turn about it, as a wrist does)."""

    E: np.ndarray
    Rw: np.ndarray
    grip: float = 0.0
    hand: np.ndarray | None = None


Motion = Callable[[Mapping[str, float], Start], list[Waypoint]]
"""A motion: its parameters and where it starts -> its waypoints (the return to the start is added after)."""


def _moved(E: np.ndarray, Rw: np.ndarray, dp: Sequence[float] | np.ndarray = (0, 0, 0), axis: str | None = None,
           angle: float = 0.0, pivot: np.ndarray | None = None) -> np.ndarray:
    """``E`` translated by ``dp`` (engage-frame axes) and rotated by ``angle`` about an engage-frame axis through
    ``pivot`` (world point; default the effector origin)."""
    T = E.copy()
    T[:3, 3] = E[:3, 3] + Rw @ np.asarray(dp, dtype=float)
    if axis is not None and angle:
        v = np.zeros(3)
        v[AXIS_NAMES[axis]] = angle
        R = Rw @ Rotation.from_rotvec(v).as_matrix() @ Rw.T
        T[:3, :3] = R @ E[:3, :3]
        if pivot is not None:
            T[:3, 3] = pivot + R @ (T[:3, 3] - pivot)
    return T


def saw(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Down, then ``strokes`` back-and-forth strokes of ``amplitude`` along ``axis``, sinking ``depth`` in all."""
    g = params.get
    down, depth, n, amp = g("down", 0.03), g("depth", 0.02), int(g("strokes", 3)), g("amplitude", 0.03)
    ax = AXIS_NAMES[str(g("axis", "x"))] if isinstance(g("axis", "x"), str) else 0
    base = np.zeros(3)
    base[2] = -down
    out = [Waypoint(_moved(s.E, s.Rw, base))]
    for k in range(n):
        for sign in (1, -1):
            d = base.copy()
            d[ax] += sign * amp
            d[2] -= depth * (2 * k + (1 if sign > 0 else 2)) / (2 * n)
            out.append(Waypoint(_moved(s.E, s.Rw, d)))
    end = base.copy()
    end[2] -= depth
    out.append(Waypoint(_moved(s.E, s.Rw, end)))
    return out


def circle(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Down, then ``turns`` circles of ``radius`` around the engage point, starting on its +x side."""
    g = params.get
    down, r, turns = g("down", 0.05), g("radius", 0.03), g("turns", 2)
    out = [Waypoint(_moved(s.E, s.Rw, (0, 0, -down)))]
    for k in range(int(16 * turns) + 1):
        phase = 2 * math.pi * k / 16
        out.append(Waypoint(_moved(s.E, s.Rw, (r * math.cos(phase), r * math.sin(phase), -down))))
    out.append(Waypoint(_moved(s.E, s.Rw, (0, 0, -down))))
    return out


def tilt(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Tip by ``angle`` about ``axis`` (the first of its options) through the hand, hold, shake ``shakes``
    times; what it releases is let go at the tilt."""
    g = params.get
    angle = math.radians(g("angle", 90))
    axis = str(params.get("axis", "y")).split(",")[0]
    direction = -1.0 if axis == "y" else 1.0  # positive angles tip the top away from the arm (-x) or sideways
    if axis.startswith("-"):
        axis, direction = axis[1:], -direction
    tilted = _moved(s.E, s.Rw, axis=axis, angle=direction * angle, pivot=s.hand)
    out = [Waypoint(tilted, hold=g("hold", 0.5), lets_go=True)]
    for _ in range(int(g("shakes", 0))):
        out.append(Waypoint(_moved(s.E, s.Rw, axis=axis, angle=direction * (angle + g("shake", 0.15)),
                                   pivot=s.hand)))
        out.append(Waypoint(tilted))
    return out


def strokes(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Down, then ``count`` back-and-forth strokes of ``amplitude`` along ``axis`` at that depth."""
    g = params.get
    down, amp, n = g("down", 0.03), g("amplitude", 0.03), int(g("count", 3))
    ax = AXIS_NAMES[str(params.get("axis", "x"))]
    base = np.array([0.0, 0.0, -down])
    out = [Waypoint(_moved(s.E, s.Rw, base))]
    for _ in range(n):
        for sign in (1, -1):
            d = base.copy()
            d[ax] += sign * amp
            out.append(Waypoint(_moved(s.E, s.Rw, d)))
    out.append(Waypoint(_moved(s.E, s.Rw, base)))
    return out


def dip(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Straight down by ``down`` and hold there."""
    return [Waypoint(_moved(s.E, s.Rw, (0, 0, -params.get("down", 0.05))), hold=params.get("hold", 0.5))]


def squeeze(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """``cycles`` times: close the fingers a little while twisting, then open back."""
    twist = math.radians(params.get("twist", 20))
    out = []
    for _ in range(int(params.get("cycles", 3))):
        out.append(Waypoint(_moved(s.E, s.Rw, axis="z", angle=twist), fingers=max(s.grip - 0.006, 0.0), hold=0.2))
        out.append(Waypoint(s.E, fingers=s.grip, hold=0.1))
    return out


def wrap(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Half a turn of ``radius`` over and around, the effector rolling a quarter of the way with it."""
    r = params.get("radius", 0.04)
    out = []
    for k in range(1, 9):
        a = math.pi * k / 8
        out.append(Waypoint(_moved(s.E, s.Rw, (r * (1 - math.cos(a)), 0, r * math.sin(a)), axis="y", angle=-a / 4)))
    return out


def scoop(params: Mapping[str, float], s: Start) -> list[Waypoint]:
    """Down, then a ``sweep`` along x while turning up by ``angle``."""
    g = params.get
    down, sweep, angle = g("down", 0.05), g("sweep", 0.03), math.radians(g("angle", 15))
    return [Waypoint(_moved(s.E, s.Rw, (0, 0, -down))),
            Waypoint(_moved(s.E, s.Rw, (sweep, 0, -down), axis="y", angle=angle))]


MOTION_PATHS: Mapping[str, Motion] = {"saw": saw, "circle": circle, "tilt": tilt, "strokes": strokes, "dip": dip,
                                      "squeeze": squeeze, "wrap": wrap, "scoop": scoop}
"""Motion name (as skills name it) -> its path."""
MOTIONS: tuple[str, ...] = tuple(MOTION_PATHS)


def actuation_path(motion: str, params: Mapping[str, float], E: np.ndarray, Rw: np.ndarray,
                   grip: float = 0.0, hand: np.ndarray | None = None) -> list[Waypoint]:
    """Effector waypoints of the actuation ``motion`` (see :data:`MOTION_PATHS`) from the engage pose ``E``
    (4x4, world) in the engage frame ``Rw``; tilts turn about ``hand`` (default the effector origin). Ends
    where it starts."""
    path = MOTION_PATHS.get(motion)
    if path is None:
        raise ValueError(f"unknown motion {motion!r}")
    return [*path(params, Start(E, Rw, grip, hand)), Waypoint(E)]
