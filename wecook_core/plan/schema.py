"""The JSON Schema of a plan file (``wecook_plan: 1``), and :func:`check_plan_schema`, which checks parsed plan data
against it (with jsonschema) and raises one :class:`InputError` naming the file and the place.

The schema says what :func:`~wecook_core.plan.yaml_file.plan_from_dict` reads, field by field, and no more:
unknown keys are errors (a misspelt ``ingredient:`` would otherwise be dropped without a word). What it cannot
say (names that refer to the scene, cycles in ``after``, reach) is :func:`~wecook_core.plan.checks.plan_problems`'
part.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from functools import cache
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError, yaml_error
from wecook_core.files import read_text
from wecook_core.model import PERSONS, VERBS, Category
from wecook_core.plan.checks import validate
from wecook_core.plan.model import PLAN_VERBS, PLAN_VERSION, SHAPES, Plan
from wecook_core.plan.yaml_file import MAX_PLAN_BYTES, parse_plan_yaml, plan_from_dict

SCHEMA_ID = "urn:wecook:plan:1"

_NAME: dict[str, Any] = {"type": "string", "minLength": 1}
_OPTIONAL_NAME: dict[str, Any] = {"type": ["string", "null"], "minLength": 1}
_NAMES: dict[str, Any] = {"type": ["array", "null"], "items": {"$ref": "#/$defs/name"}}


def _numbers(n: int, description: str, *, positive: bool = False) -> dict[str, Any]:
    item: dict[str, Any] = {"type": "number"}
    if positive:
        item["exclusiveMinimum"] = 0
    return {"type": "array", "items": item, "minItems": n, "maxItems": n, "description": description}


def _act(verbs: Sequence[str], required: Sequence[str], extra: dict[str, Any] | None = None) -> dict[str, Any]:
    properties: dict[str, Any] = {
        "verb": {"enum": list(verbs)},
        "tool": {"$ref": "#/$defs/optional_name",
                 "description": "what the arm grasps to act (a tool, or the ingredient or container it pours)"},
        "ingredients": {"$ref": "#/$defs/names", "description": "the ingredients acted on"},
        "location": {"$ref": "#/$defs/optional_name", "description": "the container or target acted on / into"},
        "source": {"$ref": "#/$defs/optional_name", "description": "transfer: the container the ingredients leave"},
        **(extra or {}),
    }
    return {"type": "object", "required": list(required), "additionalProperties": False, "properties": properties}


@cache
def _schema() -> str:
    schema: dict[str, Any] = {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": SCHEMA_ID,
        "title": "wecook plan",
        "description": "What two robot arms must do, built from a cooking video (metres, radians, world frame: "
                       "z up, table top centred on the origin, P1 at -x facing +x, P2 at +x facing -x).",
        "type": "object",
        "required": ["wecook_plan"],
        "additionalProperties": False,
        "properties": {
            "wecook_plan": {"const": PLAN_VERSION, "description": "the format's version"},
            "agents": {"type": ["array", "null"], "items": {"$ref": "#/$defs/agent"}},
            "scene": {"$ref": "#/$defs/scene"},
            "actions": {"type": ["array", "null"], "items": {"$ref": "#/$defs/action"}},
        },
        "$defs": {
            "name": _NAME,
            "optional_name": _OPTIONAL_NAME,
            "names": _NAMES,
            "agent": {
                "type": "object", "required": ["pid"], "additionalProperties": False,
                "properties": {
                    "pid": {"enum": list(PERSONS)},
                    "robot": {"$ref": "#/$defs/name",
                              "description": "URDF of the arm, relative to pybullet_data unless absolute"},
                    "base": {"type": "object", "additionalProperties": False, "properties": {
                        "position": _numbers(3, "metres, world frame"),
                        "yaw": {"type": "number", "description": "radians about z; 0 faces +x"}}},
                },
            },
            "scene": {
                "type": "object", "additionalProperties": False,
                "properties": {
                    "table": {"type": "object", "additionalProperties": False, "properties": {
                        "size": _numbers(2, "metres along x (between the arms) and y", positive=True),
                        "height": {"type": "number", "description": "metres: z of the table top"},
                        "reach": _numbers(2, "metres: half extents of the region both arms reach")}},
                    "objects": {"type": ["array", "null"], "items": {"$ref": "#/$defs/object"}},
                    "containing": {"type": ["array", "null"], "description": "[ingredient, container]: the "
                                   "ingredient starts inside the container",
                                   "items": {"type": "array", "items": {"$ref": "#/$defs/name"},
                                             "minItems": 2, "maxItems": 2}},
                },
            },
            "object": {
                "type": "object", "required": ["name", "category", "shape", "size", "pose"],
                "additionalProperties": False,
                "properties": {
                    "name": {"$ref": "#/$defs/name"},
                    "category": {"enum": [c.value for c in Category]},
                    "shape": {"enum": list(SHAPES)},
                    "size": _numbers(3, "metres: box extents; cylinder (diameter, diameter, height); sphere "
                                        "(d, d, d)", positive=True),
                    "pose": {"type": "object", "required": ["x", "y"], "additionalProperties": False,
                             "properties": {"x": {"type": "number"}, "y": {"type": "number"},
                                            "yaw": {"type": "number"}}},
                },
            },
            "action": _act(PLAN_VERBS, ["id", "pid", "verb"], {
                "id": {"$ref": "#/$defs/name"},
                "pid": {"description": "P1 or P2, or a list of them ([giver, receiver], [holder, actor])",
                        "oneOf": [{"enum": list(PERSONS)},
                                  {"type": "array", "items": {"enum": list(PERSONS)}, "minItems": 1}]},
                "partner": {"oneOf": [{"type": "null"}, {"$ref": "#/$defs/partner"}],
                            "description": "holding: what the actor does on the held object"},
                "after": {"$ref": "#/$defs/names", "description": "ids of actions that must end before it"},
                "frames": {"oneOf": [{"type": "null"},
                                     {"type": "array", "items": {"type": "integer", "minimum": 0},
                                      "minItems": 2, "maxItems": 2}],
                           "description": "source video frames [start, end)"},
                "tree": {"type": ["string", "null"], "description": "the action tree, bracket notation"},
            }),
            "partner": _act(VERBS, ["verb"]),
        },
    }
    return json.dumps(schema, indent=2)


def plan_schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a plan file, as a fresh dict."""
    result: dict[str, Any] = json.loads(_schema())
    return result


