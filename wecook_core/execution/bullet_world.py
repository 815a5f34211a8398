"""The PyBullet world of the executor: a simulating client, a planning client, and the primitives
grasp / engage / actuate / place as programs (generators, see :mod:`wecook_core.execution.executor`).

Arms are driven along their trajectories kinematically (joints set every step, motors holding them); objects
are dynamic bodies; a grasped object rides on a fixed constraint to the hand (and is kept exactly on it).
Goals come from TSR samples through re-seeded IK, checked for collisions in the planning client; paths come from
the motion planner (every query time-limited). A goal that fails is retried with new samples, up to
``attempts`` rounds of ``samples`` samples; then the primitive fails with its reason.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
import pybullet as p
from scipy.spatial.transform import Rotation, Slerp

from wecook_core.execution.executor import WAIT, WORK, ActionFailed, Meeting, Program
from wecook_core.execution.motion import MotionProblem, path_free, plan_motion
from wecook_core.execution.observer import FrameInfo, RunEvent, RunObserver
from wecook_core.execution.planning_scene import ARM_MARGIN, PlanningScene, Riding, boxes_overlap
from wecook_core.execution.robot import (
    EE_LINK,
    HOME,
    LOWER,
    MAX_SPEED,
    REST,
    UPPER,
    Panda,
    attach,
    detach,
    set_arm_collisions,
)
from wecook_core.execution.scene import SIM_HZ, SceneBodies, build_scene, link_frames, world_poses
from wecook_core.execution.skills import (
    Half,
    SkillLibrary,
    Step,
    TSRSpec,
    Waypoint,
    actuation_path,
    evaluate,
    load_skills,
    object_kind,
    skill_name,
)
from wecook_core.execution.tsr import TSR, pose_to_matrix, sample, xyzrpy_to_matrix
from wecook_core.model import Category
from wecook_core.plan import Plan, PlanAction

Accept = Callable[[np.ndarray], bool]
"""Takes a candidate ee pose (4x4, world) or not."""
Rank = Callable[[np.ndarray], float]
"""Orders candidate ee poses: the lowest is tried first."""

JOINT_NAMES = [f"panda_joint{k + 1}" for k in range(7)] + ["panda_finger_joint1", "panda_finger_joint2"]
STATE_EVERY = SIM_HZ // 30
"""Steps between two ``on_state`` calls (30 Hz)."""
CONTACT_EVERY = 2
TOUCH_DEPTH = 0.0005
"""Metres of penetration from which two arms count as touching (contact points closer than zero)."""
"""Steps between two arm-arm contact queries."""
JOINT_SPEED = 0.45
"""Fraction of the joint speed limits used by planned motions."""
LINEAR_SPEED = 0.12
"""Metres per second of straight moves and actuations."""
TURN_SPEED = 1.2
"""Radians per second of the effector's rotation in straight moves and actuations."""
IMAGE_SIZE = (320, 240)
YIELD_SECONDS = 30.0
"""Simulated seconds an arm waits for the other to go home when the other arm blocked all its goals."""
APPROACH_OPENING = 0.008
"""Metres per finger beyond the grip width the fingers open to approach an object."""
ZONE_MARGIN = 0.08
"""Metres around the objects of an action that its arm may sweep over while working."""
ZONE_WAIT_SECONDS = 120.0
"""Longest wait for the other arm to leave an overlapping zone (then the action goes ahead, reservations still
keep the arms apart)."""
HAND_SPAN = 0.22
"""Metres: the Panda hand's length along its finger axis (it lies across an object it takes from above)."""
HAND_CLEAR_HEIGHT = 0.04
"""Metres above the table from which an object can be in the way of a hand taking something from above."""
CROWDED = 0.35
"""Metres: when the other arm's hand is this close to where a pose is sought, the poses farthest from it come
first."""
FREE_MARGIN = 0.1
"""Metres of clearance around an object put down on a free spot beyond which spots count as equally roomy
(room for the hand to take it again)."""


@dataclass
class Hand:
    """What one arm holds now."""

    carried: str | None = None
    constraint: int | None = None
    riding: list[Riding] = field(default_factory=list)
    grip: float = 0.04


