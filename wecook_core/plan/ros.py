"""A plan for the paper's ROS platform (icaros-usc/wecook): the ``TaskMsg`` it takes on the topic ``WeCookDispatch``.

:func:`ros_task` maps a plan onto the platform's messages (:mod:`~wecook_core.plan.ros_messages`); the
standalone ROS 1 script that publishes it is :mod:`~wecook_core.plan.ros_script`'s. Only what the platform can
plan is sent (:mod:`~wecook_core.plan.ros_platform`: its planners, read from its sources): the platform's
``TaskGraph::merge`` crashes on an action without a plan.

How a plan maps:

- pids ``P1``/``P2`` -> ``p1``/``p2``, arms mounted where :attr:`UrdfTable.mounts` says (as the platform's two-arm
  demos mount them); objects keep their names, except that an object whose URDF is food has "food" in its name
  (``food_tomato``) and any other has none (a bottle of oil stays ``oil``), since the platform's motion planner
  skips collisions with every name containing "food"; every object is in the scene, with its URDF or a stand-in
  of its category; the platform's table (:attr:`UrdfTable.table_name`) joins every scene; the tags are
  :attr:`UrdfTable.tags`.
- an individual action: ``ActionMsg([p], verb, [location], tool, ingredients)``; ``tool`` is ``hand`` when the
  hand acts itself; without a location, the container its first ingredient is in at that point of the plan.
- ``transfer``: ``location`` is ``[source, destination]`` (the source, when the plan does not name it, is where
  the ingredient is at that point: the scene's containing pairs, moved by earlier transfers, else the table).
- ``pour`` and ``sprinkle`` (no planner of their own): the transfer that tips the held container over the
  location, ``ActionMsg([p], 'transfer', [held, location], held, ingredients)``, reported as mapped.
- ``handover``: ``ActionMsg([giver, receiver], 'handover', ['air'], 'hand', [object])``.
- ``holding``: ``ActionMsg([holder, actor], 'holding_<object>_<verb>', location, tool, ingredients)`` with the
  actor's action's fields, where the platform has that holding planner (cut, and a transfer with a tool from or
  into the held object); otherwise the actor's action alone, the hold reported as left out.
- peel, squeeze, spread, wrap and dip, and any action the platform would not plan (a cut by hand, an object with
  no URDF): left out of the dispatch and reported, with the dispatched actions that wait for it in the plan.
  Each arm's chain of actions on the platform is then its dispatched actions in plan order, so no action
  without a plan is ever merged.
- ``SceneMsg.containingMap``: ``ContainingMsg([container, ingredient])`` (the platform's order).

Poses are ``x y z qx qy qz qw`` in the platform's world: the centre of the plan's table top placed at
:attr:`UrdfTable.origin`, turned by :attr:`UrdfTable.origin_yaw`; objects stand :attr:`Urdf.z` above it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

from wecook_core.model import Category
from wecook_core.plan.model import Act, Plan, PlanAction
from wecook_core.plan.ros_messages import (
    MESSAGES,
    TOPIC,
    ActionMsg,
    AgentMsg,
    ContainingMsg,
    ObjectMsg,
    TagMsg,
    TaskMsg,
)
from wecook_core.plan.ros_platform import AIR, FOLLOWS, HAND, NO_PLANNER, planner_problem
from wecook_core.plan.ros_table import URDF_TABLE, Pose, Urdf, UrdfTable, kind_of, load_urdf_table

__all__ = ["MESSAGES", "TOPIC", "URDF_TABLE", "ActionMsg", "AgentMsg", "ContainingMsg", "ObjectMsg", "RosExport",
           "TagMsg", "TaskMsg", "Urdf", "UrdfTable", "kind_of", "load_urdf_table", "ros_task"]


@dataclass(frozen=True)
class RosExport:
    task: TaskMsg
    dispatched: tuple[str, ...]
    """Ids of the plan actions behind ``task.actions``, one each, in order."""
    names: Mapping[str, str]
    """Plan object -> its name on the platform."""
    stand_ins: Mapping[str, str]
    """Plan object -> the URDF url standing in for it (no URDF of its own on the platform)."""
    missing: Mapping[str, tuple[str, ...]]
    """Plan object with no URDF on the platform (left out of the scene) -> ids of the plan actions naming it."""
    left_out: Mapping[str, str]
    """Plan action id -> why it is not dispatched."""
    mapped: Mapping[str, str]
    """Plan action id -> how it is dispatched, when not as itself."""
    waiting: Mapping[str, tuple[str, ...]]
    """Left-out action id -> ids of dispatched actions that wait for it in the plan (``after``)."""

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
        for action_id, why in self.left_out.items():
            waits = self.waiting.get(action_id, ())
            out.append(f"{action_id} left out: {why}" + (f" ({', '.join(waits)} wait{'s' if len(waits) == 1 else ''}"
                                                         " for it in the plan)" if waits else ""))
        out += [f"{action_id} sent as {how}" for action_id, how in self.mapped.items()]
        return out


def _quat(yaw: float) -> tuple[float, float, float, float]:
    return 0.0, 0.0, round(math.sin(yaw / 2), 7), round(math.cos(yaw / 2), 7)


def _place(table: UrdfTable, x: float, y: float, z: float, yaw: float) -> Pose:
    """The pose in the platform's world of a point of the plan's frame (``z`` above the plan's table top)."""
    c, s = math.cos(table.origin_yaw), math.sin(table.origin_yaw)
    ox, oy, oz = table.origin
    px, py = ox + c * x - s * y, oy + s * x + c * y
    return (round(px, 4), round(py, 4), round(oz + z, 4), *_quat(table.origin_yaw + yaw))


def _platform_name(name: str, food: bool, prefix: str) -> str:
    """The object's name on the platform: with "food" in it if and only if it is food (see the module's
    docstring); "mouth", which the platform's planner skips too, only in food."""
    if food:
        return name if "food" in name else prefix + name
    return re.sub("food|mouth", lambda m: {"food": "fd", "mouth": "mth"}[m.group()], name)


class _Mapper:
    """Plan actions -> ActionMsg (or why not), following where each ingredient is as the plan goes."""

    def __init__(self, plan: Plan, names: Mapping[str, str], table: str) -> None:
        self.names = names
        self.table = table
        self.inside = dict(plan.scene.containing)

    def n(self, name: str) -> str:
        return self.names.get(name, name)

    def container(self, ingredients: tuple[str, ...]) -> str | None:
        return next((self.inside[i] for i in ingredients if i in self.inside), None)

    def individual(self, pid: str, act: PlanAction | Act) -> tuple[ActionMsg | str, str | None]:
        """The ActionMsg of one arm's action, or why it is left out; and how it was mapped (None: as itself)."""
        verb, ingredients = act.verb, tuple(self.n(i) for i in act.ingredients)
        hand = act.tool is None or act.tool in act.ingredients
        tool = HAND if hand or act.tool is None else self.n(act.tool)
        if verb == "transfer":
            first = act.ingredients[0] if act.ingredients else None
            source = act.source or (self.inside.get(first) if first else None) or self.table
            destination = act.location or self.table
            for name in act.ingredients:
                self.inside[name] = destination
            return ActionMsg((pid,), verb, (self.n(source), self.n(destination)), tool, ingredients), None
        if verb in FOLLOWS:
            held, into = act.tool, act.location or self.container(act.ingredients)
            if held is None:
                return f"{verb} by hand: the platform tips only a held container", None
            if into is None:
                return f"{verb} into no container: the plan names none", None
            how = f"{FOLLOWS[verb]} ({verb}: {self.n(held)} tipped over {self.n(into)}, planTransfer's second form)"
            return ActionMsg((pid,), FOLLOWS[verb], (self.n(held), self.n(into)), self.n(held), ingredients), how
        if verb in NO_PLANNER:
            return f"{verb}: {NO_PLANNER[verb]}", None
        if tool == HAND:
            return f"{verb} by hand: the platform's planner for {verb} grasps a tool", None
        where = act.location or self.container(act.ingredients)
        return ActionMsg((pid,), verb, (self.n(where),) if where else (), tool, ingredients), None

    def action(self, action: PlanAction) -> tuple[ActionMsg | str, str | None]:
        pids = tuple(p.lower() for p in action.pids)
        if action.verb == "handover":
            if action.tool is None:
                return "a handover of nothing", None
            return ActionMsg(pids, "handover", (AIR,), HAND, (self.n(action.tool),)), None
        if action.verb == "holding" and action.partner is not None:
            holder, actor = pids
            inner, how = self.individual(actor, action.partner)
            if isinstance(inner, str):
                return f"{action.partner.verb} held by {holder}: {inner}", None
            held = self.n(action.tool) if action.tool else None
            if held is not None and inner.verb == "cut":
                return ActionMsg(pids, f"holding_{held}_cut", inner.location or (held,), inner.tool,
                                 inner.ingredients), None
            if (held is not None and inner.verb == "transfer" and how is None and held in inner.location
                    and inner.tool not in (HAND, inner.location[0])):
                return ActionMsg(pids, f"holding_{held}_transfer", inner.location, inner.tool,
                                 inner.ingredients), None
            alone = f"{actor}'s {inner.verb} alone" + (f" ({how})" if how else "")
            return inner, (f"{alone}: the platform's holding planner has no holding_{held}_{inner.verb}, so "
                           f"{holder}'s hold of {held} is left out")
        return self.individual(pids[0], action)


def ros_task(plan: Plan, table: UrdfTable | None = None, *, if_sim: bool = True) -> RosExport:
    """The plan as the platform's ``TaskMsg`` (see the module's docstring for how each part maps)."""
    table = table or load_urdf_table()
    reserved = {table.table_name, HAND, AIR}
    names: dict[str, str] = {}
    urdfs: dict[str, tuple[Urdf | None, bool]] = {}
    for obj in plan.scene.objects:
        urdf, standing_in = urdfs[obj.name] = table.urdf(obj.name, obj.category)
        food = urdf.food if urdf is not None else obj.category is Category.INGREDIENT
        name = _platform_name(obj.name, food, table.food_prefix)
        while name in reserved:
            name += "_"
        reserved.add(name)
        names[obj.name] = name
    objects = [ObjectMsg(table.table_name, table.table_url, table.table_pose)]
    stand_ins: dict[str, str] = {}
    missing: dict[str, tuple[str, ...]] = {}
    for obj in plan.scene.objects:
        urdf, standing_in = urdfs[obj.name]
        if urdf is None:
            missing[obj.name] = tuple(a.id for a in plan.actions if obj.name in _objects_named(a))
            continue
        if standing_in:
            stand_ins[obj.name] = urdf.url
        objects.append(ObjectMsg(names[obj.name], urdf.url, _place(table, obj.x, obj.y, urdf.z, obj.yaw)))
    in_scene = {o.name for o in objects}
    containing = tuple(ContainingMsg((names[c], names[i])) for i, c in plan.scene.containing
                       if names.get(c) in in_scene and names.get(i) in in_scene)
    agents = tuple(AgentMsg(a.pid.lower(), table.agent_type, _agent_pose(table, plan, a.pid), table.if_float)
                   for a in plan.agents)
    pids = {a.pid for a in agents}
    mapper = _Mapper(plan, names, table.table_name)
    actions: list[ActionMsg] = []
    dispatched: list[str] = []
    left_out: dict[str, str] = {}
    mapped: dict[str, str] = {}
    for action in plan.actions:
        msg, how = mapper.action(action)
        if isinstance(msg, ActionMsg):
            problem = planner_problem(msg, in_scene, pids)
            if problem is not None:
                msg = f"the platform would not plan {msg.verb}: {problem}"
        if isinstance(msg, str):
            left_out[action.id] = msg
            continue
        actions.append(msg)
        dispatched.append(action.id)
        if how is not None:
            mapped[action.id] = how
    waiting = {gone: tuple(a.id for a in plan.actions if gone in a.after and a.id in dispatched)
               for gone in left_out}
    task = TaskMsg(tuple(objects), containing, tuple(actions), agents, table.tags, if_sim=if_sim)
    return RosExport(task, tuple(dispatched), names, stand_ins, missing, left_out, mapped,
                     {k: v for k, v in waiting.items() if v})


def _agent_pose(table: UrdfTable, plan: Plan, pid: str) -> Pose:
    if pid in table.mounts:
        return table.mounts[pid]
    agent = next(a for a in plan.agents if a.pid == pid)
    x, y, z = agent.base_position
    return _place(table, x, y, z - plan.scene.table.height, agent.base_yaw)


def _objects_named(action: PlanAction) -> list[str]:
    acts: list[PlanAction | Act] = [action] if action.partner is None else [action, action.partner]
    return [name for act in acts for name in (act.tool, act.location, act.source, *act.ingredients)
            if name is not None]
