"""The URDF table of the ROS export (``ros_objects.yaml``, ``wecook_ros_objects: 1``): which URDF of the platform's
asset package stands for each kind of object, whether the platform's motion planner collides with it, where the
plan's table lies in the platform's world, where the arms are mounted and which tags are sent.

Bad files raise :class:`~wecook_core.errors.InputError` naming the file and the key.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError, read_input_text, yaml_error
from wecook_core.model import Category
from wecook_core.plan.ros_messages import TagMsg
from wecook_core.resources import ASSETS_DIR

URDF_TABLE = ASSETS_DIR / "ros_objects.yaml"
"""The shipped table (``wecook_ros_objects: 1``)."""

Pose = tuple[float, float, float, float, float, float, float]
"""``x y z qx qy qz qw``: metres and a unit quaternion, the platform's world frame."""


@dataclass(frozen=True)
class Urdf:
    url: str
    z: float = 0.0
    """Metres: height of the URDF's origin above the table top."""
    food: bool = False
    """The URDF is food: the platform's motion planner must not collide with it (what a knife cuts, a spoon
    stirs), so the object's name contains "food" (``ObjectMgr::createCollisionGroupExceptFoodAndToMoveObj``
    leaves every name containing "food" or "mouth" out of the collision group). Default: a url under ``food/``."""


@dataclass(frozen=True)
class UrdfTable:
    """Which URDF stands for each kind of object, and where the plan's table and arms lie (``ros_objects.yaml``)."""

    table_name: str
    table_url: str
    table_pose: Pose
    origin: tuple[float, float, float]
    """Metres: where the centre of the plan's table top lies in the platform's world."""
    origin_yaw: float
    """Radians about z: the plan's x axis in the platform's world."""
    agent_type: str
    if_float: bool
    food_prefix: str
    objects: Mapping[str, Urdf]
    """Kind (``bowl``, ``chopping_board``) -> URDF."""
    stand_ins: Mapping[str, Urdf]
    """Category -> URDF of a kind not in :attr:`objects`."""
    mounts: Mapping[str, Pose] = field(default_factory=dict)
    """Plan pid (``P1``) -> the arm's base pose on the platform; a pid not listed stands where the plan puts it."""
    tags: tuple[TagMsg, ...] = ()
    """The AprilTags sent with the scene, as the platform's ``TagMsg`` (pose: the object's in the tag's frame, ``x y z
    qx qy qz qw``, 7 numbers as its ``vectorToIsometry`` reads)."""

    def urdf(self, name: str, category: Category) -> tuple[Urdf | None, bool]:
        """The URDF of the object ``name`` and whether it is a stand-in (``(None, False)``: none)."""
        for key in (name, kind_of(name)):
            if key in self.objects:
                return self.objects[key], False
        stand_in = self.stand_ins.get(str(category))
        return stand_in, stand_in is not None


def kind_of(name: str) -> str:
    """``bowl_2 -> bowl``: an object's name without the number the importer gives a second object of a label."""
    return re.sub(r"_\d+$", "", name)


def _read_table_file(path: Path) -> dict[str, Any]:
    try:
        data = yaml.safe_load(read_input_text(path, "no such URDF table"))
    except yaml.YAMLError as error:
        raise yaml_error(path, error) from None
    if not isinstance(data, dict) or data.get("wecook_ros_objects") != 1:
        raise InputError(path, "not a URDF table: expected a mapping with `wecook_ros_objects: 1`",
                         place="top level")
    return data


def _urdfs(value: Any, path: Path, place: str, package: str) -> dict[str, Urdf]:
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise InputError(path, f"expected a mapping of names to URDFs, got {value!r}", place=place)
    out = {}
    for key, entry in value.items():
        here = f"{place}.{key}"
        raw = entry if isinstance(entry, dict) else {"url": entry}
        url, z = raw.get("url"), raw.get("z", 0.0)
        if not isinstance(url, str) or not url:
            raise InputError(path, f"expected a URDF url, got {url!r}", place=here)
        if isinstance(z, bool) or not isinstance(z, int | float):
            raise InputError(path, f"expected a height in metres, got {z!r}", place=f"{here}.z")
        food = raw.get("food", url.startswith("food/") or "/food/" in url)
        if not isinstance(food, bool):
            raise InputError(path, f"expected true or false, got {food!r}", place=f"{here}.food")
        full = url if url.startswith(("package://", "file://", "/")) else package + url
        out[str(key)] = Urdf(full, float(z), food)
    return out


