"""The one retry policy of the primitives (:mod:`wecook_core.execution.world`): a primitive is tried up to
``world.attempts`` times; before each new attempt the other arm gets the chance to move out of the way (it may
have caused the failure) and a ``retry`` event says why; after the last, the primitive fails with the last
attempt's reason.

An attempt is a program (a generator) that returns ``None`` when the primitive is done, else the reason it failed
(a string), so the next attempt sees the world as it is now.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import TYPE_CHECKING

from wecook_core.execution.program import ActionFailed, Program, Tick
from wecook_core.plan import PlanAction

if TYPE_CHECKING:
    from wecook_core.execution.world.moves import ArmMotion

Attempt = Callable[[int], Generator[Tick, None, str | None]]
"""One attempt of a primitive (its number, from 0): a program returning None when done, else why it failed."""


def retrying(world: ArmMotion, action: PlanAction | None, pid: str, primitive: str, label: str, detail: str,
             attempt: Attempt, reason: str) -> Program:
    """Run ``attempt`` until it succeeds, at most ``world.attempts`` times (``reason``: the failure when no attempt
    ran). Emits ``primitive_end`` (with ``detail``), a ``retry`` per new attempt and ``primitive_failed``
    (the caller emits ``primitive_start``); raises :class:`ActionFailed` ``"<label>: <reason>"`` after the last."""
    for k in range(world.attempts):
        if k:
            yield from world._let_other_move(pid)
            world._event("retry", action, pid, f"{label}: attempt {k + 1} ({reason})", primitive)
        world._sync()
        failed = yield from attempt(k)
        if failed is None:
            world._event("primitive_end", action, pid, detail, primitive)
            return
        reason = failed
    world._event("primitive_failed", action, pid, reason, primitive)
    raise ActionFailed(f"{label}: {reason}")
