"""Whether a hand has room to work where an action needs it: a check of a plan before it runs (``wecook plan
check``), by the rules the layout keeps (:mod:`wecook_core.plan.layout`, :mod:`wecook_core.plan.contents`).

- A hand carrying a tool comes down over what the tool works on where it lies on the table (cut, peel, roll,
  spread...), turned whichever way the tool needs: nothing taller than :data:`~wecook_core.plan.layout.LOW` may
  stand within :data:`MIN_HAND_ROOM` of it (footprints, along x or y). (Stirring, and work on food in a container,
  is over the container: the container's own rules apply.)
- A hand holding a board still (or food lying on a board: by the board) presses its end farthest from the
  partner's arm: what the partner works on must lie :data:`~wecook_core.plan.contents.HOLD_ROOM` clear of that
  end.

Positions are those when the action comes (:func:`wecook_core.plan.reach.positions`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from wecook_core.model import Category
from wecook_core.plan.contents import HOLD_ROOM
from wecook_core.plan.layout import HAND_ROOM, LOW
from wecook_core.plan.model import Plan, SceneObject
from wecook_core.plan.reach import positions

MIN_HAND_ROOM = HAND_ROOM / 2
"""Metres a hand carrying a tool needs at the least between what it works on and anything tall: the layout keeps
:data:`~wecook_core.plan.layout.HAND_ROOM`, half of it on a crowded table (where runs still pass); less, and the
hand meets it (a pot 4 cm from the dough to roll)."""


@dataclass(frozen=True)
class Crowded:
    """An object lying too close to where a hand must work in an action."""

    action_id: str
    verb: str
    pid: str
    what: str
    """What the hand works on (or the board it holds)."""
    name: str
    """What is in the way."""
    distance: float
    need: float
    """Metres: the room there is and the room the hand needs."""
    holding: bool = False

    def __str__(self) -> str:
        if self.holding:
            return (f"{self.action_id} ({self.verb} by {self.pid}): the {self.name} lies {self.distance:.2f} m from "
                    f"the end of the {self.what} the holder presses, too close for the partner's tool "
                    f"({self.need:.2f} m needed)")
        return (f"{self.action_id} ({self.verb} by {self.pid}): the {self.name} stands {self.distance:.2f} m from "
                f"the {self.what}, too close for the hand carrying the tool over it ({self.need:.2f} m needed)")


def _apart(a: SceneObject, ax: float, ay: float, b: SceneObject, bx: float, by: float) -> float:
    """Metres between the footprints of ``a`` at (ax, ay) and ``b`` at (bx, by), along the axis they are
    farthest apart on (negative: they overlap)."""
    (ahx, ahy), (bhx, bhy) = a.half_extents(), b.half_extents()
    return max(abs(ax - bx) - ahx - bhx, abs(ay - by) - ahy - bhy)


def room_problems(plan: Plan) -> list[Crowded]:
    """Every action whose hand lacks the room the layout's rules keep (see the module's docstring), in plan
    order."""
    objects = {o.name: o for o in plan.scene.objects}
    bases = {a.pid: a.base_position for a in plan.agents}
    inside = dict(plan.scene.containing)
    out: list[Crowded] = []
    for action, where in positions(plan):
        if action.verb == "transfer" and action.location is not None:  # what it moves now lies in its destination
            inside.update({n: action.location for n in action.ingredients})
        acts = [(action.pids[0], action.verb, action.tool, action.ingredients)] if action.partner is None else \
            [(action.pids[-1], action.partner.verb, action.partner.tool, action.partner.ingredients)]
        for pid, verb, tool, ingredients in acts:
            if tool is None or tool not in objects or objects[tool].category is not Category.TOOL \
                    or verb == "transfer":
                continue
            for name in ingredients:
                if name not in objects or name not in where or name in inside:
                    continue
                worked, (x, y) = objects[name], where[name]
                for other in objects.values():
                    if other.name in (name, tool) or other.size[2] <= LOW or other.name not in where:
                        continue
                    gap = _apart(worked, x, y, other, *where[other.name])
                    if gap < MIN_HAND_ROOM - 1e-3:
                        out.append(Crowded(action.id, action.verb, pid, name, other.name, max(gap, 0.0),
                                           MIN_HAND_ROOM))
        held = inside.get(action.tool, action.tool) if action.tool is not None else None  # food: by its board
        if action.verb == "holding" and action.partner is not None and held in objects \
                and objects[held].shape == "box" and len(action.pids) > 1 and action.pids[1] in bases:
            food = [n for n in (*action.partner.ingredients, action.tool) if n in objects and n != held]
            out += _hold_problems(action.id, action.verb, action.pids[0], objects[held], where,
                                  bases[action.pids[1]], food, objects)
    return out


def _hold_problems(action_id: str, verb: str, holder: str, board: SceneObject,
                   where: dict[str, tuple[float, float]], actor_base: tuple[float, float, float],
                   food: list[str], objects: dict[str, SceneObject]) -> list[Crowded]:
    """The food the partner works on that lies too near the end of ``board`` the holder presses (the end
    farther from the actor's base)."""
    if board.name not in where:
        return []
    cx, cy = where[board.name]
    half = board.size[0] / 2
    ux, uy = math.cos(board.yaw), math.sin(board.yaw)  # the board's long axis
    ends = [(cx + s * half * ux, cy + s * half * uy) for s in (1.0, -1.0)]
    end = max(ends, key=lambda e: math.hypot(e[0] - actor_base[0], e[1] - actor_base[1]))
    inward = (cx - end[0], cy - end[1])
    norm = math.hypot(*inward) or 1.0
    out = []
    for name in food:
        if name not in where:
            continue
        x, y = where[name]
        along = ((x - end[0]) * inward[0] + (y - end[1]) * inward[1]) / norm  # from the end, along the board
        o = objects[name]
        reach = abs(o.size[0] / 2 * math.cos(o.yaw - board.yaw)) + abs(o.size[1] / 2 * math.sin(o.yaw - board.yaw))
        room = along - reach
        if 0.0 <= along <= board.size[0] and room < HOLD_ROOM - 1e-6:
            out.append(Crowded(action_id, verb, holder, board.name, name, max(room, 0.0), HOLD_ROOM, holding=True))
    return out
