"""Turning rows of (track, frame, box) from any importer into model tracks, with unique object names."""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

import numpy as np

from wecook_core.errors import InputError
from wecook_core.model import HANDS, HandTrack, ObjectTrack

_NON_WORD = re.compile(r"[^a-z0-9]+")


def object_name(label: str) -> str:
    """``"Chopping Board" -> "chopping_board"``: the tree terminal for a label."""
    name = _NON_WORD.sub("_", label.strip().lower()).strip("_")
    if not name or not name[0].isalpha():
        name = "object_" + name if name else "object"
    return name


def object_tracks(
    rows: Iterable[tuple[int, str, int, Sequence[float]]], source: str | Path, *, frame_base: int = 0
) -> tuple[ObjectTrack, ...]:
    """Group ``(track_id, label, frame, (x1, y1, x2, y2))`` rows into tracks named uniquely.

    Tracks are ordered by track id; a repeated label gets ``_2``, ``_3``... in that order. A track with two
    labels or two boxes in one frame is an error naming the source and the frame as the file numbers it (its
    first frame is ``frame_base``: 1 for MOT and Label Studio).
    """
    frames: dict[int, list[int]] = defaultdict(list)
    boxes: dict[int, list[Sequence[float]]] = defaultdict(list)
    labels: dict[int, str] = {}
    for track_id, label, frame, box in rows:
        known = labels.setdefault(track_id, label)
        if known != label:
            raise InputError(source, f"track {track_id} is labelled both {known!r} and {label!r}",
                             place=f"frame {frame + frame_base}")
        frames[track_id].append(frame)
        boxes[track_id].append(box)
    seen: dict[str, int] = defaultdict(int)
    tracks = []
    for track_id in sorted(labels):
        f = np.asarray(frames[track_id], dtype=np.int64)
        b: np.ndarray = np.asarray(boxes[track_id], dtype=np.float64).reshape(-1, 4)
        order = np.argsort(f, kind="stable")
        f, b = f[order], b[order]
        repeated = np.flatnonzero(np.diff(f) == 0)
        if len(repeated):
            raise InputError(source, f"track {track_id} has two boxes in one frame",
                             place=f"frame {int(f[repeated[0]]) + frame_base}")
        base = object_name(labels[track_id])
        seen[base] += 1
        name = base if seen[base] == 1 else f"{base}_{seen[base]}"
        tracks.append(ObjectTrack(track_id, labels[track_id], name, f, b))
    return tuple(tracks)


def hand_tracks(
    rows: Iterable[tuple[str, int, Sequence[float], Sequence[float]]], source: str | Path
) -> tuple[HandTrack, ...]:
    """Group ``(hand, frame, (x, y), (x1, y1, x2, y2))`` rows into one track per hand, in HANDS order."""
    frames: dict[str, list[int]] = defaultdict(list)
    xy: dict[str, list[Sequence[float]]] = defaultdict(list)
    boxes: dict[str, list[Sequence[float]]] = defaultdict(list)
    for hand, frame, centre, box in rows:
        frames[hand].append(frame)
        xy[hand].append(centre)
        boxes[hand].append(box)
    tracks = []
    for hand in HANDS:
        if hand not in frames:
            continue
        f = np.asarray(frames[hand], dtype=np.int64)
        order = np.argsort(f, kind="stable")
        f = f[order]
        repeated = np.flatnonzero(np.diff(f) == 0)
        if len(repeated):
            raise InputError(source, f"hand {hand} appears twice in one frame", place=f"frame {int(f[repeated[0]])}")
        tracks.append(HandTrack(
            hand, f,
            np.asarray(xy[hand], dtype=np.float64).reshape(-1, 2)[order],
            np.asarray(boxes[hand], dtype=np.float64).reshape(-1, 4)[order],
        ))
    return tuple(tracks)


def fill_sparse(
    tracks: Sequence[ObjectTrack], *, factor: float = 1.5, warn: Callable[[str], None] | None = None,
    source: str | Path = "",
) -> tuple[ObjectTrack, ...]:
    """Sparse tracks filled in between their boxes; dense ones (boxes on consecutive frames) as they are.

    A track is sparse when its median step between boxes is more than one frame: it was annotated every so
    many frames (YouCook2-BB: one box a second), so the object is there between two boxes and its box is
    interpolated linearly, as CVAT interpolates between keyframes. A gap longer than ``factor`` times the
    track's own step is a sample where the object was absent, and stays a gap. Relative to each track's
    sampling, so it holds at any frame rate.
    """
    result = []
    for track in tracks:
        steps = np.diff(track.frames)
        if len(steps) == 0 or float(np.median(steps)) <= 1:
            result.append(track)
            continue
        step = float(np.median(steps))
        frames: list[np.ndarray] = [track.frames[:1]]
        boxes: list[np.ndarray] = [track.boxes[:1]]
        for i, gap in enumerate(steps.tolist()):
            if 1 < gap <= factor * step:
                t = np.arange(1, gap, dtype=np.float64)[:, None] / gap
                frames.append(track.frames[i] + np.arange(1, gap, dtype=np.int64))
                boxes.append(track.boxes[i] + t * (track.boxes[i + 1] - track.boxes[i]))
            frames.append(track.frames[i + 1:i + 2])
            boxes.append(track.boxes[i + 1:i + 2])
        filled = ObjectTrack(track.track_id, track.label, track.name, np.concatenate(frames),
                             np.concatenate(boxes).reshape(-1, 4))
        if warn is not None:
            warn(f"{source}: track {track.track_id} ({track.label}) has a box every {step:g} frames; "
                 f"interpolated to {len(filled.frames)} frames")
        result.append(filled)
    return tuple(result)
