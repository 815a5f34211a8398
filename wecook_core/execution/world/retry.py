"""The one retry policy of the primitives (:mod:`wecook_core.execution.world`): a primitive is tried up to
``attempts`` times; before each new attempt the other arm gets the chance to move out of the way (it may
have caused the failure) and a ``retry`` event says why; after the last, the primitive fails with the last
attempt's reason.

An attempt is a program (a generator) that returns ``None`` when the primitive is done, else the reason it failed
(a string), so the next attempt sees the world as it is now.
"""

from __future__ import annotations

from collections.abc import Callable, Generator

from wecook_core.execution.schedule.program import ActionFailed, Program, Tick
from wecook_core.execution.world.protocols import Arm, Scene
from wecook_core.plan import PlanAction

Attempt = Callable[[int], Generator[Tick, None, str | None]]
"""One attempt of a primitive (its number, from 0): a program returning None when done, else why it failed."""


def retrying(scene: Scene, arm: Arm, attempts: int, action: PlanAction | None, primitive: str, label: str,
             detail: str, attempt: Attempt, reason: str) -> Program:
    """Run ``attempt`` of ``arm``'s primitive until it succeeds, at most ``attempts`` times (``reason``: the
    failure when no attempt ran). Emits ``primitive_end`` (with ``detail``), a ``retry`` per new attempt and
    ``primitive_failed`` (the caller emits ``primitive_start``); raises :class:`ActionFailed`
    ``"<label>: <reason>"`` after the last."""
    for k in range(attempts):
        if k:
            yield from arm.let_other_move()
            scene.event("retry", action, arm.pid, f"{label}: attempt {k + 1} ({reason})", primitive)
        scene.sync()
        failed = yield from attempt(k)
        if failed is None:
            scene.event("primitive_end", action, arm.pid, detail, primitive)
            return
        reason = failed
    scene.event("primitive_failed", action, arm.pid, reason, primitive)
    raise ActionFailed(f"{label}: {reason}")
