"""Building a plan from an action graph and the video's observations."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from wecook_core.model import PERSONS, Action, ActionGraph, ActionKind, Category, Observations, person_of
from wecook_core.plan.layout import layout_scene
from wecook_core.plan.model import DEFAULT_ROBOT, DEFAULT_TABLE, Act, Agent, Plan, PlanAction, Table
from wecook_core.trees.notation import action_of, format_tree


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

    ``after`` (see :func:`object_dependencies`): each action comes after the latest earlier action that uses or
    changes each of its objects. An arm still does its own actions in plan order, and a collaboration starts when
    both its arms have come to it (so the graph's collaboration edges, which only say that, are not ``after``
    edges); but a failure skips only the actions that depend on it through their objects: a failed holding does
    not skip the partner's next action on other things.
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
    after = {k: set(v) for k, v in object_dependencies(kept).items()}
    return tuple(PlanAction(a.id, a.pids, a.verb, a.tool, a.ingredients, a.location, a.source, a.partner,
                            tuple(sorted(after[a.id], key=order.__getitem__)), a.frames, a.tree) for a in kept)


def action_objects(action: PlanAction) -> frozenset[str]:
    """The objects an action uses or changes: its tool, ingredients, location and source, and its partner's."""
    acts: list[PlanAction | Act] = [action] if action.partner is None else [action, action.partner]
    return frozenset(n for a in acts for n in (a.tool, a.location, a.source, *a.ingredients) if n is not None)


def object_dependencies(actions: Sequence[PlanAction]) -> dict[str, tuple[str, ...]]:
    """Action id -> the earlier actions (in the order given) it depends on through its objects: for each object it
    names, the latest earlier action naming that object (that one depends on the ones before it, so the chain
    covers every earlier user). Two actions that share no object do not depend on each other, whatever the
    order the video showed them in."""
    last: dict[str, str] = {}
    out: dict[str, tuple[str, ...]] = {}
    order = {a.id: k for k, a in enumerate(actions)}
    for a in actions:
        names = sorted(action_objects(a))
        out[a.id] = tuple(sorted({last[n] for n in names if n in last}, key=order.__getitem__))
        for n in names:
            last[n] = a.id
    return out


def plan_from_graph(graph: ActionGraph, obs: Observations, *, table: Table = DEFAULT_TABLE,
                    robot: str = DEFAULT_ROBOT) -> Plan:
    """The plan of an action graph: scene from the video (:func:`wecook_core.layout.layout_scene`), one arm per person
    (:func:`agents_for`), actions and their order (:func:`plan_actions`)."""
    actions = plan_actions(graph, obs.categories)
    persons = {pid for a in actions for pid in a.pids} | set(graph.sequences) | {n.person for n in graph.nodes}
    persons = {p for p in persons if p in PERSONS} or {"P1"}
    return Plan(agents=agents_for(sorted(persons), table, robot), scene=layout_scene(graph, obs, table, robot),
                actions=actions)
