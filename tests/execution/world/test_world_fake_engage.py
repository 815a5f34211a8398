"""The engage primitive of the world (:mod:`wecook_core.execution.world`) against the plain-Python scene and arms
of ``test_world_fake.py``: its goal is a query (it reads and reports nothing), the engage acts on it."""

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
from wecook_core.execution.schedule.program import ActionFailed, PathBlocked
from wecook_core.execution.skills.library import evaluate
from wecook_core.execution.skills.motions import actuation_path
from wecook_core.execution.world import actuating
from wecook_core.model import Category
from wecook_core.plan import PlanAction, SceneObject


def test_the_engage_goal_is_a_query_and_engage_keeps_the_axis_it_chose():
    w = world()
    run(w.primitives.grasp(ACTION, "P1", "spoon"))
    engage, stir = SKILLS.skills["stir"].steps
    roles = {"tool": "spoon", "ingredient": "bowl", "location": "bowl", "source": None}
    hands = [(h.carried, [r.name for r in h.riding]) for h in w.scene.hands.values()]
    ee, calls = w.scene.ees["P1"].copy(), len(w.scene.calls)
    goal = actuating.engage_goal(w.cell, "P1", engage.tsr, roles, None, None, stir)
    assert goal.q is not None and goal.variant == 0 and goal.reason == "" and goal.unreached is None
    assert w.primitives.variants == {} and np.array_equal(w.scene.ees["P1"], ee) and len(w.scene.calls) == calls
    assert [(h.carried, [r.name for r in h.riding]) for h in w.scene.hands.values()] == hands
    run(w.primitives.engage(ACTION, "P1", engage.tsr, roles, then=stir))
    assert w.primitives.variants == {"P1": 0} and ops(w, "P1")[-2:] == ["transit engage",
                                                                        "primitive_end engage facing:location"]
    assert not np.array_equal(w.scene.ees["P1"], ee)


def test_an_engage_goal_out_of_reach_says_so_and_only_engage_reports_it():
    w = world()
    run(w.primitives.grasp(ACTION, "P1", "spoon"))
    w.arms["P1"].reachable = lambda T: False
    engage, stir = SKILLS.skills["stir"].steps
    roles = {"tool": "spoon", "ingredient": "bowl", "location": "bowl", "source": None}
    goal = actuating.engage_goal(w.cell, "P1", engage.tsr, roles, None, None, stir)
    assert goal.q is None and goal.unreached == w.cell.samples and "no goal facing:location" not in ops(w, "P1")
    with pytest.raises(ActionFailed, match=r"engage facing:location: no reachable pose at facing:location in 6 "):
        run(w.primitives.engage(ACTION, "P1", engage.tsr, roles, then=stir))
    assert ops(w, "P1").count("no goal pose at facing:location") == w.cell.attempts


def test_a_stir_in_a_low_pan_goes_no_deeper_than_the_table_lets_the_spoon():
    """The stir's depth is set for a bowl; in a pan 3 cm deep the tilted spoon's tip would pass through the pan's
    floor into the table. The spoon's lowest corner keeps TABLE_CLEARANCE above the table all the way round."""
    pan = SceneObject("pan", Category.CONTAINER, "cylinder", (0.2, 0.2, 0.03), 0.1, -0.1)
    scene = FakeScene((*(o for o in OBJECTS if o.name != "bowl"), pan), inside={"rice": "pan"})
    w = FakeWorld(scene, {pid: FakeArm(pid, scene) for pid in ("P1", "P2")})
    action = PlanAction("a1", ("P1",), "stir", "spoon", (), "pan")
    run(w.primitives.grasp(action, "P1", "spoon"))
    engage, stir = SKILLS.skills["stir"].steps
    roles = {"tool": "spoon", "ingredient": "pan", "location": "pan", "source": None}
    run(w.primitives.engage(action, "P1", engage.tsr, roles, then=stir))
    ee = scene.ees["P1"]
    half = np.array(scene.objects["spoon"].size) / 2

    def lowest(poses: list[np.ndarray]) -> float:
        return min(float(T[2, 3] - np.abs(T[2, :3]) @ half) for T in poses)

    path = actuating.actuation_waypoints(scene, "P1", stir, roles, ee, 0)
    assert lowest([wp.pose for wp in path]) >= scene.table_height + actuating.TABLE_CLEARANCE - 1e-9
    T_ee_spoon = scene.hand("P1").riding[0].T_ee_obj
    sizes = {"t": scene.half("spoon"), "i": scene.half("pan"), "l": scene.half("pan"), "f": scene.half("pan")}
    params = {k: evaluate(v, sizes) for k, v in stir.params.items()}
    as_asked = actuation_path("circle", params, ee @ T_ee_spoon, scene.facing("pan", "P1")[:3, :3])
    assert lowest([wp.pose for wp in as_asked]) < scene.table_height  # the skill's own depth would hit the table
    assert lowest([wp.pose for wp in path]) == pytest.approx(actuating.TABLE_CLEARANCE, abs=1e-6)  # still low


