"""The Franka Panda of ``pybullet_data`` as the executor sees it: 7 arm joints, a two-finger gripper, an end
effector, IK and fixed-constraint grasps.

End-effector frame ``e`` = ``panda_grasptarget`` (between the fingertip pads): z points out of the gripper (the
approach direction), y is the direction the fingers open along. A top-down grasp has z_e = -z_world.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pybullet as p

from wecook_core.execution.planning.limits import (
    ARM_JOINT_NAMES,
    FINGER_JOINT_NAMES,
    arm_acceleration,
    arm_velocity,
    urdf_limits,
)
from wecook_core.execution.skills.tsr import matrix_to_pose, pose_to_matrix

ARM_JOINTS = (0, 1, 2, 3, 4, 5, 6)
FINGER_JOINTS = (9, 10)
EE_LINK = 11
"""``panda_grasptarget``."""
HAND_LINK = 8
HOME = np.array([0.0, -1.0, 0.0, -2.7, 0.0, 1.7, 0.785])
"""Radians: gripper down 26 cm in front of the base, 39 cm up; the first seed of IK."""
REST = np.array([0.0, -1.6, 0.0, -2.9, 0.0, 1.3, 0.785])
"""Radians: folded back over the base (nothing beyond 21 cm in front of it), gripper down; the arms start here and
return here between actions, leaving the table to the other arm."""
FINGER_OPEN = 0.04
"""Metres per finger (the Panda opens 8 cm)."""
LOWER = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
UPPER = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])
"""Franka's documented limits (the URDF's are close); the planner and IK keep inside them."""
MAX_SPEED = arm_velocity()
"""Radians per second (the URDF's, Franka's published ones); motions use a fraction of them."""
MAX_ACCEL = arm_acceleration()
"""Radians per second squared (Franka's published limits; the URDF has none)."""


@dataclass
class Panda:
    """One arm in one PyBullet client. Holds no simulation state of its own: it reads and writes the client's."""

    client: int
    body: int

    def q(self) -> np.ndarray:
        states = p.getJointStates(self.body, ARM_JOINTS, physicsClientId=self.client)
        return np.array([s[0] for s in states])

    def fingers(self) -> float:
        return float(p.getJointState(self.body, FINGER_JOINTS[0], physicsClientId=self.client)[0])

    def set_q(self, q: np.ndarray, fingers: float | None = None, velocity: np.ndarray | None = None) -> None:
        """Teleport the joints (and hold them there with the position motors)."""
        c = self.client
        targets = [float(v) for v in q]
        joints = list(ARM_JOINTS)
        if fingers is not None:
            targets += [float(fingers)] * 2
            joints += list(FINGER_JOINTS)
        speeds = [[0.0]] * len(joints) if velocity is None else [[float(v)] for v in velocity] + [[0.0]] * (
            len(joints) - 7)
        p.resetJointStatesMultiDof(self.body, joints, [[v] for v in targets], speeds, physicsClientId=c)
        p.setJointMotorControlArray(self.body, joints, p.POSITION_CONTROL, targetPositions=targets,
                                    forces=[500.0] * len(joints), physicsClientId=c)

    def ee(self) -> np.ndarray:
        """4x4 world pose of the end effector (current joints)."""
        state = p.getLinkState(self.body, EE_LINK, computeForwardKinematics=True, physicsClientId=self.client)
        return pose_to_matrix((state[4], state[5]))

    def link_pose(self, link: int) -> np.ndarray:
        state = p.getLinkState(self.body, link, computeForwardKinematics=True, physicsClientId=self.client)
        return pose_to_matrix((state[4], state[5]))

    def fk(self, q: np.ndarray) -> np.ndarray:
        """End-effector pose at ``q``. Moves the joints: use on the planning client."""
        self.set_q(q)
        return self.ee()

    def ik(self, target: np.ndarray, rng: np.random.Generator, seed_q: np.ndarray | None = None, *,
           tolerance: float = 1e-4, angle_tolerance: float = 1e-3, iterations: int = 20,
           restarts: int = 4) -> np.ndarray | None:
        """Joints reaching ``target`` (4x4) within ``tolerance`` metres and ``angle_tolerance`` radians and inside
        the joint limits, or None. One PyBullet IK call is ~1 cm off; it is called again from its own answer
        (re-seeding) up to ``iterations`` times, from ``seed_q`` first and then from random restarts.
        Moves the joints: use on the planning client."""
        c = self.client
        pos = target[:3, 3].tolist()
        orn = list(matrix_to_pose(target)[1])
        seeds = [HOME if seed_q is None else seed_q] + [rng.uniform(LOWER, UPPER) for _ in range(restarts)]
        lower, upper = [*list(LOWER), 0.0, 0.0], [*list(UPPER), 0.04, 0.04]
        ranges = [u - lo for u, lo in zip(upper, lower, strict=True)]
        fingers = self.fingers()
        for start in seeds:
            q = np.array(start, dtype=float)
            for _ in range(iterations):
                self.set_q(q, fingers)
                solution = p.calculateInverseKinematics(
                    self.body, EE_LINK, pos, orn, lowerLimits=lower, upperLimits=upper, jointRanges=ranges,
                    restPoses=[*map(float, q), fingers, fingers], maxNumIterations=60, residualThreshold=1e-6,
                    physicsClientId=c)
                q = np.clip(np.array(solution[:7]), LOWER, UPPER)
                reached = self.fk(q)
                err = np.linalg.norm(reached[:3, 3] - target[:3, 3])
                cos = (np.trace(reached[:3, :3].T @ target[:3, :3]) - 1) / 2
                angle = float(np.arccos(np.clip(cos, -1.0, 1.0)))
                if err <= tolerance and angle <= angle_tolerance:
                    return q
        return None

    def finger_pair(self) -> tuple[float, float]:
        """Each finger's opening (metres), from its own joint."""
        states = p.getJointStates(self.body, FINGER_JOINTS, physicsClientId=self.client)
        return float(states[0][0]), float(states[1][0])

    def set_fingers(self, width: float | tuple[float, float], velocity: tuple[float, float] = (0.0, 0.0)) -> None:
        """Finger opening per finger (metres; one for both, or each its own), held by the motors."""
        widths = (width, width) if isinstance(width, float | int) else width
        for j, w, v in zip(FINGER_JOINTS, widths, velocity, strict=True):
            p.resetJointState(self.body, j, float(w), float(v), physicsClientId=self.client)
        p.setJointMotorControlArray(self.body, list(FINGER_JOINTS), p.POSITION_CONTROL,
                                    targetPositions=[float(w) for w in widths], forces=[50.0, 50.0],
                                    physicsClientId=self.client)


def drive(arm: Panda, q: np.ndarray, fingers: tuple[float, float]) -> None:
    """Physics mode: position control of the arm's joints toward ``q`` and of the fingers toward ``fingers``,
    each motor within its URDF effort and velocity limits."""
    c = arm.client
    limits = urdf_limits()
    for j, (name, target) in enumerate(zip(ARM_JOINT_NAMES, q, strict=True)):
        lim = limits[name]
        p.setJointMotorControl2(arm.body, ARM_JOINTS[j], p.POSITION_CONTROL, targetPosition=float(target),
                                force=lim.effort, maxVelocity=lim.velocity, positionGain=0.3, velocityGain=1.0,
                                physicsClientId=c)
    for joint, name, target in zip(FINGER_JOINTS, FINGER_JOINT_NAMES, fingers, strict=True):
        lim = limits[name]
        p.setJointMotorControl2(arm.body, joint, p.POSITION_CONTROL, targetPosition=max(float(target), 0.0),
                                force=lim.effort, maxVelocity=lim.velocity, physicsClientId=c)


def grip_friction(arm: Panda, friction: float = 1.5) -> None:
    """The fingers' pads grip (physics mode): high lateral and some spinning friction."""
    for link in FINGER_JOINTS:
        p.changeDynamics(arm.body, link, lateralFriction=friction, spinningFriction=0.05,
                         physicsClientId=arm.client)


def attach(client: int, arm_body: int, obj: int) -> tuple[int, np.ndarray]:
    """Fix ``obj`` to the hand where it is now: a JOINT_FIXED constraint (hand link -> object), collisions between
    the object and this arm switched off. Returns the constraint id and the ee <- object transform."""
    ee = p.getLinkState(arm_body, EE_LINK, computeForwardKinematics=True, physicsClientId=client)
    pos, orn = p.getBasePositionAndOrientation(obj, physicsClientId=client)
    T_ee_obj = np.linalg.inv(pose_to_matrix((ee[4], ee[5]))) @ pose_to_matrix((pos, orn))
    set_arm_collisions(client, arm_body, obj, enabled=False)
    inv_pos, inv_orn = p.invertTransform(ee[4], ee[5])
    local_pos, local_orn = p.multiplyTransforms(inv_pos, inv_orn, pos, orn)
    constraint = p.createConstraint(arm_body, EE_LINK, obj, -1, p.JOINT_FIXED, [0, 0, 0], local_pos, [0, 0, 0],
                                    parentFrameOrientation=local_orn, physicsClientId=client)
    p.changeConstraint(constraint, maxForce=2000, physicsClientId=client)
    return constraint, T_ee_obj


def detach(client: int, constraint: int) -> None:
    p.removeConstraint(constraint, physicsClientId=client)


def set_arm_collisions(client: int, arm_body: int, obj: int, *, enabled: bool) -> None:
    for link in range(-1, p.getNumJoints(arm_body, physicsClientId=client)):
        p.setCollisionFilterPair(arm_body, obj, link, -1, int(enabled), physicsClientId=client)
