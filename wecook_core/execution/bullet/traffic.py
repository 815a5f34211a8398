"""What the two arms of the PyBullet world (:mod:`wecook_core.execution.world`) share: the random generator, the
planner's settings and budget, and how they keep out of each other's way (see :mod:`.bullet_arm`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wecook_core.execution.bullet.planning_scene import ARM_MARGIN


@dataclass
class Traffic:
    """What the two arms share: the random generator, the planner's settings and budget, and how they keep out
    of each other's way (reservations, right of way, the margin kept between them)."""

    pids: list[str]
    rng: np.random.Generator
    seed: int = 0
    planner: str = "rrtconnect"
    planning_time: float = 1.0
    attempts: int = 3
    queries: int = 0
    arm_margin: float = ARM_MARGIN
    """Metres kept between the arms when planning (lowered while the receiver of a handover takes)."""
    goal_blockers: set[str] = field(default_factory=set)
    """What blocked the goal candidates since the last failure report."""
    other_in_the_way: bool = False
    """The other arm blocked the last goals or straight path (the next retry waits for it to go home)."""
    right_of_way: str | None = None
    """An arm the other one blocked: the other waits at rest until this arm's primitive ends."""
    reserved: dict[str, np.ndarray | None] = field(default_factory=dict)
    """Arm -> the region its running motion swept (None: none)."""
    moved_at: dict[str, float] = field(default_factory=dict)
    """Simulated time each arm last moved."""

    def other(self, pid: str) -> str | None:
        return next((k for k in self.pids if k != pid), None)

    def primitive_over(self, pid: str) -> None:
        if pid == self.right_of_way:
            self.right_of_way = None