def test_a_scoop_engages_a_centimetre_and_the_tools_thickness_above_the_food_on_a_board():
    """The spoon's tip comes over the board's middle pointing down at 45 degrees before it scoops: with the meat
    lying there, its lowest corner stays a centimetre above the meat (it grazed it, and every engage pose was
    'in the way: meat (touched by the spoon)', in a held-out stand-in's run)."""
    board = SceneObject("board", Category.CONTAINER, "box", (0.29, 0.14, 0.02), 0.0, -0.1)
    meat = SceneObject("meat", Category.INGREDIENT, "box", (0.04, 0.04, 0.03), 0.0, -0.1)
    scene = FakeScene((*OBJECTS, board, meat), inside={"rice": "bowl", "meat": "board"})
    scene.poses["meat"][2, 3] = 0.02 + 0.015  # on the board
    w = FakeWorld(scene, {pid: FakeArm(pid, scene) for pid in ("P1", "P2")})
    action = PlanAction("a9", ("P1",), "transfer", "spoon", ("meat",), "bowl", "board")
    run(w.primitives.grasp(action, "P1", "spoon"))
    engage = SKILLS.skills["transfer"].steps[0]
    roles = {"tool": "spoon", "ingredient": "meat", "location": "bowl", "source": "board"}
    half = np.array(scene.objects["spoon"].size) / 2
    T_ee_spoon = scene.hand("P1").riding[0].T_ee_obj
    for _ in range(10):
        goal = actuating.engage_goal(w.cell, "P1", engage.tsr, roles, None, None, None)
        assert goal.q is not None
        spoon = w.arms["P1"].goals[goal.q.tobytes()] @ T_ee_spoon
        lowest = float(spoon[2, 3] - np.abs(spoon[2, :3]) @ half)
        assert lowest >= 0.02 + 0.03 + 0.01 - 1e-6  # the meat's top, and a centimetre


def test_a_rolling_pin_may_lie_across_the_dough_any_way_round():
    """A pin rolls dough the same whichever way it lies; with neighbours at both sides of the dough, the only way
    clear is along the arm's line of sight (a bowl and a pot 14 cm either side blocked every pose of s302's roll
    at +-60 degrees)."""
    pin = SceneObject("rolling_pin", Category.TOOL, "box", (0.24, 0.04, 0.04), 0.15, 0.2)
    dough = SceneObject("dough", Category.INGREDIENT, "box", (0.06, 0.05, 0.03), 0.1, 0.0)
    scene = FakeScene((*OBJECTS, pin, dough), inside={})
    w = FakeWorld(scene, {pid: FakeArm(pid, scene) for pid in ("P1", "P2")})
    action = PlanAction("a12", ("P2",), "roll", "rolling_pin", ("dough",))
    run(w.primitives.grasp(action, "P2", "rolling_pin"))
    T_ee_pin = scene.hand("P2").riding[0].T_ee_obj

    def along_the_line_of_sight(T: np.ndarray) -> bool:
        axis = (T @ T_ee_pin)[:3, 0]
        return abs(axis[0]) > np.cos(np.radians(25))

    w.arms["P2"].reachable = along_the_line_of_sight
    engage, strokes = SKILLS.skills["roll"].steps
    roles = {"tool": "rolling_pin", "ingredient": "dough", "location": "dough", "source": None}
    goal = actuating.engage_goal(w.cell, "P2", engage.tsr, roles, None, None, strokes)
    assert goal.q is not None, goal


class _Neighbourly(FakeArm):
    """Its first goal's actuation passes 1 mm into a neighbour, every later goal's keeps 3 mm from it."""

    def cartesian_path(self, q, poses, ignore, what, margin=-0.01):
        distance = -0.001 if q[3] == 0 else 0.003
        if distance < margin:
            raise PathBlocked(f"{what}: the straight path collides with knife")
        return super().cartesian_path(q, poses, ignore, what, margin)


def test_an_actuation_keeps_clear_of_its_neighbours_when_a_pose_lets_it():
    """A knife sawing meat 3 cm from a whisk passed 1 mm into it at each stroke (taken as clear) and walked it
    1 cm away, onto its edge (s304 run seed 0). A pose whose path keeps clear of every neighbour comes before one
    that touches one; one that touches before one that grazes."""
    scene = FakeScene()
    w = FakeWorld(scene, {pid: _Neighbourly(pid, scene) for pid in ("P1", "P2")})
    run(w.primitives.grasp(ACTION, "P1", "spoon"))
    engage, stir = SKILLS.skills["stir"].steps
    roles = {"tool": "spoon", "ingredient": "bowl", "location": "bowl", "source": None}
    goal = actuating.engage_goal(w.cell, "P1", engage.tsr, roles, None, None, stir)
    assert goal.q is not None and goal.q[3] != 0 and goal.margin == actuating.CLEAR_MARGIN > 0
    only = FakeWorld(scene, {pid: _Neighbourly(pid, scene, reachable=lambda T, n=[0]: n.append(1) or len(n) == 2)
                             for pid in ("P1", "P2")})  # one goal only, the touching one
    goal = actuating.engage_goal(only.cell, "P1", engage.tsr, roles, None, None, stir)
    assert goal.q is not None and goal.margin == actuating.TOUCH_MARGIN
