"""The plan reader, fed malformed plans (text edits, swapped values, random structures), returns a validated plan
or raises one InputError line naming the file; never another exception."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from contract import NASTY, field_swapped, keeps_contract, mutated
from hypothesis import given
from hypothesis import strategies as st

from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_core.plan import Plan, plan_from_dict, read_plan, validate

YAML_NASTY = [".nan", ".inf", "-.inf", "1e400", "-1", "0", "1" + "0" * 30, "~", "[]", "{}", "[[[[[]]]]]", "*x",
              "&x 1", "!!binary aGk=", "!!python/object:os.system", "!!set {a}", "2001-12-14", "yes", "'", "{a: *b}",
              "/etc/passwd", "../../../../etc/passwd.urdf", *NASTY]

scalars = st.one_of(st.none(), st.booleans(), st.integers(-(10**30), 10**30),
                    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=12))
json_like = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                          st.dictionaries(st.text(max_size=8), inner, max_size=4)),
                         max_leaves=25)


def _read(path: Path) -> Plan | Exception:
    return keeps_contract(lambda: read_plan(path), path)


@given(data=mutated(ONE_ARM_CUTS.encode()))
def test_mutated_plan_text(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "plan.yaml"
    path.write_bytes(data)
    _read(path)


@given(text=field_swapped(ONE_ARM_CUTS, separators=",:{}[]\n"), token=st.sampled_from(YAML_NASTY))
def test_swapped_plan_values(tmp_path: Path, text: str, token: str) -> None:
    path = tmp_path / "plan.yaml"
    path.write_text(text.replace("0.0", token, 1))
    result = _read(path)
    if isinstance(result, Plan):
        validate(result, path)  # what read_plan accepts passes validation


_GOOD = yaml.safe_load(ONE_ARM_CUTS)


@given(where=st.sampled_from(["agents", "scene", "actions", "wecook_plan", "table", "objects", "base", "pose",
                              "position", "robot", "size", "height", "pid", "after", "frames"]),
       value=json_like)
@pytest.mark.slow
def test_random_values_anywhere(tmp_path: Path, where: str, value: object) -> None:
    data = yaml.safe_load(ONE_ARM_CUTS)
    targets = {"agents": (data, "agents"), "scene": (data, "scene"), "actions": (data, "actions"),
               "wecook_plan": (data, "wecook_plan"), "table": (data["scene"], "table"),
               "objects": (data["scene"], "objects"), "base": (data["agents"][0], "base"),
               "pose": (data["scene"]["objects"][0], "pose"), "position": (data["agents"][0]["base"], "position"),
               "robot": (data["agents"][0], "robot"), "size": (data["scene"]["objects"][1], "size"),
               "height": (data["scene"]["table"], "height"), "pid": (data["actions"][0], "pid"),
               "after": (data["actions"][1], "after"), "frames": (data["actions"][0], "frames")}
    holder, key = targets[where]
    holder[key] = value
    path = tmp_path / "plan.yaml"
    path.write_text(yaml.safe_dump(data))
    _read(path)
    keeps_contract(lambda: validate(plan_from_dict(data, path), path), path)
