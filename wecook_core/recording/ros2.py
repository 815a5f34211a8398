"""A run's recording as a ROS 2 bag (``wecook runs export FILE --ros2 OUT``), for ``ros2 bag`` and rosbags tools.

The recording itself stays as it is (JSON messages with Foxglove schemas, what Foxglove shows); the bag holds the
same run as ROS 2 messages, CDR-encoded, in rosbag2's layout (a folder ``OUT`` with ``metadata.yaml`` and the
storage file: ``OUT.mcap`` with the ``ros2`` profile and ``ros2msg`` schemas, or ``OUT.db3``), written by
rosbags (the ``ros2`` extra) with the message definitions of ROS 2 :data:`DISTRO`.

=====================  =====================================  ===================================================
recording              bag                                    ROS 2 message
=====================  =====================================  ===================================================
``/tf``                ``/tf``                                tf2_msgs/msg/TFMessage (every frame in ``world``,
                                                              the camera's optical frame too)
``/joint_states``      ``/<pid>/joint_states`` (one per arm)  sensor_msgs/msg/JointState: joint names as in the
                                                              URDF, ``header.frame_id`` the arm's root frame
                                                              (``P1/panda_link0``: the arm's namespace)
``/camera``            ``/camera/image/compressed``           sensor_msgs/msg/CompressedImage
``/camera/calibration``  ``/camera/camera_info``              sensor_msgs/msg/CameraInfo
``/log``               ``/rosout``                            rcl_interfaces/msg/Log
``/plan/events``       ``/plan/events``                       std_msgs/msg/String (the event as JSON)
=====================  =====================================  ===================================================

``/scene`` and ``/robot`` (Foxglove scene entities and meshes) have no standard ROS 2 message and are left out
(:attr:`Ros2Export.left_out` says so). Every message keeps its log time as the bag's receive time; stamps are the
recording's. The recording's ``wecook`` metadata (versions, seed) goes in the bag's ``custom_data``.
"""

from __future__ import annotations

import contextlib
import json
import math
import shutil
from collections import Counter
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from wecook_core.errors import InputError
from wecook_core.recording.report import read_extras, read_messages

DISTRO = "ROS2_JAZZY"
"""The rosbags type store whose message definitions the bag carries (rosbag2 format version :data:`VERSION`)."""
VERSION: Literal[8] = 8
STORAGES = ("mcap", "sqlite3")

ROS_LOG_LEVELS = {0: 0, 1: 10, 2: 20, 3: 30, 4: 40, 5: 50}
"""foxglove.Log level -> rcl_interfaces/msg/Log level."""


@dataclass(frozen=True)
class Ros2Export:
    """What :func:`export_ros2` wrote."""

    out: Path
    """The bag's folder."""
    storage: str
    """``mcap`` or ``sqlite3``."""
    messages: dict[str, int]
    """Bag topic -> messages written."""
    types: dict[str, str]
    """Bag topic -> ROS 2 message type."""
    left_out: dict[str, int] = field(default_factory=dict)
    """Recording topic -> messages not exported (no ROS 2 message for them)."""


def _writer(out: Path, storage: str) -> tuple[Any, Any]:
    """A rosbags writer of the bag ``out`` (not opened; mcap chunks zstd-compressed) and the type store."""
    try:
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise InputError(None, "--ros2 needs rosbags: pip install 'wecook[ros2]'") from None
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    writer = Writer(out, version=VERSION, storage_plugin=plugin)
    if storage == "mcap":  # zstd chunks, read by every mcap reader (sqlite3 would need whole-file compression)
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    return writer, get_typestore(getattr(Stores, DISTRO))


