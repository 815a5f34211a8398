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


LEMON: Box = (300, 150, 330, 180)


def squeezing(frame_count: int = 90) -> Observations:
    """LH_P1 holds a lemon in the air and squeezes it (the hand hardly moves) over the whole video."""
    hand = (305, 160, 335, 190)
    return observations(
        frame_count,
        {"lemon": (Category.INGREDIENT, [still(0, frame_count, LEMON)]),
         "bowl": (Category.CONTAINER, [still(0, frame_count, (400, 350, 520, 420))])},
        {"LH_P1": [still(0, frame_count, hand)]},
    )


POT: Box = (300, 300, 450, 420)
OIL_REST: Box = (100, 200, 130, 260)
OIL_POUR: Box = (340, 240, 370, 300)
OIL_TIPPED: Box = (325, 255, 385, 285)
"""The bottle lying over the pot: a pour tips it."""


def pouring(frame_count: int = 120) -> Observations:
    """RH_P1 grasps the oil at 0, brings it over the pot by 30, tips it (30-45) and pours until 75, sets it
    upright by 90, puts it back by 120."""
    grip = (105, 220, 135, 250)
    over = at(grip, 240, 40)
    return observations(
        frame_count,
        {"oil": (Category.INGREDIENT, [(0, 30, OIL_REST, OIL_POUR), (30, 45, OIL_POUR, OIL_TIPPED),
                                       still(45, 75, OIL_TIPPED), (75, 90, OIL_TIPPED, OIL_POUR),
                                       (90, 120, OIL_POUR, OIL_REST)]),
         "pot": (Category.CONTAINER, [still(0, frame_count, POT)])},
        {"RH_P1": [(0, 30, grip, over), still(30, 90, over), (90, 120, over, grip)]},
    )


BOWL: Box = (60, 320, 200, 420)
MEAT_IN_BOWL: Box = (110, 350, 150, 390)
MEAT_IN_POT: Box = (360, 340, 400, 380)


def transferring(frame_count: int = 150) -> Observations:
    """RH_P1 takes a spoon at 0, scoops the meat out of the bowl (30-45), carries it (45-90) into the pot
    (90-105), puts the spoon back (105-150)."""
    spoon_rest = (250, 200, 270, 260)
    spoon_bowl = (115, 330, 135, 390)
    spoon_pot = (365, 320, 385, 380)
    hand_rest, hand_bowl, hand_pot = (245, 195, 275, 225), (110, 325, 140, 355), (360, 315, 390, 345)
    return observations(
        frame_count,
        {"bowl": (Category.CONTAINER, [still(0, frame_count, BOWL)]),
         "pot": (Category.CONTAINER, [still(0, frame_count, POT)]),
         "meat": (Category.INGREDIENT, [still(0, 45, MEAT_IN_BOWL), (45, 90, MEAT_IN_BOWL, MEAT_IN_POT),
                                        still(90, frame_count, MEAT_IN_POT)]),
         "spoon": (Category.TOOL, [(0, 30, spoon_rest, spoon_bowl), still(30, 45, spoon_bowl),
                                   (45, 90, spoon_bowl, spoon_pot), still(90, 105, spoon_pot),
                                   (105, 150, spoon_pot, spoon_rest)])},
        {"RH_P1": [(0, 30, hand_rest, hand_bowl), still(30, 45, hand_bowl), (45, 90, hand_bowl, hand_pot),
                   still(90, 105, hand_pot), (105, 150, hand_pot, hand_rest)]},
    )


def handing_over(frame_count: int = 120) -> Observations:
    """RH_P1 carries a knife to the middle (0-50); LH_P2 takes it (50-60, both hold it); P2 takes it away."""
    knife_left, knife_mid, knife_right = (100, 200, 180, 215), (280, 200, 360, 215), (460, 200, 540, 215)
    p1_left, p1_mid = (95, 195, 125, 225), (275, 195, 305, 225)
    p2_mid, p2_right = (335, 195, 365, 225), (515, 195, 545, 225)
    return observations(
        frame_count,
        {"knife": (Category.TOOL, [(0, 50, knife_left, knife_mid), still(50, 60, knife_mid),
                                   (60, 120, knife_mid, knife_right)])},
        {"RH_P1": [(0, 50, p1_left, p1_mid), still(50, 60, p1_mid), (60, 120, p1_mid, (100, 100, 130, 130))],
         "LH_P2": [(0, 40, (560, 100, 590, 130), (340, 190, 370, 220)), (40, 50, (340, 190, 370, 220), p2_mid),
                   still(50, 60, p2_mid), (60, 120, p2_mid, p2_right)]},
    )


def holding(frame_count: int = 120) -> Observations:
    """LH_P1 holds the board with the tomato while RH_P2 cuts the tomato with a knife (30-90)."""
    knife_rest = (500, 100, 580, 115)
    knife_cut = (215, 345, 295, 360)
    return observations(
        frame_count,
        {"chopping_board": (Category.CONTAINER, [still(0, frame_count, BOARD)]),
         "tomato": (Category.INGREDIENT, [still(0, frame_count, TOMATO)]),
         "knife": (Category.TOOL, [(0, 30, knife_rest, knife_cut), still(30, 90, knife_cut),
                                   (90, 120, knife_cut, knife_rest)])},
        {"LH_P1": [still(0, frame_count, (90, 400, 120, 430))],
         "RH_P2": [(0, 30, (570, 95, 600, 125), (285, 340, 315, 370)), still(30, 90, (285, 340, 315, 370)),
                   (90, 120, (285, 340, 315, 370), (570, 95, 600, 125))]},
    )
