"""The roles of the world (:mod:`wecook_core.execution.world`) against the plain-Python scene and arms of
``test_world_fake.py``, run by the real scheduler or step by step: an individual action's primitives, a holder
waiting for its partner, a handover's order, the recovery of a failed role."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.execution.world.test_world_fake import (
    ACTION,
    OBJECTS,
    FakeArm,
    FakeScene,
    FakeWorld,
    ops,
    run,
    until_waiting,
    world,
)
from wecook_core.execution.schedule.executor import run_schedule
from wecook_core.execution.schedule.program import WAIT, ActionFailed, Meeting
from wecook_core.model import Category
from wecook_core.plan import Act, Plan, PlanAction, SceneObject, agents_for
from wecook_core.plan import Scene as PlanScene


def test_an_individual_action_grasps_engages_actuates_puts_back_and_goes_home():
    w = world()
    results = run_schedule(Plan(agents_for(["P1", "P2"]), PlanScene(OBJECTS), (ACTION,)), w)
    assert [r.status for r in results] == ["done"], results
    starts = [what.split()[0] for p, op, what in w.scene.calls if p == "P1" and op == "primitive_start"]
    assert starts == ["grasp", "engage", "actuate", "place"]
    assert ops(w, "P1")[-1] == "home" and w.scene.hand("P1").carried is None
    assert np.linalg.norm(w.scene.pose("spoon")[:2, 3] - [0.15, 0.2]) < 0.02  # back on its spot


def test_a_holder_grasps_only_once_the_actor_has_its_tool_and_lets_go_only_once_it_has_acted():
    w = world()
    action = PlanAction("h", ("P1", "P2"), "holding", "bowl", partner=Act("stir", "spoon", (), "bowl"))
    meeting = Meeting(frozenset(action.pids))
    holder = w.roles.program(action, "P1", meeting)
    until_waiting(holder)
    for _ in range(50):
        assert next(holder) == WAIT
    assert w.scene.hand("P1").carried is None and not [c for c in ops(w, "P1") if c.startswith("primitive")]
    meeting.signal("tool_ready")
    until_waiting(holder)
    assert w.scene.hand("P1").carried == "bowl" and meeting.signals == {"tool_ready", "held"}
    assert [c for c in ops(w, "P1") if c.startswith("primitive_start")] == ["primitive_start hold bowl"]
    for _ in range(50):
        assert next(holder) == WAIT
    assert w.scene.hand("P1").carried == "bowl"
    meeting.signal("acted")
    run(holder)
    assert w.scene.hand("P1").carried is None and ops(w, "P1")[-1] == "home"


@pytest.mark.parametrize(("inside", "held"), [({"cucumber": "board"}, "board"), ({}, "cucumber")])
def test_food_held_for_a_partner_is_held_by_the_board_it_lies_on(inside: dict[str, str], held: str):
    """A gripper closed on a cucumber covers it and leaves the partner's knife nowhere to cut: food lying on a
    board is held steady by the board; food lying on the table, by itself."""
    objects = (*OBJECTS, SceneObject("board", Category.CONTAINER, "box", (0.28, 0.16, 0.02), 0.0, -0.1),
               SceneObject("cucumber", Category.INGREDIENT, "box", (0.06, 0.04, 0.03), 0.0, -0.1))
    scene = FakeScene(objects, inside={"rice": "bowl", **inside})
    w = FakeWorld(scene, {pid: FakeArm(pid, scene) for pid in ("P1", "P2")})
    action = PlanAction("h", ("P1", "P2"), "holding", "cucumber", partner=Act("cut", "knife", (), "board"))
    meeting = Meeting(frozenset(action.pids))
    holder = w.roles.program(action, "P1", meeting)
    until_waiting(holder)
    meeting.signal("tool_ready")
    until_waiting(holder)
    assert scene.hand("P1").carried == held and meeting.signals == {"tool_ready", "held"}
    meeting.signal("acted")
    run(holder)
    assert scene.hand("P1").carried is None


def test_a_holder_whose_partner_fails_stops_waiting_with_the_partners_reason():
    w = world()
    action = PlanAction("h", ("P1", "P2"), "holding", "bowl", partner=Act("stir", "spoon", (), "bowl"))
    meeting = Meeting(frozenset(action.pids))
    holder = w.roles.program(action, "P1", meeting)
    until_waiting(holder)
    meeting.fail("stir: no path")
    with pytest.raises(ActionFailed, match="partner failed: stir: no path"):
        run(holder)


def test_a_handover_mid_air_goes_grasp_meet_take_let_go_then_put_down_in_that_order():
    w = world()
    handover = PlanAction("h", ("P1", "P2"), "handover", "knife")
    results = run_schedule(Plan(agents_for(["P1", "P2"]), PlanScene(OBJECTS), (handover,)), w)
    assert [r.status for r in results] == ["done"], results
    steps = [(p, op, what) for p, op, what in w.scene.calls
             if op in ("primitive_end", "attach", "detach", "home", "margin")]
    assert steps == [
        ("P1", "attach", "knife"), ("P1", "primitive_end", "grasp knife"), ("P1", "primitive_end", "engage meet"),
        ("P2", "margin", "0.0"), ("P2", "attach", "knife"), ("P2", "primitive_end", "take knife"),
        ("P2", "margin", "back"), ("P1", "detach", "knife"), ("P1", "home", ""),
        ("P2", "detach", "knife"), ("P2", "primitive_end", "place knife"), ("P2", "home", "")]
    assert w.scene.hand("P1").carried is None and w.scene.hand("P2").carried is None
    assert w.scene.pose("knife")[0, 3] > 0.0  # put down on the receiver's side


@pytest.mark.slow
def test_a_failed_role_is_recovered_the_object_put_back_near_where_it_was_picked_up():
    w = world()
    action = PlanAction("a1", ("P1",), "stir", "spoon", (), "bowl")
    w.arms["P1"].reachable = lambda T: T[2, 3] < 0.12  # the spoon, yes; no engage pose over the bowl
    results = run_schedule(Plan(agents_for(["P1", "P2"]), PlanScene(OBJECTS), (action,)), w)
    assert results[0].status == "failed" and results[0].reason.startswith("engage facing:location: ")
    assert w.scene.hand("P1").carried is None and ops(w, "P1")[-1] == "home"
    assert np.linalg.norm(w.scene.pose("spoon")[:2, 3] - [0.15, 0.2]) <= 0.12 * math.sqrt(2) + 1e-9


def test_a_tool_found_tilted_is_put_back_lying_flat_where_it_was():
    """A whisk pushed onto the spoon beside it rests tilted; put back at that pose, the hand holding it meets the
    table. It goes back where it lay, turned as it lay, flat on the table."""
    w = world()
    tilted = w.scene.poses["spoon"].copy()
    lean = math.radians(25)
    tilted[:3, :3] = tilted[:3, :3] @ np.array([[1, 0, 0], [0, math.cos(lean), -math.sin(lean)],
                                                 [0, math.sin(lean), math.cos(lean)]])
    tilted[2, 3] += 0.008
    w.scene.poses["spoon"] = tilted
    results = run_schedule(Plan(agents_for(["P1", "P2"]), PlanScene(OBJECTS), (ACTION,)), w)
    assert [r.status for r in results] == ["done"], results
    after = w.scene.pose("spoon")
    assert after[2, 2] > 0.999  # flat
    assert np.linalg.norm(after[:2, 3] - tilted[:2, 3]) < 0.02  # where it lay
    assert abs(after[2, 3] - 0.01) < 0.01  # on the table (half its height up)
    assert abs(math.atan2(after[1, 0], after[0, 0]) - math.atan2(tilted[1, 0], tilted[0, 0])) <= 0.1  # turned so