class _Messages:
    """Builders of ROS 2 messages from the recording's JSON, with the type store's classes."""

    def __init__(self, store: Any) -> None:
        self.store = store
        t = store.types
        self.Time, self.Header = t["builtin_interfaces/msg/Time"], t["std_msgs/msg/Header"]
        self.Vector3, self.Quaternion = t["geometry_msgs/msg/Vector3"], t["geometry_msgs/msg/Quaternion"]
        self.Transform = t["geometry_msgs/msg/Transform"]
        self.TransformStamped = t["geometry_msgs/msg/TransformStamped"]
        self.TFMessage, self.JointState = t["tf2_msgs/msg/TFMessage"], t["sensor_msgs/msg/JointState"]
        self.CompressedImage, self.CameraInfo = t["sensor_msgs/msg/CompressedImage"], t["sensor_msgs/msg/CameraInfo"]
        self.RegionOfInterest, self.Log = t["sensor_msgs/msg/RegionOfInterest"], t["rcl_interfaces/msg/Log"]
        self.String = t["std_msgs/msg/String"]

    def time(self, stamp: dict[str, Any] | None, ns: int) -> Any:
        """A recording's ``{sec, nsec}`` (or ``{sec, nanosec}``) stamp; the log time when it has none."""
        if not isinstance(stamp, dict):
            return self.Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)
        nanosec = stamp["nsec"] if "nsec" in stamp else stamp.get("nanosec", 0)
        return self.Time(sec=int(stamp.get("sec", 0)), nanosec=int(nanosec))

    def header(self, stamp: dict[str, Any] | None, ns: int, frame_id: str) -> Any:
        return self.Header(stamp=self.time(stamp, ns), frame_id=frame_id)

    def tf(self, ns: int, message: dict[str, Any]) -> Any:
        transforms = []
        headers: dict[tuple[Any, str], Any] = {}  # one per stamp and parent: a message has one of each
        for t in message.get("transforms") or ():
            p, q = t.get("translation") or {}, t.get("rotation") or {}
            stamp, parent = t.get("timestamp"), str(t.get("parent_frame_id", ""))
            key = (tuple(stamp.items()) if isinstance(stamp, dict) else None, parent)
            if key not in headers:
                headers[key] = self.header(stamp, ns, parent)
            transforms.append(self.TransformStamped(
                header=headers[key],
                child_frame_id=str(t.get("child_frame_id", "")),
                transform=self.Transform(translation=self.Vector3(x=_f(p, "x"), y=_f(p, "y"), z=_f(p, "z")),
                                         rotation=self.Quaternion(x=_f(q, "x"), y=_f(q, "y"), z=_f(q, "z"),
                                                                  w=_f(q, "w", 1.0)))))
        return self.TFMessage(transforms=transforms)

    def joint_state(self, ns: int, stamp: Any, frame_id: str, names: list[str], position: list[float],
                    velocity: list[float]) -> Any:
        return self.JointState(header=self.header(stamp, ns, frame_id), name=names,
                               position=np.asarray(position, dtype=np.float64),
                               velocity=np.asarray(velocity, dtype=np.float64), effort=np.zeros(0, dtype=np.float64))

    def image(self, ns: int, message: dict[str, Any]) -> Any:
        import base64

        data = base64.b64decode(message.get("data") or "")
        return self.CompressedImage(header=self.header(message.get("timestamp"), ns, str(message.get("frame_id", ""))),
                                    format=str(message.get("format", "jpeg")),
                                    data=np.frombuffer(data, dtype=np.uint8))

    def camera_info(self, ns: int, message: dict[str, Any]) -> Any:
        def array(key: str, n: int | None) -> np.ndarray:
            values = np.asarray([float(v) for v in message.get(key) or ()], dtype=np.float64)
            return values if n is None or len(values) == n else np.zeros(n, dtype=np.float64)

        return self.CameraInfo(header=self.header(message.get("timestamp"), ns, str(message.get("frame_id", ""))),
                               height=int(message.get("height", 0)), width=int(message.get("width", 0)),
                               distortion_model=str(message.get("distortion_model", "")), d=array("D", None),
                               k=array("K", 9), r=array("R", 9), p=array("P", 12), binning_x=0, binning_y=0,
                               roi=self.RegionOfInterest(x_offset=0, y_offset=0, height=0, width=0, do_rectify=False))

    def log(self, ns: int, message: dict[str, Any]) -> Any:
        return self.Log(stamp=self.time(message.get("timestamp"), ns),
                        level=ROS_LOG_LEVELS.get(int(message.get("level", 0)), 0), name=str(message.get("name", "")),
                        msg=str(message.get("message", "")), file=str(message.get("file", "")), function="",
                        line=int(message.get("line", 0)))


def _f(values: dict[str, Any], key: str, default: float = 0.0) -> float:
    """A number of the recording's JSON; ``null`` (written for a non-finite number) is NaN."""
    value = values.get(key, default)
    return math.nan if value is None else float(value)


