"""The grasp of a tool on a crowded table (:mod:`wecook_core.execution.world.grasping`) against the plain-Python
scene and arms of ``test_world_fake.py``: when a neighbour blocks every sample of a grasp's bounds, the last attempt
takes the grasp's looser bounds for a crowded table (``crowded`` in ``skills.yaml``); when something else blocks
them, it does not."""

from __future__ import annotations

import numpy as np
import pytest

from tests.execution.world.test_world_fake import (
    ACTION,
    OBJECTS,
    SKILLS,
    FakeArm,
    FakeScene,
    FakeWorld,
    ops,
    run,
    world,
)
from wecook_core.execution.schedule.program import ActionFailed
from wecook_core.execution.skills.tsr import contains
from wecook_core.execution.world.grasping import grasp_tsrs
from wecook_core.execution.world.placing import HAND_CLEAR_HEIGHT, HAND_SPAN
from wecook_core.model import Category
from wecook_core.plan import SceneObject

SPOON = next(o for o in OBJECTS if o.name == "spoon")
POT = SceneObject("pot", Category.CONTAINER, "cylinder", (0.12, 0.1, 0.12), 0.1005, 0.335)
"""A tall pot beside the spoon's handle (taken at x 0.1005), its near side 8.5 cm across from the handle's middle:
the palm of a hand taking the handle within the bounds meets it at every sample (0 of 3000 clear), one within the
looser bounds misses it at 3 in 10 (the stand-in crowded s304, a7: the spoon beside the bowl, 'in the way:
bowl' at every sample of three attempts)."""


class _Palm(FakeArm):
    """Reaches every pose whose palm (a bar :data:`HAND_SPAN` long across the fingers, at the ee, seen from above)
    meets nothing taller than :data:`HAND_CLEAR_HEIGHT` but what it is told to ignore; reports what was in the
    way as the PyBullet arm does."""

    def __init__(self, pid: str, scene: FakeScene):
        super().__init__(pid, scene)
        self.blockers: set[str] = set()

    def _in_the_way(self, T: np.ndarray, ignore) -> list[str]:
        along = np.linspace(-0.5, 0.5, 41)[:, None] * HAND_SPAN * T[:2, 1]
        bar = T[:2, 3] + along
        out = []
        for name, box in zip(self.scene.names(), self.scene.boxes(self.scene.names()), strict=True):
            if name in ignore or box[1, 2] <= HAND_CLEAR_HEIGHT:
                continue
            if np.any(np.all((bar >= box[0, :2]) & (bar <= box[1, :2]), axis=1)):
                out.append(name)
        return out

    def ik_goal(self, targets, ignore, check=True):
        for T in targets:
            found = self._in_the_way(T, ignore) if check else []
            if not found:
                return super().ik_goal([T], ignore, check)
            self.blockers.update(found)
        return None

    def no_goal(self, what, count, accept=None):
        blockers, self.blockers = sorted(self.blockers), set()
        return f"no collision-free {what} in {count} TSR samples (in the way: {', '.join(blockers)})"


def test_a_tool_crowded_out_by_a_neighbour_is_taken_with_the_looser_bounds_on_the_last_attempt():
    scene = FakeScene((SPOON, POT), inside={})
    w = FakeWorld(scene, {pid: _Palm(pid, scene) for pid in ("P1", "P2")})
    w.cell.samples = 12  # as the PyBullet world's
    run(w.primitives.grasp(ACTION, "P1", "spoon", lift=False))
    assert scene.hand("P1").carried == "spoon"
    retries = [c for c in ops(w, "P1") if c.startswith("retry")]
    assert len(retries) == 2 and all("(in the way: pot)" in c for c in retries)  # the bounds: blocked twice
    assert any("bounds for a crowded table" in text for _, level, text in scene.calls if level == "info")
    ee = scene.ees["P1"]
    assert not any(contains(r, ee) for r in grasp_tsrs(w.cell, "spoon", "P1"))  # outside the bounds
    assert any(contains(r, ee) for r in grasp_tsrs(w.cell, "spoon", "P1", crowded=True))
    assert not w.arms["P1"]._in_the_way(ee, ["spoon"])


def test_the_looser_bounds_are_not_tried_when_the_neighbour_is_not_what_blocks():
    """Out of reach (or blocked by the table, the other arm): looser bounds would not help, and are not tried."""
    w = world(P1={"reachable": lambda T: False})
    with pytest.raises(ActionFailed, match="no reachable grasp of knife"):
        run(w.primitives.grasp(ACTION, "P1", "knife"))
    assert not any("crowded" in text for _, _, text in w.scene.calls)


def test_the_grasps_of_tools_have_looser_bounds_for_a_crowded_table_containing_their_own():
    for spec in SKILLS.grasps["tool"]:
        assert spec.crowded is not None
        wide, own = np.array(spec.crowded), np.array(spec.bounds)
        assert np.all(wide[:, 0] <= own[:, 0]) and np.all(wide[:, 1] >= own[:, 1]) and not np.array_equal(wide, own)
        assert spec.on_a_crowded_table().bounds == spec.crowded and spec.on_a_crowded_table().crowded is None
