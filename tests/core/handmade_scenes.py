"""Small hand-built observations with known answers, for the association, action and graph tests.

A track is a list of pieces ``(first_frame, end_frame, box_at_first, box_at_end)``: the box moves linearly
over ``[first_frame, end_frame)``. Images are 640 x 480.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from wecook_core.model import Category, HandTrack, ObjectTrack, Observations, VideoInfo

Box = tuple[float, float, float, float]
Piece = tuple[int, int, Box, Box]


def _frames_boxes(pieces: Sequence[Piece]) -> tuple[np.ndarray, np.ndarray]:
    frames, boxes = [], []
    for first, end, a, b in pieces:
        n = end - first
        t = np.linspace(0.0, 1.0, n, endpoint=False)[:, None] if n > 1 else np.zeros((1, 1))
        frames.append(np.arange(first, end))
        boxes.append(np.asarray(a, float) + t * (np.asarray(b, float) - np.asarray(a, float)))
    return np.concatenate(frames).astype(np.int64), np.concatenate(boxes)


def still(first: int, end: int, box: Box) -> Piece:
    return (first, end, box, box)


def at(box: Box, dx: float = 0, dy: float = 0) -> Box:
    return (box[0] + dx, box[1] + dy, box[2] + dx, box[3] + dy)


def observations(
    frame_count: int,
    objects: Mapping[str, tuple[Category, Sequence[Piece]]],
    hands: Mapping[str, Sequence[Piece]],
) -> Observations:
    tracks = []
    for i, (name, (_, pieces)) in enumerate(objects.items()):
        frames, boxes = _frames_boxes(pieces)
        tracks.append(ObjectTrack(i + 1, name.replace("_", " "), name, frames, boxes))
    hand_tracks = []
    for hand, pieces in hands.items():
        frames, boxes = _frames_boxes(pieces)
        xy = np.stack([(boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2], axis=1)
        hand_tracks.append(HandTrack(hand, frames, xy, boxes))
    return Observations(
        VideoInfo("handmade.mp4", 30.0, frame_count, 640, 480),
        tuple(tracks),
        tuple(hand_tracks),
        {name: category for name, (category, _) in objects.items()},
    )


BOARD: Box = (100, 300, 400, 450)
TOMATO: Box = (200, 340, 240, 380)
KNIFE_REST: Box = (500, 300, 600, 320)
KNIFE_CUT: Box = (205, 330, 285, 350)
HAND_AWAY: Box = (580, 150, 620, 190)


def cutting(frame_count: int = 150) -> Observations:
    """RH_P1 grasps the knife at frame 30, cuts the tomato on the board over 60-120, puts it back by 150."""
    hand_on = (575, 295, 605, 325)  # over the knife's handle end
    return observations(
        frame_count,
        {
            "chopping_board": (Category.CONTAINER, [still(0, frame_count, BOARD)]),
            "tomato": (Category.INGREDIENT, [still(0, frame_count, TOMATO)]),
            "knife": (Category.TOOL, [still(0, 30, KNIFE_REST), (30, 60, KNIFE_REST, KNIFE_CUT),
                                      still(60, 120, KNIFE_CUT), (120, 150, KNIFE_CUT, KNIFE_REST)]),
        },
        {
            "RH_P1": [(0, 30, HAND_AWAY, hand_on), (30, 60, hand_on, at(hand_on, -295, 30)),
                      still(60, 120, at(hand_on, -295, 30)), (120, 150, at(hand_on, -295, 30), hand_on)],
        },
    )
