"""The physics mode (`execute --dynamics`): the joints driven by position control within the URDF's limits, a
taken object held by the fingers' friction (no constraint), the recording within the joint limits."""

from __future__ import annotations

from pathlib import Path
from unittest import mock

import pybullet
import pytest

from wecook_core.execution.run import execute_plan
from wecook_core.model import Category
from wecook_core.plan import DEFAULT_ROBOT, Agent, Plan, PlanAction, Scene, SceneObject, Table
from wecook_core.recording.check import check_recording
from wecook_core.recording.writer import McapRecorder

pytestmark = [pytest.mark.sim, pytest.mark.slow]


def test_a_cut_in_the_physics_mode_holds_the_knife_by_friction_and_keeps_to_the_limits(tmp_path: Path) -> None:
    from wecook_core.execution.bullet.scene import BulletScene

    plan = Plan(agents=(Agent("P1", DEFAULT_ROBOT, (-0.5, 0.0, 0.0), 0.0),),
                scene=Scene(table=Table(size=(1.0, 0.8)), objects=(
                    SceneObject("knife", Category.TOOL, "box", (0.14, 0.03, 0.025), -0.15, 0.2, 0.0),
                    SceneObject("tomato", Category.INGREDIENT, "sphere", (0.04, 0.04, 0.04), -0.1, -0.1, 0.0))),
                actions=(PlanAction("a1", ("P1",), "cut", "knife", ("tomato",)),))
    constraints: list[int] = []
    carried: list[float] = []
    create = pybullet.createConstraint
    step = BulletScene.step

    def watched_step(scene: BulletScene) -> None:
        step(scene)
        if scene.hands["P1"].carried == "knife" and scene.steps % 60 == 0:  # the knife rides up with the hand
            carried.append(float(scene.pose("knife")[2, 3]))

    with mock.patch.object(pybullet, "createConstraint", lambda *a, **k: constraints.append(1) or create(*a, **k)), \
            mock.patch.object(BulletScene, "step", watched_step):
        path = tmp_path / "run.mcap"
        result = execute_plan(plan, McapRecorder(path), seed=0, images=False, dynamics=True)
    assert constraints == []  # nothing fixed to the hand
    assert carried and max(carried) > 0.05  # lifted off the table (2.5 cm thick), held by the fingers alone
    report = check_recording(path)
    assert report.metadata["wecook"]["mode"] == "dynamics"
    assert not [p for p in report.problems if " over its limit " in p]
    assert result.actions[0].status in ("done", "failed")  # a failure is reported, never raised
