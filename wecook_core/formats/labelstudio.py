"""Label Studio video object tracking exports (``VideoRectangle``): the JSON export and JSON-MIN.

- JSON: a list of tasks (or one task), each ``{"data": {"video": ...}, "annotations": [{"result": [...]}]}``;
  a result of ``"type": "videorectangle"`` is one track, its ``value`` holding ``labels`` and ``sequence``.
  The first annotation of a task is taken (a task annotated twice gets a warning), its ``predictions`` when it
  has none.
- JSON-MIN: a list of tasks ``{"video": ..., "<name>": [{"sequence": [...], "labels": [...]}, ...]}``.

A sequence item is a keyframe ``{"frame", "x", "y", "width", "height", "enabled"}``: frames are 1-based,
coordinates are percentages (0-100) of the frame's width and height. As Label Studio plays it back, a box is
interpolated linearly from a keyframe to the next one while the keyframe is ``enabled``; a keyframe with
``"enabled": false`` shows its box on its own frame only; the last keyframe, when enabled, holds until the end
of the video. Frames past the video's end are an error found before anything is interpolated.

A file with several tasks needs the video: the task whose video has the same file name (or stem) as the video,
or the one chosen by ``select`` (its id or video name).
"""

from __future__ import annotations

from collections.abc import Mapping
from itertools import pairwise
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError, load_json
from wecook_core.files import read_text
from wecook_core.formats.fields import Box, Warn, ignore_warning, parse_float, parse_int
from wecook_core.formats.tracks import object_tracks
from wecook_core.model import ObjectTrack, VideoInfo

_Keyframe = tuple[int, Box, bool]  # 0-based frame, pixel box, interpolate to the next keyframe


def looks_like_labelstudio(head: str) -> bool:
    """Whether the first KB of a JSON file read like a Label Studio video export."""
    return '"sequence"' in head or '"videorectangle"' in head or ('"annotations"' in head and '"data"' in head)


def read_labelstudio(
    path: str | Path,
    *,
    video: VideoInfo | None,
    select: str | None = None,
    warn: Warn = ignore_warning,
) -> tuple[ObjectTrack, ...]:
    """Object tracks of one task of a Label Studio video export, in pixels of ``video`` (required: the
    coordinates are percentages of its size)."""
    path = Path(path)
    if video is None:
        raise InputError(path, "Label Studio boxes are percentages of the frame: the video is needed")
    data = _load(path)
    tasks = data if isinstance(data, list) else [data]
    if not tasks:
        raise InputError(path, "no tasks: the export is an empty list")
    index, task = _choose_task(path, tasks, select, video.path)
    regions = _regions(path, index, task, warn)
    count = video.decoded_frames if video.decoded_frames is not None else video.frame_count
    rows: list[tuple[int, str, int, Box]] = []
    for track_id, (place, region) in enumerate(regions, 1):
        label = _label(path, place, region)
        keyframes = _keyframes(path, place, region, video, count)
        rows.extend((track_id, label, frame, box) for frame, box in _frames(keyframes, count))
    if not rows:
        raise InputError(path, f"no boxes: task {index} has no videorectangle with a keyframe")
    return object_tracks(rows, path)


def _load(path: Path) -> Any:
    """The file's JSON, read as every importer reads the user's files (a regular file of bounded size; bounded
    nesting and integers: :func:`~wecook_core.errors.load_json`)."""
    return load_json(path, read_text(path, "Label Studio JSON file").removeprefix("\ufeff"))


def _video_name(task: Mapping[str, Any]) -> str | None:
    data = task.get("data")
    value = data.get("video") if isinstance(data, Mapping) else task.get("video")
    return str(value) if isinstance(value, str) else None


def _choose_task(path: Path, tasks: list[Any], select: str | None, video_path: str) -> tuple[int, Mapping[str, Any]]:
    for i, task in enumerate(tasks):
        if not isinstance(task, Mapping):
            raise InputError(path, f"expected a task object, got {type(task).__name__}", place=f"task {i}")
    if len(tasks) == 1 and select is None:
        return 0, tasks[0]
    wanted = Path(video_path)
    for i, task in enumerate(tasks):
        name = _video_name(task) or ""
        base = Path(name.split("?")[0]).name
        if select is not None:
            if select in (str(task.get("id")), name, base, Path(base).stem):
                return i, task
        elif base == wanted.name or Path(base).stem == wanted.stem or base.endswith("-" + wanted.name):
            return i, task  # Label Studio prefixes uploaded files with a hash and "-"
    names = ", ".join(f"{t.get('id')}: {Path((_video_name(t) or '?').split('?')[0]).name}" for t in tasks)
    what = f"no task is {select!r}" if select is not None else f"no task is of the video {wanted.name}"
    raise InputError(path, f"{what}; the tasks are {names} (choose one with --select-video)")


