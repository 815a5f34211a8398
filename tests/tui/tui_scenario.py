"""A small session made in the test: a 90-frame video and native CSVs with a knife carried to a tomato on a
board and sawed back and forth, then put down; opened by the real session and pipeline code."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

FRAMES = 90
SIZE = (320, 180)


def hand_path(frames: int = FRAMES, seed: int = 3) -> np.ndarray:
    """RH_P1 centre per frame: rest, reach the knife, carry it to the tomato, saw, carry it back."""
    rng = np.random.default_rng(seed)
    xy = np.zeros((frames, 2))
    for f in range(frames):
        if f < 15:
            p = (60.0, 60.0)
        elif f < 30:
            t = (f - 15) / 15
            p = (60 + 105 * t, 60 + 35 * t)
        elif f < 65:
            p = (165 + 12 * np.sin((f - 30) * 1.3), 95.0)
        elif f < 80:
            t = (f - 65) / 15
            p = (165 - 105 * t, 95 - 35 * t)
        else:
            p = (60.0, 60.0)
        xy[f] = p
    return xy + rng.normal(0, 0.6, xy.shape)


def write_inputs(folder: Path, frames: int = FRAMES, size: tuple[int, int] = SIZE) -> tuple[Path, Path, Path]:
    """(video, objects.csv, hands.csv) in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    right = hand_path(frames)
    left = np.tile([250.0, 140.0], (frames, 1))
    board = (120.0, 70.0, 230.0, 150.0)
    tomato = (150.0, 85.0, 185.0, 115.0)
    bowl = (255.0, 20.0, 305.0, 70.0)
    object_rows = ["frame,track_id,label,x1,y1,x2,y2"]
    hand_rows = ["frame,hand,x,y,x1,y1,x2,y2"]
    video = folder / "video.mp4"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"mp4v"), 30.0, size)
    for f in range(frames):
        hx, hy = right[f]
        knife = (hx - 25, hy - 6, hx + 5, hy + 4) if f >= 12 else (35.0, 54.0, 65.0, 64.0)
        boxes = {1: ("knife", knife), 2: ("chopping board", board), 3: ("tomato", tomato), 4: ("bowl", bowl)}
        image = np.full((size[1], size[0], 3), (60, 110, 150), np.uint8)
        for track, (label, (x1, y1, x2, y2)) in boxes.items():
            object_rows.append(f"{f},{track},{label},{x1:.1f},{y1:.1f},{x2:.1f},{y2:.1f}")
            colour = {1: (200, 200, 200), 2: (40, 120, 180), 3: (40, 40, 220), 4: (230, 230, 230)}[track]
            cv2.rectangle(image, (int(x1), int(y1)), (int(x2), int(y2)), colour, -1)
        for hand, (x, y) in (("RH_P1", (hx, hy)), ("LH_P1", tuple(left[f]))):
            hand_rows.append(f"{f},{hand},{x:.1f},{y:.1f},{x - 8:.1f},{y - 8:.1f},{x + 8:.1f},{y + 8:.1f}")
            cv2.circle(image, (int(x), int(y)), 8, (150, 180, 230), -1)
        cv2.putText(image, str(f), (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (255, 255, 255), 1)
        writer.write(image)
    writer.release()
    objects = folder / "objects.csv"
    objects.write_text("\n".join(object_rows) + "\n")
    hands = folder / "hands.csv"
    hands.write_text("\n".join(hand_rows) + "\n")
    return video, objects, hands
