"""The Franka Panda's joint limits, as the executor drives the arm within them and ``wecook runs check`` checks a
recording against them. Pure data: no simulator.

Position, velocity and effort limits are the URDF's (``pybullet_data/franka_panda/panda.urdf``, read once by
:func:`urdf_limits`); the URDF states no acceleration limits, so those are Franka's published ones: "Robot and
interface specifications", Franka Control Interface documentation
(https://frankaemika.github.io/docs/control_parameters.html#limits-for-panda): q_ddot_max = 15, 7.5, 10, 12.5, 15,
20, 20 rad/s² for joints 1-7. The gripper's finger speed is the URDF's 0.2 m/s; Franka publishes no finger
acceleration, so :data:`FINGER_ACCEL` is ours.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

ARM_JOINT_NAMES = tuple(f"panda_joint{k + 1}" for k in range(7))
FINGER_JOINT_NAMES = ("panda_finger_joint1", "panda_finger_joint2")
ARM_ACCEL = (15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0)
"""Radians per second squared, Franka's published limits (module docstring)."""
FINGER_ACCEL = 2.0
"""Metres per second squared per finger: ours (Franka publishes none); a finger reaches 0.2 m/s in 0.1 s."""


@dataclass(frozen=True)
class JointLimit:
    """One joint's limits."""

    lower: float
    upper: float
    """Radians (revolute) or metres (prismatic)."""
    velocity: float
    """Rad/s or m/s."""
    acceleration: float
    """Rad/s² or m/s²."""
    effort: float
    """N·m or N (the URDF's)."""


def panda_urdf() -> Path:
    import pybullet_data

    return Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"


@cache
def urdf_limits(path: str | None = None) -> dict[str, JointLimit]:
    """Joint name -> limits of the Panda's URDF (``path``, default :func:`panda_urdf`) with the accelerations
    above."""
    root = ET.parse(path or panda_urdf()).getroot()
    accel = dict(zip(ARM_JOINT_NAMES, ARM_ACCEL, strict=True)) | dict.fromkeys(FINGER_JOINT_NAMES, FINGER_ACCEL)
    out = {}
    for joint in root.iter("joint"):
        name, limit = joint.get("name", ""), joint.find("limit")
        if limit is None or name not in accel:
            continue
        out[name] = JointLimit(float(limit.get("lower", "0")), float(limit.get("upper", "0")),
                               float(limit.get("velocity", "0")), accel[name], float(limit.get("effort", "0")))
    return out


def arm_velocity() -> np.ndarray:
    """Rad/s of joints 1-7 (the URDF's)."""
    limits = urdf_limits()
    return np.array([limits[n].velocity for n in ARM_JOINT_NAMES])


def arm_acceleration() -> np.ndarray:
    """Rad/s² of joints 1-7 (Franka's)."""
    return np.array(ARM_ACCEL)


def finger_velocity() -> float:
    """M/s per finger (the URDF's)."""
    return urdf_limits()[FINGER_JOINT_NAMES[0]].velocity
