"""Where a carried object is put down on a free spot (:func:`wecook_core.execution.world.placing.free_poses`),
against the plain-Python scene of ``test_world_fake.py``: never where the fingers taking another tool reach down,
nor where its own fingers would meet another object (a spoon put down across the whisk's handle left neither to
be taken, in a scenario's run)."""

from __future__ import annotations

import math

import numpy as np

from tests.execution.world.test_world_fake import SKILLS, FakeArm, FakeScene
from wecook_core.execution.skills.tsr import TSR, xyzrpy_to_matrix
from wecook_core.execution.world.placing import FINGERS_ALONG, FINGERS_OUT, free_poses
from wecook_core.execution.world.protocols import Cell
from wecook_core.model import Category
from wecook_core.plan import SceneObject

WHISK = SceneObject("whisk", Category.TOOL, "box", (0.26, 0.05, 0.02), 0.0, 0.0)
SPOON = SceneObject("spoon", Category.TOOL, "box", (0.18, 0.03, 0.02), 0.5, 0.5)
HANDLE = WHISK.x - 0.55 * WHISK.size[0] / 2
"""Where the whisk is taken (x)."""
BOX = tuple[np.ndarray, np.ndarray]


def _cell(*objects: SceneObject) -> Cell:
    scene = FakeScene(objects, inside={})
    return Cell(scene, {pid: FakeArm(pid, scene) for pid in scene.bases}, SKILLS)


def _across_the_handle(dx: float) -> TSR:
    """Spoon poses lying along y, their end 1.5 cm from the whisk's edge, within ``dx`` of its handle (x): as
    roomy as each other."""
    T0 = xyzrpy_to_matrix([HANDLE, WHISK.size[1] / 2 + 0.015 + SPOON.size[0] / 2, 0.01, 0, 0, 0])
    return TSR(T0, np.eye(4), np.array([[-dx, dx], [0, 0], [0, 0], [0, 0], [0, 0], [math.pi / 2, math.pi / 2]]))


def _world_box(T: np.ndarray, corners: np.ndarray) -> BOX:
    pts = corners @ T[:2, :2].T + T[:2, 3]
    return pts.min(axis=0), pts.max(axis=0)


def _footprint(tool: SceneObject, T: np.ndarray) -> BOX:
    hx, hy = tool.size[0] / 2, tool.size[1] / 2
    return _world_box(T, np.array([[sx * hx, sy * hy] for sx in (-1, 1) for sy in (-1, 1)]))


def _fingers(tool: SceneObject, T: np.ndarray) -> BOX:
    """Where the fingers taking ``tool`` at pose ``T`` by its handle reach down to the table."""
    grip, reach = -0.55 * tool.size[0] / 2, tool.size[1] / 2 + FINGERS_OUT
    return _world_box(T, np.array([[grip + sx * FINGERS_ALONG, sy * reach] for sx in (-1, 1) for sy in (-1, 1)]))


def _overlap(a: BOX, b: BOX) -> bool:
    return bool(np.all(a[0] < b[1]) and np.all(b[0] < a[1]))


WHISK_AT = xyzrpy_to_matrix([WHISK.x, WHISK.y, 0.01, 0, 0, 0])


def test_a_tool_is_not_put_down_where_the_fingers_taking_the_tool_beside_it_reach_down() -> None:
    region = _across_the_handle(0.06)
    spots = free_poses(_cell(WHISK, SPOON), "spoon", region)
    assert not _overlap(_footprint(SPOON, spots[0]), _fingers(WHISK, WHISK_AT))  # the whisk can be taken
    assert not _overlap(_fingers(SPOON, spots[0]), _footprint(WHISK, WHISK_AT))  # and the spoon again
    # the region's middle, as roomy as the rest, lies across the whisk's handle
    assert _overlap(_footprint(SPOON, region.T0_w @ xyzrpy_to_matrix([0, 0, 0, 0, 0, math.pi / 2])),
                    _fingers(WHISK, WHISK_AT))


def test_a_spot_in_the_fingers_way_is_still_offered_last() -> None:
    """When the whole region is in the way, its spots are still given (the last resort, not nothing)."""
    spots = free_poses(_cell(WHISK, SPOON), "spoon", _across_the_handle(0.02))
    assert spots
    assert all(_overlap(_footprint(SPOON, T), _fingers(WHISK, WHISK_AT)) for T in spots)
