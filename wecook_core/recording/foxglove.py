"""Foxglove well-known schemas (JSON Schema, JSON encoding) and the JSON messages of a run's recording.

Field names follow the Foxglove schemas (foxglove.FrameTransforms, foxglove.SceneUpdate, foxglove.Log,
foxglove.CompressedImage, foxglove.CameraCalibration): times are ``{sec, nsec}``, vectors ``{x, y, z}``,
quaternions ``{x, y, z, w}``, colours ``{r, g, b, a}`` in 0..1, image and model bytes base64. Joint states use ROS 2's
``sensor_msgs/msg/JointState`` layout (``header.stamp {sec, nanosec}``, ``name``, ``position``, ``velocity``,
``effort``), one message for both arms with names ``<pid>/<joint>``, so tools that know ROS joint states read
them. ``wecook.RunEvent`` is wecook's own.

Every object schema lists its ``required`` fields and allows no others, so a validator (``jsonschema``) catches
a missing or misspelt field; Foxglove ignores both keywords.

``/robot`` holds the arms' link meshes (foxglove.SceneUpdate with model primitives, GLB data embedded), written
once at the start: it is large, and a viewer that seeks gets the latest message of each topic anyway.
``/scene`` holds the table and the objects (small; repeated at every flush).
"""

from __future__ import annotations

import base64
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, Shape, Vec3

WORLD_FRAME = "world"

JOINT_STATE = "sensor_msgs/msg/JointState"

TOPIC_SCHEMAS: dict[str, str] = {
    "/tf": "foxglove.FrameTransforms",
    "/scene": "foxglove.SceneUpdate",
    "/robot": "foxglove.SceneUpdate",
    "/joint_states": JOINT_STATE,
    "/plan/events": "wecook.RunEvent",
    "/log": "foxglove.Log",
    "/camera": "foxglove.CompressedImage",
    "/camera/calibration": "foxglove.CameraCalibration",
}
"""Topic -> schema name of every topic a run records."""
REQUIRED_TOPICS: tuple[str, ...] = ("/tf", "/scene", "/joint_states", "/plan/events", "/log")
"""Topics every finished recording has (``/camera``, ``/camera/calibration`` and ``/robot`` are optional)."""

LOG_LEVELS = {"debug": 1, "info": 2, "warning": 3, "error": 4}
"""foxglove.Log levels (0 unknown, 5 fatal)."""


# ---------------------------------------------------------------------------------------- JSON Schema


def _number(description: str) -> dict[str, Any]:
    return {"type": "number", "description": description}


def _object(title: str | None, description: str, properties: dict[str, Any],
            optional: tuple[str, ...] = ()) -> dict[str, Any]:
    """An object schema whose properties are all required (but ``optional``) and the only ones allowed."""
    out: dict[str, Any] = {"type": "object", "description": description, "properties": properties,
                           "required": [k for k in properties if k not in optional], "additionalProperties": False}
    if title is not None:
        out["title"] = title
    return out


def _time(description: str, nsec: str = "nsec") -> dict[str, Any]:
    return _object("time", description, {"sec": {"type": "integer", "minimum": 0},
                                         nsec: {"type": "integer", "minimum": 0, "maximum": 999_999_999}})


def _vector3(description: str) -> dict[str, Any]:
    return _object("foxglove.Vector3", description, {axis: _number(f"{axis} (metres)") for axis in "xyz"})


def _quaternion(description: str) -> dict[str, Any]:
    return _object("foxglove.Quaternion", description, {axis: _number(f"{axis} component") for axis in "xyzw"})


def _pose(description: str) -> dict[str, Any]:
    return _object("foxglove.Pose", description,
                   {"position": _vector3("position"), "orientation": _quaternion("orientation")})


def _color() -> dict[str, Any]:
    return _object("foxglove.Color", "colour, each channel 0..1",
                   {c: {"type": "number", "minimum": 0, "maximum": 1} for c in "rgba"})


def _array(items: dict[str, Any], description: str) -> dict[str, Any]:
    return {"type": "array", "items": items, "description": description}


def _primitive(title: str, description: str, extra: Mapping[str, Any] = {}) -> dict[str, Any]:
    return _object(title, description, {"pose": _pose("centre and orientation in the entity's frame"),
                                        "size": _vector3("full extents along each axis (metres)"),
                                        "color": _color(), **extra})


def _model() -> dict[str, Any]:
    return _object("foxglove.ModelPrimitive", "a 3D model (embedded GLB)", {
        "pose": _pose("origin of the model in the entity's frame"),
        "scale": _vector3("scale along each axis"), "color": _color(),
        "override_color": {"type": "boolean", "description": "draw in color instead of the model's materials"},
        "url": {"type": "string", "description": "empty: the model is embedded in data"},
        "media_type": {"type": "string", "description": "model/gltf-binary"},
        "data": {"type": "string", "contentEncoding": "base64", "description": "the model file"}})


