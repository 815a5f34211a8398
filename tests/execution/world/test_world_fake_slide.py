"""The slide of an engage (:mod:`wecook_core.execution.world.sliding`) against the plain-Python scene and arms of
``test_world_fake.py``: a rolling pin whose every pose over the dough rolls into the pot beside it is slid along
itself, clear of the pot, and the poses slid are tried clearest first."""

from __future__ import annotations

import dataclasses

import numpy as np

from tests.execution.world.test_world_fake import OBJECTS, SKILLS, FakeArm, FakeScene, FakeWorld, run
from wecook_core.execution.schedule.program import PathBlocked
from wecook_core.execution.world import actuating, sliding
from wecook_core.model import Category
from wecook_core.plan import PlanAction, SceneObject

PIN = SceneObject("rolling_pin", Category.TOOL, "box", (0.24, 0.04, 0.04), 0.15, 0.2)
DOUGH = SceneObject("dough", Category.INGREDIENT, "box", (0.06, 0.05, 0.03), 0.1, 0.0)
POT = SceneObject("pot", Category.CONTAINER, "cylinder", (0.1, 0.1, 0.12), -0.1, 0.0)
"""A tall pot on the line of sight from P2 to the dough, its near side 15 cm from the dough's middle: the pin
lying along that line, 12 cm either side of the dough, reaches it at each 3 cm stroke (scaled s302 x0.8, a12:
'the straight path collides with pot' at every pose of three attempts)."""
ROLES = {"tool": "rolling_pin", "ingredient": "dough", "location": "dough", "source": None}


class _Pot(FakeArm):
    """Its straight paths are blocked where the carried tool, seen from above, comes within ``margin`` of the
    pot (the tool's long axis, less its half width)."""

    def cartesian_path(self, q, poses, ignore, what, margin=-0.01):
        riding = self.scene.hand(self.pid).riding
        if riding:
            tool = riding[0]
            half = np.array(self.scene.size(tool.name)) / 2
            pot = self.scene.boxes(["pot"])[0][:, :2]
            for T in poses:
                E = T @ tool.T_ee_obj
                points = E[:2, 3] + np.linspace(-half[0], half[0], 25)[:, None] * E[:2, 0]
                gap = np.maximum(np.maximum(pot[0] - points, points - pot[1]), 0.0)
                if float(np.hypot(gap[:, 0], gap[:, 1]).min()) - half[1] < margin:
                    raise PathBlocked(f"{what}: the straight path collides with pot")
        return super().cartesian_path(q, poses, ignore, what, margin)


def _world() -> FakeWorld:
    scene = FakeScene((*(o for o in OBJECTS if o.name in ("knife", "spoon")), PIN, DOUGH, POT), inside={})
    w = FakeWorld(scene, {pid: _Pot(pid, scene) for pid in ("P1", "P2")})
    action = PlanAction("a12", ("P2",), "roll", "rolling_pin", ("dough",))
    run(w.primitives.grasp(action, "P2", "rolling_pin"))
    return w


def _from_the_hand(w: FakeWorld, G: np.ndarray) -> tuple[float, float]:
    """Where the dough's middle lies along the pin taken at ``G`` (from the pin's middle) and how far the hand is
    from it, metres."""
    carrier = w.scene.hand("P2").riding[0]
    pin = G @ carrier.T_ee_obj
    along = float(pin[:3, 0] @ (w.scene.pose("dough")[:3, 3] - pin[:3, 3]))
    return along, abs(along - float(np.linalg.inv(carrier.T_ee_obj)[0, 3]))


def test_a_pin_whose_every_pose_rolls_into_a_pot_is_slid_along_itself_clear_of_it(monkeypatch):
    """The pin turned to lie within 10 degrees of the line of sight, its hand away from the pot (as in s302, where
    a bowl and a plate beside the dough left no other way): every pose meets the pot."""
    w = _world()
    engage, strokes = SKILLS.skills["roll"].steps
    bounds = list(engage.tsr.bounds)
    bounds[5] = (np.radians(80), np.radians(90))
    engage = dataclasses.replace(engage, tsr=dataclasses.replace(engage.tsr, bounds=tuple(bounds)))
    w.cell.samples *= sliding.SLIDE_SAMPLES
    with monkeypatch.context() as unslid:  # as many samples as the slide draws, none slid: none passes
        unslid.setattr(sliding, "SLIDE", 0.0)
        assert actuating.engage_goal(w.cell, "P2", engage.tsr, ROLES, None, None, strokes).q is None
    w.cell.samples //= sliding.SLIDE_SAMPLES
    goal = actuating.engage_goal(w.cell, "P2", engage.tsr, ROLES, None, None, strokes)
    assert goal.q is not None and 0.0 < goal.slide <= sliding.SLIDE and goal.margin == actuating.CLEAR_MARGIN
    along, hand = _from_the_hand(w, w.arms["P2"].goals[goal.q.tobytes()])
    grip = abs(float(np.linalg.inv(w.scene.hand("P2").riding[0].T_ee_obj)[0, 3]))
    assert abs(along) + 0.03 <= 0.12  # the dough (3 cm) still under the pin (12 cm)
    assert abs(hand - (grip + goal.slide)) < 1e-9  # and as much farther from the hand as the pin slid


def test_the_poses_slid_come_clearest_first_and_keep_the_ingredient_on_the_tool():
    w = _world()
    scene = w.scene
    engage, strokes = SKILLS.skills["roll"].steps
    carrier = scene.hand("P2").riding[0]
    sizes = {"f": scene.half("dough"), "t": scene.half("rolling_pin"), "i": scene.half("dough"),
             "l": scene.half("dough")}
    goals = w.arms["P2"].goal_samples([engage.tsr.tsr(scene.facing("dough", "P2"), sizes)],
                                      np.linalg.inv(carrier.T_ee_obj), 24)
    neighbours = ["pot", "knife", "spoon"]

    def path(G: np.ndarray) -> list:
        return actuating.actuation_waypoints(scene, "P2", strokes, ROLES, G, 0)

    moved = sliding.slid(scene, "P2", strokes, ROLES, goals, path, neighbours)
    assert len(moved) == len(goals)  # the pin is long: every pose may slide
    room = [sliding.clearance(scene, "rolling_pin", [wp.pose for wp in path(G)], scene.boxes(neighbours))
            for G, _ in moved]
    assert room == sorted(room, reverse=True) and room[0] > room[-1] + 0.01
    grip = abs(float(np.linalg.inv(carrier.T_ee_obj)[0, 3]))
    assert sorted({round(m / min(m for _, m in moved), 6) for _, m in moved}) == [1.0, 2.0, 3.0, 4.0]  # quarters
    for G, metres in moved:
        assert 0.0 < metres <= sliding.SLIDE + 1e-12
        along, hand = _from_the_hand(w, G)
        assert abs(along) + 0.03 <= 0.12 + 1e-9  # the dough (3 cm half length) still under the pin (12 cm)
        assert abs(hand - (grip + metres)) < 1e-9  # farther from the hand by the slide
