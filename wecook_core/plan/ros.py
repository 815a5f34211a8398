"""A plan for the paper's ROS platform (icaros-usc/wecook): the ``TaskMsg`` it takes on the topic ``WeCookDispatch``.

:func:`ros_task` maps a plan onto the platform's messages (as frozen dataclasses, one per message type, fields
named and ordered as in the platform's ``msg/`` files, see :data:`MESSAGES`); :func:`dispatch_script` writes the
standalone ROS 1 script that builds and publishes it, in the shape of the platform's demos.

How a plan maps (the platform's conventions, read from its ``ActionPlanner``):

- pids ``P1``/``P2`` -> ``p1``/``p2``; objects keep their names, ingredients with :attr:`UrdfTable.food_prefix`;
  the platform's table (:attr:`UrdfTable.table`) joins every scene.
- an individual action: ``ActionMsg([p], verb, [location], tool, ingredients)``; ``tool`` is ``hand`` when the
  hand acts itself; without a location, the container its first ingredient is in at that point of the plan.
- ``transfer``: ``location`` is ``[source, destination]`` (the source, when the plan does not name it, is where
  the ingredient is at that point: the scene's containing pairs, moved by earlier transfers, else the table).
- ``handover``: ``ActionMsg([giver, receiver], 'handover', ['air'], 'hand', [object])``.
- ``holding``: ``ActionMsg([holder, actor], 'holding_<object>_<verb>', location, tool, ingredients)`` with the
  actor's action's fields (location the held object when the actor's action names none).
- ``SceneMsg.containingMap``: ``ContainingMsg([container, ingredient])`` (the platform's order).

Poses are ``x y z qx qy qz qw`` in the platform's world: the centre of the plan's table top placed at
:attr:`UrdfTable.origin`, turned by :attr:`UrdfTable.origin_yaw`; objects stand :attr:`Urdf.z` above it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError, read_input_text, yaml_error
from wecook_core.model import Category
from wecook_core.plan.model import Act, Plan, PlanAction
from wecook_core.resources import ASSETS_DIR

URDF_TABLE = ASSETS_DIR / "ros_objects.yaml"
"""The shipped table of URDFs and frames (``wecook_ros_objects: 1``)."""
TOPIC = "WeCookDispatch"

MESSAGES: dict[str, tuple[tuple[str, str], ...]] = {
    "ObjectMsg": (("name", "string"), ("url", "string"), ("pose", "float64[]")),
    "TagMsg": (("tagId", "uint32"), ("objectName", "string"), ("objectPose", "float64[]")),
    "ContainingMsg": (("pair", "string[]"),),
    "SceneMsg": (("objects", "ObjectMsg[]"), ("tags", "TagMsg[]"), ("containingMap", "ContainingMsg[]")),
    "ActionMsg": (("pid", "string[]"), ("verb", "string"), ("location", "string[]"), ("tool", "string"),
                  ("ingredients", "string[]")),
    "AgentMsg": (("pid", "string"), ("type", "string"), ("pose", "float64[]"), ("if_float", "bool")),
    "TaskMsg": (("scene", "SceneMsg"), ("actions", "ActionMsg[]"), ("agents", "AgentMsg[]"), ("PDDLDomain", "string"),
                ("PDDLProblem", "string"), ("type", "string"), ("motionPlannerType", "string"), ("ifSim", "bool")),
}
"""The platform's messages (its ``msg/*.msg``): name -> ((field, ROS type), ...) in declaration order."""
SKILLS: tuple[str, ...] = ("cut", "stir", "handover", "transfer", "roll", "heat", "feeding")
"""Verbs the platform has a skill for, besides ``holding_<object>_<verb>``; other verbs are exported as they are
and reported."""
HAND, AIR = "hand", "air"


Pose = tuple[float, float, float, float, float, float, float]


@dataclass(frozen=True)
class Urdf:
    url: str
    z: float = 0.0
    """Metres: height of the URDF's origin above the table top."""


@dataclass(frozen=True)
class UrdfTable:
    """Which URDF stands for each kind of object, and where the plan's table lies (``ros_objects.yaml``)."""

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
        full = url if url.startswith(("package://", "file://", "/")) else package + url
        out[str(key)] = Urdf(full, float(z))
    return out


