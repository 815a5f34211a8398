"""The part of JSON Schema the recordings use, checked: what ``runs check`` holds each message to."""

from __future__ import annotations

import json
from typing import Any

from mcap.records import Schema

_KINDS: dict[str, type | tuple[type, ...]] = {"string": str, "number": (int, float), "integer": int,
                                              "boolean": bool, "object": dict, "array": list, "null": type(None)}


def schema_problems(value: Any, schema: dict[str, Any], where: str) -> list[str]:
    """Where ``value`` breaks ``schema``, for the part of JSON Schema the recordings use: ``type`` (one or a
    list), ``properties`` (no other keys allowed), ``items``, ``enum``, ``minimum`` / ``maximum``."""
    expected = schema.get("type")
    if expected is not None:
        names = expected if isinstance(expected, list) else [expected]
        if not any(isinstance(value, _KINDS[n]) and not (n in ("number", "integer") and isinstance(value, bool))
                   for n in names):
            return [f"{where}: {value!r} is not {expected}"]
    problems = []
    if "enum" in schema and value not in schema["enum"]:
        problems.append(f"{where}: {value!r} not in {schema['enum']}")
    if isinstance(value, dict) and "properties" in schema:
        for key, item in value.items():
            if key not in schema["properties"]:
                problems.append(f"{where}.{key}: not in the schema")
            else:
                problems += schema_problems(item, schema["properties"][key], f"{where}.{key}")
    if isinstance(value, list) and "items" in schema:
        for k, item in enumerate(value):
            problems += schema_problems(item, schema["items"], f"{where}[{k}]")
    if isinstance(value, int | float) and not isinstance(value, bool):
        if "minimum" in schema and value < schema["minimum"]:
            problems.append(f"{where}: {value} < {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            problems.append(f"{where}: {value} > {schema['maximum']}")
    return problems


def schema_json(schema: Schema) -> dict[str, Any]:
    try:
        data = json.loads(schema.data)
    except ValueError:
        return {}
    return data if isinstance(data, dict) else {}
