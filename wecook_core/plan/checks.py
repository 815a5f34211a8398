"""Checking a plan: every problem an :class:`InputError` naming its place (``actions[3] (a4).tool``)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any
from xml.parsers import expat

from wecook_core.errors import InputError
from wecook_core.model import COLLABORATIONS, PERSONS, VERBS, Category
from wecook_core.plan.model import ARM_REACH, PLAN_VERBS, PLAN_VERSION, SHAPES, Plan, PlanAction

MAX_PLAN_ACTIONS = 10_000
"""The most actions a plan may have (a cooking video yields tens)."""
MAX_PLAN_OBJECTS = 500
"""The most objects a plan's scene may hold (each is a body in the simulation)."""
MAX_METRES = 10.0
"""The largest distance from the origin, table side, table height or reach a plan may give, in metres (a
kitchen table is 1-2 m; a plan beyond this is not one the arms can act in)."""
MAX_URDF_BYTES = 16 << 20
"""The largest robot URDF file a plan may name."""


def robot_problem(robot: str) -> str | None:
    """Why the robot URDF ``robot`` (relative to ``pybullet_data`` unless absolute) cannot be an arm, or None:
    it must be a readable ``.urdf`` file whose XML root is ``<robot>`` and every mesh it names must be a file
    (:func:`mesh_path`)."""
    path = Path(robot)
    if not path.is_absolute():
        import pybullet_data

        path = Path(pybullet_data.getDataPath()) / path
    if path.suffix.lower() != ".urdf":
        return f"robot {robot!r} is not a .urdf file"
    meshes: list[str] = []
    try:
        if not path.is_file():
            return f"robot URDF {robot!r} not found (looked at {path})"
        if path.stat().st_size > MAX_URDF_BYTES:
            return f"robot URDF {robot!r} is larger than {MAX_URDF_BYTES} bytes"
        roots: list[str] = []
        parser = expat.ParserCreate()

        def start(name: str, attrs: dict[str, str]) -> None:
            if not roots:
                roots.append(name)
            if name == "mesh" and "filename" in attrs:
                meshes.append(attrs["filename"])

        parser.StartElementHandler = start
        with path.open("rb") as handle:
            parser.ParseFile(handle)
    except (OSError, expat.ExpatError) as error:
        return f"robot URDF {robot!r} does not read as XML ({error})"
    if roots != ["robot"]:
        return f"robot URDF {robot!r} is not a URDF (its XML root is not <robot>)"
    for mesh in dict.fromkeys(meshes):
        if mesh_path(path, mesh) is None:
            return (f"robot URDF {robot!r} names a mesh that is not a file: {mesh!r} (looked at "
                    f"{path.parent / mesh.removeprefix('package://').removeprefix('file://')})")
    return None


def mesh_path(urdf: Path, filename: str) -> Path | None:
    """The file a URDF's ``<mesh filename>`` names, as PyBullet finds it (``package://`` and ``file://`` dropped,
    relative to the URDF's folder), or None when there is none."""
    for scheme in ("package://", "file://"):
        filename = filename.removeprefix(scheme)
    candidate = Path(filename) if Path(filename).is_absolute() else urdf.parent / filename
    try:
        return candidate if candidate.is_file() else None
    except OSError:
        return None


def _finite_extent(bad: Any, place: str, values: Sequence[float]) -> None:
    if not all(math.isfinite(v) and abs(v) <= MAX_METRES for v in values):
        bad(place, f"expected finite metres within {MAX_METRES:g} m, got {[float(v) for v in values]}")


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
        elif problem := robot_problem(agent.robot):
            bad(f"agents[{i}].robot", problem)
        _finite_extent(bad, f"agents[{i}].base.position", agent.base_position)
        if not math.isfinite(agent.base_yaw):
            bad(f"agents[{i}].base.yaw", f"expected finite radians, got {agent.base_yaw}")
        pids.add(agent.pid)
    table = plan.scene.table
    _finite_extent(bad, "scene.table.size", table.size)
    _finite_extent(bad, "scene.table.height", (table.height,))
    _finite_extent(bad, "scene.table.reach", table.reach)
    if min(table.size) <= 0:
        bad("scene.table.size", f"table size must be positive, got {list(table.size)}")
    if len(plan.actions) > MAX_PLAN_ACTIONS:
        bad("actions", f"{len(plan.actions)} actions, more than the {MAX_PLAN_ACTIONS} a plan may have")
    if len(plan.scene.objects) > MAX_PLAN_OBJECTS:
        bad("scene.objects", f"{len(plan.scene.objects)} objects, more than the {MAX_PLAN_OBJECTS} a scene may "
            "hold")
    names: set[str] = set()
    for i, obj in enumerate(plan.scene.objects):
        place = f"scene.objects[{i}] ({obj.name})"
        if obj.name in names:
            bad(f"{place}.name", f"duplicate object {obj.name!r}")
        names.add(obj.name)
        if obj.shape not in SHAPES:
            bad(f"{place}.shape", f"unknown shape {obj.shape!r}, expected one of {', '.join(SHAPES)}")
        if not all(math.isfinite(v) for v in (*obj.size, obj.x, obj.y, obj.yaw)):
            bad(f"{place}", "size and pose must be finite numbers")
        elif min(obj.size) <= 0:
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
