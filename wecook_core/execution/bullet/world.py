"""The PyBullet world (:mod:`wecook_core.execution.world`) put together: a :class:`~.bullet_scene.BulletScene`,
a :class:`~.bullet_arm.BulletArm` per person sharing one :class:`~.traffic.Traffic`, the
:class:`~.primitives.Primitives` over them and the :class:`~.roles.RolePlayer` that turns actions into them."""

from __future__ import annotations

import numpy as np

from wecook_core.execution.bullet.arm import BulletArm
from wecook_core.execution.bullet.scene import BulletScene
from wecook_core.execution.bullet.traffic import Traffic
from wecook_core.execution.schedule.observer import FrameInfo, RunObserver
from wecook_core.execution.schedule.program import Meeting, Program
from wecook_core.execution.skills.library import SkillLibrary, load_skills
from wecook_core.execution.world.primitives import Primitives
from wecook_core.execution.world.protocols import Cell
from wecook_core.execution.world.roles import RolePlayer
from wecook_core.plan import Plan, PlanAction


class BulletWorld:
    """The executor's :class:`~wecook_core.execution.schedule.program.World` in PyBullet. ``primitives``: the class of
    the
    primitives the roles call (the tests put in one that records what it does)."""

    def __init__(self, plan: Plan, observer: RunObserver | None, *, seed: int = 0, realtime: bool = False,
                 planner: str = "rrtconnect", planning_time: float = 1.0, images: bool = True,
                 skills: SkillLibrary | None = None, attempts: int = 3, samples: int = 12,
                 primitives: type[Primitives] = Primitives, dynamics: bool = False):
        self.skills = skills or load_skills()
        self.scene = BulletScene(plan, observer, self.skills, realtime=realtime, images=images, dynamics=dynamics)
        self.traffic = Traffic(list(self.scene.robots), np.random.default_rng(seed), seed=seed, planner=planner,
                               planning_time=planning_time, attempts=attempts)
        self.scene.ended.append(self.traffic.primitive_over)
        self.arms = {pid: BulletArm(pid, self.scene, self.traffic) for pid in self.scene.robots}
        self.cell = Cell(self.scene, self.arms, self.skills, attempts, samples)
        self.primitives = primitives(self.cell)
        self.roles = RolePlayer(self.cell, self.primitives)

    @property
    def time(self) -> float:
        return self.scene.time

    @property
    def dt(self) -> float:
        return self.scene.dt

    @property
    def arm_contacts(self) -> int:
        return self.scene.arm_contacts

    def step(self) -> None:
        self.scene.step()

    def program(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        return self.roles.program(action, pid, meeting)

    def recover(self, pid: str) -> Program:
        return self.roles.recover(pid)

    def action_boundary(self, action: PlanAction, kind: str) -> None:
        self.scene.action_boundary(action, kind)

    def frames(self) -> list[FrameInfo]:
        return self.scene.frames()

    def publish_state(self) -> None:
        self.scene.publish_state()

    def close(self) -> None:
        self.scene.close()
