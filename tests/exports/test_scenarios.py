"""The bar: the plans of the shared scenarios (read in place from ../shared/data/scenarios) export to every format
without error; the dispatch script builds one TaskMsg whose every action the platform plans, with every object in
the scene; the PDDL steps run to the goal, and pyperplan solves the problem with each person's work as wecook's."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from exports_helpers import check_message, check_same_work, platform_checks, run_dispatch, simulate, solve

from wecook_core.plan import dump_plan, load_plan, validate
from wecook_core.plan.pddl import export_pddl, write_pddl
from wecook_core.plan.ros_script import dispatch_script
from wecook_core.plan.schema import check_plan_schema

SCENARIOS = ("s301", "s302", "s303", "s304")


@pytest.mark.slow
@pytest.mark.parametrize("name", SCENARIOS)
def test_a_shared_scenario_plan_exports_to_every_format(shared: Path, name: str, tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    from wecook_core.workflows import inputs_plan

    folder = shared / "data" / "scenarios" / name
    plan = inputs_plan(folder / "video.mp4", folder / "objects.xml", folder / "openpose")
    validate(plan)
    assert plan.actions

    text = dump_plan(plan)  # wecook's YAML: meets the schema and reads back the same
    check_plan_schema(yaml.safe_load(text), f"{name}.yaml")
    assert dump_plan(load_plan(text)) == text

    script, export = dispatch_script(plan, name)
    run = run_dispatch(script, monkeypatch)
    task = run.task
    assert check_message(run.msg, task) == len(run.msg.built)
    # the bar: every dispatched action has a planner on the platform, no object is missing from the scene
    platform_checks(plan, export, task)
    assert task.actions and len(export.dispatched) >= len(plan.actions) // 2

    pddl = export_pddl(plan, name)
    domain, problem, _ = write_pddl(pddl, tmp_path)
    simulate(domain, problem, list(pddl.steps))
    # the bar: pyperplan solves it, and its plan gives each person wecook's verbs, tools and things
    steps = solve(domain, problem)
    simulate(domain, problem, steps)
    check_same_work(plan, dict(pddl.names), domain, steps)