def _numbers(value: Any, n: int, path: Path, place: str) -> tuple[float, ...]:
    if (not isinstance(value, list) or len(value) != n
            or any(isinstance(v, bool) or not isinstance(v, int | float) for v in value)):
        raise InputError(path, f"expected {n} numbers, got {value!r}", place=place)
    return tuple(float(v) for v in value)


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
    pose = _numbers(table.get("pose"), 7, tpath, "table.pose")
    position = _numbers(origin.get("position"), 3, opath, "origin.position")
    yaw = _numbers([origin.get("yaw", 0.0)], 1, opath, "origin.yaw")[0]
    if not isinstance(agents.get("type"), str) or not isinstance(agents.get("if_float"), bool):
        raise InputError(apath, f"expected {{type: NAME, if_float: BOOL}}, got {agents!r}", place="agents")
    prefix, ppath = get("food_prefix")
    if not isinstance(prefix, str):
        raise InputError(ppath, f"expected a string, got {prefix!r}", place="food_prefix")
    return UrdfTable(name, table_urdf.url, (pose[0], pose[1], pose[2], pose[3], pose[4], pose[5], pose[6]),
                     (position[0], position[1], position[2]), yaw, agents["type"], agents["if_float"], prefix,
                     objects, stand_ins)


# ------------------------------------------------------------------------------------------------ messages


@dataclass(frozen=True)
class ObjectMsg:
    name: str
    url: str
    pose: tuple[float, ...]


@dataclass(frozen=True)
class ContainingMsg:
    pair: tuple[str, str]
    """``(container, contained)``."""


@dataclass(frozen=True)
class ActionMsg:
    pid: tuple[str, ...]
    verb: str
    location: tuple[str, ...]
    tool: str
    ingredients: tuple[str, ...]


@dataclass(frozen=True)
class AgentMsg:
    pid: str
    type: str
    pose: tuple[float, ...]
    if_float: bool


@dataclass(frozen=True)
class TaskMsg:
    """The ``TaskMsg`` (its ``SceneMsg`` flattened into the first three fields; no tags: see :func:`ros_task`)."""

    objects: tuple[ObjectMsg, ...]
    containing: tuple[ContainingMsg, ...]
    actions: tuple[ActionMsg, ...]
    agents: tuple[AgentMsg, ...]
    type: str = "follow"
    """``follow``: the platform follows the actions as given (``plan`` would have it plan from PDDL)."""
    motion_planner: str = "RRTConnect"
    if_sim: bool = True


@dataclass(frozen=True)
class RosExport:
    task: TaskMsg
    names: Mapping[str, str]
    """Plan object -> its name on the platform (objects left out of the scene keep theirs in actions)."""
    stand_ins: Mapping[str, str]
    """Plan object -> the URDF url standing in for it (no URDF of its own on the platform)."""
    missing: Mapping[str, tuple[str, ...]]
    """Plan object with no URDF on the platform (left out of the scene) -> ids of the plan actions naming it."""
    no_skill: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    """Verb the platform has no skill for -> ids of the plan actions with it (exported as they are)."""

    def warnings(self) -> list[str]:
        """What the user should know, one line each."""
        out = [f"{name}: no URDF on the platform, left out of the scene "
               + (f"(named by {', '.join(ids)})" if ids else "(no action names it)")
               for name, ids in self.missing.items()]
        by_url: dict[str, list[str]] = {}
        for name, url in self.stand_ins.items():
            by_url.setdefault(url, []).append(name)
        out += [f"{', '.join(names)}: no URDF of {'its' if len(names) == 1 else 'their'} own on the platform, "
                f"{'stands' if len(names) == 1 else 'stand'} in as {url}" for url, names in by_url.items()]
        out += [f"{verb}: the platform has no skill for it (actions {', '.join(ids)})"
                for verb, ids in self.no_skill.items()]
        return out


def _quat(yaw: float) -> tuple[float, float, float, float]:
    return 0.0, 0.0, round(math.sin(yaw / 2), 7), round(math.cos(yaw / 2), 7)


def _place(table: UrdfTable, x: float, y: float, z: float, yaw: float) -> Pose:
    """The pose in the platform's world of a point of the plan's frame (``z`` above the plan's table top)."""
    c, s = math.cos(table.origin_yaw), math.sin(table.origin_yaw)
    ox, oy, oz = table.origin
    px, py = ox + c * x - s * y, oy + s * x + c * y
    return (round(px, 4), round(py, 4), round(oz + z, 4), *_quat(table.origin_yaw + yaw))


def _objects_named(action: PlanAction) -> list[str]:
    acts: list[PlanAction | Act] = [action] if action.partner is None else [action, action.partner]
    out: list[str] = []
    for act in acts:
        for name in (act.tool, act.location, act.source, *act.ingredients):
            if name is not None and name not in out:
                out.append(name)
    return out


