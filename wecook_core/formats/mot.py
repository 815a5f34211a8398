"""MOT challenge text: ``frame,id,left,top,width,height[,conf[,class[,...]]]`` with 1-based frame and id.

Fields are separated by commas, or by spaces or tabs on a line without a comma (PathTrack's ground truth,
and what py-motmetrics' reader accepts too).

MOT files carry no labels, so a *labels file* goes with them: ``--labels FILE``, else ``labels.txt`` in the
MOT file's folder. Its lines (blank lines and ``#`` comments ignored) take one of three shapes:

- ``ID,LABEL`` on every line: the label of each track id (an optional first line ``id,label``);
- ``CLASS,LABEL`` after a first line ``class,label``: the label of each value of the class column (8th);
- ``LABEL`` alone on every line: line *k* names class *k* (1-based) of the class column, as in MOT17/20
  ground truth.

Rows whose ``conf`` is 0 are skipped: MOT ground truth marks boxes to ignore that way. Frames become 0-based;
track ids are kept as they are. Every error names the line and quotes frames as the file numbers them (from
1); given the video's frame count, a frame past it is an error at its line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from wecook_core.errors import InputError
from wecook_core.files import read_text
from wecook_core.formats.fields import (
    Box,
    Warn,
    check_box,
    check_frame,
    check_id,
    ignore_warning,
    parse_float,
    parse_int,
)
from wecook_core.formats.tracks import object_tracks
from wecook_core.model import ObjectTrack

LABELS_FILE = "labels.txt"
"""The labels file looked for beside a MOT file when none is given."""

_PAIR = re.compile(r"^\s*(-?\d+)\s*,(.*)$")


@dataclass(frozen=True)
class MotLabels:
    """Labels for a MOT file: by track id, or by the class column."""

    by: str
    """``"id"`` or ``"class"``: which column the keys match."""
    labels: dict[int, str]


def default_labels_path(mot_path: str | Path) -> Path:
    return Path(mot_path).with_name(LABELS_FILE)


def read_labels(path: str | Path) -> MotLabels:
    """Parse a labels file (see the module docstring)."""
    path = Path(path)
    lines = _text(path, "labels file").splitlines()
    entries = [(number, line.strip()) for number, line in enumerate(lines, 1)
               if line.strip() and not line.strip().startswith("#")]
    if not entries:
        raise InputError(path, "empty labels file: expected ID,LABEL lines or one LABEL per line")
    by = "id"
    header = entries[0][1].replace(" ", "").lower()
    if header in ("id,label", "class,label"):
        by = header.split(",")[0]
        entries = entries[1:]
        if not entries:
            raise InputError(path, f"labels file has the header {header} and nothing else")
    pairs = [_PAIR.match(text) for _, text in entries]
    labels: dict[int, str] = {}
    if all(pairs):
        for (number, _), match in zip(entries, pairs, strict=True):
            assert match is not None
            if len(match.group(1)) > 12:
                raise InputError(path, f"{by} {match.group(1)[:20]}... is too large", place=f"line {number}")
            key, label = int(match.group(1)), match.group(2).strip()
            if not label:
                raise InputError(path, f"no label after {key},", place=f"line {number}")
            if key in labels:
                raise InputError(path, f"{by} {key} is labelled twice", place=f"line {number}")
            labels[key] = label
        return MotLabels(by, labels)
    if any(pairs) or header in ("id,label", "class,label"):
        number = next(n for (n, _), m in zip(entries, pairs, strict=True) if not m)
        raise InputError(path, "expected ID,LABEL like the other lines", place=f"line {number}")
    return MotLabels("class", {k: text for k, (_, text) in enumerate(entries, 1)})


def split_fields(line: str) -> list[str]:
    """The fields of a MOT line: comma-separated, or whitespace-separated on a line without a comma."""
    if "," in line:
        return [field.strip() for field in line.split(",")]
    return line.split()


def read_mot(
    path: str | Path, labels: str | Path | MotLabels | None = None, *, frame_count: int | None = None,
    warn: Warn = ignore_warning,
) -> tuple[ObjectTrack, ...]:
    """Object tracks of a MOT text file, labelled by ``labels`` (a labels file path, parsed labels, or None
    for ``labels.txt`` beside ``path``). ``frame_count``, the video's frames, bounds the frames."""
    path = Path(path)
    if labels is None:
        labels = default_labels_path(path)
        if not labels.exists():
            raise InputError(path, f"MOT boxes need labels: give --labels FILE or write {labels} "
                             "(ID,LABEL per line, or one LABEL per class)")
    table = labels if isinstance(labels, MotLabels) else read_labels(labels)
    source = labels if not isinstance(labels, MotLabels) else path
    rows: list[tuple[int, str, int, Box]] = []
    ignored = 0
    seen: dict[tuple[int, int], int] = {}
    for number, line in enumerate(_text(path, "MOT file").splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        place = f"line {number}"
        fields = split_fields(line)
        if len(fields) < 6:
            raise InputError(path, f"expected frame,id,left,top,width,height[,conf,...], found {len(fields)} "
                             "fields", place=place)
        frame = parse_int(path, place, "frame", fields[0])
        track_id = parse_int(path, place, "id", fields[1])
        if frame < 1:
            raise InputError(path, f"frame {frame}: MOT frames start at 1", place=place)
        if track_id < 1:
            raise InputError(path, f"id {track_id}: expected track ids from 1 (a detection file has -1; wecook "
                             "needs tracks)", place=place)
        check_frame(path, place, frame - 1, "frame")
        if frame_count is not None and frame > frame_count:
            raise InputError(path, f"id {track_id}: frame {frame} lies past the end of the video (frames 1-"
                             f"{frame_count}, as MOT counts)", place=place)
        check_id(path, place, track_id)
        left, top, width, height = (parse_float(path, place, name, text)
                                    for name, text in zip(("left", "top", "width", "height"), fields[2:6],
                                                          strict=True))
        if len(fields) > 6 and fields[6] and parse_float(path, place, "conf", fields[6]) == 0:
            ignored += 1
            continue
        if (frame, track_id) in seen:
            raise InputError(path, f"id {track_id} has a second box in frame {frame} (first on line "
                             f"{seen[(frame, track_id)]})", place=place)
        seen[(frame, track_id)] = number
        box = check_box(path, place, left, top, left + width, top + height)
        if table.by == "id":
            key = track_id
        else:
            if len(fields) < 8 or not fields[7]:
                raise InputError(path, "the labels file names classes but this row has no class (8th field)",
                                 place=place)
            key = parse_int(path, place, "class", fields[7])
        label = table.labels.get(key)
        if label is None:
            raise InputError(source, f"no label for {table.by} {key} (used at {path}:{place})")
        rows.append((track_id, label, frame - 1, box))
    if ignored:
        warn(f"{path}: skipped {ignored} rows with conf 0 (marked to ignore)")
    if not rows:
        raise InputError(path, "no boxes: empty MOT file" if not ignored else "no boxes: every row has conf 0")
    return object_tracks(rows, path, frame_base=1)


def _text(path: Path, what: str) -> str:
    return read_text(path, what)