def _numbers(value: Any, n: int, path: Path, place: str) -> tuple[float, ...]:
    if (not isinstance(value, list) or len(value) != n
            or any(isinstance(v, bool) or not isinstance(v, int | float) for v in value)):
        raise InputError(path, f"expected {n} numbers, got {value!r}", place=place)
    return tuple(float(v) for v in value)


def _pose(value: Any, path: Path, place: str) -> Pose:
    p = _numbers(value, 7, path, place)
    if abs(sum(q * q for q in p[3:]) - 1) > 1e-3:
        raise InputError(path, f"expected a unit quaternion (qx qy qz qw), got {list(p[3:])}", place=place)
    return p[0], p[1], p[2], p[3], p[4], p[5], p[6]


def _mounts(value: Any, path: Path) -> dict[str, Pose]:
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise InputError(path, f"expected pid: [x, y, z, qx, qy, qz, qw], got {value!r}", place="agents.mounts")
    return {str(pid): _pose(pose, path, f"agents.mounts.{pid}") for pid, pose in value.items()}


def _tags(value: Any, path: Path) -> tuple[TagMsg, ...]:
    if value is None:
        return ()
    if not isinstance(value, list):
        raise InputError(path, f"expected a list of {{id, object, pose}}, got {value!r}", place="tags")
    out = []
    for k, entry in enumerate(value):
        here = f"tags[{k}]"
        if not isinstance(entry, dict):
            raise InputError(path, f"expected {{id, object, pose}}, got {entry!r}", place=here)
        tag_id, name = entry.get("id"), entry.get("object", "None")
        if isinstance(tag_id, bool) or not isinstance(tag_id, int) or not 0 <= tag_id < 2 ** 32:
            raise InputError(path, f"expected a tag id (0 to 2^32 - 1), got {tag_id!r}", place=f"{here}.id")
        if not isinstance(name, str) or not name:
            raise InputError(path, f"expected an object name (None: no object), got {name!r}",
                             place=f"{here}.object")
        out.append(TagMsg(tag_id, name, _pose(entry.get("pose"), path, f"{here}.pose")))
    return tuple(out)


def load_urdf_table(extra: Sequence[str | Path] = ()) -> UrdfTable:
    """The shipped table (:data:`URDF_TABLE`) with the files ``extra`` laid over it in turn (their ``objects`` and
    ``stand_ins`` entries added or replaced one by one, other keys replaced). Bad files raise InputError."""
    paths = [URDF_TABLE, *(Path(p) for p in extra)]
    merged: dict[str, Any] = {}
    objects: dict[str, Urdf] = {}
    stand_ins: dict[str, Urdf] = {}
    where: dict[str, Path] = {}
    for path in paths:
        data = _read_table_file(path)
        package = str(data.get("package", merged.get("package", "")))
        objects.update(_urdfs(data.get("objects"), path, "objects", package))
        stand_ins.update(_urdfs(data.get("stand_ins"), path, "stand_ins", package))
        for key, value in data.items():
            if key not in ("objects", "stand_ins"):
                merged[key] = value
                where[key] = path

    def get(key: str) -> tuple[Any, Path]:
        if key not in merged:
            raise InputError(paths[-1], f"the URDF tables give no `{key}`", place=key)
        return merged[key], where[key]

    (table, tpath), (origin, opath), (agents, apath) = get("table"), get("origin"), get("agents")
    for value, path, key in ((table, tpath, "table"), (origin, opath, "origin"), (agents, apath, "agents")):
        if not isinstance(value, dict):
            raise InputError(path, f"expected a mapping, got {value!r}", place=key)
    table_urdf = _urdfs({"table": table}, tpath, "table", str(merged.get("package", "")))["table"]
    name = table.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(tpath, f"expected a name, got {name!r}", place="table.name")
    pose = _pose(table.get("pose"), tpath, "table.pose")
    position = _numbers(origin.get("position"), 3, opath, "origin.position")
    yaw = _numbers([origin.get("yaw", 0.0)], 1, opath, "origin.yaw")[0]
    if not isinstance(agents.get("type"), str) or not isinstance(agents.get("if_float"), bool):
        raise InputError(apath, f"expected {{type: NAME, if_float: BOOL}}, got {agents!r}", place="agents")
    prefix, ppath = get("food_prefix")
    if not isinstance(prefix, str) or "food" not in prefix:
        raise InputError(ppath, f"expected a prefix containing \"food\", got {prefix!r}", place="food_prefix")
    tags = _tags(merged.get("tags"), where.get("tags", paths[-1]))
    return UrdfTable(name, table_urdf.url, pose, (position[0], position[1], position[2]), yaw, agents["type"],
                     agents["if_float"], prefix, objects, stand_ins, _mounts(agents.get("mounts"), apath), tags)
