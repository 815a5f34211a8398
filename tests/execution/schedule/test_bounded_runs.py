"""A plan whose actions all fail ends after a bounded number of attempts (issue 13: 40 failing actions took
166 s, every one tried in full): the scheduler stops after :data:`FAILURES_IN_A_ROW` failures in a row."""

from __future__ import annotations

import pytest

from tests.execution.schedule.test_scheduler import FakeWorld, plan
from wecook_core.execution.run import execute_plan
from wecook_core.execution.schedule.executor import FAILURES_IN_A_ROW, run_schedule
from wecook_core.model import Category
from wecook_core.plan import DEFAULT_ROBOT, Agent, Plan, PlanAction, Scene, SceneObject, Table, validate


def test_a_plan_whose_actions_all_fail_stops_after_a_bounded_number_of_them() -> None:
    actions = [PlanAction(f"a{k}", ("P1" if k % 2 else "P2",), "cut", f"knife{k}") for k in range(40)]
    world = FakeWorld(fail={a.id for a in actions})
    results = run_schedule(plan(*actions), world)
    tried = {a for _, a, _ in world.log}
    assert len(tried) <= FAILURES_IN_A_ROW + 1  # the other arm may have started one when the last failed
    assert sum(r.status == "failed" for r in results) == len(tried)
    skipped = [r for r in results if r.status == "skipped"]
    assert len(skipped) == 40 - len(tried)
    assert all("failed in a row" in r.reason for r in skipped)


def test_a_done_action_between_failures_keeps_the_run_going() -> None:
    actions = [PlanAction(f"a{k}", ("P1",), "cut", f"knife{k}") for k in range(12)]
    fail = {a.id for k, a in enumerate(actions) if k % FAILURES_IN_A_ROW}  # every FAILURES_IN_A_ROW-th is done
    results = run_schedule(plan(*actions), FakeWorld(fail=fail))
    assert all(r.status in ("done", "failed") for r in results)
    assert sum(r.status == "done" for r in results) == 12 - len(fail)


def test_no_limit_tries_every_failing_action() -> None:
    actions = [PlanAction(f"a{k}", ("P1",), "cut", f"knife{k}") for k in range(10)]
    results = run_schedule(plan(*actions), FakeWorld(fail={a.id for a in actions}), failures_in_a_row=None)
    assert [r.status for r in results] == ["failed"] * 10


@pytest.mark.sim
def test_forty_failing_actions_in_pybullet_stop_after_a_few_attempts() -> None:
    """The knife lies almost under P1's base, where the arm cannot take it: every cut fails at its grasp, after
    the grasp's retries, with nothing simulated; only the first few are tried."""
    table = Table(size=(1.0, 0.8))
    objects = (SceneObject("knife", Category.TOOL, "box", (0.2, 0.03, 0.025), -0.45, 0.2, 1.5708),
               SceneObject("tomato", Category.INGREDIENT, "sphere", (0.06, 0.06, 0.06), 0.15, -0.3, 0.0))
    agents = (Agent("P1", DEFAULT_ROBOT, (-0.5, 0.0, 0.0), 0.0),)
    actions = tuple(PlanAction(f"a{k + 1}", ("P1",), "cut", "knife", ("tomato",)) for k in range(40))
    failing = Plan(agents=agents, scene=Scene(table=table, objects=objects), actions=actions)
    validate(failing)

    class Count:
        def __init__(self) -> None:
            self.grasps = 0

        def on_start(self, *args: object) -> None: ...
        def on_state(self, *args: object) -> None: ...
        def on_log(self, *args: object) -> None: ...
        def on_image(self, *args: object) -> None: ...
        def on_end(self, *args: object) -> None: ...

        def on_event(self, t: float, event: object) -> None:
            if getattr(event, "kind", "") == "primitive_start" and getattr(event, "primitive", "") == "grasp":
                self.grasps += 1

    count = Count()
    result = execute_plan(failing, count, seed=0, images=False)
    assert [r.status for r in result.actions[:FAILURES_IN_A_ROW]] == ["failed"] * FAILURES_IN_A_ROW
    assert all(r.status == "skipped" for r in result.actions[FAILURES_IN_A_ROW:])
    assert count.grasps == FAILURES_IN_A_ROW  # one grasp primitive (with its bounded retries) per tried action
