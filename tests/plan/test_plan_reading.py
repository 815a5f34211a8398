"""Plan YAML read fast and bounded (wecook_core.plan.yaml_read): the data is what yaml.safe_load reads, plain plans
go the event path (no node graph), what plans never need goes the general path, and both are bounded; the JSON
Schema check passes valid data without jsonschema and still says where invalid data is wrong."""

from __future__ import annotations

import math

import pytest
import yaml

from wecook_core.errors import InputError
from wecook_core.plan import dump_plan, yaml_read
from wecook_core.plan.schema import check_plan_schema
from wecook_core.plan.yaml_read import MAX_PLAN_DEPTH, parse_plan_yaml
from wecook_core.workflows import demo_plan

PLAIN = [
    "",
    "a: 1\n",
    "wecook_plan: 1\nx: [1, -2, 0x1f, 1_000, 0o17, 1.5, -.inf, .NaN, 1e3, yes, No, ~, null, 'q', \"d\", 2001-12-14]\n",
    "- {a: [], b: {}}\n- [[], [[1]]]\n- 'two words'\n- |\n  block\n  text\n- >\n  folded\n",
    "k: 1\nk: 2\n",  # the last of a duplicate key wins, as in PyYAML
    "1: int key\n3.5: float key\nnull: null key\n",
    "? complex\n: value\n",
    "---\na: 1\n...\n",
]
GENERAL = [
    "a: &x [1, 2]\nb: *x\n",  # anchors and aliases
    "base: &b {x: 1}\nderived:\n  <<: *b\n  y: 2\n",  # a merge key
    "a: !!str 12\nb: !!float '1'\n",  # explicit tags
    "s: !!set {a, b}\n",
]


def same(a: object, b: object) -> bool:
    """Equal, with NaN equal to NaN."""
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a):
        return math.isnan(b)
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("text", PLAIN + GENERAL)
def test_the_data_is_what_safe_load_reads(text: str) -> None:
    assert same(parse_plan_yaml(text, "p.yaml"), yaml.safe_load(text))


def test_a_plain_plan_is_built_from_events_and_the_rest_goes_the_general_way(monkeypatch: pytest.MonkeyPatch) -> None:
    assert yaml_read.CLoader is not None  # PyYAML here has libyaml
    general: list[str] = []
    real = yaml_read._general

    def counting(text: str, path: object) -> object:
        general.append(text)
        return real(text, path)  # type: ignore[arg-type]

    monkeypatch.setattr(yaml_read, "_general", counting)
    text = dump_plan(demo_plan())
    assert parse_plan_yaml(text, "plan.yaml") == yaml.safe_load(text)
    for plain in PLAIN:
        parse_plan_yaml(plain, "p.yaml")
    assert general == []  # no node graph composed
    for other in GENERAL:
        parse_plan_yaml(other, "p.yaml")
    assert general == GENERAL


@pytest.mark.parametrize("general", [False, True])
def test_both_paths_are_bounded(monkeypatch: pytest.MonkeyPatch, general: bool) -> None:
    tag = "!!str " if general else ""  # an explicit tag sends the document the general way
    deep = "a: " + "[" * MAX_PLAN_DEPTH + tag + "x" + "]" * MAX_PLAN_DEPTH + "\n"
    with pytest.raises(yaml.MarkedYAMLError, match=f"nested deeper than {MAX_PLAN_DEPTH} levels"):
        parse_plan_yaml(deep, "p.yaml")
    ok = "a: " + "[" * (MAX_PLAN_DEPTH - 2) + tag + "x" + "]" * (MAX_PLAN_DEPTH - 2) + "\n"
    assert parse_plan_yaml(ok, "p.yaml") == yaml.safe_load(ok)
    with pytest.raises(yaml.MarkedYAMLError, match="nested deeper"):  # past libyaml's own 1000 levels
        parse_plan_yaml("a: " + "[" * 5000 + "]" * 5000, "p.yaml")
    monkeypatch.setattr(yaml_read, "MAX_PLAN_NODES", 50)
    many = "a: [" + ", ".join([tag + "x"] * 60) + "]\n"
    with pytest.raises(InputError, match="more than 50 values") as error:
        parse_plan_yaml(many, "p.yaml")
    assert error.value.place == "line 1"
    bomb = "a: &a [x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a]\n"
    with pytest.raises(InputError, match="more than 50 values"):
        parse_plan_yaml(bomb, "p.yaml")


def test_two_documents_and_bad_yaml_are_errors() -> None:
    with pytest.raises(yaml.YAMLError, match="expected a single document"):
        parse_plan_yaml("a: 1\n---\nb: 2\n", "p.yaml")
    with pytest.raises(yaml.YAMLError):
        parse_plan_yaml("a: [1, 2\n", "p.yaml")
    with pytest.raises(yaml.YAMLError):
        parse_plan_yaml("{[1]: x}\n", "p.yaml")  # an unhashable key: the safe constructor's error
    with pytest.raises(InputError, match="not valid YAML"):
        parse_plan_yaml("a: " + "9" * 5000 + "\n", "p.yaml")


def test_valid_plan_data_passes_the_schema_without_jsonschema(monkeypatch: pytest.MonkeyPatch) -> None:
    import jsonschema.exceptions

    data = yaml.safe_load(dump_plan(demo_plan()))

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("jsonschema judged valid data")

    monkeypatch.setattr(jsonschema.exceptions, "best_match", refuse)
    check_plan_schema(data, "plan.yaml")
    monkeypatch.undo()
    data["actions"][3]["tool"] = 3
    with pytest.raises(InputError) as error:
        check_plan_schema(data, "plan.yaml")
    assert error.value.place == "actions[3] (a4).tool"
    data["actions"][3]["tool"] = "spoon"
    data["scene"]["objects"][0]["pose"]["x"] = float("nan")  # jsonschema-rs refuses NaN; jsonschema has the word
    check_plan_schema(data, "plan.yaml")


def test_without_libyaml_the_python_loader_reads_and_bounds(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(yaml_read, "CLoader", None)
    text = dump_plan(demo_plan())
    assert parse_plan_yaml(text, "plan.yaml") == yaml.safe_load(text)
    with pytest.raises(yaml.MarkedYAMLError, match="nested deeper"):
        parse_plan_yaml("a: " + "[" * 5000 + "]" * 5000, "p.yaml")
