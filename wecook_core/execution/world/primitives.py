"""The primitives of the world (:mod:`wecook_core.execution.world`) for the roles to call: grasp and release
(:mod:`.grasping`), engage and actuate (:mod:`.actuating`), place (:mod:`.placing`), each a program over a
:class:`~.protocols.Cell` (a scene and its arms). Every primitive is tried again with new samples by one retry
policy (:mod:`.retry`): up to ``attempts`` rounds of ``samples`` samples; then it fails with its reason.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from wecook_core.execution.schedule.program import Program
from wecook_core.execution.skills.library import Step, TSRSpec
from wecook_core.execution.skills.tsr import TSR
from wecook_core.execution.world import actuating, grasping, placing
from wecook_core.execution.world.actuating import Missed
from wecook_core.execution.world.protocols import Accept, Cell, Rank, Roles
from wecook_core.plan import PlanAction

__all__ = ["Missed", "Primitives"]


class Primitives:
    """The primitives of the arms of ``cell``; remembers, per arm, the axis option and margin the last engage
    chose for the actuation that follows it."""

    def __init__(self, cell: Cell):
        self.cell = cell
        self.variants: dict[str, int] = {}
        self.margins: dict[str, float] = {}

    def grasp_tsrs(self, name: str, pid: str, kinds: Sequence[str] | None = None, flip: bool = False) -> list[TSR]:
        return grasping.grasp_tsrs(self.cell, name, pid, kinds, flip)

    def grasp(self, action: PlanAction, pid: str, name: str, *, lift: bool = True, ignore_extra: Sequence[str] = (),
              tsrs: list[TSR] | None = None, accept: Accept | None = None, rank: Rank | None = None,
              primitive: str = "grasp") -> Program:
        return grasping.grasp(self.cell, action, pid, name, lift=lift, ignore_extra=ignore_extra, tsrs=tsrs,
                              accept=accept, rank=rank, primitive=primitive)

    def release(self, pid: str, retreat: bool = True) -> Program:
        return grasping.release(self.cell, pid, retreat)

    def place(self, action: PlanAction | None, pid: str, target: np.ndarray | list[TSR], free: bool = False
              ) -> Program:
        return placing.place(self.cell, action, pid, target, free)

    def engage(self, action: PlanAction, pid: str, spec: TSRSpec, roles: Roles, meet: tuple[str, str] | None = None,
               accept: Accept | None = None, then: Step | None = None) -> Program:
        def chose(variant: int, margin: float) -> None:
            self.variants[pid] = variant
            self.margins[pid] = margin

        return actuating.engage(self.cell, action, pid, spec, roles, meet, accept, then, chose)

    def actuate(self, action: PlanAction, pid: str, step: Step, roles: Roles) -> Program:
        return actuating.actuate(self.cell, action, pid, step, roles, self.variants.get(pid, 0),
                                 self.margins.get(pid, actuating.GRAZE_MARGIN))
