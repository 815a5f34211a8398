"""A recorded run of the demo plan (seed 0) read back as a roboticist would: every joint within its limits in
every recorded step."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from mcap.reader import make_reader

from wecook_core.execution.run import execute_plan
from wecook_core.recording.check import check_recording
from wecook_core.recording.writer import McapRecorder

pytestmark = [pytest.mark.sim, pytest.mark.slow]


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object]:
    from wecook_core.workflows import demo_plan

    path = tmp_path_factory.mktemp("demo") / "run.mcap"
    result = execute_plan(demo_plan(), McapRecorder(path), seed=0, images=False)
    return path, result


def _messages(path: Path, topic: str) -> list[dict]:
    with open(path, "rb") as f:
        return [json.loads(m.data) for _, c, m in make_reader(f).iter_messages(topics=[topic])]


def test_the_recorded_demo_run_does_every_action_with_no_joint_over_its_limits(demo_run) -> None:
    path, result = demo_run
    assert [a.status for a in result.actions] == ["done"] * len(result.actions)
    report = check_recording(path)
    assert report.problems == ()
    states = _messages(path, "/joint_states")
    assert len(states) > 30 * result.sim_time * 0.95  # the executed trajectory at the recording rate (30 Hz)
