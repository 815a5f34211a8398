"""Golden files: the exports of one small plan (golden/small.yaml), byte for byte. After a deliberate change to an
exporter, rewrite them with `WECOOK_UPDATE_GOLDEN=1 pytest tests/exports/test_golden.py` and review the diff."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from wecook_core.plan import read_plan
from wecook_core.plan.pddl import export_pddl
from wecook_core.plan.ros_script import dispatch_script

GOLDEN = Path(__file__).parent / "golden"


def _exports() -> dict[str, str]:
    plan = read_plan(GOLDEN / "small.yaml")
    script, _ = dispatch_script(plan, "small", source="golden/small.yaml")
    pddl = export_pddl(plan, "small")
    return {"small_dispatch.py.txt": script, "small_domain.pddl": pddl.domain, "small_problem.pddl": pddl.problem,
            "small_plan.pddl": pddl.plan_text()}


@pytest.mark.parametrize("name", sorted(_exports()))
def test_exports_of_the_small_plan_match_the_golden_files(name: str) -> None:
    text = _exports()[name]
    path = GOLDEN / name
    if os.environ.get("WECOOK_UPDATE_GOLDEN"):
        path.write_text(text)
    assert path.read_text() == text, f"{name} changed; if on purpose, rewrite with WECOOK_UPDATE_GOLDEN=1"
