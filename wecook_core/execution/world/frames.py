"""The TSR frame a skill's spec names, from what any :class:`~.protocols.Scene` says (written once, above the
scene: the PyBullet scene and the tests' fake answer the same geometry queries and share this logic)."""

from __future__ import annotations

import math

import numpy as np

from wecook_core.execution.schedule.program import ActionFailed
from wecook_core.execution.skills.library import Half, TSRSpec
from wecook_core.execution.world.protocols import Roles, Scene

TILTED = math.cos(math.radians(5))
"""An object whose z axis leans more than 5 degrees from the vertical lies tilted (see :func:`levelled`)."""


def tilted(T: np.ndarray) -> bool:
    """Whether the frame ``T`` (4x4) leans: its z axis more than 5 degrees from the vertical."""
    return bool(T[2, 2] <= TILTED)


def levelled(T: np.ndarray) -> np.ndarray:
    """The frame ``T`` stood upright where it is: its origin kept, its z axis vertical, turned about z as ``T``
    lies (its x axis along the table, unless it stands up: then as its y axis lies)."""
    along = float(np.hypot(*T[:2, 0])) > 0.3
    x = T[:2, 0] if along else T[:2, 1]
    yaw = math.atan2(x[1], x[0]) - (0.0 if along else math.pi / 2)
    out = np.eye(4)
    out[:2, :2] = [[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]
    out[:3, 3] = T[:3, 3]
    return out


def skill_frame(scene: Scene, spec: TSRSpec, roles: Roles, pid: str, meet: tuple[str, str] | None = None
                ) -> tuple[np.ndarray, dict[str, Half]]:
    """The TSR frame (4x4) of ``spec`` for ``pid`` and the half-extent table for its expressions: the meeting
    point of ``meet`` (giver, receiver), the drop zone of ``pid``'s arm, or a role's object (``object:ROLE``:
    the object upright; ``facing:ROLE``: at the object, turned toward ``pid``'s base)."""
    sizes = {"t": scene.half(roles.get("tool")), "i": scene.half(roles.get("ingredient")),
             "l": scene.half(roles.get("location"))}
    if spec.frame == "meet":
        assert meet is not None
        return scene.meet(*meet), sizes
    if spec.frame == "drop":
        return scene.drop(pid), sizes
    kind, role = spec.frame.split(":", 1)
    name = roles.get(role)
    if name is None:
        raise ActionFailed(f"the skill needs a {role} and the action names none")
    sizes["f"] = scene.half(name)
    return (scene.upright(name) if kind == "object" else scene.facing(name, pid)), sizes
