"""Where the gripper's fingers go around what they take (pure geometry, no simulator): how wide they must open
to pass down around an object to a grasp pose without entering it (:func:`open_around`)."""

from __future__ import annotations

import itertools

import numpy as np

FINGER_HALF_WIDTH = 0.011
"""Metres either side of the grasp target, along the hand's x axis, that a Panda finger's pad spans."""
FINGER_TIP = 0.0074
"""Metres the Panda's fingertips reach beyond the grasp target (``panda_grasptarget``) along the approach."""
FINGER_CLEARANCE = 0.003
"""Metres between a finger passing down beside an object and the object."""
FULL_OPEN = 0.04
"""Metres per finger: the Panda gripper's widest opening."""

_TRIPLES = np.array(list(itertools.combinations(range(9), 3)))


def half_span(pose: np.ndarray, half: np.ndarray, grasp: np.ndarray) -> float:
    """Metres from the grasp's axis, along its finger axis (y), to the farthest point of the box at ``pose``
    (4x4, half extents ``half``) that the fingers pass by on their way down to ``grasp`` (4x4, z the approach):
    the part of the box within the fingers' width (:data:`FINGER_HALF_WIDTH` along x) and above their tips
    (:data:`FINGER_TIP` along z); 0 when none of it is. Exact: the largest ``|y|`` over the vertices of the box
    cut by those planes."""
    A = grasp[:3, :3].T @ pose[:3, :3]  # box coordinates -> grasp coordinates
    b = grasp[:3, :3].T @ (pose[:3, 3] - grasp[:3, 3])
    eye = np.eye(3)
    normals = np.vstack([eye, -eye, A[0], -A[0], A[2]])
    limits = np.concatenate([half, half, [FINGER_HALF_WIDTH - b[0], FINGER_HALF_WIDTH + b[0], FINGER_TIP - b[2]]])
    N, d = normals[_TRIPLES], limits[_TRIPLES]
    ok = np.abs(np.linalg.det(N)) > 1e-9
    points = np.linalg.solve(N[ok], d[ok][..., None])[..., 0]
    inside = np.all(points @ normals.T <= limits + 1e-9, axis=1)
    if not np.any(inside):
        return 0.0
    return float(np.max(np.abs(points[inside] @ A[1] + b[1])))


def open_around(pose: np.ndarray, half: np.ndarray, grasp: np.ndarray, least: float) -> float:
    """Metres per finger to open for the way down to ``grasp`` around the box at ``pose``: ``least``, or wider
    when the box reaches farther across the fingers (:func:`half_span`, plus :data:`FINGER_CLEARANCE`; a tool
    lying tilted, or taken turned across its handle, is wider there than its own width), at most
    :data:`FULL_OPEN`. The grasp asks it for boxes lying tilted only: turned grasps of flat tools open as the grip
    says (opened wider, synthetic plan 9 at run seed 0 held its spoon otherwise and its stir found the holder's
    arm in every pose)."""
    return min(max(least, half_span(pose, half, grasp) + FINGER_CLEARANCE), FULL_OPEN)
