"""Writing a scenario's persons as OpenPose would: one ``<name>_<frame:012d>_keypoints.json`` per frame,
``people[]`` in a random order each frame (OpenPose does not track persons), each with ``pose_keypoints_2d``
(BODY_25), ``hand_left_keypoints_2d`` and ``hand_right_keypoints_2d`` as flat ``x, y, confidence`` triples.

Undetected hands have all-zero keypoints and no wrist, like the frames missing from ``hands.csv``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from wecook_core.synth.scenario import Scenario

NAME = "video"


def _flat(points: np.ndarray) -> list[float]:
    """``(k, 3)`` keypoints -> OpenPose's flat list, zeros where the confidence is 0."""
    points = np.where(points[:, 2:3] > 0, points, 0.0)
    return [round(float(v), 3 if i % 3 == 2 else 2) for i, v in enumerate(points.reshape(-1))]


def write_openpose(scenario: Scenario, out_dir: str | Path, name: str = NAME) -> Path:
    """One JSON file per frame in ``out_dir`` (created), compact (no indentation)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(scenario.seed + 1)
    bodies = scenario.bodies
    for frame in range(scenario.frames):
        people = []
        for body in bodies:
            people.append({
                "person_id": [-1],
                "pose_keypoints_2d": _flat(body.keypoints[frame]),
                "face_keypoints_2d": [],
                "hand_left_keypoints_2d": _flat(body.left.keypoints[frame]),
                "hand_right_keypoints_2d": _flat(body.right.keypoints[frame]),
                "pose_keypoints_3d": [], "face_keypoints_3d": [],
                "hand_left_keypoints_3d": [], "hand_right_keypoints_3d": [],
            })
        order = rng.permutation(len(people))
        document = {"version": 1.3, "people": [people[i] for i in order]}
        (out / f"{name}_{frame:012d}_keypoints.json").write_text(json.dumps(document, separators=(",", ":")))
    return out
