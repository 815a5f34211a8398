"""The robot plan: what two arms must do, built from an action graph, in and out of YAML (``wecook_plan: 1``).

World frame of a plan (the executor and the recording use the same one): metres, z up, the table top is the
rectangle ``|x| <= size_x / 2, |y| <= size_y / 2`` at ``z = table.height``. Arm P1 stands at the ``-x`` end of
the table facing ``+x``, arm P2 at the ``+x`` end facing ``-x``. Seen from the camera of the video, P1 (the
left person) is on the left: image x grows with world x, and the image's top (far from the camera) is ``+y``.

A plan file::

    wecook_plan: 1
    agents:
    - {pid: P1, robot: franka_panda/panda.urdf, base: {position: [-0.5, 0.0, 0.0], yaw: 0.0}}
    scene:
      table: {size: [1.0, 0.8], height: 0.0}
      objects:
      - {name: knife, category: tool, shape: box, size: [0.2, 0.03, 0.025], pose: {x: 0.1, y: 0.0, yaw: 0.0}}
      containing:
      - [tomato, chopping_board]
    actions:
    - {id: a1, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], location: chopping_board,
       after: [], frames: [10, 52], tree: "(HP ...)"}
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError
from wecook_core.model import (
    COLLABORATIONS,
    PERSONS,
    VERBS,
    Action,
    ActionGraph,
    ActionKind,
    Category,
    Observations,
    person_of,
)
from wecook_core.trees import action_of, format_tree

PLAN_VERSION = 1
DEFAULT_ROBOT = "franka_panda/panda.urdf"
"""URDF of an arm, relative to ``pybullet_data`` unless absolute."""
SHAPES: tuple[str, ...] = ("box", "cylinder", "sphere")
ARM_REACH: dict[str, float] = {DEFAULT_ROBOT: 0.85}
"""Metres: how far from its base (horizontally) an arm reaches an object on the table, by robot URDF (the
Franka Panda reaches 0.855 m from its shoulder). Objects an action uses must lie within the reach of one of its
agents; robots not listed are not checked."""
PLAN_VERBS: tuple[str, ...] = (*VERBS, *COLLABORATIONS)
"""Verbs a plan action may have: the vocabulary, ``handover`` and ``holding``."""

Vec3 = tuple[float, float, float]


# -------------------------------------------------------------------------------------------- model


@dataclass(frozen=True)
class Table:
    """The table top, centred on the world origin."""

    size: tuple[float, float] = (1.0, 0.8)
    """Metres: extent along x (between the arms) and along y."""
    height: float = 0.0
    """Metres: z of the table top (the arms' bases stand on it)."""
    reach: tuple[float, float] = (0.1, 0.3)
    """Metres: half extents of the region, centred on the origin, that both arms reach comfortably; objects
    laid out from a video are placed inside it (see :func:`plan_from_graph`)."""

    def holds(self, x: float, y: float, half_x: float = 0.0, half_y: float = 0.0) -> bool:
        """True when a footprint of the given half extents centred at (x, y) lies on the table top."""
        return abs(x) + half_x <= self.size[0] / 2 + 1e-9 and abs(y) + half_y <= self.size[1] / 2 + 1e-9


DEFAULT_TABLE = Table()


@dataclass(frozen=True)
class Agent:
    """One robot arm; person ``pid`` of the video."""

    pid: str
    """``P1`` or ``P2``."""
    robot: str = DEFAULT_ROBOT
    """URDF path, relative to ``pybullet_data`` unless absolute."""
    base_position: Vec3 = (0.0, 0.0, 0.0)
    """Metres, world frame."""
    base_yaw: float = 0.0
    """Radians about z; 0 faces +x."""


@dataclass(frozen=True)
class SceneObject:
    """An object on the table, drawn and simulated as one primitive shape."""

    name: str
    """As in the trees (``chopping_board``, ``bowl_2``)."""
    category: Category
    shape: str
    """``box``, ``cylinder`` or ``sphere``. Containers are built open on top by the simulation."""
    size: Vec3
    """Metres: box full extents (x, y, z before yaw); cylinder (diameter, diameter, height); sphere (d, d, d)."""
    x: float
    y: float
    """Metres: centre of the footprint on the table, world frame. For an ingredient inside a container: where
    it sits inside it."""
    yaw: float = 0.0
    """Radians about z."""

    def half_extents(self) -> tuple[float, float]:
        """Half extents of the footprint along world x and y (yaw taken into account)."""
        hx, hy = self.size[0] / 2, self.size[1] / 2
        c, s = abs(math.cos(self.yaw)), abs(math.sin(self.yaw))
        return hx * c + hy * s, hx * s + hy * c


@dataclass(frozen=True)
class Scene:
    table: Table = field(default_factory=Table)
    objects: tuple[SceneObject, ...] = ()
    containing: tuple[tuple[str, str], ...] = ()
    """``(ingredient, container)`` pairs: the ingredient starts inside the container."""

    def object(self, name: str) -> SceneObject:
        for obj in self.objects:
            if obj.name == name:
                return obj
        raise KeyError(name)

    def names(self) -> frozenset[str]:
        return frozenset(obj.name for obj in self.objects)


@dataclass(frozen=True)
class Act:
    """What the other arm does during a ``holding`` action."""

    verb: str
    tool: str | None = None
    ingredients: tuple[str, ...] = ()
    location: str | None = None
    source: str | None = None


@dataclass(frozen=True)
class PlanAction:
    """One action of the plan.

    Fields by verb:

    - vocabulary verbs (``cut``, ``pour``, ...): ``pids == (p,)``; ``tool`` is the object the arm grasps to act
      (a tool such as ``knife``, or the held ingredient / container for pour, sprinkle, dip and tipping
      transfers; None for an action by the hand itself such as squeeze); ``ingredients`` are the ingredients
      acted on; ``location`` the container or target acted on / into.
    - ``transfer``: ``ingredients`` move from ``source`` to ``location``, carried by ``tool``.
    - ``handover``: ``pids == (giver, receiver)``; ``tool`` is the object handed over.
    - ``holding``: ``pids == (holder, actor)``; ``tool`` is the object the holder keeps still while the actor
      does ``partner`` on it.
    """

    id: str
    pids: tuple[str, ...]
    verb: str
    tool: str | None = None
    ingredients: tuple[str, ...] = ()
    location: str | None = None
    source: str | None = None
    """Transfer only: the container the ingredients leave."""
    partner: Act | None = None
    """Holding only: the actor's action."""
    after: tuple[str, ...] = ()
    """Ids of actions that must end before this one starts."""
    frames: tuple[int, int] | None = None
    """Source video frames ``[start, end)``."""
    tree: str | None = None
    """The action tree it came from, bracket notation."""


@dataclass(frozen=True)
class Plan:
    agents: tuple[Agent, ...]
    scene: Scene
    actions: tuple[PlanAction, ...]
    version: int = PLAN_VERSION

    def action(self, action_id: str) -> PlanAction:
        for action in self.actions:
            if action.id == action_id:
                return action
        raise KeyError(action_id)


# ---------------------------------------------------------------------------------------- validation


def _place(index: int, action: PlanAction, name: str) -> str:
    return f"actions[{index}] ({action.id}).{name}"


def plan_problems(plan: Plan, path: str | Path | None = None) -> list[InputError]:
    """Every problem of a plan, each an :class:`InputError` naming the place (``actions[3] (a4).tool``)."""
    errors: list[InputError] = []

    def bad(place: str, message: str) -> None:
        errors.append(InputError(path, message, place=place))

    if plan.version != PLAN_VERSION:
        bad("wecook_plan", f"unsupported plan version {plan.version!r}, expected {PLAN_VERSION}")
    pids: set[str] = set()
    for i, agent in enumerate(plan.agents):
        if agent.pid in pids:
            bad(f"agents[{i}].pid", f"duplicate agent {agent.pid!r}")
        if agent.pid not in PERSONS:
            bad(f"agents[{i}].pid", f"unknown pid {agent.pid!r}, expected one of {', '.join(PERSONS)}")
        if not agent.robot:
            bad(f"agents[{i}].robot", "empty robot URDF path")
        pids.add(agent.pid)
    table = plan.scene.table
    if min(table.size) <= 0:
        bad("scene.table.size", f"table size must be positive, got {list(table.size)}")
    names: set[str] = set()
    for i, obj in enumerate(plan.scene.objects):
        place = f"scene.objects[{i}] ({obj.name})"
        if obj.name in names:
            bad(f"{place}.name", f"duplicate object {obj.name!r}")
        names.add(obj.name)
        if obj.shape not in SHAPES:
            bad(f"{place}.shape", f"unknown shape {obj.shape!r}, expected one of {', '.join(SHAPES)}")
        if min(obj.size) <= 0:
            bad(f"{place}.size", f"sizes must be positive metres, got {list(obj.size)}")
        elif not table.holds(obj.x, obj.y, *obj.half_extents()):
            bad(f"{place}.pose", f"({obj.x:.3f}, {obj.y:.3f}) is off the table "
                f"({table.size[0]:.2f} x {table.size[1]:.2f} m centred on the origin)")
    categories = {obj.name: obj.category for obj in plan.scene.objects}
    inside: set[str] = set()
    for i, (ingredient, container) in enumerate(plan.scene.containing):
        for name, what in ((ingredient, "ingredient"), (container, "container")):
            if name not in names:
                bad(f"scene.containing[{i}]", f"{what} {name!r} is not in the scene")
        if container in categories and categories[container] is not Category.CONTAINER:
            bad(f"scene.containing[{i}]", f"{container!r} is a {categories[container]}, not a container")
        if ingredient in inside:
            bad(f"scene.containing[{i}]", f"{ingredient!r} is in two containers")
        inside.add(ingredient)

    ids: dict[str, int] = {}
    for i, action in enumerate(plan.actions):
        if action.id in ids:
            bad(_place(i, action, "id"), f"duplicate action id {action.id!r} (also actions[{ids[action.id]}])")
        else:
            ids[action.id] = i
    for i, action in enumerate(plan.actions):
        _check_action(i, action, pids, names, ids, bad)
        _check_reach(i, action, plan, bad)
    cycle = _after_cycle(plan.actions)
    if cycle:
        i = ids[cycle[0]]
        bad(_place(i, plan.actions[i], "after"), "cycle in after: " + " -> ".join([*cycle, cycle[0]]))
    return errors


def _check_action(i: int, action: PlanAction, pids: set[str], names: set[str], ids: Mapping[str, int],
                  bad: Any) -> None:
    if action.verb not in PLAN_VERBS:
        bad(_place(i, action, "verb"), f"unknown verb {action.verb!r}, expected one of {', '.join(PLAN_VERBS)}")
    if not action.pids:
        bad(_place(i, action, "pid"), "no agent")
    for pid in action.pids:
        if pid not in pids:
            bad(_place(i, action, "pid"), f"unknown pid {pid!r} (agents: {', '.join(sorted(pids)) or 'none'})")
    if action.verb in COLLABORATIONS:
        if len(action.pids) != 2 or action.pids[0] == action.pids[1]:
            bad(_place(i, action, "pid"), f"a {action.verb} needs two different agents, got {list(action.pids)}")
        if action.tool is None:
            bad(_place(i, action, "tool"), f"a {action.verb} needs the object it is about in tool")
    elif len(action.pids) > 1:
        bad(_place(i, action, "pid"), f"a {action.verb} action has one agent, got {list(action.pids)}")
    if action.verb == "holding" and action.partner is None:
        bad(_place(i, action, "partner"), "a holding needs the partner's action")
    if action.verb != "holding" and action.partner is not None:
        bad(_place(i, action, "partner"), "only a holding has a partner action")
    _check_objects(i, action, "", action.tool, action.ingredients, action.location, action.source, names, bad)
    if action.partner is not None:
        if action.partner.verb not in VERBS:
            bad(_place(i, action, "partner.verb"),
                f"unknown verb {action.partner.verb!r}, expected one of {', '.join(VERBS)}")
        p = action.partner
        _check_objects(i, action, "partner.", p.tool, p.ingredients, p.location, p.source, names, bad)
    if action.verb == "transfer" and (not action.ingredients or action.location is None):
        bad(_place(i, action, "location"), "a transfer needs ingredients and a location")
    for dep in action.after:
        if dep not in ids:
            bad(_place(i, action, "after"), f"unknown action id {dep!r}")
        elif dep == action.id:
            bad(_place(i, action, "after"), "an action cannot come after itself")
    if action.frames is not None and not 0 <= action.frames[0] < action.frames[1]:
        bad(_place(i, action, "frames"), f"expected [start, end) with 0 <= start < end, got {list(action.frames)}")


def _check_reach(i: int, action: PlanAction, plan: Plan, bad: Any) -> None:
    agents = [a for a in plan.agents if a.pid in action.pids]
    reaches = [(a, ARM_REACH.get(a.robot)) for a in agents]
    if not agents or any(r is None for _, r in reaches):
        return
    fields: list[tuple[str, str | None]] = [("tool", action.tool), ("location", action.location),
                                            ("source", action.source)]
    fields += [(f"ingredients[{k}]", name) for k, name in enumerate(action.ingredients)]
    objects = {o.name: o for o in plan.scene.objects}
    for key, name in fields:
        obj = objects.get(name) if name is not None else None
        if obj is None:
            continue
        distances = {a.pid: math.hypot(obj.x - a.base_position[0], obj.y - a.base_position[1]) for a in agents}
        if all(distances[a.pid] > (reach or 0.0) for a, reach in reaches):
            nearest = min(distances, key=distances.__getitem__)
            reach = {a.pid: r for a, r in reaches}[nearest]
            bad(_place(i, action, key), f"{name} at ({obj.x:.2f}, {obj.y:.2f}) is {distances[nearest]:.2f} m from "
                f"{nearest}'s base, beyond the arm's reach ({reach:.2f} m)")


def _check_objects(i: int, action: PlanAction, prefix: str, tool: str | None, ingredients: Sequence[str],
                   location: str | None, source: str | None, names: set[str], bad: Any) -> None:
    for key, value in (("tool", tool), ("location", location), ("source", source)):
        if value is not None and value not in names:
            bad(_place(i, action, prefix + key), f"object {value!r} is not in the scene")
    for k, name in enumerate(ingredients):
        if name not in names:
            bad(_place(i, action, f"{prefix}ingredients[{k}]"), f"object {name!r} is not in the scene")


def _after_cycle(actions: Sequence[PlanAction]) -> list[str]:
    """One cycle of the ``after`` relation, as ids in order, or [] when there is none."""
    deps = {a.id: [d for d in a.after if d != a.id] for a in actions}
    state: dict[str, int] = {}  # 1 on the stack, 2 done
    for root in deps:
        if state.get(root):
            continue
        stack: list[tuple[str, int]] = [(root, 0)]
        path: list[str] = [root]
        state[root] = 1
        while stack:
            node, k = stack[-1]
            children = [d for d in deps[node] if d in deps]
            if k < len(children):
                stack[-1] = (node, k + 1)
                child = children[k]
                if state.get(child) == 1:
                    return path[path.index(child):]
                if not state.get(child):
                    state[child] = 1
                    stack.append((child, 0))
                    path.append(child)
            else:
                state[node] = 2
                stack.pop()
                path.pop()
    return []


def validate(plan: Plan, path: str | Path | None = None) -> None:
    """Raise the first problem of :func:`plan_problems` (an :class:`InputError`), if any."""
    problems = plan_problems(plan, path)
    if problems:
        raise problems[0]


# --------------------------------------------------------------------------------------------- YAML


def _num(value: float) -> float | int:
    return int(value) if isinstance(value, int) else float(value)


def _act_dict(verb: str, tool: str | None, ingredients: Sequence[str], location: str | None,
              source: str | None) -> dict[str, Any]:
    out: dict[str, Any] = {"verb": verb, "tool": tool, "ingredients": list(ingredients), "location": location}
    if source is not None:
        out["source"] = source
    return out


def plan_to_dict(plan: Plan) -> dict[str, Any]:
    """The plan as plain YAML-ready data."""
    actions = []
    for a in plan.actions:
        entry: dict[str, Any] = {"id": a.id, "pid": list(a.pids)}
        entry.update(_act_dict(a.verb, a.tool, a.ingredients, a.location, a.source))
        if a.partner is not None:
            p = a.partner
            entry["partner"] = _act_dict(p.verb, p.tool, p.ingredients, p.location, p.source)
        entry["after"] = list(a.after)
        if a.frames is not None:
            entry["frames"] = list(a.frames)
        if a.tree is not None:
            entry["tree"] = a.tree
        actions.append(entry)
    table = plan.scene.table
    return {
        "wecook_plan": plan.version,
        "agents": [{"pid": ag.pid, "robot": ag.robot,
                    "base": {"position": [_num(v) for v in ag.base_position], "yaw": _num(ag.base_yaw)}}
                   for ag in plan.agents],
        "scene": {
            "table": {"size": list(table.size), "height": table.height, "reach": list(table.reach)},
            "objects": [{"name": o.name, "category": str(o.category), "shape": o.shape, "size": list(o.size),
                         "pose": {"x": o.x, "y": o.y, "yaw": o.yaw}} for o in plan.scene.objects],
            "containing": [list(pair) for pair in plan.scene.containing],
        },
        "actions": actions,
    }


def dump_plan(plan: Plan) -> str:
    """The plan's YAML text."""
    return yaml.safe_dump(plan_to_dict(plan), sort_keys=False, default_flow_style=None, width=120)


def write_plan(plan: Plan, path: str | Path) -> Path:
    """Write the plan's YAML (creating the folder); returns the path."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(dump_plan(plan))
    return out


class _Reader:
    """Typed access to the parsed YAML, raising InputError naming the place."""

    def __init__(self, path: str | Path | None) -> None:
        self.path = path

    def fail(self, place: str, message: str) -> InputError:
        return InputError(self.path, message, place=place)

    def mapping(self, value: Any, place: str) -> Mapping[str, Any]:
        if not isinstance(value, Mapping):
            raise self.fail(place, f"expected a mapping, got {type(value).__name__}")
        return value

    def seq(self, value: Any, place: str) -> list[Any]:
        if value is None:
            return []
        if not isinstance(value, list):
            raise self.fail(place, f"expected a list, got {type(value).__name__}")
        return value

    def string(self, value: Any, place: str, *, optional: bool = False) -> Any:
        if value is None and optional:
            return None
        if not isinstance(value, str) or not value:
            raise self.fail(place, f"expected a name, got {value!r}")
        return value

    def number(self, value: Any, place: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(place, f"expected a number, got {value!r}")
        return float(value)

    def numbers(self, value: Any, place: str, n: int) -> tuple[float, ...]:
        items = self.seq(value, place)
        if len(items) != n:
            raise self.fail(place, f"expected {n} numbers, got {value!r}")
        return tuple(self.number(v, f"{place}[{k}]") for k, v in enumerate(items))

    def names(self, value: Any, place: str) -> tuple[str, ...]:
        return tuple(self.string(v, f"{place}[{k}]") for k, v in enumerate(self.seq(value, place)))


def plan_from_dict(data: Any, path: str | Path | None = None) -> Plan:
    """Build a plan from parsed YAML; structural errors raise :class:`InputError` (not validated further)."""
    r = _Reader(path)
    top = r.mapping(data, "top level")
    version = top.get("wecook_plan")
    if not isinstance(version, int) or isinstance(version, bool):
        raise r.fail("wecook_plan", f"not a wecook plan: expected `wecook_plan: {PLAN_VERSION}`, got {version!r}")
    agents = []
    for i, raw in enumerate(r.seq(top.get("agents"), "agents")):
        m = r.mapping(raw, f"agents[{i}]")
        base = r.mapping(m.get("base", {}), f"agents[{i}].base")
        position = r.numbers(base.get("position", [0, 0, 0]), f"agents[{i}].base.position", 3)
        agents.append(Agent(pid=r.string(m.get("pid"), f"agents[{i}].pid"),
                            robot=r.string(m.get("robot", DEFAULT_ROBOT), f"agents[{i}].robot"),
                            base_position=(position[0], position[1], position[2]),
                            base_yaw=r.number(base.get("yaw", 0.0), f"agents[{i}].base.yaw")))
    scene_raw = r.mapping(top.get("scene", {}), "scene")
    t = r.mapping(scene_raw.get("table", {}), "scene.table")
    default = Table()
    size = r.numbers(t.get("size", list(default.size)), "scene.table.size", 2)
    reach = r.numbers(t.get("reach", list(default.reach)), "scene.table.reach", 2)
    table = Table(size=(size[0], size[1]), height=r.number(t.get("height", default.height), "scene.table.height"),
                  reach=(reach[0], reach[1]))
    objects = []
    for i, raw in enumerate(r.seq(scene_raw.get("objects"), "scene.objects")):
        place = f"scene.objects[{i}]"
        m = r.mapping(raw, place)
        name = r.string(m.get("name"), f"{place}.name")
        place = f"{place} ({name})"
        try:
            category = Category(str(m.get("category")))
        except ValueError:
            raise r.fail(f"{place}.category", f"unknown category {m.get('category')!r}, expected one of "
                         + ", ".join(c.value for c in Category)) from None
        pose = r.mapping(m.get("pose"), f"{place}.pose")
        osize = r.numbers(m.get("size"), f"{place}.size", 3)
        objects.append(SceneObject(
            name=name, category=category, shape=r.string(m.get("shape"), f"{place}.shape"),
            size=(osize[0], osize[1], osize[2]),
            x=r.number(pose.get("x"), f"{place}.pose.x"), y=r.number(pose.get("y"), f"{place}.pose.y"),
            yaw=r.number(pose.get("yaw", 0.0), f"{place}.pose.yaw")))
    containing = []
    for i, raw in enumerate(r.seq(scene_raw.get("containing"), "scene.containing")):
        pair = r.names(raw, f"scene.containing[{i}]")
        if len(pair) != 2:
            raise r.fail(f"scene.containing[{i}]", f"expected [ingredient, container], got {raw!r}")
        containing.append((pair[0], pair[1]))
    actions = []
    for i, raw in enumerate(r.seq(top.get("actions"), "actions")):
        m = r.mapping(raw, f"actions[{i}]")
        aid = r.string(m.get("id"), f"actions[{i}].id")
        place = f"actions[{i}] ({aid})"
        pid_raw = m.get("pid")
        pids = (r.string(pid_raw, f"{place}.pid"),) if isinstance(pid_raw, str) else r.names(pid_raw, f"{place}.pid")
        partner = None
        if m.get("partner") is not None:
            p = r.mapping(m["partner"], f"{place}.partner")
            partner = Act(verb=r.string(p.get("verb"), f"{place}.partner.verb"),
                          tool=r.string(p.get("tool"), f"{place}.partner.tool", optional=True),
                          ingredients=r.names(p.get("ingredients"), f"{place}.partner.ingredients"),
                          location=r.string(p.get("location"), f"{place}.partner.location", optional=True),
                          source=r.string(p.get("source"), f"{place}.partner.source", optional=True))
        frames = None
        if m.get("frames") is not None:
            fr = r.seq(m["frames"], f"{place}.frames")
            if len(fr) != 2 or not all(isinstance(v, int) and not isinstance(v, bool) for v in fr):
                raise r.fail(f"{place}.frames", f"expected [start, end] frame indices, got {m['frames']!r}")
            frames = (int(fr[0]), int(fr[1]))
        tree = m.get("tree")
        actions.append(PlanAction(
            id=aid, pids=pids, verb=r.string(m.get("verb"), f"{place}.verb"),
            tool=r.string(m.get("tool"), f"{place}.tool", optional=True),
            ingredients=r.names(m.get("ingredients"), f"{place}.ingredients"),
            location=r.string(m.get("location"), f"{place}.location", optional=True),
            source=r.string(m.get("source"), f"{place}.source", optional=True),
            partner=partner, after=r.names(m.get("after"), f"{place}.after"), frames=frames,
            tree=r.string(tree, f"{place}.tree", optional=True)))
    return Plan(agents=tuple(agents), scene=Scene(table, tuple(objects), tuple(containing)),
                actions=tuple(actions), version=version)


def load_plan(text: str, path: str | Path | None = None, *, check: bool = True) -> Plan:
    """Parse plan YAML text (and validate it unless ``check`` is False)."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        place = f"line {mark.line + 1}" if mark is not None else None
        raise InputError(path, f"not valid YAML ({getattr(error, 'problem', None) or error})", place=place) from None
    plan = plan_from_dict(data, path)
    if check:
        validate(plan, path)
    return plan


def read_plan(path: str | Path, *, check: bool = True) -> Plan:
    """Read and validate a plan file; any problem raises :class:`InputError` naming the file and the place."""
    try:
        text = Path(path).read_text()
    except OSError as error:
        raise InputError(path, f"cannot read the plan ({error.strerror or error})") from None
    return load_plan(text, path, check=check)


# ------------------------------------------------------------------------------- building from video


def agents_for(persons: Sequence[str], table: Table = DEFAULT_TABLE, robot: str = DEFAULT_ROBOT) -> tuple[Agent, ...]:
    """One arm per person: P1 at the ``-x`` end of the table facing ``+x``, P2 at the ``+x`` end facing ``-x``."""
    out = []
    for pid in sorted(set(persons)):
        sign = -1.0 if pid == "P1" else 1.0
        out.append(Agent(pid, robot, (sign * table.size[0] / 2, 0.0, table.height), 0.0 if sign < 0 else math.pi))
    return tuple(out)


def _fields(action: Action, categories: Mapping[str, Category]) -> tuple[str | None, tuple[str, ...],
                                                                           str | None, str | None]:
    """(tool, ingredients, location, source) of an individual action."""
    targets = action.targets
    if action.kind is ActionKind.TRANSFER and len(targets) == 3:
        return action.held, (targets[0],), targets[2], targets[1]
    ingredients = tuple(t for t in targets if categories.get(t, Category.INGREDIENT) is Category.INGREDIENT)
    others = [t for t in targets if t not in ingredients]
    return action.held, ingredients, (others[-1] if others else None), None


def plan_actions(graph: ActionGraph, categories: Mapping[str, Category]) -> tuple[PlanAction, ...]:
    """Plan actions of the graph's nodes that contain an action or a collaboration (grasp-only nodes, and holdings
    where the partner only holds too, are left out), in order of start frame.

    ``after``: each action comes after the previous action of every agent it involves (so a handover waits
    for the receiver to be free and the receiver's next action waits for the handover; a holding waits for
    both arms and both arms' next actions wait for it), plus the graph's collaboration edges between kept
    actions when they point forward in time.
    """
    nodes = sorted(graph.nodes, key=lambda n: (n.span.start, n.id))
    kept: list[PlanAction] = []
    for node in nodes:
        action = action_of(node.span.tree, node.span.start, node.span.end)
        frames = (node.span.start, node.span.end)
        tree = format_tree(node.span.tree)
        if action.kind is ActionKind.GRASP:
            continue
        if action.kind in (ActionKind.HANDOVER, ActionKind.HOLDING):
            assert action.partner is not None
            pids = (person_of(action.hand), person_of(action.partner.hand))
            partner = None
            if action.kind is ActionKind.HOLDING:
                if action.partner.verb is None:  # both only hold the object: nothing for the arms to do
                    continue
                tool, ingredients, location, source = _fields(action.partner, categories)
                partner = Act(action.partner.verb, tool, ingredients, location, source)
            kept.append(PlanAction(node.id, pids, str(action.kind), tool=action.held, partner=partner,
                                   frames=frames, tree=tree))
            continue
        tool, ingredients, location, source = _fields(action, categories)
        kept.append(PlanAction(node.id, (person_of(action.hand),), action.verb or "transfer", tool, ingredients,
                               location, source, frames=frames, tree=tree))
    order = {a.id: k for k, a in enumerate(kept)}
    after: dict[str, set[str]] = {a.id: set() for a in kept}
    last: dict[str, str] = {}
    for a in kept:
        for pid in a.pids:
            if pid in last:
                after[a.id].add(last[pid])
            last[pid] = a.id
    for edge in graph.edges:
        if edge.kind != "sequence" and edge.source in order and edge.target in order \
                and order[edge.source] < order[edge.target]:
            after[edge.target].add(edge.source)
    return tuple(PlanAction(a.id, a.pids, a.verb, a.tool, a.ingredients, a.location, a.source, a.partner,
                            tuple(sorted(after[a.id], key=order.__getitem__)), a.frames, a.tree) for a in kept)


def plan_from_graph(graph: ActionGraph, obs: Observations, *, table: Table = DEFAULT_TABLE,
                    robot: str = DEFAULT_ROBOT) -> Plan:
    """The plan of an action graph: scene from the video (:func:`wecook_core.layout.layout_scene`), one arm per person
    (:func:`agents_for`), actions and their order (:func:`plan_actions`)."""
    actions = plan_actions(graph, obs.categories)
    persons = {pid for a in actions for pid in a.pids} | set(graph.sequences) | {n.person for n in graph.nodes}
    persons = {p for p in persons if p in PERSONS} or {"P1"}
    from wecook_core.layout import layout_scene

    return Plan(agents=agents_for(sorted(persons), table, robot), scene=layout_scene(graph, obs, table),
                actions=actions)
