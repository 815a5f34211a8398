"""`wecook runs check` finds every recorded joint step over the arm's position, velocity or acceleration limit."""

from __future__ import annotations

import numpy as np

from wecook_core.execution.planning.limits import urdf_limits
from wecook_core.recording.limits import JointTrack, limit_violations

NAMES = [f"P{k}/panda_joint{j + 1}" for k in (1, 2) for j in range(7)]


def _track(positions: np.ndarray, hz: float = 30.0) -> JointTrack:
    track = JointTrack()
    for k, row in enumerate(positions):
        track.add(100.0 + k / hz, NAMES, row.tolist())
    return track


def test_the_limits_are_the_urdfs_and_frankas() -> None:
    limits = urdf_limits()
    assert limits["panda_joint1"].velocity == 2.175
    assert limits["panda_joint2"].acceleration == 7.5
    assert limits["panda_finger_joint2"].velocity == 0.2
    assert limits["panda_joint4"].upper == 0.0


def test_a_smooth_slow_track_has_no_violation() -> None:
    t = np.arange(90) / 30.0
    q = np.column_stack([0.3 * np.sin(t) + c for c in (0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0) * 2])
    assert limit_violations(_track(q)) == []


def test_a_step_too_fast_is_one_line_naming_the_arm_joint_time_value_and_limit() -> None:
    q = np.zeros((60, 14))
    q[30:, 7] = 2.35 / 30  # P2 panda_joint1 moves 2.35 rad/s for one step, from 1.0 s
    lines = limit_violations(_track(q))
    speed = [line for line in lines if "speed" in line]
    assert speed == ["P2 panda_joint1 at 1.000 s: speed 2.350 rad/s over its limit 2.175 rad/s"]
    assert any(line.startswith("P2 panda_joint1 at 0.967 s: acceleration") for line in lines)
    assert all(line.startswith("P2 panda_joint1") for line in lines)


def test_a_joint_past_its_range_is_reported() -> None:
    q = np.zeros((10, 14))
    q[:, 3] = 0.05  # P1 joint 4's range ends at 0
    assert limit_violations(_track(q)) == ["P1 panda_joint4 at 0.000 s: position 0.050 rad over its limit [-3.1416, 0] "
                                           "rad"]
