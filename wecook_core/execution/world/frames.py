"""The TSR frame a skill's spec names, from what any :class:`~.protocols.Scene` says (written once, above the
scene: the PyBullet scene and the tests' fake answer the same geometry queries and share this logic)."""

from __future__ import annotations

import numpy as np

from wecook_core.execution.schedule.program import ActionFailed
from wecook_core.execution.skills.library import Half, TSRSpec
from wecook_core.execution.world.protocols import Roles, Scene


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
