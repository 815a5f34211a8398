"""The PDDL export: domain and problem parse back with the `pddl` library, hold the plan's objects, containment and
free hands, and the plan's own steps run on them to the goal."""

from __future__ import annotations

from pathlib import Path

import pytest
from exports_helpers import simulate

from wecook_core.execution.plan_samples import synthetic_plan
from wecook_core.plan import Plan, read_plan
from wecook_core.plan.pddl import TABLETOP, export_pddl, ordered, pddl_name, write_pddl
from wecook_core.workflows import demo_plan

SMALL = Path(__file__).parent / "golden" / "small.yaml"


def round_trip(plan: Plan, folder: Path, name: str = "plan") -> set[tuple[str, ...]]:
    """Export, parse back, check objects and initial state against the plan, run the steps; the final state."""
    from pddl import parse_problem

    export = export_pddl(plan, name)
    domain, problem, steps_file = write_pddl(export, folder)
    parsed = parse_problem(problem)
    n = export.names
    objects = {str(o.name): {str(t) for t in o.type_tags} for o in parsed.objects}
    assert objects == {**{n[o.name]: {str(o.category)} for o in plan.scene.objects},
                       **{n[a.pid]: {"agent"} for a in plan.agents}}
    init = {(str(f.name), *(str(t.name) for t in f.terms)) for f in parsed.init}
    for ingredient, container in plan.scene.containing:
        assert ("in", n[ingredient], n[container]) in init
    assert {("free", n[a.pid]) for a in plan.agents} <= init
    assert not [f for f in init if f[0] == "holding"]  # no hand holds anything at the start
    lines = [line for line in steps_file.read_text().splitlines() if not line.startswith(";")]
    assert [tuple(line.strip("()").split()) for line in lines] == list(export.steps)
    assert {a.id for a in plan.actions} == set(export.step_actions)  # every action has its steps
    return simulate(domain, problem, list(export.steps))


@pytest.mark.slow
def test_the_small_plan_round_trips_and_its_steps_reach_the_goal(tmp_path: Path) -> None:
    plan = read_plan(SMALL)
    state = round_trip(plan, tmp_path, "small")
    assert ("in", "tomato", "pot") in state and ("in", "onion", "pot") in state
    assert ("done-cut", "tomato") in state and ("done-stir", "onion") in state
    assert ("received", "p2", "spoon") in state and ("steadied", "pot") in state
    assert not [f for f in state if f[0] == "holding"]


@pytest.mark.slow
def test_the_demo_plan_and_sample_plans_round_trip(tmp_path: Path) -> None:
    round_trip(demo_plan(), tmp_path / "demo", "demo")
    for seed in range(4):
        round_trip(synthetic_plan(seed), tmp_path / f"s{seed}")


@pytest.mark.slow
def test_steps_that_break_the_domain_are_caught(tmp_path: Path) -> None:
    export = export_pddl(read_plan(SMALL))
    domain, problem, _ = write_pddl(export, tmp_path)
    steps = list(export.steps)
    grasp = next(k for k, s in enumerate(steps) if s[0] == "grasp")
    with pytest.raises(AssertionError, match="precondition fails"):
        simulate(domain, problem, steps[:grasp] + steps[grasp + 1:])  # acting with a tool it never grasped
    with pytest.raises(AssertionError):
        simulate(domain, problem, steps[:-1])  # the last release missing: the goal wants every hand free


def test_names_and_order() -> None:
    assert pddl_name("Bell Pepper") == "bell-pepper"
    assert pddl_name("2nd_bowl") == "o-2nd_bowl"
    assert pddl_name(TABLETOP) == "tabletop-1"
    assert pddl_name("bowl", ["bowl"]) == "bowl-2"
    plan = read_plan(SMALL)
    a1, a2, *rest = plan.actions
    assert [a.id for a in ordered((a2, *rest, a1))] == ["a1", "a2", "a3", "a4", "a5", "a6"]  # a2 comes after a1
