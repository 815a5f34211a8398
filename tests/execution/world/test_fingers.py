"""How wide the fingers open to pass down around what they take (:mod:`wecook_core.execution.world.fingers`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wecook_core.execution.world.fingers import (
    FINGER_CLEARANCE,
    FINGER_HALF_WIDTH,
    FULL_OPEN,
    half_span,
    open_around,
)

TOOL = np.array([0.12, 0.015, 0.0125])
"""Half extents of a knife."""


def _pose(x: float = 0.0, y: float = 0.0, z: float = 0.0125, yaw: float = 0.0, roll: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    c, s = math.cos(yaw), math.sin(yaw)
    Rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    c, s = math.cos(roll), math.sin(roll)
    Rx = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    T[:3, :3] = Rz @ Rx
    T[:3, 3] = [x, y, z]
    return T


def _from_above(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """A grasp pose at (x, y, z), approach straight down, the fingers across the world's y turned by ``yaw``."""
    G = _pose(x, y, z, yaw)
    G[:3, :3] = G[:3, :3] @ np.diag([1.0, -1.0, -1.0])  # z down
    return G


def test_a_tool_taken_straight_across_is_as_wide_as_it_is_and_the_fingers_open_as_the_grip_says():
    G = _from_above(-0.066, 0.0, 0.0205)
    assert half_span(_pose(), TOOL, G) == pytest.approx(0.015)
    assert open_around(_pose(), TOOL, G, 0.019) == 0.019


def test_a_tool_taken_turned_is_wider_across_the_fingers_by_their_width():
    turn = math.radians(25)
    G = _from_above(-0.066, 0.0, 0.0205, turn)
    expected = 0.015 / math.cos(turn) + FINGER_HALF_WIDTH * math.tan(turn)
    assert half_span(_pose(), TOOL, G) == pytest.approx(expected)
    assert open_around(_pose(), TOOL, G, 0.019) == pytest.approx(expected + FINGER_CLEARANCE)


def test_a_tool_rolled_on_its_edge_is_wider_across_than_its_width():
    lean = math.radians(45)
    pose = _pose(z=(0.015 + 0.0125) * math.sin(lean), roll=lean)
    G = _from_above(-0.066, 0.0, pose[2, 3] + 0.0045)
    assert half_span(pose, TOOL, G) == pytest.approx((0.015 + 0.0125) * math.sin(lean), abs=1e-6)


def test_what_lies_outside_the_fingers_takes_no_room_and_the_opening_is_bounded():
    G = _from_above(0.5, 0.5, 0.02)
    assert half_span(_pose(), TOOL, G) == 0.0
    huge = np.array([0.2, 0.2, 0.05])
    assert open_around(_pose(), huge, _from_above(0.0, 0.0, 0.05), 0.019) == FULL_OPEN
