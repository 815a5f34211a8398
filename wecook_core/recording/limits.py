"""A recording's joint states against the arm's limits: every recorded step's position, velocity and
acceleration (finite differences of the recorded positions at their log times) within the Panda's URDF position
and velocity limits and Franka's acceleration limits (:mod:`wecook_core.execution.planning.limits`).

A violation is a run of consecutive recorded steps over one joint's limit: one line, at its worst step.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from wecook_core.execution.planning.limits import JointLimit, urdf_limits

TOLERANCE = 0.02
"""Share over a velocity or acceleration limit that is still within it (rounding of the recorded times and
positions); positions get :data:`POSITION_TOLERANCE`."""
POSITION_TOLERANCE = 1e-3
"""Radians or metres."""


@dataclass
class JointTrack:
    """The recorded positions of every ``<arm>/<joint>``, in log order."""

    times: list[float] = field(default_factory=list)
    """Seconds."""
    names: list[str] = field(default_factory=list)
    positions: list[list[float]] = field(default_factory=list)

    def add(self, t: float, names: Sequence[str], positions: Sequence[float]) -> None:
        if self.names and list(names) != self.names:
            return  # a different layout: only the first is checked
        self.names = list(names)
        if len(positions) == len(names):
            self.times.append(t)
            self.positions.append([float(v) for v in positions])


def limit_violations(track: JointTrack, limits: Mapping[str, JointLimit] | None = None) -> list[str]:
    """One line per violation: ``<arm> <joint> at <t> s: <what> <value> over its limit <limit>``, ``t`` in seconds
    since the first recorded state."""
    limits = urdf_limits() if limits is None else limits
    if len(track.times) < 2:
        return []
    t = np.array(track.times) - track.times[0]  # seconds since the first recorded state (the run's start)
    q = np.array(track.positions)
    dt = np.diff(t)
    keep = dt > 1e-9
    out: list[str] = []
    for k, full in enumerate(track.names):
        arm, _, joint = full.rpartition("/")
        limit = limits.get(joint)
        if limit is None:
            continue
        unit = "m" if joint.startswith("panda_finger") else "rad"
        qk = q[:, k]
        low = np.maximum(limit.lower - qk, 0.0)
        high = np.maximum(qk - limit.upper, 0.0)
        out += _runs(arm or "?", joint, t, np.maximum(low, high), POSITION_TOLERANCE, "position",
                     f"{unit}", qk, f"[{limit.lower:g}, {limit.upper:g}] {unit}")
        v = np.diff(qk)[keep] / dt[keep]
        tv = t[1:][keep]
        out += _runs(arm or "?", joint, tv, np.abs(v) - limit.velocity * (1 + TOLERANCE), 0.0, "speed",
                     f"{unit}/s", np.abs(v), f"{limit.velocity:g} {unit}/s")
        if len(v) >= 2:
            a = np.diff(v) / ((dt[keep][1:] + dt[keep][:-1]) / 2)
            ta = tv[:-1]
            out += _runs(arm or "?", joint, ta, np.abs(a) - limit.acceleration * (1 + TOLERANCE), 0.0,
                         "acceleration", f"{unit}/s²", np.abs(a), f"{limit.acceleration:g} {unit}/s²")
    return out


def _runs(arm: str, joint: str, times: np.ndarray, excess: np.ndarray, tolerance: float, what: str, unit: str,
          values: np.ndarray, limit: str) -> list[str]:
    """A line per run of consecutive steps with ``excess`` over ``tolerance``, at its largest excess."""
    over = excess > tolerance
    out = []
    k = 0
    n = len(over)
    while k < n:
        if not over[k]:
            k += 1
            continue
        end = k
        while end + 1 < n and over[end + 1]:
            end += 1
        worst = k + int(np.argmax(excess[k:end + 1]))
        out.append(f"{arm} {joint} at {times[worst]:.3f} s: {what} {values[worst]:.3f} {unit} over its limit "
                   f"{limit}")
        k = end + 1
    return out
