"""Probing a video: fps, size, declared frame count, and whether the declared frames really decode.

Counting every frame means decoding the whole video (slow), so :func:`probe_video` checks cheaply instead:
it seeks to the last declared frame and reads it, then tries one frame more. Only when that disagrees with
the container does it search (by seeking, ``O(log n)`` reads) for the last frame that decodes, or count the
frames beyond the declared end.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError
from wecook_core.files import regular_file
from wecook_core.model import VideoInfo

MAX_EXTRA_FRAMES = 100_000
"""Most frames counted past the declared end before giving up (a container that lies that much is broken)."""


def probe_video(path: str | Path, *, count_frames: bool = False) -> VideoInfo:
    """What the video at ``path`` holds. ``decoded_frames`` is set whenever it was checked.

    ``count_frames=True`` decodes every frame to count them (slow; for damaged files).
    Raises :class:`InputError` when the file is missing, does not open as a video, has no decodable frame
    or no frame rate. FFmpeg's own messages about damaged frames are silenced (they would print over the
    workbench) unless ``$OPENCV_FFMPEG_LOGLEVEL`` says otherwise.
    """
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    import cv2

    path = Path(path)
    if not path.exists():
        raise InputError(path, "no such video file")
    if path.is_dir():
        raise InputError(path, "is a directory, expected a video file")
    regular_file(path, "video file")  # a FIFO or a device would block the decoder
    capture = cv2.VideoCapture(str(path))
    try:
        if not capture.isOpened():
            raise InputError(path, "does not open as a video (OpenCV cannot read it)")
        fps = float(capture.get(cv2.CAP_PROP_FPS))
        declared = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        width = int(capture.get(cv2.CAP_PROP_FRAME_WIDTH))
        height = int(capture.get(cv2.CAP_PROP_FRAME_HEIGHT))
        ok, frame = capture.read()
        if not ok or frame is None:
            raise InputError(path, "no frame decodes: not a readable video")
        if width <= 0 or height <= 0:
            height, width = frame.shape[:2]
        if not math.isfinite(fps) or fps <= 0 or fps > 1000:
            raise InputError(path, f"the container gives no usable frame rate ({fps}); re-encode the video")
        if count_frames or declared <= 0:
            decoded = 1 + _count_from(capture)
            return VideoInfo(str(path), fps, declared if declared > 0 else decoded, width, height, decoded)
        decoded = _check_declared(capture, declared)
        return VideoInfo(str(path), fps, declared, width, height, decoded)
    finally:
        capture.release()


def usable_frames(info: VideoInfo) -> int:
    """Frames that can be addressed: the decoded count when it was checked, else the declared one."""
    return info.decoded_frames if info.decoded_frames is not None else info.frame_count


def frame_count_note(info: VideoInfo) -> str | None:
    """A one-line note when the container's frame count disagrees with what decodes, else None."""
    if info.decoded_frames is None or info.decoded_frames == info.frame_count:
        return None
    return (
        f"{info.path}: the container declares {info.frame_count} frames but {info.decoded_frames} decode; "
        f"using {info.decoded_frames}"
    )


def _read_at(capture: Any, index: int) -> bool:
    import cv2

    capture.set(cv2.CAP_PROP_POS_FRAMES, index)
    ok, frame = capture.read()
    return bool(ok) and frame is not None


def _count_from(capture: Any, limit: int | None = None) -> int:
    """Frames that still decode from the capture's current position (up to ``limit``)."""
    count = 0
    while (limit is None or count < limit) and capture.grab():
        count += 1
    return count


def _check_declared(capture: Any, declared: int) -> int:
    """Frames that decode, checked cheaply against the ``declared`` count (frame 0 is known to decode)."""
    if _read_at(capture, declared - 1):
        # The last declared frame decodes; more frames than declared would show as one more frame.
        return declared + _count_from(capture, MAX_EXTRA_FRAMES)
    low, high = 0, declared - 1  # frame `low` decodes, frame `high` does not
    while high - low > 1:
        middle = (low + high) // 2
        if _read_at(capture, middle):
            low = middle
        else:
            high = middle
    return low + 1
