"""The plan file's JSON Schema: every plan wecook writes meets it, a bad file is one line naming file and place, and
the README publishes it as `wecook export --schema` prints it."""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from wecook_core.errors import InputError
from wecook_core.execution.plan_samples import ONE_ARM_CUTS, synthetic_plan
from wecook_core.plan import dump_plan, load_plan
from wecook_core.plan.schema import check_plan_file, check_plan_schema, plan_schema, schema_text
from wecook_core.resources import REPO_DIR
from wecook_tui.cli import main

SMALL = Path(__file__).parent / "golden" / "small.yaml"


def test_the_schema_is_a_valid_draft_2020_12_schema() -> None:
    from jsonschema import Draft202012Validator

    Draft202012Validator.check_schema(plan_schema())


@pytest.mark.slow
def test_every_plan_wecook_writes_meets_the_schema() -> None:
    texts = [ONE_ARM_CUTS, SMALL.read_text(), *(dump_plan(synthetic_plan(seed)) for seed in range(6))]
    for text in texts:
        data = yaml.safe_load(text)
        check_plan_schema(data, "plan.yaml")
        check_plan_schema(yaml.safe_load(dump_plan(load_plan(text))), "again.yaml")


def _broken(change: Any) -> dict[str, Any]:
    data = yaml.safe_load(SMALL.read_text())
    out = copy.deepcopy(data)
    change(out)
    return out


@pytest.mark.parametrize(("change", "place", "words"), [
    (lambda d: d["actions"][3].__setitem__("tool", 5), "actions[3] (a4).tool", "expected string or null, got 5"),
    (lambda d: d["actions"][0].__setitem__("ingredient", ["tomato"]), "actions[0] (a1).ingredient", "unknown key"),
    (lambda d: d["actions"][4].__setitem__("verb", "fly"), "actions[4] (a5).verb", "expected one of cut"),
    (lambda d: d["actions"][4].pop("pid"), "actions[4] (a5)", "missing `pid`"),
    (lambda d: d["actions"][3]["partner"].__setitem__("verb", "holding"), "actions[3] (a4).partner.verb",
     "expected one of"),
    (lambda d: d["actions"][1].__setitem__("frames", [3, -1]), "actions[1] (a2).frames[1]", "at least 0"),
    (lambda d: d["scene"]["objects"][2]["size"].__setitem__(0, 0), "scene.objects[2] (whisk).size[0]",
     "more than 0"),
    (lambda d: d["scene"]["objects"][2].__setitem__("category", "spoon"), "scene.objects[2] (whisk).category",
     "expected one of tool, container, ingredient"),
    (lambda d: d["scene"]["containing"].append(["tomato"]), "scene.containing[2]", "expected 2 items"),
    (lambda d: d["agents"][1].__setitem__("pid", "P3"), "agents[1].pid", "expected one of P1, P2"),
    (lambda d: d.__setitem__("wecook_plan", 2), "wecook_plan", "not a wecook plan"),
    (lambda d: d.pop("wecook_plan"), "top level", "not a wecook plan"),
])
def test_a_plan_off_the_schema_is_one_line_naming_file_and_place(change: Any, place: str, words: str) -> None:
    with pytest.raises(InputError) as error:
        check_plan_schema(_broken(change), "kitchen/plan.yaml")
    assert error.value.path == "kitchen/plan.yaml" and error.value.place == place
    assert words in error.value.message
    assert "\n" not in str(error.value) and len(str(error.value)) < 240


def test_check_plan_file_reads_checks_and_returns_the_plan(tmp_path: Path) -> None:
    assert [a.id for a in check_plan_file(SMALL).actions] == ["a1", "a2", "a3", "a4", "a5", "a6"]
    bad = tmp_path / "bad.yaml"
    bad.write_text(SMALL.read_text().replace("ingredients: [tomato], location: chopping_board, after: []",
                                             "ingredients: [tomato], location: chopping_board, afer: []"))
    with pytest.raises(InputError, match=r"bad.yaml:actions\[0\] \(a1\).afer: unknown key"):
        check_plan_file(bad)
    bad.write_text(SMALL.read_text().replace("tool: knife,", "tool: spork,"))  # the schema's fine, the plan isn't
    with pytest.raises(InputError, match=r"actions\[0\] \(a1\).tool: object 'spork' is not in the scene"):
        check_plan_file(bad)
    with pytest.raises(InputError, match="no such plan file"):
        check_plan_file(tmp_path / "none.yaml")


def test_wecook_export_schema_prints_it_and_the_readme_publishes_it(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", "--schema"]) == 0
    printed = capsys.readouterr().out
    assert printed == schema_text() and json.loads(printed) == plan_schema()
    readme = (REPO_DIR / "README.md").read_text()
    block = re.search(r"<!-- plan schema -->\n```json\n(.*?)```", readme, re.S)
    assert block is not None, "the README's schema block is missing"
    assert block.group(1) == printed, "README's schema differs from `wecook export --schema`: paste it again"


def test_wecook_plan_check_refuses_a_plan_off_the_schema(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(SMALL.read_text().replace("ingredients: [tomato], location: chopping_board, after: []",
                                             "ingredients: [tomato], location: chopping_board, afer: []"))
    assert main(["plan", "check", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "bad.yaml:actions[0] (a1).afer: unknown key" in err
    bomb = tmp_path / "bomb.yaml"  # the schema check reads through the bounded plan reader
    bomb.write_text("a: &a [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, "
        f"*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}]\n"
        for i in range(9)))
    assert main(["plan", "check", str(bomb)]) == 2
    assert "bomb.yaml" in capsys.readouterr().err
