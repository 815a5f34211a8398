"""Sliding food off a plate into a bowl (a tipping transfer from a container whose rim is lower than the food):
tipped only just past the vertical, which the wrist reaches (at 135 degrees, as a bowl is tipped, no sample of
s303's plate was feasible)."""

from __future__ import annotations

import pytest

from tests.execution.bullet.test_simulation import Recorder
from wecook_core.execution.bullet.world import BulletWorld
from wecook_core.execution.schedule.executor import run_schedule
from wecook_core.execution.skills.library import evaluate, load_skills
from wecook_core.model import Category
from wecook_core.plan import Plan, PlanAction, Scene, SceneObject, agents_for
from wecook_core.plan.layout import _shape_for

PLATE = _shape_for("plate", Category.CONTAINER, 0.1, 0.1)
BOWL = _shape_for("bowl", Category.CONTAINER, 0.1, 0.1)
ONION = _shape_for("onion", Category.INGREDIENT, 0.04, 0.04)


def tilt_angle(carrier: tuple[float, float, float], content: tuple[float, float, float]) -> float:
    from wecook_core.execution.skills.library import Half

    step = load_skills().skills["transfer_tipping"].steps[-1]
    sizes = {"t": Half(*(v / 2 for v in carrier)), "i": Half(*(v / 2 for v in content))}
    return evaluate(step.params["angle"], sizes)


def test_a_plate_is_tipped_just_past_the_vertical_and_a_bowl_until_its_wall_slopes_past_friction() -> None:
    assert tilt_angle(PLATE[1], ONION[1]) == pytest.approx(100.0)
    assert tilt_angle(BOWL[1], ONION[1]) == pytest.approx(135.0)


@pytest.mark.sim
@pytest.mark.parametrize("seed", [0])
def test_the_onion_slides_off_a_plate_into_the_bowl(seed: int) -> None:
    objects = (SceneObject("plate", Category.CONTAINER, PLATE[0], PLATE[1], 0.0, -0.2),
               SceneObject("onion", Category.INGREDIENT, ONION[0], ONION[1], 0.0, -0.2),
               SceneObject("bowl", Category.CONTAINER, BOWL[0], BOWL[1], -0.07, 0.2))
    plan = Plan(agents=agents_for(["P1", "P2"]), scene=Scene(objects=objects, containing=(("onion", "plate"),)),
                actions=(PlanAction("a1", ("P1",), "transfer", "plate", ("onion",), "bowl", "plate"),))
    world = BulletWorld(plan, Recorder(), seed=seed, images=False)
    try:
        results = run_schedule(plan, world)
        assert results[0].status == "done", results
        assert world.scene.container_of("onion") == "bowl"
        assert world.scene.pose("plate")[2, 2] > 0.99  # put back upright
    finally:
        world.close()
