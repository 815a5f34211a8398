"""The two small protocols the primitives and roles of the world (:mod:`wecook_core.execution.world`) are written
against: a :class:`Scene` (where things are, what each hand holds, stepping and events) and an :class:`Arm` (one
person's arm: goals, planned and straight moves, the gripper, going home). The PyBullet world implements them
(:mod:`.bullet_scene`, :mod:`.bullet_arm`); the tests implement them in plain Python.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from contextlib import AbstractContextManager
from dataclasses import dataclass, field
from functools import cached_property
from typing import Literal, Protocol

import numpy as np

from wecook_core.execution.schedule.program import Program
from wecook_core.execution.skills.library import Half, SkillLibrary
from wecook_core.execution.skills.tsr import TSR, matrix_to_pose
from wecook_core.model import Category
from wecook_core.plan import PlanAction

Accept = Callable[[np.ndarray], bool]
"""Takes a candidate ee pose (4x4, world) or not."""
Rank = Callable[[np.ndarray], float]
"""Orders candidate ee poses: the lowest is tried first."""
YIELD_SECONDS = 30.0
"""Simulated seconds an arm waits for the other to go home when the other arm blocked all its goals (or for the
other hand to let go of what it is to take)."""
Roles = dict[str, str | None]
"""Skill role (``tool``, ``ingredient``, ``location``, ``source``) -> the object playing it."""


@dataclass(frozen=True, eq=False)
class Riding:
    """An object carried by a hand: its name and the ee <- object transform (4x4)."""

    name: str
    T_ee_obj: np.ndarray

    @cached_property
    def local(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """``T_ee_obj`` as (position, quaternion xyzw)."""
        return matrix_to_pose(self.T_ee_obj)


@dataclass
class Hand:
    """What one arm holds now."""

    carried: str | None = None
    constraint: int | None = None
    """The scene's handle of the attachment of ``carried`` (None: nothing attached)."""
    riding: list[Riding] = field(default_factory=list)
    """What moves with the hand: the carried object first, then what lies in or on it."""
    grip: float = 0.04


class Scene(Protocol):
    """Where things are and what the hands hold; the clock and what the observer is told."""

    @property
    def time(self) -> float: ...

    @property
    def hz(self) -> int:
        """Steps per simulated second."""
        ...

    @property
    def table_height(self) -> float: ...

    def event(self, kind: str, action: PlanAction | None, pid: str | None, detail: str = "",
              primitive: str | None = None) -> None:
        """Tell the observer (``primitive_start`` / ``primitive_end`` / ``primitive_failed`` / ``retry``)."""
        ...

    def log(self, level: Literal["debug", "info", "warning", "error"], text: str) -> None: ...

    def hold(self, seconds: float) -> Program:
        """Let the simulation run ``seconds`` with the arms where they are (yields WORK)."""
        ...

    def sync(self) -> None:
        """Bring the planning copy of the world up to date (before a primitive's attempt)."""
        ...

    # -- where things are (queries: they change nothing)
    def names(self) -> list[str]: ...

    def pose(self, name: str) -> np.ndarray: ...

    def half(self, name: str | None) -> Half: ...

    def kind(self, name: str) -> str: ...

    def category(self, name: str) -> Category: ...

    def shape(self, name: str) -> str: ...

    def size(self, name: str) -> tuple[float, float, float]: ...

    def supports(self, name: str) -> list[str]:
        """The containers the plan says ``name`` lies in."""
        ...

    def container_of(self, name: str) -> str | None: ...

    def contents(self, name: str) -> list[str]: ...

    def boxes(self, names: Iterable[str]) -> list[np.ndarray]:
        """World AABBs (``[[x0, y0, z0], [x1, y1, z1]]``) of ``names``."""
        ...

    def base(self, pid: str) -> np.ndarray:
        """The base pose (4x4) of ``pid``'s arm."""
        ...

    def meet(self, giver: str, receiver: str) -> np.ndarray: ...

    def facing(self, name: str, pid: str) -> np.ndarray: ...

    def drop(self, pid: str) -> np.ndarray:
        """Where ``pid``'s arm puts things down out of the way (4x4, x toward the arm)."""
        ...

    def upright(self, name: str) -> np.ndarray:
        """The object's pose as a TSR frame (a sphere's only by its position)."""
        ...

    # -- hands
    def hand(self, pid: str) -> Hand: ...

    def holder_of(self, name: str, pid: str) -> str | None:
        """The other arm whose hand carries ``name`` (or has it riding), if any."""
        ...

    def picked_from(self, name: str) -> np.ndarray | None:
        """Its pose when last grasped."""
        ...

    def attach(self, pid: str, name: str) -> None:
        """``name`` is fixed to ``pid``'s hand where it is now (carried, riding first)."""
        ...

    def detach(self, pid: str) -> None:
        """Whatever ``pid``'s hand holds is let go (carried, attachment and riding cleared)."""
        ...

    def ride(self, pid: str, name: str, T_ee_obj: np.ndarray | None = None) -> None:
        """``name`` moves with ``pid``'s hand from now on (and with no other hand)."""
        ...

    def drop_riding(self, pid: str, names: Iterable[str]) -> None:
        """``names`` no longer move with ``pid``'s hand."""
        ...

    def collide_with_arm(self, pid: str, name: str, *, enabled: bool) -> None: ...

    def set_collisions(self, pairs: Sequence[tuple[str, str]], *, enabled: bool) -> None:
        """Collisions between each pair of objects on or off."""
        ...


