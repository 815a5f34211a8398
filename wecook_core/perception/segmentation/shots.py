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

But a cut between two shots of the same counter (the same bowl a minute later, the cook's second cupful)
keeps the mix of colours, and the histogram test misses it. What such a cut changes is where things are: the
picture's pixels, all at once, on one frame. So a second test reads the frames' mean absolute grey-level
difference (frames shrunk as above) with the sliding-window test of Yeo and Liu ("Rapid scene analysis on
compressed video", 1995): a frame is a cut when its difference is the largest of the :data:`SPIKE_NEIGHBOURS`
frames on each side and at least :data:`SPIKE_RATIO` times the second largest there, and is an outlier of the
video's own differences (:data:`OUTLIER` median absolute deviations above their median, and above
:data:`SPIKE_FLOOR`). Motion inside a shot
(a hand sweeping across, the camera shaking) changes many pixels too, but on several frames in a row; a cut is
a spike of one frame. A frame is a cut when either test says so.
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
SPIKE_NEIGHBOURS = 5
"""Frames on each side of a frame that its grey-level difference is compared with (Yeo and Liu's window): a
cut is an event of one frame, its neighbours show the shot's own motion. Frames, not seconds: the spike is one
frame whatever the rate."""
SPIKE_RATIO = 2.0
"""A cut's grey-level difference is at least this many times the largest of its neighbours' (Yeo and Liu take
2 to 3)."""
SPIKE_FLOOR = 5.0
"""Grey levels (of 255): a frame whose mean absolute difference to the one before is below this is never a cut,
however it stands out of a still video's differences (the rendered scenarios change by 0.2 levels a frame and
by at most 1.2 when an object appears; kfc-b's cuts between two moments of the same counter change by 15 and
more). Half-way, on a log scale, between the two: the value is not a fine line."""
SPREAD = 0.25
"""A cut replaces the picture: at least this fraction of the frame's :data:`BLOCKS` x :data:`BLOCKS` blocks must
change by more than :data:`SPIKE_FLOOR` (an object that jumps, a jar that appears, changes one place of it)."""
BLOCKS = 8
"""Blocks a side the grey-level difference is read in for :data:`SPREAD` (a resolution, not a tunable)."""
DETECTOR = 2
"""Version of the detection, part of the sessions' cache key (``shots.json``): cuts found by an older one are
found again. 1: histograms alone; 2: histograms or grey-level spikes."""
FFMPEG_QUIET = "-8"
"""OpenCV's FFmpeg log level that prints nothing (a damaged frame is not the user's business here)."""


def frame_changes(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """float64 ``(frames,)`` three times, each frame against the frame before (0 for the first): the
    Bhattacharyya distance of their hue-saturation histograms, their mean absolute grey-level difference
    (0-255), and the fraction of the picture's blocks whose own mean difference exceeds :data:`SPIKE_FLOOR`.
    One decoding of the video gives all three."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", FFMPEG_QUIET)
    import cv2

    capture = cv2.VideoCapture(str(path))
    distances: list[float] = []
    differences: list[float] = []
    spread: list[float] = []
    previous = previous_grey = None
    try:
        while True:
            ok, frame = capture.read()
            if not ok or frame is None:
                break
            small = cv2.resize(frame, (SIZE, SIZE), interpolation=cv2.INTER_AREA)
            hsv = cv2.cvtColor(small, cv2.COLOR_BGR2HSV)
            hist = cv2.calcHist([hsv], [0, 1], None, list(BINS), list(HSV_RANGES))
            cv2.normalize(hist, hist, 1.0, 0.0, cv2.NORM_L1)
            grey = cv2.cvtColor(small, cv2.COLOR_BGR2GRAY)
            distances.append(0.0 if previous is None else
                             float(cv2.compareHist(previous, hist, cv2.HISTCMP_BHATTACHARYYA)))
            if previous_grey is None:
                differences.append(0.0)
                spread.append(0.0)
            else:
                change = cv2.absdiff(grey, previous_grey).astype(np.float64)
                differences.append(float(change.mean()))
                side = SIZE // BLOCKS
                blocks = change.reshape(BLOCKS, side, BLOCKS, side).mean(axis=(1, 3))
                spread.append(float((blocks > SPIKE_FLOOR).mean()))
            previous, previous_grey = hist, grey
    finally:
        capture.release()
    return (np.asarray(distances, dtype=np.float64), np.asarray(differences, dtype=np.float64),
            np.asarray(spread, dtype=np.float64))


def histogram_distances(path: str | Path) -> np.ndarray:
    """float64 ``(frames,)``: each frame's Bhattacharyya distance to the frame before (0 for the first)."""
    return frame_changes(path)[0]


def _outliers(values: np.ndarray, outlier: float) -> float:
    """The level ``outlier`` median absolute deviations above the median of ``values[1:]``."""
    inner = values[1:]
    median = float(np.median(inner))
    return median + outlier * float(np.median(np.abs(inner - median)))


def spikes(differences: np.ndarray, spread: np.ndarray, outlier: float = OUTLIER,
           neighbours: int = SPIKE_NEIGHBOURS, ratio: float = SPIKE_RATIO) -> np.ndarray:
    """bool ``(frames,)``: Yeo and Liu's sliding-window test (module docstring) on the grey-level differences:
    the largest of its ``neighbours`` on each side, at least ``ratio`` times the second largest, above the
    video's outlier level and :data:`SPIKE_FLOOR`, and spread over at least :data:`SPREAD` of the picture."""
    length = len(differences)
    found = np.zeros(length, dtype=bool)
    if length < MIN_FRAMES:
        return found
    padded = np.concatenate([np.full(neighbours, -np.inf), differences, np.full(neighbours, -np.inf)])
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * neighbours + 1)
    others = np.delete(windows, neighbours, axis=1).max(axis=1)  # the largest neighbour of each frame
    found = (differences > others) & (differences >= ratio * np.maximum(others, 0.0))
    found &= (differences > max(SPIKE_FLOOR, _outliers(differences, outlier))) & (spread >= SPREAD)
    found[0] = False
    return found


def cuts_of(distances: np.ndarray, threshold: float = THRESHOLD, outlier: float = OUTLIER,
            differences: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[int, ...]:
    """The frames that start a new shot: where the histogram distance to the frame before exceeds ``threshold``
    and lies ``outlier`` median absolute deviations above the median, or (given the grey-level
    ``differences`` and their spread, :func:`frame_changes`) where the difference is a spike (:func:`spikes`)."""
    if len(distances) < MIN_FRAMES:
        return ()
    cut = distances > max(threshold, _outliers(distances, outlier))
    if differences is not None:
        cut |= spikes(*differences, outlier)
    return tuple(int(i) for i in np.flatnonzero(cut) if i > 0)


def shot_cuts(path: str | Path, threshold: float = THRESHOLD) -> tuple[int, ...]:
    """The first frame of every shot but the first, of the video at ``path``; () when it does not open."""
    if not Path(path).is_file():
        return ()
    distances, differences, spread = frame_changes(path)
    return cuts_of(distances, threshold, differences=(differences, spread))
