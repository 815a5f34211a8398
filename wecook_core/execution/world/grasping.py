"""Grasping and letting go (a layer of the PyBullet world, :mod:`wecook_core.execution.world`): the grasp TSRs
of an object's kind, the grasp (pre-grasp, straight approach, close, attach, lift) and the release."""

from __future__ import annotations

import contextlib
from collections.abc import Generator, Sequence

import numpy as np

from wecook_core.execution.planning_scene import Riding
from wecook_core.execution.program import WAIT, ActionFailed, Program, Tick
from wecook_core.execution.robot import attach, detach
from wecook_core.execution.scene import SIM_HZ
from wecook_core.execution.skills import evaluate
from wecook_core.execution.tsr import TSR
from wecook_core.execution.world.moves import YIELD_SECONDS, Accept, ArmMotion, Rank
from wecook_core.execution.world.retry import retrying
from wecook_core.plan import PlanAction

APPROACH_OPENING = 0.008
"""Metres per finger beyond the grip width the fingers open to approach an object."""


class Grasping(ArmMotion):
    def _grasp_tsrs(self, name: str, pid: str, kinds: Sequence[str] | None = None,
                    flip: bool = False) -> list[TSR]:
        out = []
        for kind in kinds or [self._kind(name)]:
            for spec in self.skills.grasps[kind]:
                T0_w, sizes = self.frame(spec, {"object": name}, pid)
                if spec.frame.startswith("object") and flip:
                    T0_w = T0_w @ np.diag([-1.0, -1.0, 1.0, 1.0])
                sizes["f"] = self.half(name)
                out.append(spec.tsr(T0_w, sizes))
                if flip and spec.frame.startswith("object"):
                    out.append(spec.tsr(self.pose(name), sizes))
        return out

    def grasp(self, action: PlanAction, pid: str, name: str, *, lift: bool = True, ignore_extra: Sequence[str] = (),
              tsrs: list[TSR] | None = None, accept: Accept | None = None, rank: Rank | None = None,
              primitive: str = "grasp") -> Program:
        """Pre-grasp (planned), straight approach, close, attach, lift (straight up)."""
        self._event("primitive_start", action, pid, name, primitive)
        body = self.bodies.objects[name]
        holder = self._holder_of(name, pid)
        if holder is not None and primitive != "take":  # in the other hand: wait until it is let go
            for _ in range(int(YIELD_SECONDS * SIM_HZ)):
                if self._holder_of(name, pid) is None:
                    break
                yield WAIT
            else:
                raise ActionFailed(f"{primitive} {name}: {holder} kept holding it")
        kind = self._kind(name)
        regions = tsrs or self._grasp_tsrs(name, pid)
        grip = min(max(evaluate(self.skills.grip[kind], {"f": self.half(name)}), 0.0), 0.04)
        self._set_grip(pid, min(grip + APPROACH_OPENING, 0.04))  # open just enough: neighbours stay clear
        # never its own obstacle: the object, what it lies in and what lies in it (that rides along) are touched
        support = [c for n, c in self.plan.scene.containing if n == name]
        own = [name, *(self._contents(name) if primitive != "hold" else ())]  # a holding hand keeps off the food
        ignore = [*own, *support, *ignore_extra]
        near = [*own, *ignore_extra]  # the pre-grasp may touch what it is about to take, never its neighbours
        approach = self.skills.approach_distance

        def attempt(_k: int) -> Generator[Tick, None, str | None]:
            candidates = self._goal_samples(regions, np.eye(4), self.samples, accept, rank)
            pre_goal = None
            blocked = None
            for G in candidates:
                found = self._ik_goal(pid, [G], ignore)
                if found is None:
                    continue
                pre = G.copy()
                pre[:3, 3] -= G[:3, 2] * approach
                found_pre = self._ik_goal(pid, [pre], near)
                if found_pre is None:
                    continue
                try:  # the straight approach (and the lift) must be feasible from there
                    moves = [G, G @ _lifted(self.skills.lift, G)] if lift else [G]
                    self.cartesian_path(pid, found_pre[0], moves, ignore, f"approach {name}")
                except ActionFailed as error:
                    blocked = str(error)
                    continue
                pre_goal = (found_pre[0], pre, G)
                break
            if pre_goal is None:
                return blocked or self._no_goal(f"grasp of {name}", len(candidates), accept)
            try:
                yield from self.transit(pid, pre_goal[0], near, what=f"{primitive} {name}")
                # the fingers close into the object without pushing it about: the constraint will hold it
                self._collide_with_arm(pid, name, enabled=False)
                yield from self.linear(pid, [pre_goal[2]], ignore=ignore, what=f"approach {name}")
            except ActionFailed as error:
                self._collide_with_arm(pid, name, enabled=True)
                return str(error)
            self._set_grip(pid, grip)
            yield from self._hold(0.2)
            self.picked_from[name] = self.pose(name)
            constraint, T_ee_obj = attach(self.client, self.bodies.arms[pid].body, body.body)
            hand = self.hands[pid]
            hand.carried, hand.constraint = name, constraint
            hand.riding = [Riding(name, T_ee_obj)]
            for content in self._contents(name):  # what lies in a container moves with it
                self._ride(pid, content)
            if lift:
                up = self.arms[pid].ee()
                up[2, 3] += self.skills.lift
                try:
                    yield from self.linear(pid, [up], ignore=[*ignore], what=f"lift {name}")
                except ActionFailed as error:  # let go, back off, try another grasp
                    yield from self.release(pid)
                    return str(error)
            return None

        yield from retrying(self, action, pid, primitive, f"{primitive} {name}", name, attempt,
                            "no reachable collision-free grasp")

    def release(self, pid: str, retreat: bool = True) -> Program:
        """Open, detach, move straight back along the approach."""
        hand = self.hands[pid]
        name = hand.carried
        self._set_grip(pid, 0.04)
        if hand.constraint is not None:
            detach(self.client, hand.constraint)
        for r in hand.riding[1:]:
            self._collide_with_arm(pid, r.name, enabled=True)
        hand.carried, hand.constraint, hand.riding = None, None, []
        yield from self._hold(0.15)
        if retreat:
            back = self.arms[pid].ee()
            back[:3, 3] -= back[:3, 2] * self.skills.approach_distance
            with contextlib.suppress(ActionFailed):
                yield from self.linear(pid, [back], ignore=[name] if name else [], what="retreat")
        if name is not None:
            self._collide_with_arm(pid, name, enabled=True)



def _lifted(height: float, T: np.ndarray) -> np.ndarray:
    """The transform that, right-multiplied onto ``T``, raises it by ``height`` along world z."""
    up = np.eye(4)
    up[:3, 3] = T[:3, :3].T @ np.array([0.0, 0.0, height])
    return up

