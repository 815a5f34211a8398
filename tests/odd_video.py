"""Odd MP4 files for the video probe's tests: written by OpenCV, then their sample table rewritten.

``variable_rate_mp4``: half the frames 1/45 s long, half 1/24 s (a variable frame rate, as phones record);
``zero_rate_mp4``: a media header whose timescale is 0 (no usable frame rate). OpenCV's FFmpeg muxer puts the
``moov`` box after ``mdat``, so growing it moves no sample and only the sizes of the boxes around it change."""

from __future__ import annotations

import struct
from collections.abc import Iterator
from pathlib import Path

import cv2
import numpy as np

CONTAINERS = ("moov", "trak", "mdia", "minf", "stbl", "edts")


def write_mp4(path: Path, frames: int, size: tuple[int, int] = (64, 48), fps: float = 24.0) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, size)
    assert writer.isOpened(), "OpenCV cannot write MP4 here"
    for i in range(frames):
        image = np.full((size[1], size[0], 3), (i * 4) % 256, np.uint8)
        cv2.putText(image, str(i), (2, 30), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255), 1)
        writer.write(image)
    writer.release()
    return path


def _boxes(data: bytes, start: int, end: int,
           parents: tuple[int, ...] = ()) -> Iterator[tuple[int, str, tuple[int, ...]]]:
    """(offset, type, offsets of the enclosing boxes) of every box, depth first."""
    i = start
    while i + 8 <= end:
        size, kind = struct.unpack(">I4s", data[i:i + 8])
        name = kind.decode("latin1")
        yield i, name, parents
        if name in CONTAINERS:
            yield from _boxes(data, i + 8, i + size, (*parents, i))
        i += size


def _find(data: bytes, name: str) -> tuple[int, tuple[int, ...]]:
    return next((i, parents) for i, kind, parents in _boxes(data, 0, len(data)) if kind == name)


def _replace_box(data: bytearray, offset: int, parents: tuple[int, ...], new: bytes) -> bytearray:
    old = struct.unpack(">I", data[offset:offset + 4])[0]
    grow = len(new) - old
    for parent in parents:  # before `offset`: their offsets do not move
        struct.pack_into(">I", data, parent, struct.unpack(">I", data[parent:parent + 4])[0] + grow)
    return data[:offset] + bytearray(new) + data[offset + old:]


def variable_rate_mp4(path: Path, frames: int = 120, rates: tuple[int, int] = (45, 24)) -> Path:
    """An MP4 of ``frames`` frames, the first half at ``rates[0]`` frames per second, the rest at ``rates[1]``."""
    write_mp4(path, frames, fps=rates[0])
    data = bytearray(path.read_bytes())
    timescale = rates[0] * rates[1]
    deltas = [timescale // rates[0 if k < frames // 2 else 1] for k in range(frames)]
    mdhd, _ = _find(data, "mdhd")
    assert data[mdhd + 8] == 0, "a version-0 mdhd"
    struct.pack_into(">II", data, mdhd + 20, timescale, sum(deltas))
    edts, _ = _find(data, "edts")
    data[edts + 4:edts + 8] = b"free"  # the edit list would cut the longer track at the old duration
    stts, parents = _find(data, "stts")
    body = struct.pack(">4xI", frames) + b"".join(struct.pack(">II", 1, d) for d in deltas)
    data = _replace_box(data, stts, parents, struct.pack(">I4s", 8 + len(body), b"stts") + body)
    path.write_bytes(bytes(data))
    return path


def zero_rate_mp4(path: Path, frames: int = 60) -> Path:
    """An MP4 whose media timescale is 0."""
    write_mp4(path, frames)
    data = bytearray(path.read_bytes())
    mdhd, _ = _find(data, "mdhd")
    struct.pack_into(">I", data, mdhd + 20, 0)
    path.write_bytes(bytes(data))
    return path
