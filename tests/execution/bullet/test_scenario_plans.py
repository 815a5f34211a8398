"""Plans exported from every scenario of the independent generator (``../shared/data/scenarios/``), as a user
would export them (imported, analysed, laid out), run in PyBullet with recording on."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import pytest

from wecook_core.execution.run import execute_plan
from wecook_core.plan import Plan, action_objects
from wecook_core.recording.check import check_recording
from wecook_core.recording.writer import McapRecorder
from wecook_core.resources import shared_dir

pytestmark = [pytest.mark.sim, pytest.mark.slow]

SCENARIOS = sorted(p.name for p in (shared_dir() / "data" / "scenarios").glob("s*") if (p / "objects.xml").is_file())


@cache
def scenario_plan(name: str) -> Plan:
    from wecook_core.workflows import inputs_plan

    folder = shared_dir() / "data" / "scenarios" / name
    return inputs_plan(folder / "video.mp4", folder / "objects.xml", folder / "openpose")


def test_the_shared_scenarios_are_there() -> None:
    assert len(SCENARIOS) >= 4


@pytest.mark.parametrize("name", SCENARIOS)
def test_a_scenario_plan_leaves_every_arm_its_reach_and_every_hand_room(name: str) -> None:
    """What `wecook plan check` asks: each action's objects within its arm's reach, no tall object beside what a
    tool works on, food clear of the end of a board a hand holds (a held board lies along x, between the arms)."""
    from wecook_core.plan.reach import reach_problems
    from wecook_core.plan.room import room_problems

    plan = scenario_plan(name)
    assert reach_problems(plan) == []
    assert room_problems(plan) == []
    held = {a.tool for a in plan.actions if a.verb == "holding" and a.partner is not None}
    for obj in plan.scene.objects:
        if obj.name in held and obj.shape == "box":
            assert obj.yaw == 0.0


@pytest.mark.parametrize("name", SCENARIOS)
def test_a_scenario_plan_runs_recorded_the_arms_never_touch_and_failures_skip_only_their_dependents(
        name: str, tmp_path: Path) -> None:
    plan = scenario_plan(name)
    path = tmp_path / "run.mcap"
    result = execute_plan(plan, McapRecorder(path), seed=0, images=False)
    assert result.arm_contacts == 0
    assert check_recording(path).ok
    status = {r.action_id: r for r in result.actions}
    assert len(status) == len(plan.actions)
    done = sum(r.status == "done" for r in result.actions)
    assert done >= 0.85 * len(plan.actions), [(r.action_id, r.status, r.reason) for r in result.actions]
    by_id = {a.id: a for a in plan.actions}
    for r in result.actions:
        if r.status == "failed":
            assert r.reason
        if r.status == "skipped" and r.reason.startswith("needs "):  # names what it needs, which was not done
            needed = r.reason.split()[1]
            assert needed in by_id[r.action_id].after and status[needed].status != "done"
            assert action_objects(by_id[needed]) & action_objects(by_id[r.action_id]) or \
                by_id[needed].verb in ("handover", "holding")
    # the run is bounded: a failing action ends, it does not hang the run
    assert result.wall_time < 60 + 30 * len(plan.actions)
