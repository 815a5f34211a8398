"""Joint paths made into trajectories within the joints' velocity and acceleration limits.

A path (joint waypoints, each segment with its nominal duration) is densified, interpolated by a cubic spline
through the waypoints and time-parameterised by TOPP-RA (``toppra``: time-optimal path parameterisation by
reachability analysis, Pham & Pham 2018) under the joint velocity and acceleration limits and one more: the path
never runs ahead of its nominal clock (a pseudo joint, the nominal time, limited to 1 s/s), so a straight move
keeps its Cartesian speed and a planned one its share of the joint speeds. The trajectory starts and ends at
rest and is sampled at the simulation rate. When TOPP-RA finds no parameterisation (it should not: the path is
feasible at rest), each segment is run rest to rest on a trapezoidal profile instead.

The spline passes through every waypoint; between densified points it strays from the straight segment by a
small fraction of :data:`DENSE` (corners are where it strays most, and where TOPP-RA slows down).
"""

from __future__ import annotations

import itertools
import logging
import math
from collections.abc import Sequence

import numpy as np

DENSE = 0.06
"""Radians: the largest joint step between two points of the interpolated path."""
GRID = 3
"""TOPP-RA grid points per interval between two points of the path (one lets the spline's joint accelerations
between grid points reach twice the limit; three keep them at the limit, measured)."""
MARGIN = 0.8
"""Share of the acceleration limits trajectories are planned to (the spline between TOPP-RA's grid points goes a
little over what is planned at them; finite differences at the recording rate stay under the limits themselves)."""
DRIVE_MARGIN = 0.6
"""Share of the acceleration limit a driven joint (:func:`toward`) plans to: its last step onto the target and a
turn at full braking each reach up to 1.5 times what is planned, in one step (measured over random targets)."""
SPEED_MARGIN = 0.98
"""Share of the velocity limits trajectories are planned to."""


def timed_path(path: Sequence[np.ndarray], durations: Sequence[float], velocity: np.ndarray,
               acceleration: np.ndarray, hz: float) -> np.ndarray:
    """Joint positions (one row per step of ``1 / hz`` s, the last one the path's end) of ``path`` run within
    ``velocity`` (rad/s, planned to :data:`SPEED_MARGIN` of it) and ``acceleration`` (rad/s², planned to
    :data:`MARGIN` of it) and never faster than
    ``durations`` (seconds per segment). A path that does not move gives its end once."""
    points, clock = _dense(path, durations)
    if len(points) < 2:
        return np.asarray(path[-1], dtype=float)[None, :]
    samples = _toppra(points, clock, velocity * SPEED_MARGIN, acceleration * MARGIN, hz)
    if samples is None:
        samples = _rest_to_rest(points, velocity * SPEED_MARGIN, acceleration * MARGIN, hz)
    samples[-1] = points[-1]
    return samples


