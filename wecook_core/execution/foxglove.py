"""Foxglove well-known schemas (JSON Schema, JSON encoding) and the JSON messages of a run's recording.

Field names follow the Foxglove schemas (foxglove.FrameTransforms, foxglove.SceneUpdate, foxglove.Log,
foxglove.CompressedImage): times are ``{sec, nsec}``, vectors ``{x, y, z}``, quaternions ``{x, y, z, w}``,
colours ``{r, g, b, a}`` in 0..1, image bytes base64. Two schemas are wecook's own: ``wecook.JointState`` and
``wecook.RunEvent``.
"""

from __future__ import annotations

import base64
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from wecook_core.execution.observer import FrameInfo, Quat, RunEvent, Shape, Vec3

WORLD_FRAME = "world"

TOPIC_SCHEMAS: dict[str, str] = {
    "/tf": "foxglove.FrameTransforms",
    "/scene": "foxglove.SceneUpdate",
    "/joint_states": "wecook.JointState",
    "/plan/events": "wecook.RunEvent",
    "/log": "foxglove.Log",
    "/camera": "foxglove.CompressedImage",
}
"""Topic -> schema name of every topic a run records."""
REQUIRED_TOPICS: tuple[str, ...] = ("/tf", "/scene", "/joint_states", "/plan/events", "/log")
"""Topics every finished recording has (``/camera`` is optional)."""

LOG_LEVELS = {"debug": 1, "info": 2, "warning": 3, "error": 4}
"""foxglove.Log levels (0 unknown, 5 fatal)."""


# ---------------------------------------------------------------------------------------- JSON Schema


def _number(description: str) -> dict[str, Any]:
    return {"type": "number", "description": description}


