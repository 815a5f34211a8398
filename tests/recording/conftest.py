"""Fixtures of the recording tests."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def one_arm_recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A real run recorded as `wecook execute PLAN --record F --camera-hz 2` records it: the one-arm cutting
    sample plan, made once for the tests that read a real recording (do not write to it)."""
    from wecook_core.execution.plan_samples import ONE_ARM_CUTS
    from wecook_tui.cli import main

    folder = tmp_path_factory.mktemp("one_arm_run")
    plan = folder / "plan.yaml"
    plan.write_text(ONE_ARM_CUTS)
    record = folder / "run.mcap"
    assert main(["execute", str(plan), "--record", str(record), "--camera-hz", "2"]) in (0, 1)
    return record
