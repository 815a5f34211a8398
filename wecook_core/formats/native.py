"""wecook's own CSVs: objects ``frame,track_id,label,x1,y1,x2,y2`` and hands ``frame,hand,x,y,x1,y1,x2,y2``.

Frames are 0-based; coordinates are pixels, top-left origin. Both files start with that header line.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO

from wecook_core.errors import InputError
from wecook_core.files import regular_file, write_text_atomic
from wecook_core.formats.fields import MAX_COORDINATE, check_frame, check_id
from wecook_core.formats.tracks import hand_tracks, object_tracks
from wecook_core.model import HANDS, HandTrack, ObjectTrack

OBJECT_COLUMNS = ("frame", "track_id", "label", "x1", "y1", "x2", "y2")
HAND_COLUMNS = ("frame", "hand", "x", "y", "x1", "y1", "x2", "y2")


def _rows(path: Path, columns: tuple[str, ...]) -> Iterator[tuple[int, list[str]]]:
    """Data rows with their 1-based line numbers, after checking the header."""
    regular_file(path, "CSV file")
    try:
        handle = path.open(newline="", encoding="utf-8-sig")  # a byte-order mark is no part of the header
    except FileNotFoundError:
        raise InputError(path, "file not found") from None
    except OSError as error:
        raise InputError(path, f"cannot read: {error.strerror}") from None
    with handle:
        reader = csv.reader(handle)
        try:
            header = next(reader, None)
        except (csv.Error, UnicodeDecodeError) as error:
            raise InputError(path, f"not a CSV file ({error})", place="line 1") from None
        if header is None:
            raise InputError(path, f"empty file; expected the header {','.join(columns)}")
        if tuple(cell.strip().lower() for cell in header) != columns:
            raise InputError(path, f"expected the header {','.join(columns)}, found {','.join(header)}",
                             place="line 1")
        try:
            for row in reader:
                if not row or all(not cell.strip() for cell in row):
                    continue
                if len(row) != len(columns):
                    raise InputError(path, f"expected {len(columns)} fields ({','.join(columns)}), found {len(row)}",
                                     place=f"line {reader.line_num}")
                yield reader.line_num, row
        except (csv.Error, UnicodeDecodeError) as error:
            raise InputError(path, f"malformed CSV ({error})", place=f"line {reader.line_num}") from None


def _int(path: Path, line: int, column: str, text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise InputError(path, f"{column} must be an integer, found {text!r}", place=f"line {line}") from None
    if value < 0:
        raise InputError(path, f"{column} must not be negative, found {value}", place=f"line {line}")
    if column == "frame":
        return check_frame(path, f"line {line}", value)
    return check_id(path, f"line {line}", value, column)


def _floats(path: Path, line: int, columns: Sequence[str], texts: Sequence[str]) -> list[float]:
    values = []
    for column, text in zip(columns, texts, strict=True):
        try:
            value = float(text)
        except ValueError:
            raise InputError(path, f"{column} must be a number, found {text!r}", place=f"line {line}") from None
        if not math.isfinite(value) or abs(value) > MAX_COORDINATE:
            raise InputError(path, f"{column} must be a finite pixel position (at most {MAX_COORDINATE:g}), "
                             f"found {text!r}", place=f"line {line}")
        values.append(value)
    return values


def _box(path: Path, line: int, values: list[float]) -> list[float]:
    x1, y1, x2, y2 = values
    if x2 < x1 or y2 < y1:
        raise InputError(path, f"box has x2 < x1 or y2 < y1: ({x1:g}, {y1:g}, {x2:g}, {y2:g})", place=f"line {line}")
    return values


def read_objects_csv(path: str | Path) -> tuple[ObjectTrack, ...]:
    path = Path(path)
    rows = []
    for line, row in _rows(path, OBJECT_COLUMNS):
        frame = _int(path, line, "frame", row[0])
        track_id = _int(path, line, "track_id", row[1])
        label = row[2].strip()
        if not label:
            raise InputError(path, "label is empty", place=f"line {line}")
        box = _box(path, line, _floats(path, line, OBJECT_COLUMNS[3:], row[3:]))
        rows.append((track_id, label, frame, box))
    if not rows:
        raise InputError(path, "no boxes: the file has a header and nothing else")
    return object_tracks(rows, path)


def read_hands_csv(path: str | Path) -> tuple[HandTrack, ...]:
    path = Path(path)
    rows = []
    for line, row in _rows(path, HAND_COLUMNS):
        frame = _int(path, line, "frame", row[0])
        hand = row[1].strip()
        if hand not in HANDS:
            raise InputError(path, f"hand must be one of {' '.join(HANDS)}, found {hand!r}", place=f"line {line}")
        values = _floats(path, line, HAND_COLUMNS[2:], row[2:])
        rows.append((hand, frame, values[:2], _box(path, line, values[2:])))
    if not rows:
        raise InputError(path, "no hands: the file has a header and nothing else")
    return hand_tracks(rows, path)


def _number(value: float) -> str:
    return f"{value:.2f}".rstrip("0").rstrip(".")


def write_objects_csv(path: str | Path, tracks: Sequence[ObjectTrack]) -> None:
    """Rows sorted by frame, then track id."""
    rows = []
    for track in tracks:
        for frame, box in zip(track.frames.tolist(), track.boxes.tolist(), strict=True):
            rows.append((frame, track.track_id, track.label, *box))
    rows.sort(key=lambda r: (r[0], r[1]))
    def write(handle: IO[str]) -> None:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(OBJECT_COLUMNS)
        writer.writerows((f, t, label, *(_number(v) for v in box)) for f, t, label, *box in rows)

    write_text_atomic(path, write, what="object box file")


def write_hands_csv(path: str | Path, tracks: Sequence[HandTrack]) -> None:
    """Rows sorted by frame, then hand in HANDS order."""
    order = {hand: i for i, hand in enumerate(HANDS)}
    rows = []
    for track in tracks:
        for frame, xy, box in zip(track.frames.tolist(), track.xy.tolist(), track.boxes.tolist(), strict=True):
            rows.append((frame, track.hand, *xy, *box))
    rows.sort(key=lambda r: (r[0], order[r[1]]))
    def write(handle: IO[str]) -> None:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(HAND_COLUMNS)
        writer.writerows((f, hand, *(_number(v) for v in values)) for f, hand, *values in rows)

    write_text_atomic(path, write, what="hands file")