class Arm(Protocol):
    """One person's arm."""

    pid: str

    def q(self) -> np.ndarray: ...

    def ee(self) -> np.ndarray: ...

    def set_grip(self, width: float) -> None:
        """Drive both fingers to ``width`` (metres each); goals and paths checked from now on have them there."""
        ...

    def close_on(self, name: str, width: float) -> tuple[float, float]:
        """Close each finger until it touches ``name`` (never into it; to ``width``, metres per finger, when
        nothing is there); returns each finger's opening."""
        ...

    def goal_samples(self, tsrs: Sequence[TSR], T_eff_ee: np.ndarray, n: int, accept: Accept | None = None,
                     rank: Rank | None = None, spin: bool = False) -> list[np.ndarray]:
        """Up to ``n`` ee poses drawn from ``tsrs`` (the effector at ``T_eff_ee`` from the ee) that ``accept``
        takes, lowest ``rank`` first; ``spin``: each turned by a random angle about the effector's z."""
        ...

    def ik_goal(self, targets: Iterable[np.ndarray], ignore: Sequence[str], check: bool = True
                ) -> tuple[np.ndarray, np.ndarray] | None:
        """The joints and pose of the first target reachable clear of everything but ``ignore`` (``check``:
        collisions checked at all); what blocked the others is kept for :meth:`no_goal`."""
        ...

    def no_goal(self, what: str, count: int, accept: Accept | None = None) -> str:
        """Why no goal was found among ``count`` samples, for a failure report (it also notes, for the next
        retry, whether the other arm was in the way, and forgets what blocked the goals)."""
        ...

    def clear_blockers(self) -> None:
        """Forget what blocked goals so far (a failure that was not about goals was reported)."""
        ...

    def away_from_other(self, near: np.ndarray) -> Rank | None: ...

    def transit(self, goal: np.ndarray, ignore: Sequence[str] = (), what: str = "move") -> Program:
        """A planned, collision-free move to the joints ``goal``; raises ``ActionFailed`` ("<what>: no path ...")."""
        ...

    def cartesian_path(self, q: np.ndarray, poses: Sequence[np.ndarray], ignore: Sequence[str] | None, what: str,
                       margin: float = -0.01) -> tuple[list[np.ndarray], list[float], list[int]]:
        """The joint path of straight effector moves from ``q`` through ``poses``, each segment's duration and the
        index ending each move; raises ``ActionFailed`` when it is out of reach, ``PathBlocked`` (an
        ``ActionFailed``) when it collides (noting, for the next retry, whether the other arm was in the way).
        Moves nothing."""
        ...

    def linear(self, poses: Sequence[np.ndarray], ignore: Sequence[str] | None = None,
               holds: Sequence[float] | None = None, fingers: Sequence[float | None] | None = None,
               what: str = "straight move", margin: float = -0.01,
               reached: Callable[[int], None] | None = None) -> Program:
        """Follow :meth:`cartesian_path` from where the arm is: at each pose ``j``, call ``reached(j)``, set the
        fingers to ``fingers[j]``, stay ``holds[j]`` seconds."""
        ...

    def let_other_move(self, limit: float = 4.0) -> Program:
        """Before a retry: give the other arm the chance to get out of the way."""
        ...

    def park(self, what: str = "move to rest") -> Program:
        """A planned move to the rest pose, once."""
        ...

    def home(self) -> Program:
        """Back to the rest pose (retried), then out of the other arm's way while it has the right of way."""
        ...

    def margin_to_other(self, metres: float) -> AbstractContextManager[None]:
        """A context in which plans keep only ``metres`` from the other arm."""
        ...

    def forget_motion(self) -> None:
        """Drop the region a failed motion reserved."""
        ...


@dataclass
class Cell:
    """What primitives and roles work with: the scene, the arms by person, the skills and the retry budget."""

    scene: Scene
    arms: Mapping[str, Arm]
    skills: SkillLibrary
    attempts: int = 3
    """Rounds of samples a primitive is tried with."""
    samples: int = 12
    """TSR samples per round."""
