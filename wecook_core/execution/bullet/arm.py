"""An arm of the PyBullet world (:mod:`wecook_core.execution.world`), a :class:`~.protocols.Arm`: goals (TSR
samples through re-seeded IK, checked in the planning client, and why none was found), planned transits (the
motion planner, time-limited), straight effector moves (IK along the line, checked against the other arm and the
table), and sharing the table with the other arm (:class:`~.traffic.Traffic`): every motion reserves the region
it sweeps, and an arm the other one blocked gets the right of way.
"""

from __future__ import annotations

import contextlib
import itertools
import math
from collections.abc import Callable, Iterable, Iterator, Sequence

import numpy as np
import pybullet as p
from scipy.spatial.transform import Rotation, Slerp

from wecook_core.execution.bullet.bodies import SIM_HZ
from wecook_core.execution.bullet.planning_scene import ARM_MARGIN, boxes_overlap
from wecook_core.execution.bullet.robot import (
    FINGER_JOINTS,
    FINGER_OPEN,
    HOME,
    LOWER,
    MAX_ACCEL,
    MAX_SPEED,
    REST,
    UPPER,
)
from wecook_core.execution.bullet.scene import BulletScene
from wecook_core.execution.bullet.traffic import Traffic
from wecook_core.execution.planning.motion import MotionProblem, path_free, plan_motion
from wecook_core.execution.planning.timing import timed_path
from wecook_core.execution.schedule.program import WORK, ActionFailed, PathBlocked, Program, waiting
from wecook_core.execution.skills.tsr import TSR, sample, xyzrpy_to_matrix
from wecook_core.execution.world.protocols import YIELD_SECONDS, Accept, Rank

JOINT_SPEED = 0.45
"""Fraction of the joint speed limits used by planned motions."""
LINEAR_SPEED = 0.12
"""Metres per second of straight moves and actuations."""
TURN_SPEED = 1.2
"""Radians per second of the effector's rotation in straight moves and actuations."""
TOUCH = 2e-4
"""Metres: a finger this close to what it grips touches it."""
CROWDED = 0.35
"""Metres: when the other arm's hand is this close to where a pose is sought, the poses farthest from it come
first."""


