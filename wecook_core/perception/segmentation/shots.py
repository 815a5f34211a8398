"""Shot cuts: the frames where an edited video jumps to another view (a close-up, another angle).

A cut ends whatever was going on in the picture: boxes jump, hands vanish, a pan that filled a corner fills
the frame. Read as motion, a cut looks like every object being flung across the image at once. So the
pipeline cuts its segments at every shot cut and never compares positions across one
(:mod:`wecook_core.perception.association.holding`, :mod:`wecook_core.perception.repairs.unseen`).

Detection: the colour histogram test of shot-boundary detection (Zhang, Kankanhalli, Smoliar, "Automatic
partitioning of full-motion video", 1993; the baseline that TRECVID's shot-boundary systems start from). Each
frame, shrunk to :data:`SIZE` pixels a side, gives a joint hue-saturation histogram (:data:`BINS`); a cut is
a frame whose histogram's Bhattacharyya distance to the previous frame's is an outlier of the video's own
distances: above :data:`THRESHOLD` and more than :data:`OUTLIER` median absolute deviations above their
median (a video full of motion has higher distances throughout than a still one). Why a
histogram and not a frame difference: inside one shot of a cooking video, hands, spoons and food move and the
camera shakes, which changes many pixels but hardly the mix of colours; a cut changes the mix of the whole
picture. Hue and saturation, not brightness, so a flicker or an auto-exposure step is not a cut. Gradual
transitions (fades) are not looked for: recipe videos cut hard.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

SIZE = 64
"""Pixels a side frames are shrunk to before their histogram is taken (speed; colours survive). A resolution
of the computation: the histogram is normalised, so the result hardly depends on it."""
BINS = (16, 8)
"""Hue and saturation bins of the histogram (counts)."""
HSV_RANGES = (0, 180, 0, 256)
"""OpenCV's ranges of 8-bit hue (0-179) and saturation (0-255): the whole of each, not a tunable."""
THRESHOLD = 0.3
"""Bhattacharyya distance (unitless, 0: same colours, 1: none shared) below which consecutive frames are never
a cut: within a shot it stays near 0.05-0.2."""
OUTLIER = 8.0
"""Median absolute deviations: a cut's distance lies more than this many above the video's median (a robust
outlier test: motion inside shots spreads the distances, a cut stands out of them)."""
MIN_FRAMES = 3
"""Frames a video needs before cuts are looked for: the median and spread of its distances need two of them
(the first frame has none)."""
FFMPEG_QUIET = "-8"
"""OpenCV's FFmpeg log level that prints nothing (a damaged frame is not the user's business here)."""


def histogram_distances(path: str | Path) -> np.ndarray:
    """float64 ``(frames,)``: each frame's Bhattacharyya distance to the frame before (0 for the first)."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", FFMPEG_QUIET)
    import cv2

    capture = cv2.VideoCapture(str(path))
    distances: list[float] = []
    previous = None
    try:
        while True:
            ok, frame = capture.read()
            if not ok or frame is None:
                break
            small = cv2.resize(frame, (SIZE, SIZE), interpolation=cv2.INTER_AREA)
            hsv = cv2.cvtColor(small, cv2.COLOR_BGR2HSV)
            hist = cv2.calcHist([hsv], [0, 1], None, list(BINS), list(HSV_RANGES))
            cv2.normalize(hist, hist, 1.0, 0.0, cv2.NORM_L1)
            distances.append(0.0 if previous is None else
                             float(cv2.compareHist(previous, hist, cv2.HISTCMP_BHATTACHARYYA)))
            previous = hist
    finally:
        capture.release()
    return np.asarray(distances, dtype=np.float64)


def cuts_of(distances: np.ndarray, threshold: float = THRESHOLD, outlier: float = OUTLIER) -> tuple[int, ...]:
    """The frames that start a new shot: where the distance to the frame before exceeds ``threshold`` and
    lies ``outlier`` median absolute deviations above the median."""
    if len(distances) < MIN_FRAMES:
        return ()
    inner = distances[1:]
    median = float(np.median(inner))
    spread = float(np.median(np.abs(inner - median)))
    bar = max(threshold, median + outlier * spread)
    return tuple(int(i) for i in np.flatnonzero(distances > bar) if i > 0)


def shot_cuts(path: str | Path, threshold: float = THRESHOLD) -> tuple[int, ...]:
    """The first frame of every shot but the first, of the video at ``path``; () when it does not open."""
    if not Path(path).is_file():
        return ()
    return cuts_of(histogram_distances(path), threshold)