def frame_transforms_schema() -> dict[str, Any]:
    transform = _object("foxglove.FrameTransform", "pose of child_frame_id in parent_frame_id",
                        {"timestamp": _time("time of the transform"), "parent_frame_id": {"type": "string"},
                         "child_frame_id": {"type": "string"}, "translation": _vector3("translation"),
                         "rotation": _quaternion("rotation")})
    return _object("foxglove.FrameTransforms", "transforms between frames",
                   {"transforms": _array(transform, "transforms")})


def scene_update_schema() -> dict[str, Any]:
    deletion = _object("foxglove.SceneEntityDeletion", "a deletion",
                       {"timestamp": _time("entities older than this are deleted"),
                        "type": {"type": "integer", "description": "0 matching id, 1 all"}, "id": {"type": "string"}})
    entity = _object("foxglove.SceneEntity", "shapes drawn in one frame", {
        "timestamp": _time("time of the entity"),
        "frame_id": {"type": "string", "description": "frame the primitives are given in"},
        "id": {"type": "string", "description": "replaces an earlier entity with the same id"},
        "lifetime": _object("duration", "zero: until replaced", {"sec": {"type": "integer"},
                                                                 "nsec": {"type": "integer"}}),
        "frame_locked": {"type": "boolean", "description": "follow frame_id as it moves"},
        "metadata": _array(_object("foxglove.KeyValuePair", "a pair", {"key": {"type": "string"},
                                                                      "value": {"type": "string"}}),
                           "key-value pairs"),
        "cubes": _array(_primitive("foxglove.CubePrimitive", "a box"), "boxes"),
        "spheres": _array(_primitive("foxglove.SpherePrimitive", "a sphere (size: diameters)"), "spheres"),
        "cylinders": _array(_primitive("foxglove.CylinderPrimitive", "a cylinder along z",
                                       {"bottom_scale": _number("bottom diameter ratio 0..1"),
                                        "top_scale": _number("top diameter ratio 0..1")}), "cylinders"),
        "models": _array(_model(), "meshes"),
        **{kind: _array({"type": "object"}, f"{kind} primitives (never written by wecook)")
           for kind in ("arrows", "lines", "triangles", "texts")},
    })
    return _object("foxglove.SceneUpdate", "entities of a 3D scene",
                   {"deletions": _array(deletion, "entities to delete"),
                    "entities": _array(entity, "entities to add or replace")})


def log_schema() -> dict[str, Any]:
    return _object("foxglove.Log", "a log line", {
        "timestamp": _time("time of the line"),
        "level": {"type": "integer", "minimum": 0, "maximum": 5,
                  "description": "0 unknown 1 debug 2 info 3 warning 4 error 5 fatal"},
        "message": {"type": "string"}, "name": {"type": "string"},
        "file": {"type": "string"}, "line": {"type": "integer", "minimum": 0}})


def compressed_image_schema() -> dict[str, Any]:
    return _object("foxglove.CompressedImage", "a compressed image", {
        "timestamp": _time("time of the image"), "frame_id": {"type": "string"},
        "data": {"type": "string", "contentEncoding": "base64"},
        "format": {"type": "string", "enum": ["jpeg", "png"]}})


def camera_calibration_schema() -> dict[str, Any]:
    def numbers(n: int | None, description: str) -> dict[str, Any]:
        out = _array({"type": "number"}, description)
        return out if n is None else {**out, "minItems": n, "maxItems": n}

    return _object("foxglove.CameraCalibration", "a pinhole camera's intrinsics (as ROS's CameraInfo)", {
        "timestamp": _time("time of the calibration"),
        "frame_id": {"type": "string", "description": "the camera's optical frame: z forward, x right, y down"},
        "width": {"type": "integer", "minimum": 0, "description": "image width, pixels"},
        "height": {"type": "integer", "minimum": 0, "description": "image height, pixels"},
        "distortion_model": {"type": "string", "description": "plumb_bob: D holds k1 k2 t1 t2 k3"},
        "D": numbers(None, "distortion coefficients"),
        "K": numbers(9, "intrinsic matrix, row-major 3x3 (pixels)"),
        "R": numbers(9, "rectification matrix, row-major 3x3"),
        "P": numbers(12, "projection matrix, row-major 3x4 (pixels)")})


def joint_state_schema() -> dict[str, Any]:
    header = _object("std_msgs/msg/Header", "stamp and frame", {"stamp": _time("time of the state", "nanosec"),
                                                                "frame_id": {"type": "string"}})
    return _object(JOINT_STATE, "both arms' joints (ROS 2 layout); names are <pid>/<joint>", {
        "header": header,
        "name": _array({"type": "string"}, "joint names, e.g. P1/panda_joint1"),
        "position": _array({"type": "number"}, "radians (revolute) or metres (prismatic)"),
        "velocity": _array({"type": "number"}, "rad/s or m/s (differences of the recorded positions)"),
        "effort": _array({"type": "number"}, "empty: not measured")})