class BulletArm:
    """The arm of person ``pid`` in a :class:`BulletScene`."""

    def __init__(self, pid: str, scene: BulletScene, traffic: Traffic):
        self.pid = pid
        self.scene = scene
        self.traffic = traffic
        self.planning = scene.planning
        self.robot = scene.robots[pid]
        traffic.reserved.setdefault(pid, None)
        traffic.moved_at.setdefault(pid, 0.0)

    def q(self) -> np.ndarray:
        return self.robot.q()

    def ee(self) -> np.ndarray:
        return self.robot.ee()

    def set_grip(self, width: float) -> None:
        """Drive both fingers to ``width``; the planning copy has them there at once (what is planned from now on
        is for when they are)."""
        self.scene.set_grip(self.pid, width)
        self.planning.arms[self.pid].set_fingers((width, width))

    def close_on(self, name: str, width: float) -> tuple[float, float]:
        """Each finger closed until it touches ``name`` (found in the planning client: the finger moved by its
        gap to the object until the gap is under :data:`TOUCH`), never into it; a finger with nothing within
        5 cm closes to ``width``. The fingers are driven there; returns each one's opening (metres)."""
        self.scene.sync()
        c = self.planning.client
        arm = self.planning.arms[self.pid]
        body = self.planning.bodies.objects[name].body
        openings = list(arm.finger_pair())
        for k, joint in enumerate(FINGER_JOINTS):  # a finger's link has its joint's index
            opening = openings[k]
            for _ in range(10):
                p.resetJointState(arm.body, joint, opening, physicsClientId=c)
                points = p.getClosestPoints(arm.body, body, 0.05, linkIndexA=joint, physicsClientId=c)
                if not points:
                    opening = width
                    break
                gap = min(x[8] for x in points)
                if abs(gap) < TOUCH:
                    break
                opening = min(max(opening - gap, 0.0), FINGER_OPEN)  # the gap is at most along the finger's axis
            openings[k] = opening
        pair = (openings[0], openings[1])
        self.scene.set_fingers(self.pid, pair, grips=True)
        self.scene.log("info", f"{self.pid} grips {name}: {1000 * (pair[0] + pair[1]):.1f} mm between the fingers "
                               f"(finger 1 {1000 * pair[0]:.1f} mm, finger 2 {1000 * pair[1]:.1f} mm open)")
        return pair

    def clear_blockers(self) -> None:
        self.traffic.goal_blockers = set()

    @contextlib.contextmanager
    def margin_to_other(self, metres: float) -> Iterator[None]:
        self.traffic.arm_margin = metres
        try:
            yield
        finally:
            self.traffic.arm_margin = ARM_MARGIN

    def forget_motion(self) -> None:
        self.traffic.reserved[self.pid] = None

    # ------------------------------------------------------------------------------- goals

    def _planning_seed(self) -> int:
        self.traffic.queries += 1
        return (self.traffic.seed * 1_000_003 + self.traffic.queries * 7919) % (2**31 - 2)

    def ik_goal(self, targets: Iterable[np.ndarray], ignore: Sequence[str],
                 check: bool = True) -> tuple[np.ndarray, np.ndarray] | None:
        """First target (ee pose) with a collision-free IK solution: (q, pose). Each target is tried from the
        current joints, from home and from two random seeds (IK finds one of several arm postures)."""
        arm = self.planning.arms[self.pid]
        collides = self.planning.collision_fn(self.pid, ignore=ignore, arm_margin=self.traffic.arm_margin)
        current = self.robot.q()
        for T in targets:
            rng = self.traffic.rng
            for seed_q in (HOME, current, rng.uniform(LOWER, UPPER), rng.uniform(LOWER, UPPER)):
                q = arm.ik(T, self.traffic.rng, seed_q, restarts=0)
                if q is None:
                    continue
                if not (check and collides(q)):
                    return q, T
                self.traffic.goal_blockers.update(self._in_the_way(ignore))
        return None

    def _in_the_way(self, ignore: Iterable[str] = ()) -> set[str]:
        """What the planning client's arm ``self.pid`` (as last checked) penetrates: object names, ``table``, an arm;
        never what the check ignored (the object the hand takes, which it may touch), nor what the hand carries."""
        c = self.planning.client
        names = {b.body: n for n, b in self.planning.bodies.objects.items()}
        names[self.planning.bodies.table] = "table"
        names.update({a.body: f"arm {k}" for k, a in self.planning.arms.items() if k != self.pid})
        own = {r.name for r in self.scene.hands[self.pid].riding} | set(ignore)
        body = self.planning.arms[self.pid].body
        links = self.scene.bodies.arms[self.pid].links
        contacts = p.getContactPoints(bodyA=body, physicsClientId=c)
        out = {f"{names[x[2]]} ({links[x[3] + 1]})" if names[x[2]] == "table" else names[x[2]]
               for x in contacts if x[8] < 0.0 and x[2] in names and names[x[2]] not in own}
        for r in self.scene.hands[self.pid].riding:
            carried = self.planning.bodies.objects[r.name].body
            out |= {f"{names[x[2]]} (touched by the {r.name})"
                    for x in p.getContactPoints(bodyA=carried, physicsClientId=c)
                    if x[8] < 0.0 and x[2] in names and names[x[2]] not in own}
        out |= {f"its own {links[x[3] + 1]} and {links[x[4] + 1]}" for x in contacts
                if x[2] == body and x[8] < 0.0 and (min(x[3], x[4]), max(x[3], x[4])) not in self.planning.allowed_self}
        return out

    def no_goal(self, what: str, count: int, accept: Accept | None = None) -> str:
        """Why no goal was found among ``count`` samples (what was in the way), for a failure report."""
        if count == 0 and accept is not None:  # the role's own condition ruled every sample out
            return f"no {what} {(accept.__doc__ or 'that the role accepts').strip()} among the TSR's samples"
        blockers = sorted(self.traffic.goal_blockers)
        self.traffic.other_in_the_way = any(b.startswith("arm ") for b in blockers)
        self.traffic.goal_blockers = set()
        if blockers:
            return f"no collision-free {what} in {count} TSR samples (in the way: {', '.join(blockers)})"
        return f"no reachable {what} in {count} TSR samples"

    def goal_samples(self, tsrs: Sequence[TSR], T_eff_ee: np.ndarray, n: int, accept: Accept | None = None,
                      rank: Rank | None = None, spin: bool = False) -> list[np.ndarray]:
        """Up to ``n`` ee poses drawn from ``tsrs`` (the effector at ``T_eff_ee`` from the ee) that ``accept``
        takes, lowest ``rank`` first (else in the order drawn). ``spin``: the effector looks the same turned
        about its own z (a carried bowl or bottle), so each sample is turned by a random angle about it: the
        hand may hold it from any side."""
        out: list[np.ndarray] = []
        for _ in range(n * 12):
            if len(out) >= n:
                break
            region = tsrs[int(self.traffic.rng.integers(len(tsrs)))]
            T = sample(region, self.traffic.rng)
            if spin:
                T = T @ xyzrpy_to_matrix([0, 0, 0, 0, 0, self.traffic.rng.uniform(-math.pi, math.pi)])
            T = T @ T_eff_ee
            if accept is None or accept(T):
                out.append(T)
        return sorted(out, key=rank) if rank is not None else out

    def away_from_other(self, near: np.ndarray) -> Rank | None:
        """Farthest from the other arm's hand first, when that hand is within :data:`CROWDED` of ``near`` (a world
        point): the two arms work at one object, so the pose with the most room between them is tried first."""
        other = self.traffic.other(self.pid)
        if other is None:
            return None
        hand = self.scene.robots[other].ee()[:3, 3]
        if np.linalg.norm(hand - near) > CROWDED:
            return None
        return lambda T: -float(np.linalg.norm(T[:3, 3] - hand))

    # ------------------------------------------------------------------------------- paths

    def _plan(self, goal: np.ndarray, ignore: Sequence[str]) -> list[np.ndarray] | str:
        self.scene.sync()
        start = self.robot.q()
        traffic = self.traffic
        problem = MotionProblem(start=start, goal=goal, lower=LOWER, upper=UPPER,
                                collision_fn=self.planning.collision_fn(self.pid, ignore=ignore,
                                                                        arm_margin=traffic.arm_margin),
                                resolution=0.03)
        result = plan_motion(problem, planner=traffic.planner, time_limit=traffic.planning_time,
                             seed=self._planning_seed())
        everything = list(self.scene.bodies.objects)
        if result.status == "invalid_start":  # touching an object it just let go of, or closer to the other arm
            # than the margin (after a handover): plan without objects and margins, never through the arm or table
            loose = MotionProblem(start=start, goal=goal, lower=LOWER, upper=UPPER, resolution=0.03,
                                  collision_fn=self.planning.collision_fn(self.pid, ignore=everything,
                                                                          arm_margin=0.0))
            result = plan_motion(loose, planner=self.traffic.planner, time_limit=self.traffic.planning_time,
                                 seed=self._planning_seed())
        if not result.ok:
            if result.status in ("invalid_start", "invalid_goal"):
                q = start if result.status == "invalid_start" else goal
                self.planning.collision_fn(self.pid, ignore=everything, arm_margin=traffic.arm_margin)(q)
                blockers = sorted(self._in_the_way(ignore))
                if blockers:
                    return f"{result.status.replace('_', ' ')}: touching {', '.join(blockers)}"
            return result.status
        return list(result.path)

    def _follow(self, path: Sequence[np.ndarray], durations: Sequence[float] | None = None) -> Program:
        """Move along joint waypoints, from rest to rest, within the joints' velocity and acceleration limits
        (:func:`~wecook_core.execution.planning.timing.timed_path`) and never faster than ``durations[k]``
        seconds for segment k (default: :data:`JOINT_SPEED` of the speed limits)."""
        if durations is None:
            durations = [float(np.max(np.abs(b - a) / (MAX_SPEED * JOINT_SPEED))) for a, b in itertools.pairwise(path)]
        for q in timed_path(path, durations, MAX_SPEED, MAX_ACCEL, SIM_HZ):
            self.scene.commands[self.pid] = q
            self.traffic.moved_at[self.pid] = self.scene.time
            yield WORK

    def _reserve(self, path: Sequence[np.ndarray]) -> Program:
        """Wait until the swept region of ``path`` is clear of the other arm's moving region, then hold it."""
        self.scene.sync()
        boxes = self.planning.swept_boxes(self.pid, path)
        other = self.traffic.other(self.pid)
        waited = 0
        while other is not None and self.traffic.reserved[other] is not None:
            theirs = self.traffic.reserved[other]
            if not boxes_overlap(boxes, theirs):  # type: ignore[arg-type]
                break
            tick = waiting(f"the other arm's region ({other}'s motion crosses this one's path)")
            while self.traffic.reserved[other] is theirs:  # the same motion still runs
                waited += 1
                yield tick
        self.traffic.reserved[self.pid] = boxes
        if waited:
            raise _Replan()

    def transit(self, goal: np.ndarray, ignore: Sequence[str] = (), what: str = "move") -> Program:
        """A planned, collision-free move to joint goal ``goal`` (re-planned if the other arm was in the way)."""
        escaped = False
        for _ in range(20):
            path = self._plan(goal, ignore)
            if isinstance(path, str) and path.startswith("invalid start: touching") and "arm " not in path \
                    and not escaped:  # resting on the table or an object: straight up out of contact first
                escaped = True
                up = self.robot.ee()
                up[2, 3] += 0.06
                with contextlib.suppress(ActionFailed):
                    yield from self.linear([up], ignore=None, what="lift clear", margin=-0.03)
                continue
            if isinstance(path, str):
                raise ActionFailed(f"{what}: no path ({path})" if "touching" in path
                                   else f"{what}: no path ({path} after {self.traffic.planning_time:.1f} s)")
            try:
                yield from self._reserve(path)
            except _Replan:
                self.traffic.reserved[self.pid] = None
                continue
            try:
                yield from self._follow(path)
            finally:
                self.traffic.reserved[self.pid] = None
            return
        raise ActionFailed(f"{what}: the other arm kept the way blocked")

    def cartesian_path(self, q: np.ndarray, poses: Sequence[np.ndarray], ignore: Sequence[str] | None,
                       what: str, margin: float = -0.01) -> tuple[list[np.ndarray], list[float], list[int]]:
        """Joint path of straight effector moves from ``q`` through ee ``poses`` (IK on each step, densified to
        1 cm / 0.1 rad), checked against the other arm and the table (objects in ``ignore``, or every object
        when None, are skipped). Returns the path, each segment's duration and the index ending each move;
        raises :class:`ActionFailed`. Moves the planning client's joints only."""
        arm = self.planning.arms[self.pid]
        names = list(self.scene.bodies.objects) if ignore is None else list(ignore)
        collides = self.planning.collision_fn(self.pid, ignore=names, margin=margin, arm_margin=0.0)  # slow, straight
        path = [q]
        durations: list[float] = []
        marks: list[int] = []
        prev = arm.fk(q)
        for T in poses:
            dist = float(np.linalg.norm(T[:3, 3] - prev[:3, 3]))
            turn = float(Rotation.from_matrix(prev[:3, :3].T @ T[:3, :3]).magnitude())
            n = max(math.ceil(max(dist / 0.01, turn / 0.1)), 1)
            slerp = Slerp([0, 1], Rotation.from_matrix(np.stack([prev[:3, :3], T[:3, :3]])))
            rotations = slerp(np.arange(1, n + 1) / n).as_matrix()
            for i in range(1, n + 1):
                M = np.eye(4)
                M[:3, :3] = rotations[i - 1]
                M[:3, 3] = prev[:3, 3] + (T[:3, 3] - prev[:3, 3]) * (i / n)
                qn = arm.ik(M, self.traffic.rng, path[-1], restarts=0, iterations=40, tolerance=5e-4,
                            angle_tolerance=5e-3)
                if qn is None:
                    raise ActionFailed(f"{what}: a pose on the straight path is out of reach "
                                       f"({np.round(M[:3, 3], 3).tolist()})")
                if np.max(np.abs(qn - path[-1])) > 0.6:
                    raise ActionFailed(f"{what}: the arm would have to jump to follow the straight path")
                path.append(qn)
                durations.append(max(dist / n / LINEAR_SPEED, turn / n / TURN_SPEED, 1 / SIM_HZ))
            marks.append(len(path) - 1)
            prev = T
        if not path_free(collides, path, 0.05):
            blockers = sorted(self._in_the_way(names))
            if any(b.startswith("arm ") for b in blockers):
                self.traffic.other_in_the_way = True
            raise PathBlocked(f"{what}: the straight path collides" + (f" with {', '.join(blockers)}"
                                                                        if blockers else ""))
        return path, durations, marks

    def linear(self, poses: Sequence[np.ndarray], ignore: Sequence[str] | None = None,
               holds: Sequence[float] | None = None, fingers: Sequence[float | None] | None = None,
               what: str = "straight move", margin: float = -0.01,
               reached: Callable[[int], None] | None = None) -> Program:
        """Follow :meth:`cartesian_path` from where the arm is: at each pose ``j``, call ``reached(j)``, set the
        fingers, hold."""
        self.scene.sync()
        path, durations, marks = self.cartesian_path(self.robot.q(), poses, ignore, what, margin)
        try:
            yield from self._reserve(path)
        except _Replan:  # it waited for the other arm: check the straight path against where that arm is now
            self.scene.sync()
            names = list(self.scene.bodies.objects) if ignore is None else list(ignore)
            collides = self.planning.collision_fn(self.pid, ignore=names, margin=margin,
                                                  arm_margin=0.0)
            if not path_free(collides, path, 0.05):
                self.traffic.reserved[self.pid] = None
                raise ActionFailed(f"{what}: the other arm stopped in the way") from None
        try:
            k = 0
            for j, end in enumerate(marks):
                yield from self._follow(path[k:end + 1], durations[k:end])
                k = end
                if reached is not None:
                    reached(j)
                if fingers is not None and fingers[j] is not None:
                    self.set_grip(float(fingers[j]))  # type: ignore[arg-type]
                    yield from self.scene.hold(0.15)
                if holds is not None and holds[j] > 0:
                    yield from self.scene.hold(holds[j])
        finally:
            self.traffic.reserved[self.pid] = None

    # ------------------------------------------------------------------- sharing the table

    def let_other_move(self, limit: float = 4.0) -> Program:
        """Before a retry: if the other arm was in the way, wait until it rests at home (up to
        :data:`YIELD_SECONDS`); else if it is moving, wait (up to ``limit`` s) until that motion ends, since the
        failure may have been its fault and the world will look different."""
        other = self.traffic.other(self.pid)
        if other is not None and self.traffic.other_in_the_way:
            self.traffic.other_in_the_way = False
            self.traffic.right_of_way = self.pid  # the other arm, once home, waits for this primitive to end
            tick = waiting(f"{other} to go home (it was in the way of the last attempt)")
            for i in range(int(YIELD_SECONDS * SIM_HZ)):
                if np.max(np.abs(self.scene.robots[other].q() - REST)) < 1e-2:
                    return
                if i > 2 * SIM_HZ and self.scene.time - self.traffic.moved_at[other] > 3.0:  # itself waiting: go on
                    return
                yield tick
            return
        if other is None or self.traffic.reserved[other] is None:
            return
        current = self.traffic.reserved[other]
        tick = waiting(f"{other}'s motion to end before a retry")
        for _ in range(int(limit * SIM_HZ)):
            if self.traffic.reserved[other] is not current:
                return
            yield tick

    def park(self, what: str = "move to rest") -> Program:
        """A planned move to :data:`REST` (no retries)."""
        yield from self.transit(REST.copy(), what=what)

    def home(self) -> Program:
        """Back to :data:`REST` (a few tries, each with a longer search); then, if the other arm asked for the
        way, wait there until its primitive ends."""
        try:
            for attempt in range(self.traffic.attempts):
                if np.max(np.abs(self.robot.q() - REST)) < 1e-3:
                    break
                budget = self.traffic.planning_time
                try:
                    self.traffic.planning_time = budget * (1 + attempt)
                    yield from self.transit(REST.copy(), what="return home")
                except ActionFailed as error:  # a new seed, once the other arm has come to rest or stopped
                    if attempt == self.traffic.attempts - 1:
                        raise
                    self.scene.event("retry", None, self.pid, f"return home: attempt {attempt + 2} ({error})", "home")
                    self.traffic.other_in_the_way = True
                    yield from self.let_other_move()
                    yield from self.scene.hold(0.1)
                finally:
                    self.traffic.planning_time = budget
        finally:
            if self.traffic.right_of_way == self.pid:
                self.traffic.right_of_way = None
        tick = waiting(f"{self.traffic.right_of_way}'s primitive to end (it has the right of way)")
        for _ in range(int(YIELD_SECONDS * SIM_HZ)):
            if self.traffic.right_of_way in (None, self.pid):
                break
            yield tick


class _Replan(Exception):
    """The other arm was in the way: plan again from where things are now."""
