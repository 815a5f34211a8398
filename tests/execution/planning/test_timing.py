"""Joint paths timed within the Panda's velocity and acceleration limits (TOPP-RA), and fingers driven within
the gripper's."""

from __future__ import annotations

import itertools

import numpy as np

from wecook_core.execution.planning.limits import FINGER_ACCEL, arm_acceleration, arm_velocity, finger_velocity
from wecook_core.execution.planning.timing import timed_path, toward

HZ = 240


def _rates(samples: np.ndarray, start: np.ndarray, every: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Finite-difference speeds and accelerations (absolute, per joint) at rest before and after."""
    q = np.vstack([np.repeat(start[None], 3, 0), samples, np.repeat(samples[-1:], 3 * every, 0)])[::every]
    dt = every / HZ
    v = np.diff(q, axis=0) / dt
    return np.abs(v), np.abs(np.diff(v, axis=0) / dt)


def _distance_to_path(q: np.ndarray, path: list[np.ndarray]) -> float:
    best = np.inf
    for a, b in itertools.pairwise(path):
        d = b - a
        u = np.clip(np.dot(q - a, d) / max(np.dot(d, d), 1e-12), 0.0, 1.0)
        best = min(best, float(np.max(np.abs(q - (a + u * d)))))
    return best


def test_a_planned_path_runs_within_the_limits_through_its_waypoints() -> None:
    rng = np.random.default_rng(3)
    vmax, amax = arm_velocity(), arm_acceleration()
    for _ in range(4):
        path = [rng.uniform(-2.0, 2.0, 7) for _ in range(4)]
        durations = [float(np.max(np.abs(b - a) / vmax)) * 0.5 for a, b in itertools.pairwise(path)]  # 2x too fast
        samples = timed_path(path, durations, vmax, amax, HZ)
        for every in (1, 8):  # the simulation's rate and the recording's (30 Hz)
            v, a = _rates(samples, path[0], every)
            assert np.all(v <= vmax)
            assert np.all(a <= amax), np.max(a / amax)
        assert np.allclose(samples[-1], path[-1])
        assert max(_distance_to_path(q, path) for q in samples) < 0.02  # radians off the checked segments
        for waypoint in path[1:-1]:
            assert np.min(np.max(np.abs(samples - waypoint), axis=1)) < 0.01


def test_a_straight_move_keeps_its_nominal_pace() -> None:
    """The nominal durations (a Cartesian speed) bound the pace: a slow, dense path takes at least its time."""
    vmax, amax = arm_velocity(), arm_acceleration()
    path = [np.full(7, 0.01 * k) for k in range(40)]
    samples = timed_path(path, [0.1] * 39, vmax, amax, HZ)
    assert len(samples) / HZ >= 3.9
    v, _ = _rates(samples, path[0])
    assert np.max(v) <= 0.1 * 1.02  # 0.01 rad in 0.1 s


def test_a_path_that_does_not_move_gives_its_end() -> None:
    q = np.zeros(7)
    assert timed_path([q, q.copy()], [0.5], arm_velocity(), arm_acceleration(), HZ).shape == (1, 7)


def test_a_finger_reaches_its_target_within_the_gripper_limits_and_never_passes_it() -> None:
    for target in (0.0, 0.0385, 0.012):
        x, v, xs = 0.04, 0.0, [0.04]
        for _ in range(HZ):
            x, v = toward(x, v, target, finger_velocity(), FINGER_ACCEL, 1 / HZ)
            xs.append(x)
        arr = np.array(xs)
        assert arr[-1] == target
        assert arr.min() >= target  # closing from above: never past the target
        speed = np.abs(np.diff(arr)) * HZ
        assert speed.max() <= finger_velocity() * 1.001
        assert (np.abs(np.diff(np.diff(arr))) * HZ * HZ).max() <= FINGER_ACCEL * 1.001


def test_a_finger_whose_target_moves_while_it_moves_stays_within_the_gripper_limits() -> None:
    """Targets changed mid-motion (a release, then a grasp): the finger brakes within the limit and may pass a
    target that came too close to stop at (demo seed 1 once stopped dead: 2.6 m/s² at 30 Hz)."""
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(300):
        x, v, xs, target = 0.04, 0.0, [0.04], rng.uniform(0.0, 0.04)
        for k in range(400):
            if rng.random() < 0.01 and k < 300:
                target = rng.uniform(0.0, 0.04)
            x, v = toward(x, v, target, finger_velocity(), FINGER_ACCEL, 1 / HZ)
            xs.append(x)
        arr = np.array(xs)
        worst = max(worst, float(np.max(np.abs(np.diff(arr, 2)))) * HZ * HZ)
        assert np.max(np.abs(np.diff(arr))) * HZ <= finger_velocity() * 1.001
    assert worst <= FINGER_ACCEL