def run_event_schema() -> dict[str, Any]:
    kinds = ["action_start", "action_end", "action_failed", "primitive_start", "primitive_end",
             "primitive_failed", "retry", "wait", "run_end"]
    nullable = {"type": ["string", "null"]}
    return _object("wecook.RunEvent", "a step of the plan", {
        "timestamp": _time("time of the event"), "kind": {"type": "string", "enum": kinds},
        "action_id": nullable, "primitive": nullable, "agent": nullable,
        "detail": {"type": "string", "description": "failure reason, retry count, ..."},
        "data": {"type": "object", "description": "extra values"}})


SCHEMAS: dict[str, dict[str, Any]] = {
    "foxglove.FrameTransforms": frame_transforms_schema(),
    "foxglove.SceneUpdate": scene_update_schema(),
    "foxglove.Log": log_schema(),
    "foxglove.CompressedImage": compressed_image_schema(),
    "foxglove.CameraCalibration": camera_calibration_schema(),
    JOINT_STATE: joint_state_schema(),
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
        entity = _entity(ns, frame.frame_id)
        for shape in frame.shapes:
            key, primitive = _shape(shape)
            entity[key].append(primitive)
        entities.append(entity)
    return {"deletions": [], "entities": entities}


def joint_state(ns: int, names: Sequence[str], positions: Sequence[float],
                velocities: Sequence[float] = ()) -> dict[str, Any]:
    """A ROS 2 ``sensor_msgs/msg/JointState`` (JSON); non-finite numbers are written as 0."""
    def finite(values: Sequence[float]) -> list[float]:
        return [float(v) if math.isfinite(v) else 0.0 for v in values]

    return {"header": {"stamp": {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}, "frame_id": ""},
            "name": list(names), "position": finite(positions), "velocity": finite(velocities), "effort": []}


def _entity(ns: int, frame_id: str) -> dict[str, Any]:
    return {"timestamp": stamp(ns), "frame_id": frame_id, "id": frame_id, "lifetime": {"sec": 0, "nsec": 0},
            "frame_locked": True, "metadata": [], "arrows": [], "cubes": [], "spheres": [], "cylinders": [],
            "lines": [], "triangles": [], "texts": [], "models": []}


def model_primitive(glb: bytes, pose: tuple[Vec3, Quat], scale: Vec3 = (1.0, 1.0, 1.0)) -> dict[str, Any]:
    return {"pose": {"position": _vec(pose[0]), "orientation": _quat(pose[1])}, "scale": _vec(scale),
            "color": {"r": 1.0, "g": 1.0, "b": 1.0, "a": 1.0}, "override_color": False, "url": "",
            "media_type": "model/gltf-binary", "data": base64.b64encode(glb).decode("ascii")}


def robot_update(ns: int, models: Mapping[str, Sequence[dict[str, Any]]]) -> dict[str, Any]:
    """One entity per link (frame id -> its :func:`model_primitive` s), locked to the link's frame."""
    entities = []
    for frame_id, primitives in models.items():
        if primitives:
            entity = _entity(ns, frame_id)
            entity["models"] = list(primitives)
            entities.append(entity)
    return {"deletions": [], "entities": entities}


def run_event(ns: int, event: RunEvent) -> dict[str, Any]:
    return {"timestamp": stamp(ns), "kind": event.kind, "action_id": event.action_id,
            "primitive": event.primitive, "agent": event.agent, "detail": event.detail, "data": dict(event.data)}


def log(ns: int, level: str, message: str, name: str = "wecook.execute") -> dict[str, Any]:
    return {"timestamp": stamp(ns), "level": LOG_LEVELS.get(level, 0), "message": message, "name": name,
            "file": "", "line": 0}


def compressed_image(ns: int, data: bytes, fmt: str = "jpeg", frame_id: str = "camera") -> dict[str, Any]:
    return {"timestamp": stamp(ns), "frame_id": frame_id, "data": base64.b64encode(data).decode("ascii"),
            "format": fmt}


def camera_calibration(ns: int, width: int, height: int, focal: float, centre: tuple[float, float],
                       frame_id: str = "camera") -> dict[str, Any]:
    """A distortion-free pinhole camera with square pixels (``focal`` = fx = fy, ``centre`` = (cx, cy), pixels)."""
    f, (cx, cy) = float(focal), (float(centre[0]), float(centre[1]))
    return {"timestamp": stamp(ns), "frame_id": frame_id, "width": int(width), "height": int(height),
            "distortion_model": "plumb_bob", "D": [0.0] * 5, "K": [f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0],
            "R": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            "P": [f, 0.0, cx, 0.0, 0.0, f, cy, 0.0, 0.0, 0.0, 1.0, 0.0]}
