"""Which arm must reach which object, and whether it can: a check of a plan before it runs (``wecook plan
check``), and the rule the layout (:mod:`wecook_core.plan.layout`) places objects by.

An arm works on an object on the table (grasps it from above, engages a tool over it) reliably when its
footprint centre lies between :data:`MIN_REACH` and the arm's :data:`WORK_REACH` from the base, horizontally;
a container, which the arm works over from above with what it carries (pours, tips, stirs in), no nearer than
:data:`MIN_OVER_REACH`.
Who must reach what: an individual action's arm, every object it names; a handover's giver the object handed
over (the receiver takes it mid-air or between the arms); a holding's holder the object it holds, and the actor
its own action's objects. Objects move as the plan goes: an object handed over lies in front of the receiver
afterwards, a transferred ingredient in its destination.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from wecook_core.model import Category
from wecook_core.plan.model import DEFAULT_ROBOT, Agent, Plan, PlanAction

WORK_REACH: dict[str, float] = {DEFAULT_ROBOT: 0.68}
"""Metres from its base (horizontally) within which an arm grasps and works on objects on the table reliably,
by robot URDF (a Panda's hand pointing down reaches about 0.7 m out at the height of its base); robots not
listed are not checked."""
MIN_REACH = 0.25
"""Metres: closer to its base than this, an arm folds too tightly to take an object from above."""
MIN_OVER_REACH = 0.33
"""Metres: closer to its base than this, an arm cannot hold what it carries over a container to pour or tip it
there (a spoon tipped over a plate 0.31 m from the base found no pose, 0.32 m did)."""
DROP_DISTANCE = 0.42
"""Metres from the receiver's base to where it puts what was handed over (``collaborations.handover.drop_distance``
of the skill library)."""


@dataclass(frozen=True)
class Unreachable:
    """An object an arm must work on that lies out of its reach at that point of the plan."""

    action_id: str
    verb: str
    pid: str
    name: str
    position: tuple[float, float]
    distance: float
    """Metres from the arm's base."""
    low: float
    high: float
    """Metres: the band of distances the arm reaches."""

    def __str__(self) -> str:
        where = "beyond its reach" if self.distance > self.high else "too close to its base"
        return (f"{self.action_id} ({self.verb} by {self.pid}): the {self.name} at ({self.position[0]:.2f}, "
                f"{self.position[1]:.2f}) is {self.distance:.2f} m from {self.pid}'s base, {where} "
                f"({self.low:.2f}-{self.high:.2f} m)")


def touched(action: PlanAction) -> dict[str, tuple[str, ...]]:
    """Arm -> the objects it must reach in ``action`` (see the module's docstring)."""
    def names(tool: str | None, ingredients: tuple[str, ...], location: str | None, source: str | None
              ) -> tuple[str, ...]:
        return tuple(n for n in (tool, *ingredients, location, source) if n is not None)

    if action.verb == "handover":
        return {action.pids[0]: names(action.tool, (), None, None)}
    if action.verb == "holding" and action.partner is not None:
        act = action.partner
        actor = action.pids[1] if len(action.pids) > 1 else action.pids[0]
        return {action.pids[0]: names(action.tool, (), None, None),
                actor: names(act.tool, act.ingredients, act.location or action.tool, act.source)}
    return {action.pids[0]: names(action.tool, action.ingredients, action.location, action.source)}


def min_reach(category: Category) -> float:
    """Metres: the nearest to an arm's base that it works on an object of ``category``."""
    return MIN_OVER_REACH if category is Category.CONTAINER else MIN_REACH


def reach_band(agent: Agent, category: Category = Category.INGREDIENT) -> tuple[float, float] | None:
    """(nearest, farthest) metres from its base an arm works on an object of ``category`` at, or None for a robot
    that is not checked."""
    high = WORK_REACH.get(agent.robot)
    return None if high is None else (min_reach(category), high)


def positions(plan: Plan) -> Iterator[tuple[PlanAction, dict[str, tuple[float, float]]]]:
    """Each action of the plan, in order, with where (x, y) each object lies when it comes (see the module's
    docstring; the mapping is updated in place after each action)."""
    where: dict[str, tuple[float, float]] = {o.name: (o.x, o.y) for o in plan.scene.objects}
    agents: Mapping[str, Agent] = {a.pid: a for a in plan.agents}
    for action in plan.actions:
        yield action, where
        _move(action, where, agents)


def reach_problems(plan: Plan) -> list[Unreachable]:
    """Every object an arm must work on that is out of its reach when the action comes, in plan order."""
    agents: Mapping[str, Agent] = {a.pid: a for a in plan.agents}
    categories = {o.name: o.category for o in plan.scene.objects}
    out: list[Unreachable] = []
    for action, where in positions(plan):
        for pid, objects in touched(action).items():
            agent = agents.get(pid)
            if agent is None:
                continue
            bx, by = agent.base_position[0], agent.base_position[1]
            for name in objects:
                band = reach_band(agent, categories.get(name, Category.INGREDIENT))
                if name not in where or band is None:
                    continue
                x, y = where[name]
                d = math.hypot(x - bx, y - by)
                if not band[0] <= d <= band[1]:
                    out.append(Unreachable(action.id, action.verb, pid, name, (x, y), d, *band))
    return out


def _move(action: PlanAction, where: dict[str, tuple[float, float]], agents: Mapping[str, Agent]) -> None:
    """Where things are after ``action``: a handed-over object in front of the receiver, transferred
    ingredients in their destination."""
    if action.verb == "handover" and action.tool in where and len(action.pids) > 1 and action.pids[1] in agents:
        b = agents[action.pids[1]].base_position
        norm = math.hypot(b[0], b[1]) or 1.0
        where[action.tool] = (b[0] - b[0] / norm * DROP_DISTANCE, b[1] - b[1] / norm * DROP_DISTANCE)
    elif action.verb == "transfer" and action.location in where:
        for name in action.ingredients:
            if name in where:
                where[name] = where[action.location]
