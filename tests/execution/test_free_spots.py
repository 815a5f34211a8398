"""Where a carried object is put down on a free spot (:func:`wecook_core.execution.world.placing.free_poses`),
against the plain-Python scene of ``test_world_fake.py``: it leaves a hand room to take it again, and leaves the
others' hands room to take them (a spoon put down across the whisk's handle left neither to be
taken, in a scenario's run)."""

from __future__ import annotations

import numpy as np
from test_world_fake import SKILLS, FakeArm, FakeScene

from wecook_core.execution.tsr import TSR
from wecook_core.execution.world.placing import HAND_SPAN, free_poses
from wecook_core.execution.world.protocols import Cell
from wecook_core.model import Category
from wecook_core.plan import SceneObject

WHISK = SceneObject("whisk", Category.TOOL, "box", (0.26, 0.05, 0.02), 0.0, 0.0)
SPOON = SceneObject("spoon", Category.TOOL, "box", (0.18, 0.03, 0.02), 0.5, 0.5)


def _cell(*objects: SceneObject) -> Cell:
    scene = FakeScene(objects, inside={})
    return Cell(scene, {pid: FakeArm(pid, scene) for pid in scene.bases}, SKILLS)


def _region() -> TSR:
    """Object poses beside the whisk, yaw 0: x within 20 cm of its centre, y 5-10 cm from it (no spot is 10 cm
    clear of it, so the roomiest are the farthest out, across the width of the whisk's handle)."""
    bounds = np.array([[-0.2, 0.2], [0.05, 0.10], [0.01, 0.01], [0, 0], [0, 0], [0, 0]])
    return TSR(np.eye(4), np.eye(4), bounds)


def _handle_hand(whisk: SceneObject) -> tuple[np.ndarray, np.ndarray]:
    """The world box of a hand taking the whisk by its handle (HAND_SPAN across it, 6 cm along)."""
    x = whisk.x - 0.55 * whisk.size[0] / 2
    return np.array([x - 0.03, whisk.y - HAND_SPAN / 2]), np.array([x + 0.03, whisk.y + HAND_SPAN / 2])


def _overlaps(centre: np.ndarray, size: tuple[float, float, float], box: tuple[np.ndarray, np.ndarray]) -> bool:
    lo, hi = centre - np.array(size[:2]) / 2, centre + np.array(size[:2]) / 2
    return bool(np.all(lo < box[1]) and np.all(box[0] < hi))


def test_a_flat_tool_is_not_put_down_where_the_hand_taking_the_tool_beside_it_goes() -> None:
    cell = _cell(WHISK, SPOON)
    spots = free_poses(cell, "spoon", _region())
    assert spots
    first = spots[0][:2, 3]
    assert not _overlaps(first, SPOON.size, _handle_hand(WHISK))
    # and a hand taking the spoon again by its handle does not come down on the whisk
    spoon = SceneObject("spoon", Category.TOOL, "box", SPOON.size, float(first[0]), float(first[1]))
    whisk_box = (np.array([WHISK.x - WHISK.size[0] / 2, WHISK.y - WHISK.size[1] / 2]),
                 np.array([WHISK.x + WHISK.size[0] / 2, WHISK.y + WHISK.size[1] / 2]))
    lo, hi = _handle_hand(spoon)
    assert not (np.all(lo < whisk_box[1]) and np.all(whisk_box[0] < hi))

def test_a_spot_in_every_hand_s_way_is_still_offered_last() -> None:
    """When the region is all in the way, its spots are still given (the roomiest last resort, not nothing)."""
    cell = _cell(WHISK, SPOON)
    narrow = TSR(np.eye(4), np.eye(4),
                 np.array([[-0.10, -0.10], [0.06, 0.08], [0.01, 0.01], [0, 0], [0, 0], [0, 0]]))
    spots = free_poses(cell, "spoon", narrow)
    assert spots
    assert all(_overlaps(T[:2, 3], SPOON.size, _handle_hand(WHISK)) for T in spots)