def _arm_roots(messages: Iterable[tuple[str, str, int, bytes]]) -> dict[str, str]:
    """Arm namespace -> its root frame: the first ``<pid>/...`` frame of the first ``/tf`` message (the
    executor lists each arm's base link first)."""
    for topic, _, _, data in messages:
        if topic != "/tf":
            continue
        roots: dict[str, str] = {}
        with contextlib.suppress(ValueError, AttributeError, TypeError):
            for t in json.loads(data).get("transforms") or ():
                child = str(t.get("child_frame_id", ""))
                if "/" in child:
                    roots.setdefault(child.split("/", 1)[0], child)
        return roots
    return {}


def _arm_joints(message: dict[str, Any]) -> Iterator[tuple[str, list[str], list[float], list[float]]]:
    """(namespace, URDF joint names, positions, velocities) per arm of one recorded joint state, whose names are
    ``<pid>/<joint>`` (or, in older recordings, bare with the arm in ``agent``)."""
    names = [str(n) for n in message.get("name") or ()]
    position, velocity = list(message.get("position") or ()), list(message.get("velocity") or ())
    arms: dict[str, tuple[list[str], list[float], list[float]]] = {}
    for k, full in enumerate(names):
        pid, _, joint = full.rpartition("/")
        pid = pid or str(message.get("agent") or "")
        arm = arms.setdefault(pid, ([], [], []))
        arm[0].append(joint)
        arm[1].append(_num(position, k))
        arm[2].append(_num(velocity, k))
    for pid, (joints, pos, vel) in arms.items():
        yield pid, joints, pos, vel


def _num(values: list[Any], k: int) -> float:
    return float(values[k]) if k < len(values) and values[k] is not None else math.nan


def export_ros2(path: str | Path, out: str | Path, *, storage: Literal["mcap", "sqlite3"] = "mcap") -> Ros2Export:
    """Write the recording ``path`` as the ROS 2 bag ``out`` (a new folder; an existing one is an InputError and is
    left as it is). A bag left unfinished by an error is removed."""
    path, out = Path(path), Path(out)
    if storage not in STORAGES:
        raise InputError(None, f"--storage {storage}: expected one of {', '.join(STORAGES)}")
    if out.exists() or out.is_symlink():
        raise InputError(out, "exists; not overwritten (choose another --ros2 folder)")
    writer, store = _writer(out, storage)
    messages = list(read_messages(path))
    _, meta = read_extras(path)
    roots = _arm_roots(messages)
    build = _Messages(store)
    counts: Counter[str] = Counter()
    left_out: Counter[str] = Counter()
    types: dict[str, str] = {}
    connections: dict[str, Any] = {}

    def write(topic: str, ns: int, message: Any) -> None:
        msgtype = message.__msgtype__
        if topic not in connections:
            connections[topic] = writer.add_connection(topic, msgtype, typestore=store)
            types[topic] = msgtype
        writer.write(connections[topic], ns, store.serialize_cdr(message, msgtype))
        counts[topic] += 1

    try:
        writer.open()
        for key, value in meta.items():
            writer.set_custom_data(f"wecook.{key}", str(value))
        for topic, _, ns, data in messages:
            try:
                message = json.loads(data)
            except ValueError:
                left_out[topic] += 1
                continue
            if topic == "/tf":
                write("/tf", ns, build.tf(ns, message))
            elif topic == "/joint_states":
                stamp = (message.get("header") or {}).get("stamp")
                for pid, joints, pos, vel in _arm_joints(message):
                    write(f"/{pid}/joint_states" if pid else "/joint_states", ns,
                          build.joint_state(ns, stamp, roots.get(pid, pid), joints, pos, vel))
            elif topic == "/camera":
                write("/camera/image/compressed", ns, build.image(ns, message))
            elif topic == "/camera/calibration":
                write("/camera/camera_info", ns, build.camera_info(ns, message))
            elif topic == "/log":
                write("/rosout", ns, build.log(ns, message))
            elif topic == "/plan/events":
                write("/plan/events", ns, build.String(data=json.dumps(message, separators=(",", ":"))))
            else:
                left_out[topic] += 1
        writer.close()
    except BaseException:
        with contextlib.suppress(Exception):
            writer.close()
        shutil.rmtree(out, ignore_errors=True)
        raise
    return Ros2Export(out, storage, dict(counts), types, dict(left_out))
