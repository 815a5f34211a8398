"""The PDDL export: domain and problem parse back with the `pddl` library, hold the plan's objects, containment,
free hands and reach, and the plan's own steps run on them to the goal; steps that skip what a verb needs (the
knife, the oil, the partner's hold) are refused; and pyperplan, solving the problem its own way, gives each person
the same verbs with the same tools on the same things as wecook's plan, in an order the plan's dependencies allow."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from exports_helpers import check_same_work, simulate, solve

from wecook_core.execution.plan_samples import synthetic_plan
from wecook_core.plan import Plan, read_plan
from wecook_core.plan.pddl import TABLETOP, export_pddl, ordered, pddl_name, write_pddl
from wecook_core.plan.reach import reach_problems
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
    things = {k: v for k, v in objects.items() if v not in ({"task"}, {"gate"})}
    assert things == {**{n[o.name]: {str(o.category)} for o in plan.scene.objects},
                      **{n[a.pid]: {"arm"} for a in plan.agents}, TABLETOP: {"container"}}
    assert {k for k, v in objects.items() if v == {"task"}} == set(export.tasks)
    init = {(str(f.name), *(str(t.name) for t in f.terms)) for f in parsed.init}
    for ingredient, container in plan.scene.containing:
        assert ("in", n[ingredient], n[container]) in init
    assert {("free", n[a.pid]) for a in plan.agents} <= init
    assert not [f for f in init if f[0] == "holding"]  # no hand holds anything at the start
    assert {f[1] for f in init if f[0] == "reaches"} == {n[a.pid] for a in plan.agents}
    lines = [line for line in steps_file.read_text().splitlines() if not line.startswith(";")]
    assert [tuple(line.strip("()").split()) for line in lines] == list(export.steps)
    assert {a.id for a in plan.actions} == set(export.step_actions)  # every action has its steps
    assert {a.id for a in plan.actions} == set(export.tasks.values())  # and its tasks
    return simulate(domain, problem, list(export.steps))


@pytest.mark.slow
def test_the_small_plan_round_trips_and_its_steps_reach_the_goal(tmp_path: Path) -> None:
    plan = read_plan(SMALL)
    state = round_trip(plan, tmp_path, "small")
    assert ("in", "tomato", "pot") in state and ("in", "onion", "pot") in state
    assert {f for f in state if f[0] == "done"} == {("done", t) for t in export_pddl(plan).tasks}
    assert not [f for f in state if f[0] == "holding"]


def unchecked(plan: Plan) -> Plan:
    """The plan with arms whose reach is not checked (the sample plans have objects out of the Panda's reach)."""
    return dataclasses.replace(plan, agents=tuple(dataclasses.replace(a, robot="/my/arm.urdf") for a in plan.agents))


@pytest.mark.slow
def test_the_demo_plan_and_sample_plans_round_trip(tmp_path: Path) -> None:
    round_trip(demo_plan(), tmp_path / "demo", "demo")
    for seed in range(4):
        round_trip(unchecked(synthetic_plan(seed)), tmp_path / f"s{seed}")


def test_an_arm_grasps_only_what_it_reaches(tmp_path: Path) -> None:
    plan = synthetic_plan(0)  # a1: P1 stirs with the spoon 0.70 m from its base (it reaches 0.25-0.68 m)
    assert "a1 (stir by P1): the spoon" in str(reach_problems(plan)[0])
    export = export_pddl(plan)
    domain, problem, _ = write_pddl(export, tmp_path)
    with pytest.raises(AssertionError, match=r"\('reaches', 'p1', 'spoon'\)"):
        simulate(domain, problem, list(export.steps))
    assert ("reaches", "p2", "spoon") in {tuple(line.strip().strip("()").split()) for line in
                                          problem.read_text().splitlines()}


def _step(steps: list[tuple[str, ...]], name: str) -> int:
    return next(k for k, s in enumerate(steps) if s[0] == name)


@pytest.mark.slow
def test_steps_that_skip_what_a_verb_needs_are_refused(tmp_path: Path) -> None:
    export = export_pddl(demo_plan(), "demo")
    domain, problem, _ = write_pddl(export, tmp_path)
    steps = list(export.steps)
    domain_text = domain.read_text()
    assert "cut-by-hand" not in domain_text and "pour-by-hand" not in domain_text  # the demo cuts with a knife
    cut = _step(steps, "cut")
    assert steps[cut - 1] == ("grasp", "p1", "knife")
    with pytest.raises(AssertionError, match="precondition fails"):  # cutting without the knife in hand
        simulate(domain, problem, steps[:cut - 1] + steps[cut:])
    with_spoon = [("grasp", "p1", "spoon") if s == ("grasp", "p1", "knife") else
                  (*s[:3], "spoon", *s[4:]) if s[0] == "cut" else
                  ("release", "p1", "spoon") if s == ("release", "p1", "knife") else s for s in steps]
    with pytest.raises(AssertionError, match=r"fits-cut"):  # a spoon is no knife
        simulate(domain, problem, with_spoon)
    pour = _step(steps, "pour")
    assert steps[pour][2:4] == ("p2", "oil") and steps[pour - 1] == ("grasp", "p2", "oil")
    with pytest.raises(AssertionError, match=r"holding', 'p2', 'oil'"):  # pouring the oil without holding it
        simulate(domain, problem, steps[:pour - 1] + steps[pour:])
    held = _step(steps, "stir-held")
    hold = max(k for k in range(held) if steps[k] == ("grasp", "p2", "pot"))
    with pytest.raises(AssertionError, match=r"holding', 'p2', 'pot'"):  # stirring the pot nobody holds
        simulate(domain, problem, steps[:hold] + steps[hold + 1:])
    with pytest.raises(AssertionError):  # the last release missing: the goal wants every hand free
        simulate(domain, problem, steps[:-1])
    start = _step(steps, "start")
    with pytest.raises(AssertionError, match="precondition fails"):  # a task before the one it waits for
        simulate(domain, problem, [s for s in steps if s[0] != "pass"])
    assert start > 0


@pytest.mark.slow
def test_pyperplan_gives_each_person_the_plans_work(tmp_path: Path) -> None:
    for name, plan in [("small", read_plan(SMALL)), ("demo", demo_plan()),
                       *((f"sample{seed}", unchecked(synthetic_plan(seed))) for seed in range(2))]:
        export = export_pddl(plan, name)
        domain, problem, _ = write_pddl(export, tmp_path / name)
        steps = solve(domain, problem)
        simulate(domain, problem, steps)  # the planner's plan is a plan of the problem
        check_same_work(plan, dict(export.names), domain, steps)


def test_the_same_work_check_catches_another_person_or_tool_or_order(tmp_path: Path) -> None:
    plan = demo_plan()
    export = export_pddl(plan, "demo")
    domain, _, _ = write_pddl(export, tmp_path)
    steps = list(export.steps)
    check_same_work(plan, dict(export.names), domain, steps)
    cut = _step(steps, "cut")
    for wrong in ([*steps[:cut], (steps[cut][0], steps[cut][1], "p2", *steps[cut][3:]), *steps[cut + 1:]],
                  [*steps[:cut], (*steps[cut][:3], "spoon", *steps[cut][4:]), *steps[cut + 1:]]):
        with pytest.raises(AssertionError):
            check_same_work(plan, dict(export.names), domain, wrong)
    pour, handover = _step(steps, "pour"), _step(steps, "handover")
    swapped = list(steps)
    swapped[pour], swapped[handover] = swapped[handover], swapped[pour]
    with pytest.raises(AssertionError, match="waits for"):
        check_same_work(plan, dict(export.names), domain, swapped)


def test_names_and_order() -> None:
    assert pddl_name("Bell Pepper") == "bell-pepper"
    assert pddl_name("2nd_bowl") == "o-2nd_bowl"
    assert pddl_name(TABLETOP) == "tabletop-1"
    assert pddl_name("bowl", ["bowl"]) == "bowl-2"
    assert pddl_name("arm") == "arm-1"
    plan = read_plan(SMALL)
    a1, a2, *rest = plan.actions
    assert [a.id for a in ordered((a2, *rest, a1))] == ["a1", "a2", "a3", "a4", "a5", "a6"]  # a2 comes after a1