class _Mapper:
    """Plan actions -> ActionMsg, following where each ingredient is as the plan goes."""

    def __init__(self, plan: Plan, names: Mapping[str, str], table: str) -> None:
        self.names = names
        self.table = table
        self.inside = dict(plan.scene.containing)

    def n(self, name: str) -> str:
        return self.names.get(name, name)

    def fields(self, act: PlanAction | Act) -> tuple[list[str], str, list[str]]:
        """(location, tool, ingredients) of an individual action (moving what a transfer moves)."""
        ingredients = list(act.ingredients)
        hand = act.tool is None or act.tool in ingredients
        tool = HAND if hand or act.tool is None else self.n(act.tool)
        if act.verb == "transfer":
            first = ingredients[0] if ingredients else None
            source = act.source or (self.inside.get(first) if first else None) or self.table
            destination = act.location or self.table
            for name in ingredients:
                self.inside[name] = destination
            location = [self.n(source), self.n(destination)]
        elif act.location is not None:
            location = [self.n(act.location)]
        else:
            container = next((self.inside[i] for i in ingredients if i in self.inside), None)
            location = [self.n(container)] if container else []
        return location, tool, [self.n(i) for i in ingredients]

    def action(self, action: PlanAction) -> ActionMsg:
        pids = tuple(p.lower() for p in action.pids)
        if action.verb == "handover":
            return ActionMsg(pids, "handover", (AIR,), HAND, (self.n(action.tool),) if action.tool else ())
        if action.verb == "holding" and action.partner is not None:
            location, tool, ingredients = self.fields(action.partner)
            held = self.n(action.tool) if action.tool else self.table
            if not location:
                location = [held]
            return ActionMsg(pids, f"holding_{held}_{action.partner.verb}", tuple(location), tool, tuple(ingredients))
        location, tool, ingredients = self.fields(action)
        return ActionMsg(pids, action.verb, tuple(location), tool, tuple(ingredients))


def ros_task(plan: Plan, table: UrdfTable | None = None, *, if_sim: bool = True) -> RosExport:
    """The plan as the platform's ``TaskMsg`` (see the module's docstring for how each part maps)."""
    table = table or load_urdf_table()
    reserved = {table.table_name, HAND, AIR}
    names: dict[str, str] = {}
    for obj in plan.scene.objects:
        name = obj.name
        if obj.category is Category.INGREDIENT and "food" not in name:
            name = table.food_prefix + name
        while name in reserved:
            name += "_"
        reserved.add(name)
        names[obj.name] = name
    users: dict[str, list[str]] = {}
    for action in plan.actions:
        for name in _objects_named(action):
            users.setdefault(name, []).append(action.id)
    objects = [ObjectMsg(table.table_name, table.table_url, table.table_pose)]
    stand_ins: dict[str, str] = {}
    missing: dict[str, tuple[str, ...]] = {}
    for obj in plan.scene.objects:
        urdf, standing_in = table.urdf(obj.name, obj.category)
        if urdf is None:
            missing[obj.name] = tuple(users.get(obj.name, ()))
            continue
        if standing_in:
            stand_ins[obj.name] = urdf.url
        objects.append(ObjectMsg(names[obj.name], urdf.url, _place(table, obj.x, obj.y, urdf.z, obj.yaw)))
    in_scene = {o.name for o in objects}
    containing = tuple(ContainingMsg((names[c], names[i])) for i, c in plan.scene.containing
                       if names.get(c) in in_scene and names.get(i) in in_scene)
    mapper = _Mapper(plan, names, table.table_name)
    actions = tuple(mapper.action(a) for a in plan.actions)
    no_skill: dict[str, list[str]] = {}
    for action, msg in zip(plan.actions, actions, strict=True):
        verb = msg.verb.rsplit("_", 1)[-1]
        if verb not in SKILLS:
            no_skill.setdefault(verb, []).append(action.id)
    agents = tuple(AgentMsg(a.pid.lower(), table.agent_type,
                            _place(table, a.base_position[0], a.base_position[1],
                                   a.base_position[2] - plan.scene.table.height, a.base_yaw),
                            table.if_float) for a in plan.agents)
    task = TaskMsg(tuple(objects), containing, actions, agents, if_sim=if_sim)
    return RosExport(task, names, stand_ins, missing, {k: tuple(v) for k, v in no_skill.items()})