class BulletWorld:
    def __init__(self, plan: Plan, observer: RunObserver | None, *, seed: int = 0, realtime: bool = False,
                 planner: str = "rrtconnect", planning_time: float = 1.0, images: bool = True,
                 skills: SkillLibrary | None = None, attempts: int = 3, samples: int = 12):
        self.plan = plan
        self.observer = observer
        self.client = p.connect(p.DIRECT)
        self.bodies: SceneBodies = build_scene(self.client, plan)
        self.planning = PlanningScene(plan)
        self.arms = {pid: Panda(self.client, arm.body) for pid, arm in self.bodies.arms.items()}
        self.skills = skills or load_skills()
        self.rng = np.random.default_rng(seed)
        self.seed = seed
        self.realtime = realtime
        self.planner = planner
        self.planning_time = planning_time
        self.images = images
        self.attempts = attempts
        self.samples = samples
        self.steps = 0
        self.queries = 0
        self.wall_start = time.perf_counter()
        self.hands = {pid: Hand() for pid in self.arms}
        self.commands: dict[str, np.ndarray] = {}
        self.reserved: dict[str, np.ndarray | None] = {pid: None for pid in self.arms}
        self.arm_contacts = 0
        self.arm_margin = ARM_MARGIN
        """Metres kept between the arms when planning (lowered while the receiver of a handover takes)."""
        self.goal_blockers: set[str] = set()
        """What blocked the goal candidates since the last failure report."""
        self.other_in_the_way = False
        self.right_of_way: str | None = None
        self.zones: dict[str, np.ndarray] = {}
        """Action id -> the table area it works in, while it runs (see :meth:`_claim_zone`)."""
        self.zone_users: dict[str, set[str]] = {}
        self.picked_from: dict[str, np.ndarray] = {}
        """Object -> its pose when last grasped (where a failed action puts it back)."""
        self.variants: dict[str, int] = {}
        """Arm -> the axis option of its next actuation, chosen when engaging."""
        """An arm the other one blocked: the other waits at rest until this arm's primitive ends."""
        self.moved_at = {pid: 0.0 for pid in self.arms}
        """Simulated time each arm last moved."""
        self._touching = False
        self.homes: dict[str, np.ndarray] = {n: b.home.copy() for n, b in self.bodies.objects.items()}
        for pid, arm in self.arms.items():
            arm.set_q(REST, 0.04)
            self.commands[pid] = REST.copy()
        for _ in range(60):  # let the objects settle before the clock starts
            p.stepSimulation(physicsClientId=self.client)
        self._frames = link_frames(self.bodies)

    # ------------------------------------------------------------------------------------ world API

    @property
    def time(self) -> float:
        return self.steps / SIM_HZ

    @property
    def dt(self) -> float:
        return 1 / SIM_HZ

    def close(self) -> None:
        self.planning.close()
        if p.isConnected(self.client):
            p.disconnect(self.client)

    def frames(self) -> list[FrameInfo]:
        return self._frames

    def step(self) -> None:
        c = self.client
        for pid, arm in self.arms.items():  # kinematic arms: exactly where commanded, every step
            arm.set_q(self.commands[pid])
        for pid, hand in self.hands.items():
            if hand.riding:
                state = p.getLinkState(self.bodies.arms[pid].body, EE_LINK, computeForwardKinematics=True,
                                       physicsClientId=c)
                for r in hand.riding:
                    body = self.bodies.objects[r.name].body
                    local = r.local
                    pos, orn = p.multiplyTransforms(state[4], state[5], local[0], local[1])
                    p.resetBasePositionAndOrientation(body, pos, orn, physicsClientId=c)
                    p.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0], physicsClientId=c)
        p.stepSimulation(physicsClientId=c)
        self.steps += 1
        if self.steps % CONTACT_EVERY == 0:
            self._check_arm_contact()
        if self.steps % STATE_EVERY == 0:
            self.publish_state()
        if self.realtime:
            ahead = self.time - (time.perf_counter() - self.wall_start)
            if ahead > 0:
                time.sleep(ahead)

    def publish_state(self) -> None:
        if self.observer is None:
            return
        joints = {}
        for pid, arm in self.arms.items():
            names = self.bodies.arms[pid].links
            q = list(arm.q()) + [arm.fingers()] * 2
            joints[pid] = (JOINT_NAMES, q)
            del names
        self.observer.on_state(self.time, world_poses(self.bodies), joints)

    def _check_arm_contact(self) -> None:
        """Count each new touch (penetration deeper than :data:`TOUCH_DEPTH`) between the two arms' links."""
        c = self.client
        pids = sorted(self.arms)
        if len(pids) < 2:
            return
        a, b = (self.bodies.arms[pid].body for pid in pids[:2])
        points = [x for x in p.getContactPoints(a, b, physicsClientId=c) if x[8] < -TOUCH_DEPTH]
        touching = bool(points)
        if touching and not self._touching:
            self.arm_contacts += 1
            names_a, names_b = self.bodies.arms[pids[0]].links, self.bodies.arms[pids[1]].links
            x = min(points, key=lambda q: q[8])
            detail = (f"the two arms touched: {pids[0]} {names_a[x[3] + 1]} and {pids[1]} {names_b[x[4] + 1]} "
                      f"({-x[8] * 1000:.1f} mm deep)")
            self._event("primitive_failed", None, None, detail)
            if self.observer is not None:
                self.observer.on_log(self.time, "error", detail)
        self._touching = touching

    def _event(self, kind: str, action: PlanAction | None, pid: str | None, detail: str = "",
               primitive: str | None = None) -> None:
        if kind in ("primitive_end", "primitive_failed") and pid is not None and pid == self.right_of_way:
            self.right_of_way = None
        if self.observer is not None:
            self.observer.on_event(self.time, RunEvent(kind, action.id if action else None, primitive, pid, detail))  # type: ignore[arg-type]

    def action_boundary(self, action: PlanAction, kind: str) -> None:
        if not self.images or self.observer is None:
            return
        import cv2

        w, h = IMAGE_SIZE
        view = p.computeViewMatrix([0.0, -1.1, 0.9], [0.0, 0.0, 0.1], [0, 0, 1])
        proj = p.computeProjectionMatrixFOV(55, w / h, 0.05, 5.0)
        image = p.getCameraImage(w, h, view, proj, renderer=p.ER_TINY_RENDERER, physicsClientId=self.client)
        rgb = np.reshape(np.asarray(image[2], dtype=np.uint8), (h, w, 4))[:, :, :3]
        ok, jpeg = cv2.imencode(".jpg", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, 80])
        if ok:
            self.observer.on_image(self.time, jpeg.tobytes(), w, h)

    # ------------------------------------------------------------------------------------ geometry

    def pose(self, name: str) -> np.ndarray:
        pos, orn = p.getBasePositionAndOrientation(self.bodies.objects[name].body, physicsClientId=self.client)
        return pose_to_matrix((pos, orn))

    def half(self, name: str | None) -> Half:
        if name is None:
            return Half()
        s = self.bodies.objects[name].size
        return Half(s[0] / 2, s[1] / 2, s[2] / 2)

    def _facing(self, name: str, pid: str) -> np.ndarray:
        T = self.pose(name)
        base = self.bodies.arms[pid].base[:3, 3]
        yaw = math.atan2(base[1] - T[1, 3], base[0] - T[0, 3])
        out = np.eye(4)
        out[:3, :3] = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
        out[:3, 3] = T[:3, 3]
        return out

    def _meet(self, giver: str, receiver: str) -> np.ndarray:
        a, b = self.bodies.arms[giver].base[:3, 3], self.bodies.arms[receiver].base[:3, 3]
        yaw = math.atan2(b[1] - a[1], b[0] - a[0])
        out = np.eye(4)
        out[:3, :3] = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
        out[:3, 3] = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, self.bodies.table_height + self.skills.meet_height]
        return out

    def _drop(self, pid: str) -> np.ndarray:
        base = self.bodies.arms[pid].base
        out = base.copy()
        out[:3, 3] = base[:3, 3] + base[:3, 0] * self.skills.drop_distance
        out[2, 3] = self.bodies.table_height
        out[:3, :3] = base[:3, :3] @ np.diag([-1.0, -1.0, 1.0])  # x toward the arm
        return out

    def frame(self, spec: TSRSpec, roles: dict[str, str | None], pid: str, meet: tuple[str, str] | None = None
              ) -> tuple[np.ndarray, dict[str, Half]]:
        """The TSR frame (4x4) and the half-extent table for expressions."""
        sizes = {"t": self.half(roles.get("tool")), "i": self.half(roles.get("ingredient")),
                 "l": self.half(roles.get("location"))}
        if spec.frame == "meet":
            assert meet is not None
            return self._meet(*meet), sizes
        if spec.frame == "drop":
            return self._drop(pid), sizes
        kind, role = spec.frame.split(":", 1)
        name = roles.get(role)
        if name is None:
            raise ActionFailed(f"the skill needs a {role} and the action names none")
        sizes["f"] = self.half(name)
        return (self.pose(name) if kind == "object" else self._facing(name, pid)), sizes

    # ------------------------------------------------------------------------------------ planning

    def _sync(self) -> None:
        self.planning.sync(self.bodies, {pid: h.riding for pid, h in self.hands.items()})

    def _planning_seed(self) -> int:
        self.queries += 1
        return (self.seed * 1_000_003 + self.queries * 7919) % (2**31 - 2)

    def _ik_goal(self, pid: str, targets: Iterable[np.ndarray], ignore: Sequence[str],
                 check: bool = True) -> tuple[np.ndarray, np.ndarray] | None:
        """First target (ee pose) with a collision-free IK solution: (q, pose). Each target is tried from the
        current joints, from home and from two random seeds (IK finds one of several arm postures)."""
        arm = self.planning.arms[pid]
        collides = self.planning.collision_fn(pid, ignore=ignore, arm_margin=self.arm_margin)
        current = self.arms[pid].q()
        for T in targets:
            for seed_q in (HOME, current, self.rng.uniform(LOWER, UPPER), self.rng.uniform(LOWER, UPPER)):
                q = arm.ik(T, self.rng, seed_q, restarts=0)
                if q is None:
                    continue
                if not (check and collides(q)):
                    return q, T
                self.goal_blockers.update(self._in_the_way(pid))
        return None

    def _in_the_way(self, pid: str) -> set[str]:
        """What the planning client's arm ``pid`` (as last checked) penetrates: object names, ``table``, an arm."""
        c = self.planning.client
        names = {b.body: n for n, b in self.planning.bodies.objects.items()}
        names[self.planning.bodies.table] = "table"
        names.update({a.body: f"arm {k}" for k, a in self.planning.arms.items() if k != pid})
        own = {r.name for r in self.hands[pid].riding}
        body = self.planning.arms[pid].body
        links = self.bodies.arms[pid].links
        contacts = p.getContactPoints(bodyA=body, physicsClientId=c)
        out = {f"{names[x[2]]} ({links[x[3] + 1]})" if names[x[2]] == "table" else names[x[2]]
               for x in contacts if x[8] < 0.0 and x[2] in names and names[x[2]] not in own}
        for r in self.hands[pid].riding:
            carried = self.planning.bodies.objects[r.name].body
            out |= {f"{names[x[2]]} (touched by the {r.name})"
                    for x in p.getContactPoints(bodyA=carried, physicsClientId=c)
                    if x[8] < 0.0 and x[2] in names and names[x[2]] not in own}
        out |= {f"its own {links[x[3] + 1]} and {links[x[4] + 1]}" for x in contacts
                if x[2] == body and x[8] < 0.0 and (min(x[3], x[4]), max(x[3], x[4])) not in self.planning.allowed_self}
        return out

    def _no_goal(self, what: str, count: int) -> str:
        blockers = sorted(self.goal_blockers)
        self.other_in_the_way = any(b.startswith("arm ") for b in blockers)
        self.goal_blockers = set()
        if blockers:
            return f"no collision-free {what} in {count} TSR samples (in the way: {', '.join(blockers)})"
        return f"no reachable {what} in {count} TSR samples"

    def _goal_samples(self, tsrs: Sequence[TSR], T_eff_ee: np.ndarray, n: int, accept: Accept | None = None,
                      rank: Rank | None = None) -> list[np.ndarray]:
        """Up to ``n`` ee poses drawn from ``tsrs`` (the effector at ``T_eff_ee`` from the ee) that ``accept``
        takes, lowest ``rank`` first (else in the order drawn)."""
        out: list[np.ndarray] = []
        for _ in range(n * 12):
            if len(out) >= n:
                break
            region = tsrs[int(self.rng.integers(len(tsrs)))]
            T = sample(region, self.rng) @ T_eff_ee
            if accept is None or accept(T):
                out.append(T)
        return sorted(out, key=rank) if rank is not None else out

    def _away_from_other(self, pid: str, near: np.ndarray) -> Rank | None:
        """Farthest from the other arm's hand first, when that hand is within :data:`CROWDED` of ``near`` (a world
        point): the two arms work at one object, so the pose with the most room between them is tried first."""
        other = self._other(pid)
        if other is None:
            return None
        hand = self.arms[other].ee()[:3, 3]
        if np.linalg.norm(hand - near) > CROWDED:
            return None
        return lambda T: -float(np.linalg.norm(T[:3, 3] - hand))

    def _plan(self, pid: str, goal: np.ndarray, ignore: Sequence[str]) -> list[np.ndarray] | str:
        self._sync()
        start = self.arms[pid].q()
        problem = MotionProblem(start=start, goal=goal, lower=LOWER, upper=UPPER,
                                collision_fn=self.planning.collision_fn(pid, ignore=ignore, arm_margin=self.arm_margin),
                                resolution=0.03)
        result = plan_motion(problem, planner=self.planner, time_limit=self.planning_time, seed=self._planning_seed())
        if result.status == "invalid_start":  # touching an object it just let go of, or closer to the other arm
            # than the margin (after a handover): plan without objects and margins, never through the arm or table
            loose = MotionProblem(start=start, goal=goal, lower=LOWER, upper=UPPER, resolution=0.03,
                                  collision_fn=self.planning.collision_fn(pid, ignore=list(self.bodies.objects),
                                                                          arm_margin=0.0))
            result = plan_motion(loose, planner=self.planner, time_limit=self.planning_time,
                                 seed=self._planning_seed())
        if not result.ok:
            if result.status in ("invalid_start", "invalid_goal"):
                q = start if result.status == "invalid_start" else goal
                self.planning.collision_fn(pid, ignore=list(self.bodies.objects), arm_margin=self.arm_margin)(q)
                blockers = sorted(self._in_the_way(pid))
                if blockers:
                    return f"{result.status.replace('_', ' ')}: touching {', '.join(blockers)}"
            return result.status
        return list(result.path)

    def _other(self, pid: str) -> str | None:
        return next((k for k in self.arms if k != pid), None)

    # ------------------------------------------------------------------------------------ motion

    def _follow(self, pid: str, path: Sequence[np.ndarray], durations: Sequence[float] | None = None) -> Program:
        """Move along joint waypoints (linear interpolation), ``durations[k]`` seconds for segment k."""
        for k, (a, b) in enumerate(itertools.pairwise(path)):
            d = durations[k] if durations is not None else float(np.max(np.abs(b - a) / (MAX_SPEED * JOINT_SPEED)))
            n = max(math.ceil(d * SIM_HZ), 1)
            for i in range(1, n + 1):
                self.commands[pid] = a + (b - a) * (i / n)
                self.moved_at[pid] = self.time
                yield WORK

    def _reserve(self, pid: str, path: Sequence[np.ndarray]) -> Program:
        """Wait until the swept region of ``path`` is clear of the other arm's moving region, then hold it."""
        self._sync()
        boxes = self.planning.swept_boxes(pid, path)
        other = self._other(pid)
        waited = 0
        while other is not None and self.reserved[other] is not None:
            theirs = self.reserved[other]
            if not boxes_overlap(boxes, theirs):  # type: ignore[arg-type]
                break
            while self.reserved[other] is theirs:  # the same motion still runs
                waited += 1
                yield WAIT
        self.reserved[pid] = boxes
        if waited:
            raise _Replan()

    def transit(self, pid: str, goal: np.ndarray, ignore: Sequence[str] = (), what: str = "move") -> Program:
        """A planned, collision-free move to joint goal ``goal`` (re-planned if the other arm was in the way)."""
        escaped = False
        for _ in range(20):
            path = self._plan(pid, goal, ignore)
            if isinstance(path, str) and path.startswith("invalid start: touching") and "arm " not in path \
                    and not escaped:  # resting on the table or an object: straight up out of contact first
                escaped = True
                up = self.arms[pid].ee()
                up[2, 3] += 0.06
                with contextlib.suppress(ActionFailed):
                    yield from self.linear(pid, [up], ignore=None, what="lift clear", margin=-0.03)
                continue
            if isinstance(path, str):
                raise ActionFailed(f"{what}: no path ({path})" if "touching" in path
                                   else f"{what}: no path ({path} after {self.planning_time:.1f} s)")
            try:
                yield from self._reserve(pid, path)
            except _Replan:
                self.reserved[pid] = None
                continue
            try:
                yield from self._follow(pid, path)
            finally:
                self.reserved[pid] = None
            return
        raise ActionFailed(f"{what}: the other arm kept the way blocked")

    def cartesian_path(self, pid: str, q: np.ndarray, poses: Sequence[np.ndarray], ignore: Sequence[str] | None,
                       what: str, margin: float = -0.01) -> tuple[list[np.ndarray], list[float], list[int]]:
        """Joint path of straight effector moves from ``q`` through ee ``poses`` (IK on each step, densified to
        1 cm / 0.1 rad), checked against the other arm and the table (objects in ``ignore``, or every object
        when None, are skipped). Returns the path, each segment's duration and the index ending each move;
        raises :class:`ActionFailed`. Moves the planning client's joints only."""
        arm = self.planning.arms[pid]
        names = list(self.bodies.objects) if ignore is None else list(ignore)
        collides = self.planning.collision_fn(pid, ignore=names, margin=margin, arm_margin=0.0)  # slow, straight
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
                qn = arm.ik(M, self.rng, path[-1], restarts=0, iterations=40, tolerance=5e-4, angle_tolerance=5e-3)
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
            blockers = sorted(self._in_the_way(pid))
            if any(b.startswith("arm ") for b in blockers):
                self.other_in_the_way = True
            raise ActionFailed(f"{what}: the straight path collides" + (f" with {', '.join(blockers)}"
                                                                        if blockers else ""))
        return path, durations, marks

    def linear(self, pid: str, poses: Sequence[np.ndarray], ignore: Sequence[str] | None = None,
               holds: Sequence[float] | None = None, fingers: Sequence[float | None] | None = None,
               what: str = "straight move", margin: float = -0.01) -> Program:
        """Follow :meth:`cartesian_path` from where the arm is, holding and setting the fingers at each pose."""
        self._sync()
        path, durations, marks = self.cartesian_path(pid, self.arms[pid].q(), poses, ignore, what, margin)
        try:
            yield from self._reserve(pid, path)
        except _Replan:  # it waited for the other arm: check the straight path against where that arm is now
            self._sync()
            names = list(self.bodies.objects) if ignore is None else list(ignore)
            collides = self.planning.collision_fn(pid, ignore=names, margin=margin,
                                                  arm_margin=0.0)
            if not path_free(collides, path, 0.05):
                self.reserved[pid] = None
                raise ActionFailed(f"{what}: the other arm stopped in the way") from None
        try:
            k = 0
            for j, end in enumerate(marks):
                yield from self._follow(pid, path[k:end + 1], durations[k:end])
                k = end
                if fingers is not None and fingers[j] is not None:
                    self._set_grip(pid, float(fingers[j]))  # type: ignore[arg-type]
                    yield from self._hold(0.15)
                if holds is not None and holds[j] > 0:
                    yield from self._hold(holds[j])
        finally:
            self.reserved[pid] = None

    def _let_other_move(self, pid: str, limit: float = 4.0) -> Program:
        """Before a retry: if the other arm was in the way, wait until it rests at home (up to
        :data:`YIELD_SECONDS`); else if it is moving, wait (up to ``limit`` s) until that motion ends, since the
        failure may have been its fault and the world will look different."""
        other = self._other(pid)
        if other is not None and self.other_in_the_way:
            self.other_in_the_way = False
            self.right_of_way = pid  # the other arm, once home, waits for this primitive to end
            for i in range(int(YIELD_SECONDS * SIM_HZ)):
                if np.max(np.abs(self.arms[other].q() - REST)) < 1e-2:
                    return
                if i > 2 * SIM_HZ and self.time - self.moved_at[other] > 3.0:  # itself waiting: go on
                    return
                yield WAIT
            return
        if other is None or self.reserved[other] is None:
            return
        current = self.reserved[other]
        for _ in range(int(limit * SIM_HZ)):
            if self.reserved[other] is not current:
                return
            yield WAIT

    def _hold(self, seconds: float) -> Program:
        for _ in range(max(int(seconds * SIM_HZ), 1)):
            yield WORK

    def _ride(self, pid: str, name: str, T_ee_obj: np.ndarray | None = None) -> None:
        """``name`` moves with ``pid``'s hand from now on (and with no other hand)."""
        for other, hand in self.hands.items():
            if other != pid:
                hand.riding = [r for r in hand.riding if r.name != name]
        T = np.linalg.inv(self.arms[pid].ee()) @ self.pose(name) if T_ee_obj is None else T_ee_obj
        self.hands[pid].riding.append(Riding(name, T))
        self._collide_with_arm(pid, name, enabled=False)

    def _holder_of(self, name: str, pid: str) -> str | None:
        """The other arm whose hand carries ``name`` (or has it riding), if any."""
        return next((k for k, h in self.hands.items() if k != pid and any(r.name == name for r in h.riding)), None)

    def _contents(self, name: str) -> list[str]:
        if self.bodies.objects[name].category is not Category.CONTAINER:
            return []
        return [n for n, b in self.bodies.objects.items()
                if b.category is Category.INGREDIENT and n != name and self._container_of(n) == name]

    def _collide_with_arm(self, pid: str, name: str, *, enabled: bool) -> None:
        set_arm_collisions(self.client, self.bodies.arms[pid].body, self.bodies.objects[name].body, enabled=enabled)

    def _set_grip(self, pid: str, width: float) -> None:
        self.hands[pid].grip = width
        self.arms[pid].set_fingers(width)

    def go_home(self, pid: str) -> Program:
        """Back to :data:`REST` (a few tries, each with a longer search); then, if the other arm asked for the
        way, wait there until its primitive ends."""
        try:
            for attempt in range(self.attempts):
                if np.max(np.abs(self.arms[pid].q() - REST)) < 1e-3:
                    break
                budget = self.planning_time
                try:
                    self.planning_time = budget * (1 + attempt)
                    yield from self.transit(pid, REST.copy(), what="return home")
                except ActionFailed as error:  # a new seed, once the other arm has come to rest or stopped
                    if attempt == self.attempts - 1:
                        raise
                    self._event("retry", None, pid, f"return home: attempt {attempt + 2} ({error})", "home")
                    self.other_in_the_way = True
                    yield from self._let_other_move(pid)
                    yield from self._hold(0.1)
                finally:
                    self.planning_time = budget
        finally:
            if self.right_of_way == pid:
                self.right_of_way = None
        for _ in range(int(YIELD_SECONDS * SIM_HZ)):
            if self.right_of_way in (None, pid):
                break
            yield WAIT

    # ------------------------------------------------------------------------------------ primitives

    def _kind(self, name: str) -> str:
        b = self.bodies.objects[name]
        return object_kind(b.category, b.size, b.open_top)

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
        support = [n for n, c in self.plan.scene.containing if n == name] + \
            [c for n, c in self.plan.scene.containing if n == name]
        ignore = [name, *support, *ignore_extra]
        approach = self.skills.approach_distance
        reason = "no reachable collision-free grasp"
        for attempt in range(self.attempts):
            if attempt:
                yield from self._let_other_move(pid)
                self._event("retry", action, pid, f"{primitive} {name}: attempt {attempt + 1} ({reason})", primitive)
            self._sync()
            candidates = self._goal_samples(regions, np.eye(4), self.samples, accept, rank)
            pre_goal = None
            blocked = None
            for G in candidates:
                found = self._ik_goal(pid, [G], ignore)
                if found is None:
                    continue
                pre = G.copy()
                pre[:3, 3] -= G[:3, 2] * approach
                found_pre = self._ik_goal(pid, [pre], ignore_extra)
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
                reason = blocked or self._no_goal(f"grasp of {name}", len(candidates))
                continue
            try:
                yield from self.transit(pid, pre_goal[0], ignore_extra, what=f"{primitive} {name}")
                # the fingers close into the object without pushing it about: the constraint will hold it
                self._collide_with_arm(pid, name, enabled=False)
                yield from self.linear(pid, [pre_goal[2]], ignore=ignore, what=f"approach {name}")
            except ActionFailed as error:
                self._collide_with_arm(pid, name, enabled=True)
                reason = str(error)
                continue
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
                    reason = str(error)
                    yield from self.release(pid)
                    continue
            self._event("primitive_end", action, pid, name, primitive)
            return
        self._event("primitive_failed", action, pid, reason, primitive)
        raise ActionFailed(f"{primitive} {name}: {reason}")

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

    def engage(self, action: PlanAction, pid: str, spec: TSRSpec, roles: dict[str, str | None],
               meet: tuple[str, str] | None = None, accept: Accept | None = None, then: Step | None = None
               ) -> Program:
        """Carry the effector (the carried object, else the gripper) into a TSR, by a planned move. With
        ``then`` (the actuation that follows), only poses from which that actuation is feasible are chosen."""
        self._event("primitive_start", action, pid, spec.frame, "engage")
        hand = self.hands[pid]
        T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
        reason = "no reachable collision-free pose"
        for attempt in range(self.attempts):
            if attempt:
                yield from self._let_other_move(pid)
                self._event("retry", action, pid, f"engage: attempt {attempt + 1} ({reason})", "engage")
            self._sync()
            T0_w, sizes = self.frame(spec, roles, pid, meet)
            region = spec.tsr(T0_w, sizes)
            rank = self._away_from_other(pid, T0_w[:3, 3]) if meet is None else None
            candidates = self._goal_samples([region], T_eff_ee, self.samples, accept, rank)
            found = None
            for G in candidates:
                found = self._ik_goal(pid, [G], [])
                if found is None or then is None:
                    if found is not None:
                        break
                    continue
                options = len(str(then.params.get("axis", "")).split(","))
                for variant in range(options):
                    try:
                        waypoints = self._actuation_waypoints(pid, then, roles, G, variant)
                        self.cartesian_path(pid, found[0], [w.pose @ T_eff_ee for w in waypoints], None, "actuate")
                        self.variants[pid] = variant
                        break
                    except ActionFailed as error:
                        reason = f"the {then.motion} from there: {error}"
                else:
                    found = None
                if found is not None:
                    break
            if found is None:
                reason = self._no_goal(f"pose at {spec.frame}", len(candidates)) \
                    if then is None or not candidates or reason.startswith("no ") else reason
                continue
            try:
                yield from self.transit(pid, found[0], what="engage")
            except ActionFailed as error:
                reason = str(error)
                continue
            self._event("primitive_end", action, pid, spec.frame, "engage")
            return
        self._event("primitive_failed", action, pid, reason, "engage")
        raise ActionFailed(f"engage {spec.frame}: {reason}")

    def _free_poses(self, name: str, region: TSR) -> list[np.ndarray]:
        """Object poses of ``region`` on a 2 cm grid (yaw in 45-degree steps within the bounds), the roomiest
        first. Room is the smaller of two clearances: the object's footprint to every other object, and the
        footprint of a hand taking it again (:data:`HAND_SPAN` across the object at its grasp point) to every
        object taller than :data:`HAND_CLEAR_HEIGHT`. Clearances beyond :data:`FREE_MARGIN` count as equally
        roomy; then the spot nearest the region's centre wins."""
        own = {r.name for h in self.hands.values() for r in h.riding if h.carried == name}
        half = np.array(self.bodies.objects[name].size) / 2
        corners = np.array([[sx * half[0], sy * half[1]] for sx in (-1, 1) for sy in (-1, 1)])
        holder = next((h for h in self.hands.values() if h.carried == name), None)
        if holder is not None and holder.riding:  # where the hand holds it now, in the object's frame
            T_obj_ee = np.linalg.inv(holder.riding[0].T_ee_obj)
            centre, across, along = T_obj_ee[:2, 3], T_obj_ee[:2, 1], T_obj_ee[:2, 0]
        else:
            centre = np.array([-0.55 * half[0] if self._kind(name) == "tool" else 0.0, 0.0])
            across, along = np.array([0.0, 1.0]), np.array([1.0, 0.0])
        hand = np.array([centre + sy * HAND_SPAN / 2 * across + sx * 0.03 * along
                         for sx in (-1, 1) for sy in (-1, 1)])
        others = [(np.array(p.getAABB(b.body, physicsClientId=self.client)), b) for n, b in self.bodies.objects.items()
                  if n not in own and n != name]
        boxes = np.array([box[:, :2] for box, _ in others]).reshape(-1, 2, 2)
        tall = np.array([box[:, :2] for box, _ in others if box[1, 2] - self.bodies.table_height > HAND_CLEAR_HEIGHT]
                        ).reshape(-1, 2, 2)

        def clearance(pts: np.ndarray, against: np.ndarray) -> float:
            if not len(against):
                return 1.0
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            sep = np.maximum(against[:, 0] - hi, lo - against[:, 1])
            overlap = np.all(sep < 0, axis=1)
            gap = np.maximum(sep, 0.0)
            return float(np.min(np.where(overlap, -1.0, np.hypot(gap[:, 0], gap[:, 1]))))

        B = region.Bw
        xs = np.arange(B[0, 0], B[0, 1] + 1e-9, 0.02)
        ys = np.arange(B[1, 0], B[1, 1] + 1e-9, 0.02)
        yaws = [y for y in np.radians([-90, -45, 0, 45, 90]) if B[5, 0] - 1e-9 <= y <= B[5, 1] + 1e-9] or [0.0]
        scored = []
        for yaw in yaws:
            for x in xs:
                for y in ys:
                    T = region.T0_w @ xyzrpy_to_matrix([x, y, (B[2, 0] + B[2, 1]) / 2, 0, 0, yaw]) @ region.Tw_e
                    R, t = T[:2, :2], T[:2, 3]
                    own_room = clearance(corners @ R.T + t, boxes)
                    room = min(own_room, clearance(hand @ R.T + t, tall))
                    if own_room > 0.0:  # where the hand has no room either, only after every roomy spot
                        tier = 0 if room > 0.0 else 1
                        scored.append((tier, -min(max(room, own_room * tier), FREE_MARGIN),
                                       math.hypot(x, y) + 0.01 * abs(yaw), T))
        scored.sort(key=lambda item: item[:3])
        return [item[3] for item in scored]

    def place(self, action: PlanAction | None, pid: str, target: np.ndarray | list[TSR], free: bool = False
              ) -> Program:
        """Put the carried object down at ``target`` (object pose, or TSRs of object poses): planned move above,
        straight down, release. ``free``: only where it stands clear of the other objects."""
        hand = self.hands[pid]
        name = hand.carried
        if name is None:
            return
        self._event("primitive_start", action, pid, name, "place")
        T_obj_ee = np.linalg.inv(hand.riding[0].T_ee_obj)
        regions = target if isinstance(target, list) else [TSR(target, np.eye(4), np.array(
            [[-0.01, 0.01], [-0.01, 0.01], [0.002, 0.006], [0, 0], [0, 0], [-0.1, 0.1]]))]
        reason = "no reachable place pose"
        for attempt in range(self.attempts):
            if attempt:
                yield from self._let_other_move(pid)
                self._event("retry", action, pid, f"place {name}: attempt {attempt + 1} ({reason})", "place")
            self._sync()
            if free:
                spots = self._free_poses(name, regions[0])
                goals = [T @ T_obj_ee for T in spots[attempt * self.samples:(attempt + 1) * self.samples]]
            else:
                goals = self._goal_samples(regions, T_obj_ee, self.samples)
            chosen = None
            blocked = None
            for G in goals:
                found = self._ik_goal(pid, [G], [], check=False)
                if found is None:
                    continue
                above = G.copy()
                above[2, 3] += self.skills.lift
                found_above = self._ik_goal(pid, [above], [])
                if found_above is None:
                    continue
                try:  # the straight way down must be feasible too
                    self.cartesian_path(pid, found_above[0], [G], [], f"put down {name}")
                except ActionFailed as error:
                    blocked = str(error)
                    continue
                chosen = (found_above[0], G)
                break
            if chosen is None:
                reason = blocked or self._no_goal(f"place pose for {name}", len(goals))
                continue
            try:
                yield from self.transit(pid, chosen[0], what=f"place {name}")
                yield from self.linear(pid, [chosen[1]], ignore=[], what=f"put down {name}")
            except ActionFailed as error:
                reason = str(error)
                continue
            yield from self.release(pid)
            self._event("primitive_end", action, pid, name, "place")
            return
        self._event("primitive_failed", action, pid, reason, "place")
        raise ActionFailed(f"place {name}: {reason}")

    def _actuation_waypoints(self, pid: str, step: Step, roles: dict[str, str | None], ee: np.ndarray,
                             variant: int | None = None) -> list[Waypoint]:
        """The effector waypoints of ``step`` starting with the hand at ``ee``; ``variant`` picks one of the
        step's axis options (default: the one the last engage chose)."""
        assert step.motion is not None
        hand = self.hands[pid]
        T_ee_eff = hand.riding[0].T_ee_obj if hand.riding else np.eye(4)
        E = ee @ T_ee_eff
        sizes = {"t": self.half(roles.get("tool")), "i": self.half(roles.get("ingredient")),
                 "l": self.half(roles.get("location"))}
        if step.contact is not None:
            sizes["f"] = self.half(roles.get(step.contact[1]))
        params = {k: (v if k == "axis" else evaluate(v, sizes)) for k, v in step.params.items()}
        if "axis" in params:
            options = str(params["axis"]).split(",")
            chosen = self.variants.get(pid, 0) if variant is None else variant
            params["axis"] = options[min(chosen, len(options) - 1)]
        contact_target = roles.get(step.contact[1]) if step.contact else None
        Rw = self._facing(contact_target, pid)[:3, :3] if contact_target is not None \
            else np.eye(3)
        if not step.contact:
            target = roles.get("location") or roles.get("ingredient")
            if target is not None:
                Rw = self._facing(target, pid)[:3, :3]
        return actuation_path(step.motion, params, E, Rw, grip=hand.grip, hand=ee[:3, 3])  # type: ignore[arg-type]

    def actuate(self, action: PlanAction, pid: str, step: Step, roles: dict[str, str | None]) -> Program:
        assert step.motion is not None
        self._event("primitive_start", action, pid, step.motion, "actuate")
        hand = self.hands[pid]
        T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
        waypoints = self._actuation_waypoints(pid, step, roles, self.arms[pid].ee())
        pair = None
        if step.contact is not None:
            a, b = roles.get(step.contact[0]), roles.get(step.contact[1])
            if a is not None and b is not None and a != b:
                pair = (self.bodies.objects[a].body, self.bodies.objects[b].body)
                p.setCollisionFilterPair(pair[0], pair[1], -1, -1, 0, physicsClientId=self.client)
        try:
            yield from self.linear(pid, [w.pose @ T_eff_ee for w in waypoints], ignore=None,
                                   holds=[w.hold for w in waypoints], fingers=[w.fingers for w in waypoints],
                                   what=f"actuate {step.motion}")
        except ActionFailed as error:
            self._event("primitive_failed", action, pid, str(error), "actuate")
            raise
        finally:
            if pair is not None:
                p.setCollisionFilterPair(pair[0], pair[1], -1, -1, 1, physicsClientId=self.client)
        for role in step.attach:
            name = roles.get(role)
            if name is not None and hand.riding:
                carrier = hand.riding[0]
                tool = self.half(carrier.name)
                ing = self.half(name)
                T_tool_ing = np.eye(4)
                T_tool_ing[:3, 3] = [0.6 * tool.hx, 0.0, tool.hz + ing.hz + 0.002]
                self._ride(pid, name, carrier.T_ee_obj @ T_tool_ing)
                p.setCollisionFilterPair(self.bodies.objects[carrier.name].body, self.bodies.objects[name].body,
                                         -1, -1, 0, physicsClientId=self.client)
        for role in step.release:
            name = roles.get(role)
            if name is None:
                continue
            if name == hand.carried:
                yield from self.release(pid)
            else:
                hand.riding = [r for r in hand.riding if r.name != name]
                yield from self._hold(0.6)  # let it fall
                self._collide_with_arm(pid, name, enabled=True)
                if hand.riding:
                    p.setCollisionFilterPair(self.bodies.objects[hand.riding[0].name].body,
                                             self.bodies.objects[name].body, -1, -1, 1, physicsClientId=self.client)
        self._event("primitive_end", action, pid, step.motion, "actuate")

    # ------------------------------------------------------------------------------------ actions

    def _zone(self, action: PlanAction) -> np.ndarray:
        """The table area an action works in: ``[[x0, y0], [x1, y1]]`` around the objects it names (and the
        meeting point of a handover), grown by :data:`ZONE_MARGIN`."""
        names = {action.tool, action.location, action.source, *action.ingredients}
        if action.partner is not None:
            act = action.partner
            names |= {act.tool, act.location, act.source, *act.ingredients}
        boxes = [np.array(p.getAABB(self.bodies.objects[n].body, physicsClientId=self.client))[:, :2]
                 for n in names if n is not None]
        if action.verb == "handover":
            meet = self._meet(*action.pids[:2])[:2, 3]
            boxes.append(np.array([meet - 0.1, meet + 0.1]))
        if not boxes:
            return np.zeros((2, 2))
        stacked = np.stack(boxes)
        return np.array([stacked[:, 0].min(axis=0) - ZONE_MARGIN, stacked[:, 1].max(axis=0) + ZONE_MARGIN])

    def _claim_zone(self, action: PlanAction, pid: str) -> Program:
        """Wait until no action of the other arm works in an overlapping zone, then hold this action's zone."""
        if action.id in self.zones:
            return
        zone = self._zone(action)
        for _ in range(int(ZONE_WAIT_SECONDS * SIM_HZ)):
            busy = [z for owner, z in self.zones.items() if owner != action.id
                    and np.all(zone[0] < z[1]) and np.all(z[0] < zone[1])]
            if not busy:
                break
            yield WAIT
        self.zones[action.id] = zone

    def program(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        """The role of ``pid`` in ``action``, inside the action's workspace zone (held until every role ends)."""
        yield from self._claim_zone(action, pid)
        self.zone_users.setdefault(action.id, set()).add(pid)
        try:
            yield from self._role(action, pid, meeting)
        finally:
            users = self.zone_users.get(action.id, set())
            users.discard(pid)
            if not users:
                self.zones.pop(action.id, None)

    def _role(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        if action.verb == "handover":
            giver, _receiver = action.pids
            yield from (self._giver(action, pid, meeting) if pid == giver else self._receiver(action, pid, meeting))
        elif action.verb == "holding":
            holder = action.pids[0]
            yield from (self._holder(action, pid, meeting) if pid == holder else self._actor(action, pid, meeting))
        else:
            yield from self._individual(action, pid, action.verb, action.tool, action.ingredients, action.location,
                                        action.source)

    def _container_of(self, name: str) -> str | None:
        """The container an object is in now: the one whose footprint holds its centre, above its floor."""
        T = self.pose(name)
        for other, body in self.bodies.objects.items():
            if other == name or body.category is not Category.CONTAINER:
                continue
            local = np.linalg.inv(self.pose(other)) @ T
            h = self.half(other)
            if abs(local[0, 3]) <= h.hx and abs(local[1, 3]) <= h.hy and -h.hz <= local[2, 3] <= h.hz + 0.1:
                return other
        return None

    def _individual(self, action: PlanAction, pid: str, verb: str, tool: str | None, ingredients: Sequence[str],
                    location: str | None, source: str | None,
                    after_grasp: Callable[[], Program] | None = None,
                    after_work: Callable[[], None] | None = None) -> Program:
        tool_category = self.bodies.objects[tool].category if tool else None
        skill = self.skills.skills.get(skill_name(verb, tool, tool_category))
        if skill is None:
            raise ActionFailed(f"no skill for {verb!r}")
        carried = tool if (skill.carry == "tool" or tool is not None) else None
        carried = carried or (ingredients[0] if ingredients else None)
        if carried is None:
            raise ActionFailed(f"{verb} needs an object to hold (a tool or an ingredient)")
        ingredient = ingredients[0] if ingredients else None
        if ingredient is None and carried != tool:
            ingredient = carried
        loc = location or (self._container_of(ingredient) if ingredient else None) or ingredient
        roles: dict[str, str | None] = {"tool": carried, "ingredient": ingredient or loc, "location": loc,
                                        "source": source or (self._container_of(ingredient) if ingredient else None)}
        home = self.pose(carried)
        yield from self.grasp(action, pid, carried)
        if after_grasp is not None:
            yield from after_grasp()
        k, second_tries = 0, 1
        while k < len(skill.steps):
            step = skill.steps[k]
            if step.primitive == "engage":
                assert step.tsr is not None
                after = skill.steps[k + 1] if k + 1 < len(skill.steps) else None
                yield from self.engage(action, pid, step.tsr, roles,
                                       then=after if after is not None and after.primitive == "actuate" else None)
            else:
                try:
                    yield from self.actuate(action, pid, step, roles)
                except ActionFailed as error:  # it failed before moving: engage anew (a new sample), then again
                    if not (second_tries and k > 0 and skill.steps[k - 1].primitive == "engage"):
                        raise
                    second_tries -= 1
                    self._event("retry", action, pid, f"engage again for the {step.motion} ({error})", "actuate")
                    yield from self._let_other_move(pid)
                    k -= 1
                    continue
            k += 1
        if after_work is not None:
            after_work()
        if self.hands[pid].carried is not None:
            try:
                yield from self.place(action, pid, home)
            except ActionFailed as error:  # its spot is out of reach now: any free spot near it will do
                near = TSR(home, np.eye(4), np.array([[-0.12, 0.12], [-0.12, 0.12], [0.004, 0.004], [0, 0], [0, 0],
                                                      [-math.pi / 2, math.pi / 2]]))
                self._event("retry", action, pid, f"place {carried} near its spot ({error})", "place")
                yield from self.place(action, pid, [near], free=True)
        yield from self.go_home(pid)

    def _giver(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        """Mid-air for long objects (tools): carry it to the meeting pose, wait until the receiver holds it, let
        go. Small objects (both grippers would not fit on them) are handed over on the table between the arms:
        put down at the meeting spot, then the receiver picks them up."""
        name = action.tool
        assert name is not None
        giver, receiver = action.pids
        yield from self.grasp(action, pid, name)
        meet = self._meet(giver, receiver)
        if self._kind(name) != "tool":
            spot = meet.copy()
            spot[2, 3] = self.bodies.table_height + self.half(name).hz
            region = TSR(spot, np.eye(4), np.array([[-0.1, 0.1], [-0.25, 0.25], [0.002, 0.006], [0, 0], [0, 0],
                                                    [-math.pi, math.pi]]))
            yield from self.place(action, pid, [region], free=True)
            meeting.signal("at_meet")
            yield from self.go_home(pid)
            meeting.signal("released")  # out of the way
            return

        reach = float(np.linalg.norm(self.hands[pid].riding[0].T_ee_obj[:2, 3]))  # hand to object centre

        def on_giver_side(T_ee: np.ndarray) -> bool:
            """The tool along the giver-receiver line, the giver's hand on its own end."""
            local = np.linalg.inv(meet) @ T_ee
            return bool(local[0, 3] < -0.8 * reach)

        yield from self.engage(action, pid, self.skills.meet, {"tool": name}, meet=(giver, receiver),
                               accept=on_giver_side)
        meeting.signal("at_meet")
        yield from meeting.wait_for("taken")
        yield from self._hold(0.2)
        yield from self.release(pid)
        yield from self.go_home(pid)
        meeting.signal("released")  # and out of the way

    def _receiver(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        name = action.tool
        assert name is not None
        giver = action.pids[0]
        yield from meeting.wait_for("at_meet")
        if self._kind(name) != "tool":  # on the table: an ordinary grasp once the giver has let go
            yield from meeting.wait_for("released")
            yield from self.grasp(action, pid, name, primitive="take")
        else:
            giver_ee = self.arms[giver].ee()
            clearance = self.skills.receiver_clearance
            regions = self._grasp_tsrs(name, pid, flip=True)

            def clear_of_giver(T: np.ndarray) -> bool:
                return bool(np.linalg.norm(T[:3, 3] - giver_ee[:3, 3]) >= clearance)

            self.arm_margin = 0.0
            try:
                yield from self.grasp(action, pid, name, lift=False, tsrs=regions, accept=clear_of_giver,
                                      primitive="take")
            finally:
                self.arm_margin = ARM_MARGIN
            self.hands[giver].riding = []
            meeting.signal("taken")
            yield from meeting.wait_for("released")
        drop = self.skills.drop
        T0_w, sizes = self.frame(drop, {"tool": name}, pid)
        yield from self.place(action, pid, [drop.tsr(T0_w, sizes)], free=True)
        yield from self.go_home(pid)

    def _holder(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        name = action.tool
        assert name is not None
        yield from meeting.wait_for("tool_ready")  # the actor first takes its tool, then the container is held
        regions = self._grasp_tsrs(name, pid, kinds=["hold_rim"] if self._kind(name) == "open_container" else None)
        centre = self.pose(name)[:2, 3]
        actor = next(k for k in action.pids if k != pid)
        toward = self.bodies.arms[actor].base[:2, 3] - centre
        toward /= max(float(np.linalg.norm(toward)), 1e-9)

        def far_side(T: np.ndarray) -> float:
            """Cosine of the angle, about the container, between the grip and the actor's base: the actor works
            on the side facing its base, so the grip farthest round from there is tried first."""
            grip = T[:2, 3] - centre
            return float(grip @ toward / max(float(np.linalg.norm(grip)), 1e-9))

        for k, region in enumerate(regions):  # each grasp in the library's order
            try:
                yield from self.grasp(action, pid, name, lift=False, primitive="hold", tsrs=[region], rank=far_side)
                break
            except ActionFailed:
                if k == len(regions) - 1:
                    raise
        yield from self._hold(self.skills.hold_time)
        meeting.signal("held")
        yield from meeting.wait_for("acted")
        yield from self._hold(self.skills.hold_time)
        yield from self.release(pid)
        yield from self.go_home(pid)

    def _actor(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        act = action.partner
        if act is None:
            raise ActionFailed("holding without the partner's action")
        def ready() -> Program:  # tool in hand, wait out of the holder's way
            with contextlib.suppress(ActionFailed):
                yield from self.transit(pid, REST.copy(), what="wait at rest")
            meeting.signal("tool_ready")
            yield from meeting.wait_for("held")

        location = act.location or action.tool
        yield from self._individual(action, pid, act.verb, act.tool, act.ingredients, location, act.source,
                                    after_grasp=ready, after_work=lambda: meeting.signal("acted"))

    def recover(self, pid: str) -> Program:
        """After a failure: put what the hand carries down on a free spot near where it was picked up (else let
        it go where it is), then go home."""
        self.reserved[pid] = None
        carried = self.hands[pid].carried
        if carried is not None and self.hands[pid].constraint is not None and carried in self.picked_from:
            near = TSR(self.picked_from[carried], np.eye(4), np.array(
                [[-0.12, 0.12], [-0.12, 0.12], [0.004, 0.004], [0, 0], [0, 0], [-math.pi / 2, math.pi / 2]]))
            with contextlib.suppress(ActionFailed):
                yield from self.place(None, pid, [near], free=True)
        if self.hands[pid].carried is not None or self.hands[pid].riding:
            hand = self.hands[pid]
            for r in hand.riding:
                set_arm_collisions(self.client, self.bodies.arms[pid].body, self.bodies.objects[r.name].body,
                                   enabled=True)
            if hand.constraint is not None:
                detach(self.client, hand.constraint)
            hand.carried, hand.constraint, hand.riding = None, None, []
            self._set_grip(pid, 0.04)
        try:
            yield from self.go_home(pid)
        except ActionFailed as error:
            if self.observer is not None:
                self.observer.on_log(self.time, "warning", f"{pid} could not return home: {error}")
        self.reserved[pid] = None


def _lifted(height: float, T: np.ndarray) -> np.ndarray:
    """The transform that, right-multiplied onto ``T``, raises it by ``height`` along world z."""
    up = np.eye(4)
    up[:3, 3] = T[:3, :3].T @ np.array([0.0, 0.0, height])
    return up


class _Replan(Exception):
    """The other arm was in the way: plan again from where things are now."""


