"""Probing a video: fps, size, declared frame count, and whether the declared frames really decode.

Counting every frame means decoding the whole video (slow), so :func:`probe_video` checks cheaply instead:
it seeks to the last declared frame and reads it, then tries one frame more. Only when that disagrees with the
container does it count by decoding in order: seeking by index is unreliable exactly there (in a variable frame
rate video it lands short of the last frame, or on an earlier one), and a count in order is right whether the
container or the seeking is wrong.
"""

from __future__ import annotations

import errno
import math
import os
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError
from wecook_core.files import regular_file
from wecook_core.model import VideoInfo

MIN_FPS, MAX_FPS = 1.0, 1000.0
"""The frame rates a container may give (frames per second); outside them (a header with 0, say, that OpenCV
reads as 0.019) the rate must be given (``--fps``)."""
MAX_PIXELS = 7680 * 4320
"""The largest frame read (8K UHD, 33 Mpx): a frame is decoded whole, and detecting hands on a larger one takes
gigabytes."""


def probe_video(path: str | Path, *, count_frames: bool = False, fps: float | None = None) -> VideoInfo:
    """What the video at ``path`` holds. ``decoded_frames`` is set whenever it was checked.

    ``count_frames=True`` decodes every frame to count them (slow; for damaged files); so does a container
    whose frames cannot be found by seeking (a variable frame rate), and ``fps``, the rate given by the user
    for a container whose own is unusable (its frame count, derived from that rate, is too).
    Raises :class:`InputError` when the file is missing, does not open as a video, has no decodable frame,
    no usable frame rate (and none is given) or frames larger than :data:`MAX_PIXELS`. FFmpeg's own messages
    about damaged frames are silenced (they would print over the workbench) unless ``$OPENCV_FFMPEG_LOGLEVEL``
    says otherwise.
    """
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    os.environ.setdefault("OPENCV_LOG_LEVEL", "FATAL")  # its errors are said by the InputError (or MemoryError)
    import cv2

    path = Path(path)
    if fps is not None and not MIN_FPS <= fps <= MAX_FPS:
        raise InputError(path, f"--fps {fps:g}: expected a frame rate from {MIN_FPS:g} to {MAX_FPS:g}")
    try:
        os.stat(path)
    except OSError as error:
        if error.errno == errno.ELOOP:
            raise InputError(path, "is a loop of symbolic links, not a video file") from None
        if not isinstance(error, FileNotFoundError):
            raise InputError(path, f"cannot read: {error.strerror}") from None
    if not path.exists():
        raise InputError(path, "no such video file")
    if path.is_dir():
        raise InputError(path, "is a directory, expected a video file")
    regular_file(path, "video file")  # a FIFO or a device would block the decoder
    capture = cv2.VideoCapture(str(path))
    try:
        if not capture.isOpened():
            raise InputError(path, "does not open as a video (OpenCV cannot read it)")
        rate = float(capture.get(cv2.CAP_PROP_FPS))
        declared = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        width = int(capture.get(cv2.CAP_PROP_FRAME_WIDTH))
        height = int(capture.get(cv2.CAP_PROP_FRAME_HEIGHT))
        _check_size(path, width, height)  # before a frame is decoded
        ok, frame = capture.read()
        if not ok or frame is None:
            _check_memory(width, height)  # a decoder short of memory fails as if the video were unreadable
            raise InputError(path, "no frame decodes: not a readable video")
        if width <= 0 or height <= 0:
            height, width = frame.shape[:2]
            _check_size(path, width, height)
        if fps is None and not (math.isfinite(rate) and MIN_FPS <= rate <= MAX_FPS):
            raise InputError(path, f"the container gives no usable frame rate ({rate:.3g} fps); give the rate "
                             f"with --fps (from {MIN_FPS:g} to {MAX_FPS:g}), or re-encode the video")
        if count_frames or declared <= 0 or fps is not None:
            decoded = 1 + _count_from(capture)
            count = decoded if fps is not None or declared <= 0 else declared
            return VideoInfo(str(path), fps or rate, count, width, height, decoded)
        checked = _check_declared(capture, declared)
        if checked is None:  # seeking is unreliable here (a variable frame rate): count by decoding in order,
            capture.release()  # from a capture never seeked (seeking back to 0 is no more reliable)
            capture = cv2.VideoCapture(str(path))
            checked = _count_from(capture)
        return VideoInfo(str(path), rate, declared, width, height, checked)
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


def _check_memory(width: int, height: int, frames: int = 4) -> None:
    """MemoryError when ``frames`` frames of that size (what a decoder holds) cannot be had."""
    import numpy as np

    if width > 0 and height > 0:
        np.empty((frames, height, width, 3), np.uint8)  # address space only: nothing is written


def _check_size(path: Path, width: int, height: int) -> None:
    if width * height > MAX_PIXELS:
        raise InputError(path, f"frames of {width}x{height} pixels are more than wecook reads "
                         f"({MAX_PIXELS / 1e6:.0f} Mpx, 7680x4320); scale the video down (to 1920 wide, say)")


def _check_declared(capture: Any, declared: int) -> int | None:
    """``declared`` when seeking to the last declared frame finds it and nothing after it; else None (count in
    order): the container is wrong, or seeking is (a variable frame rate, where seeking by index lands short of
    a frame, or on an earlier one, so that frames seem to follow the last one)."""
    if _read_at(capture, declared - 1) and not capture.grab():
        return declared  # the last declared frame decodes, and no frame comes after it
    return None
