"""What starts in a container, and where on it (a part of the layout, :mod:`wecook_core.plan.layout`).

Ingredients that start in a container are spread along its longer axis; a board keeps room free at its ends, and
more at an end a holding hand presses (:data:`HOLD_ROOM`), so that the partner's tool works on the food clear of
the holder's hand.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from wecook_core.model import ActionGraph, ActionKind, Category, Observations, person_of
from wecook_core.plan.model import SceneObject
from wecook_core.trees.notation import action_of

END_ROOM = 0.06
"""Metres kept free at each end of a board, for a hand holding it still."""
HOLD_ROOM = 0.11
"""Metres kept free of food at the end of a board that a hand holds still (the end away from the partner's arm,
where the executor's holder presses first): the hand presses about 3 cm in from the end, its palm reaches about
3.5 cm either side of that, and a knife over the food reaches up to 4 cm past it."""
ITEM_GAP = 0.04
"""Metres between neighbouring ingredients on a board (room for a knife)."""
MAX_BOARD = 0.36
"""Metres: the longest a board grows to fit what starts on it and the hands holding it."""
WALL_ROOM = 0.01
"""Metres between the ingredients spread in a container and its walls."""


def taken_from_by_hand(graph: ActionGraph) -> set[str]:
    """Containers an ingredient is taken out of by hand (the source of a transfer without a tool)."""
    out = set()
    for node in graph.nodes:
        action = action_of(node.span.tree, node.span.start, node.span.end)
        for act in (action, action.partner):
            if act is not None and act.kind is ActionKind.TRANSFER and act.held is None and len(act.targets) == 3:
                out.add(act.targets[1])
    return out


def holders(graph: ActionGraph, containing: Mapping[str, str] | None = None) -> dict[str, set[str]]:
    """Container -> the persons who hold it still for a partner (HOLDING actions with a partner's action). Food
    held that starts in a container (``containing``, ingredient -> container) is held by its container, as the
    executor holds it (a gripper closed on the food would cover where the partner works)."""
    inside = containing or {}
    out: dict[str, set[str]] = {}
    for node in graph.nodes:
        action = action_of(node.span.tree, node.span.start, node.span.end)
        if action.kind is ActionKind.HOLDING and action.held is not None and action.partner is not None \
                and action.partner.verb is not None:
            out.setdefault(inside.get(action.held, action.held), set()).add(person_of(action.hand))
    return out


def worked(graph: ActionGraph, categories: Mapping[str, Category]) -> set[str]:
    """Ingredients a held tool works on where they lie (cut, peeled, rolled, spread...): a hand carrying the tool
    comes down over them, so they need room around them (see :func:`wecook_core.plan.layout._gaps`)."""
    out = set()
    for node in graph.nodes:
        action = action_of(node.span.tree, node.span.start, node.span.end)
        for act in (action, action.partner):
            if act is None or act.kind is not ActionKind.TOOL or act.held is None \
                    or categories.get(act.held) is not Category.TOOL:
                continue
            out |= {t for t in act.targets if categories.get(t, Category.INGREDIENT) is Category.INGREDIENT}
    return out


def containing(graph: ActionGraph, obs: Observations, first: Mapping[str, np.ndarray]) -> dict[str, str]:
    """Ingredient -> the container it starts in: from the first action that names it with a container (a
    transfer's source, or the container it is acted on in), else from its first box lying mostly inside a
    container's first box."""
    cat = obs.categories
    out: dict[str, str] = {}
    for node in sorted(graph.nodes, key=lambda n: (n.span.start, n.id)):
        actions = [action_of(node.span.tree, node.span.start, node.span.end)]
        if actions[0].partner is not None:
            actions.append(actions[0].partner)
        for action in actions:
            targets = action.targets
            if action.kind is ActionKind.TRANSFER and len(targets) == 3:
                out.setdefault(targets[0], targets[1])
            elif len(targets) >= 2 and cat.get(targets[0]) is Category.INGREDIENT:
                container = next((t for t in targets[1:] if cat.get(t) is Category.CONTAINER), None)
                if container is not None:
                    out.setdefault(targets[0], container)
    for name, box in first.items():
        if cat.get(name) is not Category.INGREDIENT or name in out:
            continue
        area = max((box[2] - box[0]) * (box[3] - box[1]), 1e-9)
        best, best_share = None, 0.5
        for other, obox in first.items():
            if cat.get(other) is not Category.CONTAINER:
                continue
            w = min(box[2], obox[2]) - max(box[0], obox[0])
            h = min(box[3], obox[3]) - max(box[1], obox[1])
            share = max(w, 0) * max(h, 0) / area
            if share > best_share:
                best, best_share = other, share
        if best is not None:
            out[name] = best
    return {k: v for k, v in out.items() if k in first and v in first and cat.get(v) is Category.CONTAINER}


def end_rooms(persons: set[str]) -> tuple[float, float]:
    """Metres kept free at the ``-x`` and ``+x`` ends of a board lying along x that ``persons`` hold still: P1
    (standing at ``-x``) presses the end on its side, away from its partner, P2 the other."""
    return (HOLD_ROOM if "P1" in persons else END_ROOM, HOLD_ROOM if "P2" in persons else END_ROOM)


def fit_board(board: SceneObject, items: list[SceneObject], persons: set[str]) -> SceneObject:
    """The board grown (up to :data:`MAX_BOARD`) to hold ``items`` in a row with :data:`ITEM_GAP` between them
    and the room at its ends (:func:`end_rooms`); a board held still lies along x, between the arms."""
    low, high = end_rooms(persons)
    need = sum(max(i.size[0], i.size[1]) for i in items) + ITEM_GAP * max(len(items) - 1, 0) + low + high
    size = (round(min(max(board.size[0], need), MAX_BOARD), 3), board.size[1], board.size[2])
    yaw = 0.0 if persons else board.yaw
    return SceneObject(board.name, board.category, board.shape, size, board.x, board.y, yaw)


def spread(container: SceneObject, items: list[SceneObject], persons: set[str]) -> list[SceneObject]:
    """``items`` placed in ``container``, evenly along its longer axis: wall to wall in a bowl or pot; on a board
    between the room kept at its ends (:func:`end_rooms` of the ``persons`` holding it)."""
    hx, hy = container.half_extents()
    along_x = hx >= hy
    half_long = max(hx, hy)
    halves = [max(o.half_extents()) for o in items]
    if container.shape == "box":
        low, high = end_rooms(persons) if along_x else (END_ROOM, END_ROOM)
    else:
        low = high = WALL_ROOM
    first, last = -half_long + low + halves[0], half_long - high - halves[-1]
    if first > last:  # too crowded for the room asked: the middle of what there is
        first = last = (first + last) / 2
    if len(items) == 1:
        offsets = [0.0] if not persons or first <= 0.0 <= last else [first if abs(first) < abs(last) else last]
    else:
        offsets = list(np.linspace(first, last, len(items)))
    limit = 0.8 * min(hx, hy) * 2
    out = []
    for o, s in zip(items, offsets, strict=True):
        dx, dy = (float(s), 0.0) if along_x else (0.0, float(s))
        size = (round(min(o.size[0], limit), 3), round(min(o.size[1], limit), 3), o.size[2])
        out.append(SceneObject(o.name, o.category, o.shape, size, round(container.x + dx, 4),
                               round(container.y + dy, 4), o.yaw))
    return out
