"""A small video with one patterned square moving over a textured background, for tracking tests."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np


def moving_square(path: Path, frames: int = 40, vanish: int | None = 30,
                  start: tuple[int, int] = (30, 80)) -> list[tuple[float, float, float, float]]:
    """A red square with a pattern moving right over a textured background from ``start`` (its top-left
    corner), gone from frame ``vanish``."""
    rng = np.random.default_rng(1)
    background = cv2.GaussianBlur(rng.integers(0, 255, (240, 320, 3), dtype=np.uint8), (0, 0), 3)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (320, 240))
    truth = []
    for i in range(frames):
        image = background.copy()
        x, y = start[0] + 4 * i, start[1] + 2 * i
        if vanish is None or i < vanish:
            cv2.rectangle(image, (x, y), (x + 40, y + 40), (30, 30, 220), -1)
            cv2.circle(image, (x + 20, y + 20), 10, (240, 240, 40), -1)
        writer.write(image)
        truth.append((float(x), float(y), float(x + 40), float(y + 40)))
    writer.release()
    return truth
