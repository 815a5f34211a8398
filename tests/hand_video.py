"""A small cooking-like video with a real hand (tests/data/hand_four.png, Apache-2.0, see tests/data/README.md):
the hand comes to a tomato, carries it into a bowl and leaves. MediaPipe finds the hand; OpenCV's tracker can
follow the tomato and the bowl."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

HAND = Path(__file__).resolve().parent / "data" / "hand_four.png"
SIZE = (640, 360)
TOMATO0 = (150.0, 230.0)
BOWL = (470.0, 230.0)


Box = tuple[float, float, float, float]


def hand_and_tomato(path: Path, fps: float = 10.0, seconds: float = 6.0) -> dict[str, Box]:
    """Write the video; returns the frame-0 boxes of the tomato and the bowl (pixels)."""
    hand = cv2.resize(cv2.imread(str(HAND)), None, fx=2, fy=2, interpolation=cv2.INTER_CUBIC)
    h, w = hand.shape[:2]
    rng = np.random.default_rng(3)
    table = cv2.GaussianBlur(rng.integers(90, 170, (SIZE[1], SIZE[0], 3), dtype=np.uint8), (0, 0), 2)
    frames = round(fps * seconds)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps, SIZE)
    for i in range(frames):
        t = i / max(frames - 1, 1)
        image = table.copy()
        cv2.circle(image, (int(BOWL[0]), int(BOWL[1])), 60, (200, 120, 40), 14)  # the bowl, a blue ring
        if t < 0.3:  # the hand comes to the tomato
            hx, hy = 20 + (TOMATO0[0] - 20) * t / 0.3, 40 + (TOMATO0[1] - 62 - 40) * t / 0.3
            tomato = TOMATO0
        elif t < 0.7:  # and carries it to the bowl
            s = (t - 0.3) / 0.4
            tomato = (TOMATO0[0] + (BOWL[0] - TOMATO0[0]) * s, TOMATO0[1])
            hx, hy = tomato[0], TOMATO0[1] - 62
        else:  # the tomato stays in the bowl, the hand leaves
            s = (t - 0.7) / 0.3
            tomato = BOWL
            hx, hy = BOWL[0], TOMATO0[1] - 62 - 60 * s
        cv2.circle(image, (int(tomato[0]), int(tomato[1])), 26, (40, 40, 210), -1)
        cv2.circle(image, (int(tomato[0]) - 8, int(tomato[1]) - 8), 6, (120, 200, 255), -1)
        x, y = int(hx - w / 2), int(hy - h / 2)
        x, y = max(0, min(SIZE[0] - w, x)), max(0, min(SIZE[1] - h, y))
        image[y:y + h, x:x + w] = hand
        writer.write(image)
    writer.release()
    return {"tomato": (TOMATO0[0] - 30, TOMATO0[1] - 30, TOMATO0[0] + 30, TOMATO0[1] + 30),
            "bowl": (BOWL[0] - 70, BOWL[1] - 70, BOWL[0] + 70, BOWL[1] + 70)}
