"""What a detector would report for a scene: jittered object boxes with short dropouts, hand keypoints and
boxes with frames where a hand is not found, and OpenPose body keypoints.

Everything here is in the output image's pixels (the scene's nominal 640x360 coordinates scaled per axis).
The hand boxes follow wecook's OpenPose importer (the keypoints' extent grown by 20%, at least a quarter hand
length each side) so that ``hands.csv`` and the OpenPose folder describe the same hands.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wecook_core.model import HandTrack, ObjectTrack
from wecook_core.synth.layout import HEIGHT, WIDTH
from wecook_core.synth.motion import hand_boxes, hand_keypoints
from wecook_core.synth.scene import PersonPath, Scene

BOX_JITTER = 0.7
"""Standard deviation of each box edge's jitter, pixels (clipped at 2)."""
OBJECT_DROPOUTS = 1 / 20
"""Dropouts per object per second (each 2-5 frames without a box)."""
HAND_DROPOUTS = 1 / 15
"""Dropouts per hand per second (each 2-6 frames undetected)."""


@dataclass(frozen=True, eq=False)
class HandDetections:
    hand: str
    detected: np.ndarray
    """bool ``(frames,)``."""
    keypoints: np.ndarray
    """float64 ``(frames, 21, 3)``: OpenPose hand keypoints x, y, confidence (0 where not detected)."""
    xy: np.ndarray
    """float64 ``(frames, 2)``: the hand's centre (mean of its keypoints)."""
    boxes: np.ndarray
    """float64 ``(frames, 4)``."""


@dataclass(frozen=True, eq=False)
class BodyDetections:
    person: str
    keypoints: np.ndarray
    """float64 ``(frames, 25, 3)``: BODY_25 x, y, confidence (0: not found)."""
    left: HandDetections
    right: HandDetections


def _scale(points: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    return points * np.array([size[0] / WIDTH, size[1] / HEIGHT])


def dropouts(frames: int, per_second: float, shortest: int, longest: int, fps: float,
             rng: np.random.Generator) -> np.ndarray:
    """bool ``(frames,)``: True where seen, with a few short random gaps."""
    seen = np.ones(frames, dtype=bool)
    count = rng.poisson(per_second * frames / fps)
    for start, length in zip(rng.integers(0, max(frames, 1), count), rng.integers(shortest, longest + 1, count),
                             strict=True):
        seen[start : start + length] = False
    return seen


def detect_objects(scene: Scene, size: tuple[int, int], rng: np.random.Generator) -> tuple[ObjectTrack, ...]:
    tracks = []
    for path in scene.objects:
        boxes = path.boxes()
        boxes = np.concatenate([_scale(boxes[:, :2], size), _scale(boxes[:, 2:], size)], axis=1)
        boxes += np.clip(rng.normal(0.0, BOX_JITTER, boxes.shape), -2.0, 2.0)
        boxes[:, 0::2] = np.clip(boxes[:, 0::2], 0, size[0])
        boxes[:, 1::2] = np.clip(boxes[:, 1::2], 0, size[1])
        boxes[:, 2] = np.maximum(boxes[:, 2], boxes[:, 0])
        boxes[:, 3] = np.maximum(boxes[:, 3], boxes[:, 1])
        seen = path.visible & dropouts(scene.frames, OBJECT_DROPOUTS, 2, 5, scene.fps, rng)
        frames = np.flatnonzero(seen).astype(np.int64)
        tracks.append(ObjectTrack(path.track_id, path.label, path.name, frames, np.round(boxes[seen], 1)))
    return tuple(tracks)


def _hand(arm_hand: str, centre: np.ndarray, elbow: np.ndarray, wrist: np.ndarray, size: tuple[int, int],
          fps: float, rng: np.random.Generator) -> HandDetections:
    frames = len(centre)
    c, e, w = _scale(centre, size), _scale(elbow, size), _scale(wrist, size)
    points = hand_keypoints(c, e, arm_hand.startswith("L"), rng)
    boxes = hand_boxes(points, w, e)
    detected = dropouts(frames, HAND_DROPOUTS, 2, 6, fps, rng)
    confidence = rng.uniform(0.55, 0.95, (frames, 21)) * detected[:, None]
    keypoints = np.concatenate([points, confidence[..., None]], axis=2)
    return HandDetections(arm_hand, detected, keypoints, np.round(points.mean(axis=1), 1), np.round(boxes, 1))


def _body(person: PersonPath, size: tuple[int, int], fps: float, rng: np.random.Generator) -> BodyDetections:
    frames = len(person.neck)
    forward, left = np.asarray(person.forward), np.asarray(person.left)
    neck = person.neck
    head = neck - 6 * forward
    hip = neck - 40 * forward
    arm_l, arm_r = person.arms
    points: np.ndarray = np.zeros((frames, 25, 2))
    placed = {
        0: head + 14 * forward, 1: neck,
        2: arm_r.shoulder, 3: arm_r.elbow, 4: arm_r.wrist,
        5: arm_l.shoulder, 6: arm_l.elbow, 7: arm_l.wrist,
        8: hip, 9: hip - 24 * left, 12: hip + 24 * left,
        15: head + 10 * forward - 6 * left, 16: head + 10 * forward + 6 * left,
        17: head - 12 * left, 18: head + 12 * left,
    }
    confidence = np.zeros((frames, 25))
    for index, value in placed.items():
        points[:, index] = value
        confidence[:, index] = rng.uniform(0.6, 0.95, frames)
    points = _scale(points, size) + rng.normal(0.0, 0.5, points.shape)
    inside = ((points[..., 0] >= 0) & (points[..., 0] < size[0]) & (points[..., 1] >= 0)
              & (points[..., 1] < size[1]))
    confidence *= inside
    left_hand = _hand(arm_l.hand, arm_l.centre, arm_l.elbow, arm_l.wrist, size, fps, rng)
    right_hand = _hand(arm_r.hand, arm_r.centre, arm_r.elbow, arm_r.wrist, size, fps, rng)
    confidence[:, 7] *= left_hand.detected  # an undetected hand has no wrist either
    confidence[:, 4] *= right_hand.detected
    keypoints = np.concatenate([points, confidence[..., None]], axis=2)
    return BodyDetections(person.person, keypoints, left_hand, right_hand)


def detect_bodies(scene: Scene, size: tuple[int, int], rng: np.random.Generator) -> tuple[BodyDetections, ...]:
    return tuple(_body(person, size, scene.fps, rng) for person in scene.persons)


def hand_tracks(bodies: tuple[BodyDetections, ...]) -> tuple[HandTrack, ...]:
    """The hands' tracks, in HANDS order (P1 before P2, left before right)."""
    tracks = []
    for body in sorted(bodies, key=lambda b: b.person):
        for hand in (body.left, body.right):
            frames = np.flatnonzero(hand.detected).astype(np.int64)
            tracks.append(HandTrack(hand.hand, frames, hand.xy[frames], hand.boxes[frames]))
    return tuple(tracks)