def _dense(path: Sequence[np.ndarray], durations: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """The path's points every :data:`DENSE` at most (repeated points dropped) and their nominal times."""
    points = [np.asarray(path[0], dtype=float)]
    clock = [0.0]
    for (a, b), d in zip(itertools.pairwise(path), durations, strict=True):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        step = float(np.max(np.abs(b - a)))
        if step < 1e-9:
            continue
        n = max(math.ceil(step / DENSE), 1)
        for i in range(1, n + 1):
            points.append(a + (b - a) * (i / n))
            clock.append(clock[-1] + max(d, 1e-6) / n)
    if len(points) == 2:  # a spline needs more than a line's two points to stay a line
        points.insert(1, (points[0] + points[1]) / 2)
        clock.insert(1, clock[1] / 2)
    return np.array(points), np.array(clock)


def _toppra(points: np.ndarray, clock: np.ndarray, velocity: np.ndarray, acceleration: np.ndarray,
            hz: float) -> np.ndarray | None:
    import toppra
    import toppra.algorithm
    import toppra.constraint

    logging.getLogger("toppra").setLevel(logging.WARNING)  # its debug lines cost time (not setup_logging:
    # that adds a console handler at every call)
    dof = points.shape[1]
    s = (clock - clock[0]) / clock[-1]  # the path parameter, 0..1
    spline = toppra.SplineInterpolator(s, np.column_stack([points, clock]))
    vmax = np.append(velocity, 1.0)  # the pseudo joint (the nominal clock) runs at most 1 s/s
    amax = np.append(acceleration, 1e6)
    constraints = [toppra.constraint.JointVelocityConstraint(np.column_stack([-vmax, vmax])),
                   toppra.constraint.JointAccelerationConstraint(np.column_stack([-amax, amax]))]
    grid = np.unique(np.concatenate([np.linspace(a, b, GRID + 1) for a, b in itertools.pairwise(s)]))
    try:
        solver = toppra.algorithm.TOPPRA(constraints, spline, gridpoints=grid)
        sdd, sd, _ = solver.compute_parameterization(0.0, 0.0)
    except Exception:  # toppra raises plain exceptions on numerical trouble
        return None
    if sd is None or sdd is None or np.isnan(sd).any() or np.isnan(sdd).any():
        return None
    return _sampled(spline, grid, np.maximum(sd, 0.0), sdd, hz)[:, :dof]


def _sampled(spline: object, grid: np.ndarray, sd: np.ndarray, sdd: np.ndarray, hz: float) -> np.ndarray:
    """The path at every ``1 / hz`` s of the parameterisation (constant path acceleration ``sdd[i]`` between
    grid points ``i`` and ``i + 1``, path speeds ``sd`` at the grid points), its end last. Vectorised: toppra's
    own trajectory object evaluates it at some 50 ms a path."""
    ds = np.diff(grid)
    dt = 2 * ds / np.maximum(sd[:-1] + sd[1:], 1e-9)
    starts = np.concatenate([[0.0], np.cumsum(dt)])
    duration = float(starts[-1])
    n = max(math.ceil(duration * hz - 1e-9), 1)
    times = np.minimum(np.arange(1, n + 1) / hz, duration)
    seg = np.clip(np.searchsorted(starts, times, side="right") - 1, 0, len(ds) - 1)
    tau = np.minimum(times - starts[seg], dt[seg])
    s = np.minimum(grid[seg] + sd[seg] * tau + 0.5 * sdd[seg] * tau * tau, grid[seg + 1])
    s = np.maximum(s, grid[seg])
    return np.asarray(spline(s))  # type: ignore[operator]


def _rest_to_rest(points: np.ndarray, velocity: np.ndarray, acceleration: np.ndarray, hz: float) -> np.ndarray:
    """Each segment on a trapezoidal (or triangular) speed profile from rest to rest."""
    out = []
    for a, b in itertools.pairwise(points):
        delta = b - a
        # the slowest joint sets the time; scaling every joint by the same profile keeps the segment straight
        v = float(np.min(velocity / np.maximum(np.abs(delta), 1e-12)))
        acc = float(np.min(acceleration / np.maximum(np.abs(delta), 1e-12)))
        t_ramp = v / acc
        if v * t_ramp >= 1.0:  # triangular: never reaches v
            t_ramp = math.sqrt(1.0 / acc)
            total = 2 * t_ramp
            v = acc * t_ramp
        else:
            total = 1.0 / v + t_ramp
        n = max(math.ceil(total * hz), 1)
        for t in np.minimum(np.arange(1, n + 1) / hz, total):
            if t < t_ramp:
                u = 0.5 * acc * t * t
            elif t > total - t_ramp:
                u = 1.0 - 0.5 * acc * (total - t) ** 2
            else:
                u = 0.5 * acc * t_ramp ** 2 + v * (t - t_ramp)
            out.append(a + delta * min(max(u, 0.0), 1.0))
    return np.array(out)


def toward(position: float, velocity: float, target: float, vmax: float, amax: float, dt: float
           ) -> tuple[float, float]:
    """One step of ``dt`` of a joint driven to ``target`` within ``vmax`` and ``amax`` (planned to
    :data:`DRIVE_MARGIN` of it): the new position and velocity. From rest it brakes in time and stops on the target,
    never past it; a target moved nearer than the joint can stop in is passed and come back to."""
    amax *= DRIVE_MARGIN
    error = target - position
    if abs(error) <= abs(velocity) * dt + 1e-12 and abs(velocity) <= amax * dt:
        return target, 0.0
    if velocity * error > 0 and velocity * velocity / (2 * amax) > abs(error) + abs(velocity) * dt:
        velocity -= math.copysign(amax * dt, velocity)  # too fast to stop on it: brake as hard as allowed
    else:  # the fastest speed from which it can still stop on the target, one step of braking to spare
        reachable = math.sqrt(2 * amax * max(abs(error) - abs(velocity) * dt, 0.0))
        wanted = math.copysign(min(vmax, reachable), error)
        velocity += min(max(wanted - velocity, -amax * dt), amax * dt)
    after = position + velocity * dt
    if (target - after) * error < 0 and abs(velocity) <= amax * dt:  # the last step lands on the target
        return target, 0.0
    return after, velocity
