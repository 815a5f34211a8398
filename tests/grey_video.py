"""A small real video for tests that need one to exist and decode: flat grey MJPG frames, a shade a frame."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np


def write_grey_video(path: Path, frames: int, size: tuple[int, int], fps: float) -> Path:
    """Write ``frames`` flat frames of ``size`` (width, height) pixels at ``fps`` to ``path`` (MJPG); return it."""
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps, size)
    for i in range(frames):
        writer.write(np.full((size[1], size[0], 3), (i * 6) % 256, np.uint8))
    writer.release()
    return path
