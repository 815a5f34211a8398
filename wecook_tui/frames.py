"""Video frames for the terminal: lazy decoding, a small LRU cache, overlays.

Decoding runs in worker threads (see :class:`FrameSource`); the UI thread only reads the cache, draws the
overlays on a small image and turns it into :class:`~textual.strip.Strip` lines (:mod:`wecook_tui.halfblocks`).
"""

from __future__ import annotations

import contextlib
import os
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")  # FFmpeg must not print over the terminal UI
os.environ.setdefault("OPENCV_LOG_LEVEL", "OFF")

import cv2
import numpy as np

from wecook_tui.halfblocks import HALF_BLOCK, Canvas, Label, to_strips

__all__ = ["HALF_BLOCK", "BoxMark", "Canvas", "FrameSource", "HandMark", "Label", "LinkMark", "Overlay", "VideoFacts",
           "blank", "contrasting", "draw", "fit", "to_strips"]


@dataclass(frozen=True)
class VideoFacts:
    """What opening the video found out; ``error`` says why frames cannot be shown."""

    fps: float = 30.0
    """Frames per second (30 when the container does not say)."""
    frame_count: int = 0
    """Frames the container declares."""
    width: int = 0
    """Pixels."""
    height: int = 0
    """Pixels."""
    error: str | None = None
    """One line for the notice: missing file, unreadable container, ..."""