def _regions(path: Path, index: int, task: Mapping[str, Any], warn: Warn) -> list[tuple[str, Mapping[str, Any]]]:
    """(place, region) of every video rectangle of the task: JSON's results' values, or JSON-MIN's entries."""
    regions: list[tuple[str, Mapping[str, Any]]] = []
    for key in ("annotations", "completions", "predictions"):
        annotations = task.get(key)
        if not isinstance(annotations, list) or not annotations:
            continue
        if len(annotations) > 1:
            warn(f"{path}: task {index} has {len(annotations)} {key}; the first is taken")
        first = annotations[0]
        results = first.get("result") if isinstance(first, Mapping) else None
        if not isinstance(results, list):
            raise InputError(path, f"{key}[0] has no result list", place=f"task {index}")
        skipped: set[str] = set()
        for j, result in enumerate(results):
            if not isinstance(result, Mapping):
                continue
            kind = str(result.get("type", ""))
            value = result.get("value")
            if kind.lower() == "videorectangle" and isinstance(value, Mapping):
                regions.append((f"task {index}, {key}[0].result[{j}]", value))
            elif kind:
                skipped.add(kind)
        if skipped:
            warn(f"{path}: task {index}: results of type {', '.join(sorted(skipped))} are not video boxes; skipped")
        return regions
    for key, value in task.items():  # JSON-MIN: the control's name -> its regions
        if isinstance(value, list):
            for j, region in enumerate(value):
                if isinstance(region, Mapping) and isinstance(region.get("sequence"), list):
                    regions.append((f"task {index}, {key}[{j}]", region))
    return regions


def _label(path: Path, place: str, region: Mapping[str, Any]) -> str:
    labels = region.get("labels") or region.get("videorectangle") or region.get("rectanglelabels")
    if isinstance(labels, list) and labels and isinstance(labels[0], str) and labels[0].strip():
        return labels[0].strip()
    raise InputError(path, "the box has no label (value.labels is missing or empty)", place=place)


def _keyframes(path: Path, place: str, region: Mapping[str, Any], video: VideoInfo, count: int) -> list[_Keyframe]:
    sequence = region.get("sequence")
    if not isinstance(sequence, list):
        raise InputError(path, "the box has no sequence of keyframes", place=place)
    keyframes: list[_Keyframe] = []
    for k, item in enumerate(sequence):
        where = f"{place}.sequence[{k}]"
        if not isinstance(item, Mapping):
            raise InputError(path, "a keyframe must be an object", place=where)
        frame = parse_int(path, where, "frame", item.get("frame")) - 1
        if frame < 0:
            raise InputError(path, f"frame {frame + 1} is not a frame (Label Studio counts from 1)", place=where)
        if frame >= count:
            raise InputError(path, f"frame {frame + 1} lies past the end of the video {Path(video.path).name} "
                             f"({count} frames, 1-{count} as Label Studio counts)", place=where)
        x, y, w, h = (parse_float(path, where, key, item.get(key)) for key in ("x", "y", "width", "height"))
        if w < 0 or h < 0:
            raise InputError(path, f"negative width or height ({w:g}, {h:g})", place=where)
        box = (x / 100 * video.width, y / 100 * video.height, (x + w) / 100 * video.width,
               (y + h) / 100 * video.height)
        enabled = item.get("enabled", True)
        if not isinstance(enabled, bool):
            raise InputError(path, f"enabled must be true or false, got {enabled!r}", place=where)
        keyframes.append((frame, box, enabled))
    keyframes.sort(key=lambda k: k[0])
    for (a, _, _), (b, _, _) in pairwise(keyframes):
        if a == b:
            raise InputError(path, f"two keyframes for frame {a + 1}", place=place)
    return keyframes


def _frames(keyframes: list[_Keyframe], count: int) -> list[tuple[int, Box]]:
    """Every frame the box shows in, interpolated between enabled keyframes, the last held to the end."""
    result: list[tuple[int, Box]] = []
    for i, (frame, box, enabled) in enumerate(keyframes):
        result.append((frame, box))
        if not enabled:
            continue
        if i + 1 < len(keyframes):
            following, target, _ = keyframes[i + 1]
            span = following - frame
            for step in range(1, span):
                result.append((frame + step, _lerp(box, target, step / span)))
        else:
            result.extend((f, box) for f in range(frame + 1, count))
    return result


def _lerp(a: Box, b: Box, t: float) -> Box:
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]), a[3] + t * (b[3] - a[3]))