def schema_text() -> str:
    """The schema as indented JSON (what ``wecook export --schema`` prints)."""
    return _schema() + "\n"


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _where(data: Any, path: Sequence[Any]) -> str:
    """``["actions", 3, "tool"] -> actions[3] (a4).tool``: the reader's way of naming places."""
    out, node = "", data
    for key in path:
        if isinstance(key, int):
            out += f"[{key}]"
            node = node[key] if isinstance(node, list) and key < len(node) else None
            label = node.get("id", node.get("name")) if isinstance(node, dict) else None
            if isinstance(label, str) and label:
                out += f" ({label})"
        else:
            out += f".{key}" if out else str(key)
            node = node.get(key) if isinstance(node, dict) else None
    return out or "top level"


def _message(error: Any) -> tuple[list[Any], str]:
    """(path, message) of a jsonschema error, the message one short line."""
    path = list(error.absolute_path)
    kind, expected, value = error.validator, error.validator_value, error.instance
    if kind == "type":
        types = [expected] if isinstance(expected, str) else list(expected)
        return path, f"expected {' or '.join(types)}, got {_short(value)}"
    if kind == "enum":
        return path, f"expected one of {', '.join(map(str, expected))}, got {_short(value)}"
    if kind == "const":
        if path == ["wecook_plan"]:
            return path, f"not a wecook plan: expected `wecook_plan: {expected}`, got {_short(value)}"
        return path, f"expected {expected!r}, got {_short(value)}"
    if kind == "required":
        missing = [k for k in expected if isinstance(value, dict) and k not in value]
        if path == [] and missing == ["wecook_plan"]:
            return path, f"not a wecook plan: expected `wecook_plan: {PLAN_VERSION}`"
        return path, "missing " + ", ".join(f"`{k}`" for k in missing)
    if kind == "additionalProperties":
        known = sorted(error.schema.get("properties", {}))
        extra = [k for k in value if k not in known] if isinstance(value, dict) else []
        return path + extra[:1], f"unknown key (expected one of {', '.join(known)})"
    if kind in ("minItems", "maxItems"):
        return path, f"expected {error.schema.get('minItems')} items, got {_short(value)}"
    if kind == "exclusiveMinimum":
        return path, f"must be more than {expected}, got {_short(value)}"
    if kind == "minimum":
        return path, f"must be at least {expected}, got {_short(value)}"
    if kind == "minLength":
        return path, "expected a name, got an empty string"
    if kind == "oneOf":
        return path, f"expected {error.schema.get('description') or 'another value'}, got {_short(value)}"
    return path, " ".join(str(error.message).split())[:120]


def check_plan_schema(data: Any, path: str | Path | None = None) -> None:
    """Check parsed plan data (``yaml.safe_load`` of a plan file) against :func:`plan_schema`; the first problem
    (jsonschema's best match) raises an :class:`InputError` naming ``path`` and the place
    (``actions[3] (a4).tool``).

    Valid data is passed by jsonschema-rs where it is installed (a compiled validator: 10,000 actions in about
    15 ms, where jsonschema takes seconds); jsonschema, whose errors say where and what, judges only what
    jsonschema-rs refuses or cannot read (a NaN, a non-string key), so both give the same verdicts."""
    fast = _fast_validator()
    if fast is not None:
        try:
            if fast.is_valid(data):
                return
        except (ValueError, TypeError, OverflowError):
            pass
    from jsonschema import Draft202012Validator
    from jsonschema.exceptions import best_match

    error = best_match(_validator(Draft202012Validator).iter_errors(data))
    if error is None:
        return
    where, message = _message(error)
    raise InputError(path, message, place=_where(data, where))


@cache
def _fast_validator() -> Any:
    """jsonschema-rs's validator of :func:`plan_schema`, or None where jsonschema-rs is not installed."""
    try:
        import jsonschema_rs
    except ImportError:
        return None
    return jsonschema_rs.Draft202012Validator(plan_schema())


@cache
def _validator(cls: Any) -> Any:
    return cls(plan_schema())


def check_plan_file(path: str | Path) -> Plan:
    """Read a plan file and check it: YAML, then :func:`check_plan_schema`, then the plan's own checks
    (:func:`~wecook_core.plan.checks.validate`). The first problem raises an :class:`InputError` naming the file and
    the place; otherwise returns the plan."""
    if not Path(path).exists():
        raise InputError(path, "no such plan file")
    try:
        text = read_text(path, "plan", MAX_PLAN_BYTES)
    except InputError as error:
        raise InputError(path, f"cannot read the plan ({error.message})", place=error.place) from None
    try:
        data = parse_plan_yaml(text, path)  # bounded: depth, aliases, size
    except yaml.YAMLError as error:
        raise yaml_error(path, error, "not valid YAML") from None
    check_plan_schema(data, path)
    plan = plan_from_dict(data, path)
    validate(plan, path)
    return plan
