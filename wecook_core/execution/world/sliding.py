"""The slide of an engage (a fallback of :func:`~.actuating.engage_goal`, written against the world's
:class:`~.protocols.Scene`): when no pose of a tool's TSR lets the actuation on an ingredient pass its neighbours,
the tool is slid along itself, the ingredient farther from the hand, so that it works the ingredient with
another part of itself (a rolling pin with its far half, a knife nearer its tip) and its ends come clear of what
stands beside the ingredient. The poses slid are tried clearest first.

Measured on the stand-in scaled s302 x0.8, a12 (a rolling pin on dough between a pot, a bowl and a plate; every
pose of three attempts 'collides with pot'): slid 1.1 cm, the roll keeps 2 mm clear of every neighbour. Four
times the samples unslid also found a pose, 2 mm into the pot (one that nudges it); unordered, the slide took the
same pose as in order.

A pure query: it reads the scene and returns poses; the arm checks them (:mod:`.actuating`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from wecook_core.execution.skills.library import Step, Waypoint
from wecook_core.execution.world.protocols import Roles, Scene
from wecook_core.model import Category

SLIDE = 0.045
"""Metres a tool slides along itself at the most."""
SLIDE_SAMPLES = 4
"""Times the cell's samples drawn for the slide (at slides of a quarter, a half, three quarters and all of what
each allows, in turn)."""
ON_THE_TOOL = 9
"""Points along a tool's length its clearance is measured at."""

Waypoints = Callable[[np.ndarray], list[Waypoint]]
"""The actuation's effector waypoints from an ee pose (4x4)."""


def slides(scene: Scene, pid: str, step: Step, roles: Roles) -> bool:
    """Whether ``step`` may be slid: the carried object is a tool, and what its motion touches an ingredient
    (a tool stirring in a pot may not: it would pass into the pot's wall, which it is let through)."""
    hand = scene.hand(pid)
    if not hand.riding or step.contact is None or scene.category(hand.riding[0].name) is not Category.TOOL:
        return False
    target = roles.get(step.contact[1])
    return target is not None and scene.category(target) is Category.INGREDIENT


def slid(scene: Scene, pid: str, step: Step, roles: Roles, goals: Sequence[np.ndarray], waypoints: Waypoints,
         neighbours: Sequence[str]) -> list[tuple[np.ndarray, float]]:
    """``goals`` (ee poses, 4x4) each slid along the carried tool, the ingredient ``step`` touches farther from
    the hand and never off the tool's end, by up to :data:`SLIDE` (the k-th by (k % 4 + 1) quarters of what it
    allows), with the metres slid, ordered by the clearance of their paths (:func:`clearance`) to ``neighbours``,
    the clearest first."""
    assert step.contact is not None
    hand = scene.hand(pid)
    carrier = hand.riding[0]
    tool = scene.half(carrier.name)
    target = roles.get(step.contact[1])
    assert target is not None
    at = scene.pose(target)[:3, 3]
    half = scene.half(target)
    boxes = scene.boxes(neighbours)
    out = []
    for k, G in enumerate(goals):
        E = G @ carrier.T_ee_obj
        along = E[:3, 0]
        local = float(along @ (at - E[:3, 3]))  # where the ingredient lies along the tool, from its middle
        grip = float(np.linalg.inv(carrier.T_ee_obj)[0, 3])  # where the hand holds it
        away = 1.0 if local >= grip else -1.0
        reach = float(np.abs(along[:2]) @ [half.hx, half.hy])  # the ingredient's half length along the tool
        room = min(SLIDE, tool.hx - reach - away * local)
        if room <= 0.0:
            continue
        metres = room * (k % SLIDE_SAMPLES + 1) / SLIDE_SAMPLES
        moved = G.copy()
        moved[:3, 3] -= away * metres * along  # the tool back: the ingredient farther along it
        out.append((moved, metres, clearance(scene, carrier.name, [w.pose for w in waypoints(moved)], boxes)))
    out.sort(key=lambda item: -item[2])
    return [(G, metres) for G, metres, _ in out]


def clearance(scene: Scene, tool: str, poses: Sequence[np.ndarray], boxes: Sequence[np.ndarray]) -> float:
    """Metres, seen from above, between the tool (its long axis, less its half width) at the least clear of
    ``poses`` (its poses, 4x4) and the nearest of ``boxes`` (world AABBs) rising above its lowest point there;
    1 m when none does."""
    half = scene.half(tool)
    along = np.linspace(-half.hx, half.hx, ON_THE_TOOL)
    nearest = 1.0
    for T in poses:
        points = T[:3, 3] + along[:, None] * T[:3, 0]
        low = float(points[:, 2].min() - np.abs(T[2, :3]) @ [0.0, half.hy, half.hz])
        for box in boxes:
            if box[1, 2] <= low:
                continue
            gap = np.maximum(np.maximum(box[0, :2] - points[:, :2], points[:, :2] - box[1, :2]), 0.0)
            nearest = min(nearest, float(np.hypot(gap[:, 0], gap[:, 1]).min()) - half.hy)
    return nearest