class FrameSource:
    """Frames of one video, decoded on demand, resized to the view and kept in a small LRU cache.

    Thread-safe: :meth:`decode` and :meth:`prefetch` run in worker threads and serialise on one lock around
    the OpenCV capture; :meth:`cached` is a cheap dictionary read for the UI thread. Sequential reads avoid
    seeking (seeking an H.264 file decodes from the previous key frame), so stepping forward costs one decode.
    """

    RAW_KEPT = 8
    """Native-size frames kept from the last decodes: a new view size resizes them again instead of decoding
    (the layout settles a row or a column smaller once the session's timeline lanes show)."""

    BACK_BLOCK = 16
    """Frames read forwards per seek when prefetching behind the cursor, the nearest block first."""

    def __init__(self, path: str | Path | None, cache_size: int = 600) -> None:
        self.path = Path(path) if path is not None else None
        self.cache_size = cache_size
        self._raw: OrderedDict[int, np.ndarray] = OrderedDict()
        self._lock = threading.Lock()
        self._wanted = threading.Event()
        """Set while a caller other than the prefetch waits for the lock: the prefetch lets it in between two
        frames (a plain lock is not fair: the loop would take it again at once, for many frames)."""
        self._cache: OrderedDict[int, np.ndarray] = OrderedDict()
        self._capture: cv2.VideoCapture | None = None
        self._next = 0
        """Frame index the capture would read next."""
        self._size: tuple[int, int] = (0, 0)
        """(width, height) in pixels that cached frames are resized to; (0, 0) keeps the native size."""
        self.bad_frames: set[int] = set()
        """Frames that failed to decode (a damaged file); each is reported once."""
        self.facts = self._open()

    # ----------------------------------------------------------------------------------- opening

    def _open(self) -> VideoFacts:
        if self.path is None:
            return VideoFacts(error="the session names no video")
        if not self.path.is_file():
            return VideoFacts(error=f"{self.path}: video file is missing")
        capture = cv2.VideoCapture(str(self.path))
        if not capture.isOpened():
            return VideoFacts(error=f"{self.path}: OpenCV cannot open this video (corrupt or unknown format)")
        ok, first = capture.read()
        if not ok or first is None:
            capture.release()
            return VideoFacts(error=f"{self.path}: no frame decodes (corrupt video)")
        fps = float(capture.get(cv2.CAP_PROP_FPS) or 0.0) or 30.0
        count = int(capture.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
        height, width = first.shape[:2]
        self._capture = capture
        self._next = 1
        self._first = first
        return VideoFacts(fps=fps, frame_count=count, width=width, height=height)

    @property
    def ok(self) -> bool:
        return self.facts.error is None

    @contextlib.contextmanager
    def _take(self) -> Iterator[None]:
        """Hold the lock, for everyone but the prefetch loop: the loop steps aside for the taker."""
        self._wanted.set()
        with self._lock:
            self._wanted.clear()
            yield

    def close(self) -> None:
        with self._take():
            if self._capture is not None:
                self._capture.release()
                self._capture = None

    # ------------------------------------------------------------------------------------- cache

    def set_size(self, width: int, height: int) -> None:
        """Resize future frames to ``width x height`` pixels; drops the cache when the size changes, but for the
        last few frames decoded (and frame 0), resized again from their native pictures."""
        with self._take():
            if (width, height) != self._size:
                self._size = (width, height)
                self._cache.clear()
                first = getattr(self, "_first", None)
                kept = [*([(0, first)] if first is not None and 0 not in self._raw else []), *self._raw.items()]
                for index, raw in kept:
                    self._store(index, raw, keep_raw=False)

    def forget(self) -> None:
        """Drop every decoded frame (the benchmark starts cold with it)."""
        with self._take():
            self._cache.clear()
            self._raw.clear()

    @property
    def size(self) -> tuple[int, int]:
        return self._size

    def cached(self, index: int) -> np.ndarray | None:
        """The frame if it is in the cache (BGR, resized), without decoding; safe on the UI thread."""
        frame = self._cache.get(index)
        if frame is not None:
            with contextlib.suppress(KeyError):  # evicted by a worker in between
                self._cache.move_to_end(index)
        return frame

    def _store(self, index: int, frame: np.ndarray, keep_raw: bool = True) -> np.ndarray:
        if keep_raw:
            self._raw[index] = frame
            self._raw.move_to_end(index)
            while len(self._raw) > self.RAW_KEPT:
                self._raw.popitem(last=False)
        width, height = self._size
        if width > 0 and height > 0 and (frame.shape[1], frame.shape[0]) != (width, height):
            frame = cv2.resize(frame, (width, height), interpolation=cv2.INTER_AREA)
        self._cache[index] = frame
        while len(self._cache) > self.cache_size:
            self._cache.popitem(last=False)
        return frame

    # ------------------------------------------------------------------------------------ decoding

    def _read(self, index: int) -> np.ndarray | None:
        """Read one frame with the lock held; seek only when reading forward would be slower."""
        capture = self._capture
        if capture is None:
            return None
        if index == 0 and getattr(self, "_first", None) is not None:
            return self._first
        if not self._next <= index < self._next + 24:
            capture.set(cv2.CAP_PROP_POS_FRAMES, index)
            self._next = index
        while self._next < index:
            if not capture.grab():
                return None
            self._next += 1
        ok, frame = capture.read()
        self._next += 1
        if not ok or frame is None:
            self._next = -(10**9)  # force a seek next time
            return None
        return frame

    def decode(self, index: int) -> np.ndarray | None:
        """The frame at ``index`` (from the cache, else decoded); None if it does not decode."""
        if index < 0 or (self.facts.frame_count and index >= self.facts.frame_count):
            return None
        with self._take():
            frame = self._cache.get(index)
            if frame is not None:
                return frame
            raw = self._read(index)
            if raw is None:
                self.bad_frames.add(index)
                return None
            return self._store(index, raw)

    def prefetch(self, start: int, stop: int, cancelled: Callable[[], bool] = lambda: False, step: int = 1) -> int:
        """Decode frames ``[start, stop)`` into the cache in increasing order; returns how many were decoded.

        Stops early when ``cancelled()`` turns true (a newer request replaced this one). Going backwards,
        callers pass the window below the cursor: reading it forwards costs one seek instead of one per frame.
        ``step`` > 1 keeps every step-th frame from ``start`` only (playback that cannot paint every frame):
        the others are grabbed, not converted, resized or stored.
        """
        count = 0
        last = self.facts.frame_count or stop
        for index in range(max(0, start), min(stop, last)):
            if cancelled():
                break
            if index in self._cache or (step > 1 and (index - start) % step):
                continue
            with self._lock:
                raw = self._read(index)
                if raw is None:
                    self.bad_frames.add(index)
                    continue
                self._store(index, raw)
            count += 1
            if self._wanted.is_set():
                time.sleep(0.0005)  # let the waiting caller take the lock first
        return count

    def prefetch_back(self, stop: int, count: int, cancelled: Callable[[], bool] = lambda: False) -> int:
        """Decode the ``count`` frames below ``stop`` into the cache, nearest first: blocks of
        :attr:`BACK_BLOCK` frames from ``stop`` down, each read forwards after one seek (stepping back wants
        ``stop - 1`` next, which a forward read of the whole window would decode last). Returns how many."""
        done = 0
        high, low = stop, max(0, stop - count)
        while high > low and not cancelled():
            start = max(low, high - self.BACK_BLOCK)
            done += self.prefetch(start, high, cancelled)
            high = start
        return done


# ------------------------------------------------------------------------------------ overlays


@dataclass(frozen=True)
class BoxMark:
    """An object's box at the current frame, in video pixels."""

    name: str
    box: tuple[float, float, float, float]
    colour: tuple[int, int, int]
    """RGB."""
    held: bool = False
    """Drawn thicker: a hand holds it in the current segment."""
    selected: bool = False
    """Drawn in white, thicker: the user clicked it."""


@dataclass(frozen=True)
class HandMark:
    hand: str
    xy: tuple[float, float]
    """Hand centre, video pixels."""
    colour: tuple[int, int, int]
    selected: bool = False


@dataclass(frozen=True)
class LinkMark:
    """A hand-object or object-object link drawn as a line between two points (video pixels)."""

    a: tuple[float, float]
    b: tuple[float, float]
    colour: tuple[int, int, int]


@dataclass(frozen=True)
class Overlay:
    """Everything drawn on top of one frame."""

    boxes: tuple[BoxMark, ...] = ()
    hands: tuple[HandMark, ...] = ()
    links: tuple[LinkMark, ...] = ()
    labels: bool = True


def contrasting(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    """Black or white, whichever reads better on ``rgb`` (by relative luminance)."""
    r, g, b = rgb
    return (0, 0, 0) if 0.2126 * r + 0.7152 * g + 0.0722 * b > 140 else (255, 255, 255)


def blank(width: int, height: int, shade: int = 40) -> np.ndarray:
    return np.full((height, width, 3), shade, dtype=np.uint8)


def _bgr(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    return (rgb[2], rgb[1], rgb[0])


def draw(image: np.ndarray, overlay: Overlay, video_size: tuple[int, int]) -> Canvas:
    """Draw boxes, links and hand markers on a copy of ``image`` (already the view's size).

    ``video_size`` is the (width, height) the overlay's pixel coordinates refer to.
    """
    out = image.copy()
    height, width = out.shape[:2]
    vw, vh = video_size
    sx = width / vw if vw else 1.0
    sy = height / vh if vh else 1.0

    def pt(p: tuple[float, float]) -> tuple[int, int]:
        return (round(p[0] * sx), round(p[1] * sy))

    labels: list[Label] = []
    for mark in overlay.boxes:
        x1, y1, x2, y2 = mark.box
        colour = (255, 255, 255) if mark.selected else mark.colour
        cv2.rectangle(out, pt((x1, y1)), pt((x2, y2)), _bgr(colour), 2 if mark.held or mark.selected else 1)
        if overlay.labels:  # a tag in the box colour, outside the box: above it, or below at the top edge
            cx, cy = pt((x1, y1))
            row = cy // 2 - 1 if cy // 2 >= 1 else pt((x2, y2))[1] // 2 + 1
            labels.append(Label(max(0, cx), max(0, row), mark.name, contrasting(colour), colour))
    for link in overlay.links:
        cv2.line(out, pt(link.a), pt(link.b), _bgr(link.colour), 1)
    for hand in overlay.hands:
        centre = pt(hand.xy)
        cv2.circle(out, centre, 3 if hand.selected else 2, _bgr(hand.colour), -1)
        if hand.selected:
            cv2.circle(out, centre, 5, (255, 255, 255), 1)
        if overlay.labels:
            labels.append(Label(max(0, centre[0] + 2), max(0, centre[1] // 2), hand.hand, hand.colour, (0, 0, 0)))
    return Canvas(out, _spread(labels, width, height // 2))


def _spread(labels: list[Label], columns: int, rows: int) -> list[Label]:
    """Labels moved down a row (then up) when they would overwrite another; dropped if no row is free.
    Hands' labels come last and are placed first, so they win."""
    taken: dict[int, list[tuple[int, int]]] = {}
    placed: list[Label] = []
    for label in reversed(labels):
        x = min(label.x, max(0, columns - len(label.text)))
        span = (x, x + len(label.text) + 1)
        for row in (label.y, label.y + 1, label.y - 1, label.y + 2):
            if 0 <= row < max(rows, 1) and all(span[1] <= a or b <= span[0] for a, b in taken.get(row, [])):
                taken.setdefault(row, []).append(span)
                placed.append(Label(x, row, label.text, label.colour, label.background))
                break
    return placed[::-1]


def fit(video_size: tuple[int, int], cells: tuple[int, int]) -> tuple[int, int]:
    """The largest (width, height) in pixels with the video's aspect that fits ``cells`` (columns, rows)."""
    vw, vh = video_size
    columns, rows = cells
    if vw <= 0 or vh <= 0 or columns <= 0 or rows <= 0:
        return (max(columns, 1), max(2 * rows, 2))
    scale = min(columns / vw, 2 * rows / vh)
    width = max(1, int(vw * scale))
    height = max(2, int(vh * scale))
    return (width, height - height % 2)
