"""Task Space Regions (Berenson, Srinivasa, Kuffner 2011): a set of end-effector poses around a frame.

Conventions (the same as the paper and personalrobotics/tsr):

- Poses are 4x4 homogeneous matrices ``T_a_b`` mapping coordinates in frame ``b`` to frame ``a``; ``0`` is the
  world (z up, metres), ``w`` the TSR frame, ``e`` the end effector (or the held object it stands for).
- A displacement ``d = (x, y, z, roll, pitch, yaw)`` of the ``w`` frame, in metres and radians, is drawn
  uniformly within ``Bw``; ``roll, pitch, yaw`` are extrinsic rotations about x, then y, then z
  (scipy ``"xyz"``). A sample is ``T0_e = T0_w @ T(d) @ Tw_e``.
- ``Bw[i] = (low, high)``; equal bounds pin a coordinate.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]
"""``(position xyz metres, quaternion xyzw)``, the pose type of the observer protocol and PyBullet."""


@dataclass(frozen=True, eq=False)
class TSR:
    """A Task Space Region. Arrays are copied and made read-only at construction."""

    T0_w: np.ndarray
    """float64 (4, 4): world <- TSR frame (e.g. an object's pose)."""
    Tw_e: np.ndarray
    """float64 (4, 4): TSR frame <- end effector at zero displacement (the offset)."""
    Bw: np.ndarray
    """float64 (6, 2): bounds of the displacement (x, y, z metres; roll, pitch, yaw radians)."""

    def __post_init__(self) -> None:
        for name, shape in (("T0_w", (4, 4)), ("Tw_e", (4, 4)), ("Bw", (6, 2))):
            value = np.array(getattr(self, name), dtype=np.float64)
            if value.shape != shape:
                raise ValueError(f"TSR.{name} must have shape {shape}, got {value.shape}")
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        if np.any(self.Bw[:, 0] > self.Bw[:, 1]):
            raise ValueError(f"TSR bounds must have low <= high, got {self.Bw.tolist()}")


def xyzrpy_to_matrix(d: Sequence[float] | np.ndarray) -> np.ndarray:
    """``(x, y, z, roll, pitch, yaw)`` -> 4x4 (rotations extrinsic x, y, z)."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", d[3:6]).as_matrix()
    T[:3, 3] = d[:3]
    return T


def matrix_to_xyzrpy(T: np.ndarray) -> np.ndarray:
    return np.concatenate([T[:3, 3], Rotation.from_matrix(T[:3, :3]).as_euler("xyz")])


def pose_to_matrix(pose: Pose | tuple[Sequence[float], Sequence[float]]) -> np.ndarray:
    """``(xyz, quaternion xyzw)`` -> 4x4."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_quat(pose[1]).as_matrix()
    T[:3, 3] = pose[0]
    return T


def matrix_to_pose(T: np.ndarray) -> Pose:
    q = Rotation.from_matrix(T[:3, :3]).as_quat()
    p = T[:3, 3]
    return (float(p[0]), float(p[1]), float(p[2])), (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def make_tsr(T0_w: np.ndarray, offset: Sequence[float] = (0, 0, 0, 0, 0, 0),
             bounds: Sequence[Sequence[float]] | None = None) -> TSR:
    """A TSR from a frame, an ``(x, y, z, roll, pitch, yaw)`` offset and bounds (default: a single pose)."""
    Bw = np.zeros((6, 2)) if bounds is None else np.asarray(bounds, dtype=np.float64)
    return TSR(T0_w=T0_w, Tw_e=xyzrpy_to_matrix(offset), Bw=Bw)


def sample(tsr: TSR, rng: np.random.Generator | None = None) -> np.ndarray:
    """One end-effector pose of the region, 4x4 in the world frame."""
    rng = rng if rng is not None else np.random.default_rng()
    d = rng.uniform(tsr.Bw[:, 0], tsr.Bw[:, 1])
    return tsr.T0_w @ xyzrpy_to_matrix(d) @ tsr.Tw_e


def displacement(tsr: TSR, T0_e: np.ndarray) -> np.ndarray:
    """The ``(x, y, z, roll, pitch, yaw)`` displacement that maps the offset onto ``T0_e``."""
    Tw = np.linalg.inv(tsr.T0_w) @ T0_e @ np.linalg.inv(tsr.Tw_e)
    return matrix_to_xyzrpy(Tw)


def distance(tsr: TSR, T0_e: np.ndarray) -> float:
    """How far a pose is outside the region: metres of position excess plus radians of angle excess.

    Zero inside. Angles are compared on the circle, so bounds spanning [-pi, pi] accept every angle.
    """
    d = displacement(tsr, T0_e)
    low, high = tsr.Bw[:, 0], tsr.Bw[:, 1]
    excess = np.zeros(6)
    excess[:3] = np.maximum(low[:3] - d[:3], 0) + np.maximum(d[:3] - high[:3], 0)
    for i in range(3, 6):
        if high[i] - low[i] >= 2 * np.pi - 1e-9:
            continue
        centre = (low[i] + high[i]) / 2
        offset = (d[i] - centre + np.pi) % (2 * np.pi) - np.pi
        excess[i] = max(abs(offset) - (high[i] - low[i]) / 2, 0.0)
    return float(np.linalg.norm(excess[:3]) + np.linalg.norm(excess[3:]))


def contains(tsr: TSR, T0_e: np.ndarray, tolerance: float = 1e-6) -> bool:
    return distance(tsr, T0_e) <= tolerance
