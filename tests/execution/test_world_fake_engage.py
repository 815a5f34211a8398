"""The engage primitive of the world (:mod:`wecook_core.execution.world`) against the plain-Python scene and arms
of ``test_world_fake.py``: its goal is a query (it reads and reports nothing), the engage acts on it."""

from __future__ import annotations

import numpy as np
import pytest

from tests.execution.test_world_fake import ACTION, SKILLS, ops, run, world
from wecook_core.execution.program import ActionFailed
from wecook_core.execution.world import actuating


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