def _time(description: str) -> dict[str, Any]:
    return {"type": "object", "title": "time", "description": description,
            "properties": {"sec": {"type": "integer", "minimum": 0},
                           "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}}


def _vector3(description: str) -> dict[str, Any]:
    return {"title": "foxglove.Vector3", "type": "object", "description": description,
            "properties": {axis: _number(f"{axis} (metres)") for axis in "xyz"}}


def _quaternion(description: str) -> dict[str, Any]:
    return {"title": "foxglove.Quaternion", "type": "object", "description": description,
            "properties": {axis: _number(f"{axis} component") for axis in "xyzw"}}


def _pose(description: str) -> dict[str, Any]:
    return {"title": "foxglove.Pose", "type": "object", "description": description,
            "properties": {"position": _vector3("position"), "orientation": _quaternion("orientation")}}


def _color() -> dict[str, Any]:
    return {"title": "foxglove.Color", "type": "object", "description": "colour, each channel 0..1",
            "properties": {c: _number(c) for c in "rgba"}}


def _array(items: dict[str, Any], description: str) -> dict[str, Any]:
    return {"type": "array", "items": items, "description": description}


def _primitive(title: str, description: str, extra: Mapping[str, Any] = {}) -> dict[str, Any]:
    return {"title": title, "type": "object", "description": description,
            "properties": {"pose": _pose("centre and orientation in the entity's frame"),
                           "size": _vector3("full extents along each axis (metres)"), "color": _color(), **extra}}


def frame_transforms_schema() -> dict[str, Any]:
    transform = {"title": "foxglove.FrameTransform", "type": "object",
                 "description": "pose of child_frame_id in parent_frame_id",
                 "properties": {"timestamp": _time("time of the transform"),
                                "parent_frame_id": {"type": "string"}, "child_frame_id": {"type": "string"},
                                "translation": _vector3("translation"), "rotation": _quaternion("rotation")}}
    return {"title": "foxglove.FrameTransforms", "type": "object", "description": "transforms between frames",
            "properties": {"transforms": _array(transform, "transforms")}}


def scene_update_schema() -> dict[str, Any]:
    deletion = {"title": "foxglove.SceneEntityDeletion", "type": "object",
                "properties": {"timestamp": _time("entities older than this are deleted"),
                               "type": {"type": "integer", "description": "0 matching id, 1 all"},
                               "id": {"type": "string"}}}
    entity = {"title": "foxglove.SceneEntity", "type": "object",
              "description": "shapes drawn in one frame",
              "properties": {
                  "timestamp": _time("time of the entity"),
                  "frame_id": {"type": "string", "description": "frame the primitives are given in"},
                  "id": {"type": "string", "description": "replaces an earlier entity with the same id"},
                  "lifetime": {"type": "object", "title": "duration",
                               "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}},
                               "description": "zero: until replaced"},
                  "frame_locked": {"type": "boolean", "description": "follow frame_id as it moves"},
                  "metadata": _array({"title": "foxglove.KeyValuePair", "type": "object",
                                      "properties": {"key": {"type": "string"}, "value": {"type": "string"}}},
                                     "key-value pairs"),
                  "cubes": _array(_primitive("foxglove.CubePrimitive", "a box"), "boxes"),
                  "spheres": _array(_primitive("foxglove.SpherePrimitive", "a sphere (size: diameters)"),
                                    "spheres"),
                  "cylinders": _array(_primitive("foxglove.CylinderPrimitive", "a cylinder along z",
                                                 {"bottom_scale": _number("bottom diameter ratio 0..1"),
                                                  "top_scale": _number("top diameter ratio 0..1")}), "cylinders"),
                  **{kind: _array({"type": "object"}, f"{kind} primitives (never written by wecook)")
                     for kind in ("arrows", "lines", "triangles", "texts", "models")},
              }}
    return {"title": "foxglove.SceneUpdate", "type": "object", "description": "entities of a 3D scene",
            "properties": {"deletions": _array(deletion, "entities to delete"),
                           "entities": _array(entity, "entities to add or replace")}}


def log_schema() -> dict[str, Any]:
    return {"title": "foxglove.Log", "type": "object", "description": "a log line",
            "properties": {"timestamp": _time("time of the line"),
                           "level": {"type": "integer", "description": "0 unknown 1 debug 2 info 3 warning 4 "
                                     "error 5 fatal"},
                           "message": {"type": "string"}, "name": {"type": "string"},
                           "file": {"type": "string"}, "line": {"type": "integer", "minimum": 0}}}


def compressed_image_schema() -> dict[str, Any]:
    return {"title": "foxglove.CompressedImage", "type": "object", "description": "a compressed image",
            "properties": {"timestamp": _time("time of the image"), "frame_id": {"type": "string"},
                           "data": {"type": "string", "contentEncoding": "base64"},
                           "format": {"type": "string", "description": "jpeg or png"}}}


def joint_state_schema() -> dict[str, Any]:
    return {"title": "wecook.JointState", "type": "object", "description": "one arm's joint positions",
            "properties": {"timestamp": _time("time of the state"),
                           "agent": {"type": "string", "description": "P1 or P2"},
                           "name": _array({"type": "string"}, "joint names"),
                           "position": _array({"type": "number"}, "radians (revolute) or metres (prismatic)")}}


def run_event_schema() -> dict[str, Any]:
    kinds = ["action_start", "action_end", "action_failed", "primitive_start", "primitive_end",
             "primitive_failed", "retry", "wait", "run_end"]
    nullable = {"type": ["string", "null"]}
    return {"title": "wecook.RunEvent", "type": "object", "description": "a step of the plan",
            "properties": {"timestamp": _time("time of the event"),
                           "kind": {"type": "string", "enum": kinds},
                           "action_id": nullable, "primitive": nullable, "agent": nullable,
                           "detail": {"type": "string", "description": "failure reason, retry count, ..."},
                           "data": {"type": "object", "description": "extra values"}}}


SCHEMAS: dict[str, dict[str, Any]] = {
    "foxglove.FrameTransforms": frame_transforms_schema(),
    "foxglove.SceneUpdate": scene_update_schema(),
    "foxglove.Log": log_schema(),
    "foxglove.CompressedImage": compressed_image_schema(),
    "wecook.JointState": joint_state_schema(),
    "wecook.RunEvent": run_event_schema(),
}
"""Schema name -> JSON Schema."""


# -------------------------------------------------------------------------------------------- messages


def stamp(ns: int) -> dict[str, int]:
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def _vec(v: Sequence[float]) -> dict[str, float]:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def _quat(q: Sequence[float]) -> dict[str, float]:
    return {"x": float(q[0]), "y": float(q[1]), "z": float(q[2]), "w": float(q[3])}


def frame_transforms(ns: int, poses: Mapping[str, tuple[Vec3, Quat]]) -> dict[str, Any]:
    ts = stamp(ns)
    return {"transforms": [{"timestamp": ts, "parent_frame_id": WORLD_FRAME, "child_frame_id": frame,
                            "translation": _vec(pos), "rotation": _quat(quat)}
                           for frame, (pos, quat) in poses.items()]}


def _num(value: float) -> str:
    v = float(value)
    return f"{v:.6f}" if math.isfinite(v) else "null"


_NAMES: dict[str, str] = {}
_TRANSFORM = ('{"timestamp":%s,"parent_frame_id":"' + WORLD_FRAME + '","child_frame_id":%s,'
              '"translation":{"x":%.6f,"y":%.6f,"z":%.6f},"rotation":{"x":%.6f,"y":%.6f,"z":%.6f,"w":%.6f}}')


def frame_transforms_json(ns: int, poses: Mapping[str, tuple[Vec3, Quat]]) -> bytes:
    """The JSON of :func:`frame_transforms`, compact, built by string formatting (about 4x faster than
    ``json.dumps``: ``/tf`` is most of a recording). Numbers have 6 decimals (micrometres); a non-finite one
    is written ``null``."""
    ts = f'{{"sec":{ns // 1_000_000_000},"nsec":{ns % 1_000_000_000}}}'
    parts = []
    for frame, (p, q) in poses.items():
        name = _NAMES.get(frame)
        if name is None:
            name = _NAMES[frame] = json.dumps(frame)
        if math.isfinite(p[0] + p[1] + p[2] + q[0] + q[1] + q[2] + q[3]):
            parts.append(_TRANSFORM % (ts, name, p[0], p[1], p[2], q[0], q[1], q[2], q[3]))
        else:
            parts.append((_TRANSFORM.replace("%.6f", "%s")) % (ts, name, *map(_num, (*p, *q))))
    return ('{"transforms":[' + ",".join(parts) + "]}").encode()


def _shape(shape: Shape) -> tuple[str, dict[str, Any]]:
    pos, quat = shape.pose
    r, g, b, a = shape.color
    primitive: dict[str, Any] = {"pose": {"position": _vec(pos), "orientation": _quat(quat)},
                                 "size": _vec(shape.size), "color": {"r": r, "g": g, "b": b, "a": a}}
    if shape.kind == "cylinder":
        primitive.update(bottom_scale=1.0, top_scale=1.0)
        return "cylinders", primitive
    return ("spheres" if shape.kind == "sphere" else "cubes"), primitive


def scene_update(ns: int, frames: Iterable[FrameInfo]) -> dict[str, Any]:
    """One entity per frame that has shapes, locked to its frame (it moves with the frame's /tf pose)."""
    entities = []
    for frame in frames:
        if not frame.shapes:
            continue
        entity: dict[str, Any] = {"timestamp": stamp(ns), "frame_id": frame.frame_id, "id": frame.frame_id,
                                  "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": True, "metadata": [],
                                  "arrows": [], "cubes": [], "spheres": [], "cylinders": [], "lines": [],
                                  "triangles": [], "texts": [], "models": []}
        for shape in frame.shapes:
            key, primitive = _shape(shape)
            entity[key].append(primitive)
        entities.append(entity)
    return {"deletions": [], "entities": entities}


def joint_state(ns: int, agent: str, names: Sequence[str], positions: Sequence[float]) -> dict[str, Any]:
    return {"timestamp": stamp(ns), "agent": agent, "name": list(names), "position": [float(p) for p in positions]}


def run_event(ns: int, event: RunEvent) -> dict[str, Any]:
    return {"timestamp": stamp(ns), "kind": event.kind, "action_id": event.action_id,
            "primitive": event.primitive, "agent": event.agent, "detail": event.detail, "data": dict(event.data)}


def log(ns: int, level: str, message: str, name: str = "wecook.execute") -> dict[str, Any]:
    return {"timestamp": stamp(ns), "level": LOG_LEVELS.get(level, 0), "message": message, "name": name,
            "file": "", "line": 0}


def compressed_image(ns: int, data: bytes, fmt: str = "jpeg", frame_id: str = "camera") -> dict[str, Any]:
    return {"timestamp": stamp(ns), "frame_id": frame_id, "data": base64.b64encode(data).decode("ascii"),
            "format": fmt}
