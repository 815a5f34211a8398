"""The PyBullet adapter of the motion planner: collision functions in a second client kept apart from the
simulating one (collision checking moves joints), synced from it before each query.

A configuration of arm ``pid`` is in collision when, with the arm at ``q`` and every object riding on its hand
placed by its grasp transform, a contact closer than the margin joins: the arm or a riding object with the
table, the other arm, or an object (objects named in ``ignore`` excepted: the one being grasped, a container
the tool works in); or two links of the arm that are not an allowed pair (pairs touching at the home
configuration, and the fingers, are allowed).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping, Sequence

import numpy as np
import pybullet as p

from wecook_core.execution.bullet.bodies import SceneBodies, build_scene
from wecook_core.execution.bullet.robot import ARM_JOINTS, EE_LINK, FINGER_JOINTS, HOME, Panda
from wecook_core.execution.planning.motion import CollisionFn
from wecook_core.execution.world.protocols import Riding
from wecook_core.plan import Plan

ARM_MARGIN = 0.02
"""Metres kept between the two arms (and what they carry) when planning."""


class PlanningScene:
    """The planning client: the same bodies as the simulating client (same plan, same build order)."""

    def __init__(self, plan: Plan):
        self.client = p.connect(p.DIRECT)
        self.bodies: SceneBodies = build_scene(self.client, plan, self_collision=True)
        self.arms = {pid: Panda(self.client, arm.body) for pid, arm in self.bodies.arms.items()}
        self.riding: dict[str, tuple[Riding, ...]] = {pid: () for pid in self.arms}
        self.allowed_self: set[tuple[int, int]] = set()
        for arm in self.arms.values():
            arm.set_q(HOME, 0.04)
        p.performCollisionDetection(physicsClientId=self.client)
        for arm in self.arms.values():
            for c in p.getContactPoints(arm.body, arm.body, physicsClientId=self.client):
                self.allowed_self.add((min(c[3], c[4]), max(c[3], c[4])))
        self.allowed_self |= {(FINGER_JOINTS[0], FINGER_JOINTS[1])}

    def close(self) -> None:
        if p.isConnected(self.client):
            p.disconnect(self.client)

    def sync(self, sim: SceneBodies, riding: Mapping[str, Sequence[Riding]]) -> None:
        """Copy the simulating client's arm joints and object poses; remember what each hand carries."""
        for pid, arm in sim.arms.items():
            states = p.getJointStates(arm.body, [*ARM_JOINTS, *FINGER_JOINTS], physicsClientId=sim.client)
            self.arms[pid].set_q(np.array([s[0] for s in states[:7]]), states[7][0])
            self.arms[pid].set_fingers((states[7][0], states[8][0]))
        for name, body in sim.objects.items():
            pos, orn = p.getBasePositionAndOrientation(body.body, physicsClientId=sim.client)
            p.resetBasePositionAndOrientation(self.bodies.objects[name].body, pos, orn, physicsClientId=self.client)
        self.riding = {pid: tuple(riding.get(pid, ())) for pid in self.arms}

    def _place_riding(self, pid: str) -> None:
        if not self.riding[pid]:
            return
        state = p.getLinkState(self.arms[pid].body, EE_LINK, computeForwardKinematics=True, physicsClientId=self.client)
        for r in self.riding[pid]:
            pos, orn = p.multiplyTransforms(state[4], state[5], *r.local)
            p.resetBasePositionAndOrientation(self.bodies.objects[r.name].body, pos, orn, physicsClientId=self.client)

    def collision_fn(self, pid: str, *, ignore: Iterable[str] = (), margin: float = 0.0,
                     arm_margin: float = ARM_MARGIN) -> CollisionFn:
        """``q -> True`` when arm ``pid`` at ``q`` collides (see the module docstring)."""
        c = self.client
        arm = self.arms[pid]
        other_arms = {a.body for k, a in self.arms.items() if k != pid}
        riding_bodies = {self.bodies.objects[r.name].body for r in self.riding[pid]}
        ignored = {self.bodies.objects[n].body for n in ignore} | riding_bodies
        allowed_self = self.allowed_self
        riding = self.riding[pid]

        def blocked(contacts: Sequence[tuple], own: set[int]) -> bool:
            for contact in contacts:
                other, distance = contact[2], contact[8]
                if other in own:
                    continue
                if other == arm.body:
                    if (min(contact[3], contact[4]), max(contact[3], contact[4])) in allowed_self:
                        continue
                    if distance < 0.0:
                        return True
                    continue
                if other in ignored:
                    continue
                if distance < (arm_margin if other in other_arms else margin):
                    return True
            return False

        def collides(q: np.ndarray) -> bool:
            arm.set_q(q)
            self._place_riding(pid)
            p.performCollisionDetection(physicsClientId=c)
            if blocked(p.getContactPoints(bodyA=arm.body, physicsClientId=c), set()):
                return True
            for body in riding_bodies:
                if blocked(p.getContactPoints(bodyA=body, physicsClientId=c), riding_bodies | {arm.body}):
                    return True
            return False

        del riding
        return collides

    def swept_boxes(self, pid: str, path: Sequence[np.ndarray], step: float = 0.04,
                    pad: float = 0.03) -> np.ndarray:
        """World AABBs ``(n, 2, 3)`` of the arm's links and riding objects along ``path`` (states ``step`` radians
        apart), grown by ``pad`` metres: the region the motion sweeps, reserved while it runs."""
        c = self.client
        arm = self.arms[pid]
        bodies = [self.bodies.objects[r.name].body for r in self.riding[pid]]
        boxes: list[tuple] = []
        states: list[np.ndarray] = [path[0]]
        for a, b in itertools.pairwise(path):
            n = max(int(np.ceil(np.linalg.norm(b - a) / step)), 1)
            states += [a + (b - a) * (k / n) for k in range(1, n + 1)]
        for q in states:
            arm.set_q(q)
            self._place_riding(pid)
            boxes += [p.getAABB(arm.body, link, physicsClientId=c) for link in range(2, EE_LINK)]
            boxes += [p.getAABB(body, physicsClientId=c) for body in bodies]
        out = np.array(boxes, dtype=float)
        out[:, 0] -= pad
        out[:, 1] += pad
        return out


def boxes_overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """True when any AABB of ``a`` ``(n, 2, 3)`` overlaps any of ``b`` ``(m, 2, 3)``."""
    if len(a) == 0 or len(b) == 0:
        return False
    if np.any(a[:, 0].min(axis=0) >= b[:, 1].max(axis=0)) or np.any(b[:, 0].min(axis=0) >= a[:, 1].max(axis=0)):
        return False
    lo = np.maximum(a[:, None, 0, :], b[None, :, 0, :])
    hi = np.minimum(a[:, None, 1, :], b[None, :, 1, :])
    return bool(np.any(np.all(lo < hi, axis=-1)))
