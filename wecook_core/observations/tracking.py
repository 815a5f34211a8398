"""Boxes a person draws, carried through the video by an OpenCV tracker, corrected at keyframes.

The model is CVAT's: a track is a set of **keyframes** (boxes the user drew or corrected) and, after its last
keyframe, the boxes an OpenCV tracker found frame by frame until it lost the object. Between two keyframes
the box is interpolated linearly (the tracker's boxes there are dropped: the user's correction says where the
object really was); a correction at a frame becomes a keyframe and the tracker runs again from it.

The installed opencv-python-headless has ``TrackerMIL`` only: ``TrackerNano``, ``TrackerVit`` and
``TrackerDaSiamRPN`` need ONNX model files that no package ships, and KCF/CSRT live in opencv-contrib. MIL
reports success nearly always, so loss is decided here too: the box leaving the picture, or the patch under it
looking neither like the keyframe's nor like the previous frame's (colour histogram correlation below
``min_similarity`` for both): a hand covering the object changes it gradually, frame by frame, and is not a
loss; the object vanishing changes it at once.

Frames are streamed from the video (one in memory at a time), so memory does not grow with the video's
length; only the boxes are kept.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from wecook_core.errors import InputError
from wecook_core.model import ObjectTrack

Box = tuple[float, float, float, float]


def available_trackers() -> tuple[str, ...]:
    """OpenCV trackers that work here without model files (``MIL`` in opencv-python-headless)."""
    import cv2

    found = []
    for name in ("MIL", "KCF", "CSRT", "Nano", "Vit", "DaSiamRPN"):
        make = getattr(cv2, f"Tracker{name}_create", None) or getattr(getattr(cv2, "legacy", None),
                                                                         f"Tracker{name}_create", None)
        if make is None:
            continue
        try:
            make()
        except cv2.error:
            continue
        found.append(name)
    return tuple(found)


@dataclass(frozen=True)
class TrackParams:
    tracker: str = "MIL"
    """One of :func:`available_trackers`."""
    min_similarity: float = 0.3
    """The object is lost when the colour histogram under the box correlates less than this with both the
    keyframe's and the previous frame's."""
    max_seconds: float | None = None
    """Stop after this long even if the object is still followed (None: to the end or until lost)."""


@dataclass(frozen=True)
class BoxTrack:
    """One object the user boxes: its keyframes and what the tracker made of them."""

    track_id: int
    label: str
    keyframes: Mapping[int, Box] = field(default_factory=dict)
    """Frame -> box the user drew there."""
    tracked: Mapping[int, Box] = field(default_factory=dict)
    """Frame -> box the tracker found, after the last keyframe."""
    lost_at: int | None = None
    """The first frame the tracker lost the object at (None: followed to the end, or not run)."""

    def with_keyframe(self, frame: int, box: Box) -> BoxTrack:
        """A correction: ``box`` is a keyframe; tracked boxes from there on are dropped (track again)."""
        keyframes = {**self.keyframes, frame: tuple(float(v) for v in box)}
        # After the last keyframe, what the tracker found is stale; before it, the run after it still holds.
        tracked = {} if not self.keyframes or frame >= max(self.keyframes) else dict(self.tracked)
        return replace(self, keyframes=keyframes, tracked=tracked,  # type: ignore[arg-type]
                       lost_at=None if not tracked else self.lost_at)

    def without_keyframe(self, frame: int) -> BoxTrack:
        keyframes = {f: b for f, b in self.keyframes.items() if f != frame}
        return replace(self, keyframes=keyframes)

    def boxes(self) -> dict[int, Box]:
        """Frame -> box: the keyframes, linear interpolation between them, the tracked run after the last."""
        result: dict[int, Box] = {}
        frames = sorted(self.keyframes)
        for a, b in itertools.pairwise(frames):
            box_a, box_b = np.asarray(self.keyframes[a]), np.asarray(self.keyframes[b])
            for f in range(a, b):
                t = (f - a) / (b - a)
                result[f] = tuple(float(v) for v in box_a + t * (box_b - box_a))  # type: ignore[assignment]
        if frames:
            last = frames[-1]
            result[last] = self.keyframes[last]
            result.update({f: b for f, b in self.tracked.items() if f > last})
        return result

    def object_track(self, name: str | None = None) -> ObjectTrack:
        from wecook_core.formats.tracks import object_name

        boxes = self.boxes()
        frames = sorted(boxes)
        return ObjectTrack(self.track_id, self.label, name or object_name(self.label),
                           np.asarray(frames, dtype=np.int64),
                           np.asarray([boxes[f] for f in frames], dtype=np.float64).reshape(-1, 4))


Progress = Callable[[int], None]


def _frames_from(path: str | Path, start: int) -> Iterator[tuple[int, np.ndarray]]:
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    import cv2

    capture = cv2.VideoCapture(str(path))
    if not capture.isOpened():
        raise InputError(path, "does not open as a video (OpenCV cannot read it)")
    try:
        if start:
            capture.set(cv2.CAP_PROP_POS_FRAMES, start)
        index = start
        while True:
            ok, image = capture.read()
            if not ok or image is None:
                return
            yield index, image
            index += 1
    finally:
        capture.release()


def _histogram(image: np.ndarray, box: Box) -> np.ndarray | None:
    import cv2

    h, w = image.shape[:2]
    x1, y1 = max(0, int(box[0])), max(0, int(box[1]))
    x2, y2 = min(w, round(box[2])), min(h, round(box[3]))
    if x2 - x1 < 2 or y2 - y1 < 2:
        return None
    hsv = cv2.cvtColor(image[y1:y2, x1:x2], cv2.COLOR_BGR2HSV)
    hist = cv2.calcHist([hsv], [0, 1], None, [16, 8], [0, 180, 0, 256])
    return cv2.normalize(hist, hist).flatten()


def make_tracker(name: str) -> Any:
    import cv2

    make = getattr(cv2, f"Tracker{name}_create", None)
    if make is None:
        raise InputError(None, f"OpenCV has no tracker {name!r} here; available: {', '.join(available_trackers())}")
    return make()


EDGE_ROOM = 4
"""Pixels a tracked box must keep from the frame's edges: MIL learns the object from patches of the box's size
whose corner lies within 3 px of the box's (OpenCV's ``samplerInitInRadius``), all inside the image, so a box
touching an edge (a bowl filling the frame's height, a hand entering from the side) gave it no sample and
OpenCV raised an assertion. Such a box is tracked inset by this much from each edge it touches, and given back
its full extent on every frame."""


def _inset(box: Box, width: int, height: int) -> tuple[Box, Box]:
    """``(the box kept EDGE_ROOM inside the frame, what was taken off each side: left, top, right, bottom)``."""
    x1, y1, x2, y2 = box
    inner = (max(x1, EDGE_ROOM), max(y1, EDGE_ROOM), min(x2, width - EDGE_ROOM), min(y2, height - EDGE_ROOM))
    if inner[2] - inner[0] < 1 or inner[3] - inner[1] < 1:  # thinner than the room: keep it as drawn
        return box, (0.0, 0.0, 0.0, 0.0)
    return inner, (inner[0] - x1, inner[1] - y1, x2 - inner[2], y2 - inner[3])


def propagate(video: str | Path, frame: int, box: Box, fps: float, params: TrackParams | None = None,
              *, progress: Progress | None = None) -> tuple[dict[int, Box], int | None]:
    """Boxes after ``frame`` found by the tracker from ``box`` at ``frame``, and the frame where the object
    was lost (None: followed to the end or to ``max_seconds``)."""
    import cv2

    params = params or TrackParams()
    tracker = make_tracker(params.tracker)
    limit = None if params.max_seconds is None else frame + round(params.max_seconds * fps)
    result: dict[int, Box] = {}
    reference = previous = None
    grow = (0.0, 0.0, 0.0, 0.0)
    for index, image in _frames_from(video, frame):
        h, w = image.shape[:2]
        if reference is None:
            inner, grow = _inset(box, w, h)
            x1, y1, x2, y2 = inner
            try:
                tracker.init(image, (int(x1), int(y1), max(1, int(x2 - x1)), max(1, int(y2 - y1))))
            except cv2.error:  # a box too small to sample even inside the frame: the tracker cannot start
                return result, index
            reference = previous = _histogram(image, box)
            continue
        if limit is not None and index > limit:
            return result, None
        ok, (x, y, bw, bh) = tracker.update(image)
        found: Box = (float(x) - grow[0], float(y) - grow[1], float(x + bw) + grow[2], float(y + bh) + grow[3])
        outside = found[2] <= 0 or found[3] <= 0 or found[0] >= w or found[1] >= h
        similar = True
        hist = _histogram(image, found) if ok and not outside else None
        if hist is not None and reference is not None and previous is not None:
            similar = max(cv2.compareHist(reference, hist, cv2.HISTCMP_CORREL),
                          cv2.compareHist(previous, hist, cv2.HISTCMP_CORREL)) >= params.min_similarity
        if not ok or outside or hist is None or not similar:
            return result, index
        previous = hist
        result[index] = (max(0.0, found[0]), max(0.0, found[1]), min(float(w), found[2]), min(float(h), found[3]))
        if progress is not None:
            progress(index)
    return result, None


def track_from_last_keyframe(video: str | Path, track: BoxTrack, fps: float, params: TrackParams | None = None,
                             *, progress: Progress | None = None) -> BoxTrack:
    """The track with the tracker run from its last keyframe."""
    if not track.keyframes:
        return track
    last = max(track.keyframes)
    tracked, lost = propagate(video, last, track.keyframes[last], fps, params, progress=progress)
    return replace(track, tracked=tracked, lost_at=lost)
