"""A plan in and out of YAML (``wecook_plan: 1``; the format: see :mod:`wecook_core.plan`)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError, yaml_error
from wecook_core.files import read_text, write_atomic
from wecook_core.model import Category
from wecook_core.plan.checks import validate
from wecook_core.plan.model import DEFAULT_ROBOT, PLAN_VERSION, Act, Agent, Plan, PlanAction, Scene, SceneObject, Table
from wecook_core.plan.yaml_read import MAX_PLAN_BYTES, parse_plan_yaml


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


def write_plan(plan: Plan, path: str | Path, *, replace: bool = True) -> Path:
    """Write the plan's YAML atomically (creating the folder); returns the path. An existing file is replaced
    whole (never torn) unless ``replace`` is False: then it is an :class:`InputError`."""
    return write_atomic(path, dump_plan(plan), replace=replace, what="plan")


def _short(value: Any, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters (an error message quotes what it refuses, never all of it)."""
    if isinstance(value, Mapping | list) and len(value) > 8:
        return f"a {type(value).__name__} of {len(value)} items"
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


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
            raise self.fail(place, f"expected a name, got {_short(value)}")
        return value

    def number(self, value: Any, place: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(place, f"expected a number, got {_short(value)}")
        try:
            number = float(value)
        except OverflowError:
            raise self.fail(place, f"expected a number of metres or radians, got {_short(value)}") from None
        if not math.isfinite(number):
            raise self.fail(place, f"expected a finite number, got {value!r}")
        return number

    def numbers(self, value: Any, place: str, n: int) -> tuple[float, ...]:
        items = self.seq(value, place)
        if len(items) != n:
            raise self.fail(place, f"expected {n} numbers, got {_short(value)}")
        return tuple(self.number(v, f"{place}[{k}]") for k, v in enumerate(items))

    def names(self, value: Any, place: str) -> tuple[str, ...]:
        return tuple(self.string(v, f"{place}[{k}]") for k, v in enumerate(self.seq(value, place)))


def plan_from_dict(data: Any, path: str | Path | None = None) -> Plan:
    """Build a plan from parsed YAML; structural errors raise :class:`InputError` (not validated further)."""
    r = _Reader(path)
    top = r.mapping(data, "top level")
    version = top.get("wecook_plan")
    if not isinstance(version, int) or isinstance(version, bool):
        raise r.fail("wecook_plan", f"not a wecook plan: expected `wecook_plan: {PLAN_VERSION}`, got "
                     f"{_short(version)}")
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
            raise r.fail(f"{place}.category", f"unknown category {_short(m.get('category'))}, expected one of "
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
            raise r.fail(f"scene.containing[{i}]", f"expected [ingredient, container], got {_short(raw)}")
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
                raise r.fail(f"{place}.frames", f"expected [start, end] frame indices, got {_short(m['frames'])}")
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
        data = parse_plan_yaml(text, path)
    except yaml.YAMLError as error:
        raise yaml_error(path, error, "not valid YAML") from None
    plan = plan_from_dict(data, path)
    if check:
        validate(plan, path)
    return plan


def read_plan(path: str | Path, *, check: bool = True) -> Plan:
    """Read and validate a plan file; any problem raises :class:`InputError` naming the file and the place."""
    try:
        text = read_text(path, "plan", MAX_PLAN_BYTES)
    except InputError as error:
        raise InputError(path, f"cannot read the plan ({error.message})", place=error.place) from None
    return load_plan(text, path, check=check)
