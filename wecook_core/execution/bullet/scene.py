"""The scene of the PyBullet world (:mod:`wecook_core.execution.world`), a :class:`~.protocols.Scene`: the
simulating and the planning client with the plan's scene, what each hand holds, the clock and its steps, what the
observer is told (states at 30 Hz, arm contacts, events, camera images at action boundaries), and where things are
(object poses, the frames TSRs are expressed in)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence
from typing import Literal

import numpy as np
import pybullet as p

from wecook_core.execution.bullet.bodies import SIM_HZ, SceneBodies, build_scene, link_frames, world_poses
from wecook_core.execution.bullet.planning_scene import PlanningScene
from wecook_core.execution.bullet.robot import (
    EE_LINK,
    REST,
    Panda,
    attach,
    detach,
    drive,
    grip_friction,
    set_arm_collisions,
)
from wecook_core.execution.planning.limits import FINGER_ACCEL, finger_velocity
from wecook_core.execution.planning.timing import toward
from wecook_core.execution.schedule.observer import FrameInfo, RunEvent, RunObserver
from wecook_core.execution.schedule.program import WORK, Program
from wecook_core.execution.skills.library import Half, SkillLibrary, object_kind
from wecook_core.execution.skills.tsr import pose_to_matrix
from wecook_core.execution.world.protocols import Hand, Riding
from wecook_core.model import Category
from wecook_core.plan import Plan, PlanAction

JOINT_NAMES = [f"panda_joint{k + 1}" for k in range(7)] + ["panda_finger_joint1", "panda_finger_joint2"]
FINGER_SPEED = finger_velocity()
"""Metres per second per finger (the URDF's)."""
SQUEEZE = 0.004
"""Metres per finger the physics mode's finger motors aim inside what they grip (they press with the URDF's
effort, 20 N, and stop on it)."""
STATE_EVERY = SIM_HZ // 30
"""Steps between two ``on_state`` calls (30 Hz)."""
CONTACT_EVERY = 2
"""Steps between two arm-arm contact queries."""
TOUCH_DEPTH = 0.0005
"""Metres of penetration from which two arms count as touching (contact points closer than zero)."""
IMAGE_SIZE = (320, 240)
"""Pixels of the camera images taken at action boundaries."""


class BulletScene:
    """The scene in two PyBullet clients: the simulation stepped with the arms where they are commanded, and the
    planning copy the arms plan in."""

    def __init__(self, plan: Plan, observer: RunObserver | None, skills: SkillLibrary, *, realtime: bool = False,
                 images: bool = True, dynamics: bool = False):
        self.plan = plan
        self.dynamics = dynamics
        """Physics mode: the joints follow their commands by position control within the URDF's effort and
        velocity limits (:func:`~.robot.drive`), held objects by the fingers' friction (no constraint, the
        arm's collisions with them on); else the joints are set to their commands every step."""
        self.observer = observer
        self.skills = skills
        self.client = p.connect(p.DIRECT)
        self.bodies: SceneBodies = build_scene(self.client, plan)
        self.planning = PlanningScene(plan)
        self.robots = {pid: Panda(self.client, arm.body) for pid, arm in self.bodies.arms.items()}
        self.realtime = realtime
        self.images = images
        self.steps = 0
        self.wall_start = time.perf_counter()
        self.hands = {pid: Hand() for pid in self.robots}
        self.commands: dict[str, np.ndarray] = {}
        """Arm -> the joints it is commanded to (where it is at the next step)."""
        self.arm_contacts = 0
        self.ended: list[Callable[[str], None]] = []
        """Called with the arm whose primitive ended or failed."""
        self._picked_from: dict[str, np.ndarray] = {}
        """Object -> its pose when last grasped (where a failed action puts it back)."""
        self._touching = False
        self._riding: set[str] = set()
        """Objects riding on a hand at the last step."""
        self.fingers: dict[str, list[list[float]]] = {}
        """Arm -> each finger's [opening (m), speed (m/s), target (m)]: the fingers are driven to their targets
        within the gripper's limits, a step at a time."""
        for pid, arm in self.robots.items():
            arm.set_q(REST, 0.04)
            self.commands[pid] = REST.copy()
            self.fingers[pid] = [[0.04, 0.0, 0.04], [0.04, 0.0, 0.04]]
        self.squeeze = {pid: (0.0, 0.0) for pid in self.robots}
        """Arm -> metres each finger's motor target lies inside what it grips (physics mode: it presses)."""
        if dynamics:
            for arm in self.robots.values():
                grip_friction(arm)
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

    @property
    def hz(self) -> int:
        return SIM_HZ

    @property
    def table_height(self) -> float:
        return self.bodies.table_height

    def close(self) -> None:
        self.planning.close()
        if p.isConnected(self.client):
            p.disconnect(self.client)

    def frames(self) -> list[FrameInfo]:
        return self._frames

    def hold(self, seconds: float) -> Program:
        """``seconds``, and on until every finger has reached its target."""
        for _ in range(max(int(seconds * SIM_HZ), 1)):
            yield WORK
        while self.fingers_moving():
            yield WORK

    def fingers_moving(self) -> bool:
        return any(f[0] != f[2] or f[1] != 0.0 for fingers in self.fingers.values() for f in fingers)

    def sync(self) -> None:
        """The planning copy brought up to date, each finger where it is driven to (plans are for when it is
        there: a grasp's goals are checked with the fingers at the approach opening just set, not still wide)."""
        self.planning.sync(self.bodies, {pid: h.riding for pid, h in self.hands.items()})
        for pid, arm in self.planning.arms.items():
            fingers = self.fingers[pid]
            arm.set_fingers((fingers[0][2], fingers[1][2]))

    def log(self, level: Literal["debug", "info", "warning", "error"], text: str) -> None:
        if self.observer is not None:
            self.observer.on_log(self.time, level, text)

    def step(self) -> None:
        c = self.client
        for pid, arm in self.robots.items():
            fingers = self.fingers[pid]
            for f in fingers:
                if f[0] != f[2] or f[1] != 0.0:
                    f[0], f[1] = toward(f[0], f[1], f[2], FINGER_SPEED, FINGER_ACCEL, 1 / SIM_HZ)
            if self.dynamics:  # driven: the motors pull toward the commands, within their limits
                drive(arm, self.commands[pid], (fingers[0][0] - self.squeeze[pid][0],
                                                fingers[1][0] - self.squeeze[pid][1]))
                continue
            arm.set_q(self.commands[pid])  # kinematic arms: exactly where commanded, every step
            # kinematic fingers too: where driven, never pushed by contacts, and at rest to the physics as the arm
            # joints are (a finger set moving would shove what it touches)
            arm.set_fingers((fingers[0][0], fingers[1][0]))
        for pid, hand in self.hands.items():
            if hand.riding and not self.dynamics:
                state = p.getLinkState(self.bodies.arms[pid].body, EE_LINK, computeForwardKinematics=True,
                                       physicsClientId=c)
                for r in hand.riding:
                    body = self.bodies.objects[r.name].body
                    local = r.local
                    pos, orn = p.multiplyTransforms(state[4], state[5], local[0], local[1])
                    p.resetBasePositionAndOrientation(body, pos, orn, physicsClientId=c)
                    p.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0], physicsClientId=c)
        riding = {r.name for hand in self.hands.values() for r in hand.riding}
        for name in self._riding - riding:  # let go: resting objects sleep (scene.py), this one must fall
            p.changeDynamics(self.bodies.objects[name].body, -1, activationState=p.ACTIVATION_STATE_WAKE_UP,
                             physicsClientId=c)
        self._riding = riding
        p.stepSimulation(physicsClientId=c)
        self.steps += 1
        if self.steps % CONTACT_EVERY == 0:
            self._check_arm_contact()
        if self.steps % STATE_EVERY == 0:
            if not self.dynamics:  # a contact may have nudged a joint during the step: kinematic joints are where
                self._reassert()  # commanded, and the recording says so (a finger pushed 2 mm showed as 2.5 m/s²)
            self.publish_state()
        if self.realtime:
            ahead = self.time - (time.perf_counter() - self.wall_start)
            if ahead > 0:
                time.sleep(ahead)

    def _reassert(self) -> None:
        for pid, arm in self.robots.items():
            fingers = self.fingers[pid]
            arm.set_q(self.commands[pid])
            arm.set_fingers((fingers[0][0], fingers[1][0]))

    def publish_state(self) -> None:
        if self.observer is None:
            return
        joints = {pid: (JOINT_NAMES, [*arm.q(), *arm.finger_pair()]) for pid, arm in self.robots.items()}
        self.observer.on_state(self.time, world_poses(self.bodies), joints)

    def _check_arm_contact(self) -> None:
        """Count each new touch (penetration deeper than :data:`TOUCH_DEPTH`) between the two arms' links."""
        c = self.client
        pids = sorted(self.robots)
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
            self.event("primitive_failed", None, None, detail)  # logged as an error by event()
        self._touching = touching

    def event(self, kind: str, action: PlanAction | None, pid: str | None, detail: str = "",
              primitive: str | None = None) -> None:
        if kind in ("primitive_end", "primitive_failed") and pid is not None:
            for call in self.ended:
                call(pid)
        if kind in ("retry", "primitive_failed"):  # in /log too, with their level
            who = " ".join(x for x in (action.id if action else None, pid, primitive) if x)
            self.log("warning" if kind == "retry" else "error",
                     (f"{who}: " if who else "") + f"{kind.replace('_', ' ')}: {detail}")
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

    def facing(self, name: str, pid: str) -> np.ndarray:
        T = self.pose(name)
        base = self.bodies.arms[pid].base[:3, 3]
        yaw = math.atan2(base[1] - T[1, 3], base[0] - T[0, 3])
        out = np.eye(4)
        out[:3, :3] = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
        out[:3, 3] = T[:3, 3]
        return out

    def meet(self, giver: str, receiver: str) -> np.ndarray:
        a, b = self.bodies.arms[giver].base[:3, 3], self.bodies.arms[receiver].base[:3, 3]
        yaw = math.atan2(b[1] - a[1], b[0] - a[0])
        out = np.eye(4)
        out[:3, :3] = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
        out[:3, 3] = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, self.bodies.table_height + self.skills.meet_height]
        return out

    def drop(self, pid: str) -> np.ndarray:
        base = self.bodies.arms[pid].base
        out = base.copy()
        out[:3, 3] = base[:3, 3] + base[:3, 0] * self.skills.drop_distance
        out[2, 3] = self.bodies.table_height
        out[:3, :3] = base[:3, :3] @ np.diag([-1.0, -1.0, 1.0])  # x toward the arm
        return out

    def upright(self, name: str) -> np.ndarray:
        """The object's pose as a frame for TSRs; a sphere's only by its position (it turns as it rolls, so its
        own axes say nothing: its frame is the world's, and a hand takes it from above)."""
        T = self.pose(name)
        if self.plan.scene.object(name).shape == "sphere":
            T[:3, :3] = np.eye(3)
        return T

    def kind(self, name: str) -> str:
        b = self.bodies.objects[name]
        return object_kind(b.category, b.size, b.open_top)

    def container_of(self, name: str) -> str | None:
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

    def contents(self, name: str) -> list[str]:
        if self.bodies.objects[name].category is not Category.CONTAINER:
            return []
        return [n for n, b in self.bodies.objects.items()
                if b.category is Category.INGREDIENT and n != name and self.container_of(n) == name]

    def names(self) -> list[str]:
        return list(self.bodies.objects)

    def category(self, name: str) -> Category:
        return self.bodies.objects[name].category

    def shape(self, name: str) -> str:
        return self.plan.scene.object(name).shape

    def size(self, name: str) -> tuple[float, float, float]:
        s = self.bodies.objects[name].size
        return (s[0], s[1], s[2])

    def supports(self, name: str) -> list[str]:
        return [c for n, c in self.plan.scene.containing if n == name]

    def boxes(self, names: Iterable[str]) -> list[np.ndarray]:
        return [np.array(p.getAABB(self.bodies.objects[n].body, physicsClientId=self.client)) for n in names]

    def base(self, pid: str) -> np.ndarray:
        return self.bodies.arms[pid].base

    # ------------------------------------------------------------------------------- hands

    def hand(self, pid: str) -> Hand:
        return self.hands[pid]

    def picked_from(self, name: str) -> np.ndarray | None:
        return self._picked_from.get(name)

    def attach(self, pid: str, name: str) -> None:
        self._picked_from[name] = self.pose(name)
        if self.dynamics:  # held by the fingers' friction: no constraint, the arm still collides with it
            constraint, T_ee_obj = None, np.linalg.inv(self.robots[pid].ee()) @ self.pose(name)
        else:
            constraint, T_ee_obj = attach(self.client, self.bodies.arms[pid].body, self.bodies.objects[name].body)
        hand = self.hands[pid]
        hand.carried, hand.constraint = name, constraint
        hand.riding = [Riding(name, T_ee_obj)]

    def detach(self, pid: str) -> None:
        hand = self.hands[pid]
        self.squeeze[pid] = (0.0, 0.0)
        if hand.constraint is not None:
            detach(self.client, hand.constraint)
        hand.carried, hand.constraint, hand.riding = None, None, []

    def ride(self, pid: str, name: str, T_ee_obj: np.ndarray | None = None) -> None:
        for other, hand in self.hands.items():
            if other != pid:
                hand.riding = [r for r in hand.riding if r.name != name]
        T = np.linalg.inv(self.robots[pid].ee()) @ self.pose(name) if T_ee_obj is None else T_ee_obj
        self.hands[pid].riding.append(Riding(name, T))
        self.collide_with_arm(pid, name, enabled=False)

    def drop_riding(self, pid: str, names: Iterable[str]) -> None:
        gone = set(names)
        hand = self.hands[pid]
        hand.riding = [r for r in hand.riding if r.name not in gone]

    def holder_of(self, name: str, pid: str) -> str | None:
        return next((k for k, h in self.hands.items() if k != pid and any(r.name == name for r in h.riding)), None)

    def collide_with_arm(self, pid: str, name: str, *, enabled: bool) -> None:
        if self.dynamics:  # the fingers hold by touching: the arm always collides with the objects
            return
        set_arm_collisions(self.client, self.bodies.arms[pid].body, self.bodies.objects[name].body, enabled=enabled)

    def set_collisions(self, pairs: Sequence[tuple[str, str]], *, enabled: bool) -> None:
        for a, b in pairs:
            p.setCollisionFilterPair(self.bodies.objects[a].body, self.bodies.objects[b].body, -1, -1, int(enabled),
                                     physicsClientId=self.client)

    def set_fingers(self, pid: str, openings: tuple[float, float], grips: bool = False) -> None:
        """Drive each finger to its own opening (metres); ``grips``: the openings are where the fingers touch
        what they take (physics mode: the motors then aim :data:`SQUEEZE` inside it and press)."""
        self.squeeze[pid] = (SQUEEZE, SQUEEZE) if grips and self.dynamics else (0.0, 0.0)
        self.hands[pid].grip = (openings[0] + openings[1]) / 2
        for f, w in zip(self.fingers[pid], openings, strict=True):
            f[2] = float(w)

    def set_grip(self, pid: str, width: float) -> None:
        """Drive both fingers to ``width`` each (metres); they get there over the next steps."""
        self.hands[pid].grip = width
        for f in self.fingers[pid]:
            f[2] = float(width)
