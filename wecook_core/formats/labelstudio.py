"""Label Studio video object tracking exports (``VideoRectangle``): the JSON export and JSON-MIN.

- JSON: a list of tasks (or one task), each ``{"data": {"video": ...}, "annotations": [{"result": [...]}]}``;
  a result of ``"type": "videorectangle"`` is one track, its ``value`` holding ``labels`` and ``sequence``.
  The first annotation of a task is taken (a task annotated twice gets a warning), its ``predictions`` when it
  has none.
- JSON-MIN: a list of tasks ``{"video": ..., "<name>": [{"sequence": [...], "labels": [...]}, ...]}``.
- Also read: a list of annotations or predictions (``[{"result": [...], "score": ...}]``, one video's), and a
  bare list of results (``[{"type": "videorectangle", "value": {...}}]``, as the frontend's own examples).

A sequence item is a keyframe ``{"frame", "x", "y", "width", "height", "rotation", "enabled", "time"}``:
frames are 1-based, coordinates are percentages (0-100) of the frame's width and height. A negative width or
height is a box drawn leftwards or upwards: normalised. A ``rotation`` (degrees, clockwise about the box's
top-left corner, as Label Studio turns rectangles) gives the axis-aligned box around the turned one, with a
warning. As Label Studio plays it back, a box is interpolated linearly from a keyframe to the next one while
the keyframe is ``enabled``; a keyframe with ``"enabled": false`` shows its box on its own frame only; the
last keyframe, when enabled, holds until the end of the video.

Frame rate. Label Studio counts frames at its ``<Video frameRate>`` (24 by default), not the video's: each
region records ``framesCount`` and ``duration`` (so ``framesCount / duration`` is the annotation's rate, up to
the rounding up of the last frame) and each keyframe its ``time`` (``frame / rate``). The rate read from
them, snapped to the video's when within 2% and else to a standard rate (23.976, 24, 25, 29.97, 30, 50,
59.94, 60) within 1%, maps keyframes onto the video's frames by time: annotation frame *f* is video frame
``round((f - 1) * video_fps / rate)``, with a warning when the rates differ. When regions disagree, or
``time`` and ``framesCount / duration`` do, the rate is ambiguous: refused in one line naming ``--annotation-fps`` (the
annotation's rate, which then decides). Without any of them the video's rate is taken. Frames past the
video's end are an error found before anything is interpolated.

A file with several tasks needs the video: the task whose video has the same file name (or stem) as the video,
or the one chosen by ``select`` (its id or video name).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError, load_json
from wecook_core.files import read_text
from wecook_core.formats.fields import Box, Warn, ignore_warning, parse_float, parse_int
from wecook_core.formats.tracks import object_tracks
from wecook_core.model import ObjectTrack, VideoInfo

_Keyframe = tuple[int, Box, bool]  # 0-based frame, pixel box, interpolate to the next keyframe

STANDARD_RATES = (23.976, 24.0, 25.0, 29.97, 30.0, 50.0, 59.94, 60.0)
"""Frame rates an annotation's measured rate snaps to (within 1%)."""

FPS_HINT = "give the annotation's frame rate with --annotation-fps (Label Studio's <Video frameRate>, 24 by default)"


@dataclass(frozen=True)
class _Key:
    """A keyframe as the file has it: 1-based frame at the annotation's rate, percentages."""

    where: str
    frame: int
    x: float
    y: float
    width: float
    height: float
    rotation: float
    enabled: bool
    time: float | None


def looks_like_labelstudio(head: str) -> bool:
    """Whether the first KB of a JSON file read like a Label Studio video export."""
    return '"sequence"' in head or '"videorectangle"' in head or ('"annotations"' in head and '"data"' in head)


def read_labelstudio(
    path: str | Path,
    *,
    video: VideoInfo | None,
    select: str | None = None,
    fps: float | None = None,
    warn: Warn = ignore_warning,
) -> tuple[ObjectTrack, ...]:
    """Object tracks of one task of a Label Studio video export, in pixels and frames of ``video`` (required:
    the coordinates are percentages of its size). ``fps``, when given, is the annotation's frame rate (else it
    is read from the file: see the module docstring)."""
    path = Path(path)
    if video is None:
        raise InputError(path, "Label Studio boxes are percentages of the frame: the video is needed")
    tasks = _tasks(path, _load(path))
    index, task = _choose_task(path, tasks, select, video.path)
    regions = _regions(path, index, task, warn)
    count = video.decoded_frames if video.decoded_frames is not None else video.frame_count
    read = [(place, _label(path, place, region), region, _keys(path, place, region)) for place, region in regions]
    rate = fps if fps is not None else _rate(path, [(place, region, keys) for place, _, region, keys in read],
                                             video, warn)
    if abs(rate - video.fps) > 1e-6 * video.fps:
        warn(f"{path}: annotated at {rate:g} fps, the video {Path(video.path).name} plays at {video.fps:g} fps: "
             f"frames mapped by time (frame f is video frame (f - 1) x {video.fps:g} / {rate:g}); "
             f"if that is wrong, {FPS_HINT}")
    rows: list[tuple[int, str, int, Box]] = []
    rotated = 0
    for track_id, (place, label, _, keys) in enumerate(read, 1):
        keyframes = _keyframes(path, place, keys, video, count, rate)
        rotated += sum(key.rotation != 0 for key in keys)
        rows.extend((track_id, label, frame, box) for frame, box in _frames(keyframes, count))
    if rotated:
        warn(f"{path}: {rotated} rotated keyframes taken as the axis-aligned boxes around them")
    if not rows:
        raise InputError(path, f"no boxes: task {index} has no videorectangle with a keyframe")
    return object_tracks(rows, path)


_SHAPE = "\0shape"
"""Marks a task made up around a list of annotations or of results (errors then name the file's own place)."""


def _place(task: Mapping[str, Any], index: int, key: str, j: int) -> str:
    shape = task.get(_SHAPE)
    if shape == "results":
        return f"[{j}]"
    if shape == "annotations":
        return f"[0].result[{j}]"
    return f"task {index}, {key}[0].result[{j}]"


def annotation_rate(path: str | Path, *, video: VideoInfo, select: str | None = None, fps: float | None = None
                    ) -> float:
    """The frame rate :func:`read_labelstudio` maps the file's frames from (``fps`` when given), for naming a
    video frame as the file numbers it: video frame *v* is the file's ``round(v * rate / video.fps) + 1``."""
    if fps is not None:
        return fps
    path = Path(path)
    index, task = _choose_task(path, _tasks(path, _load(path)), select, video.path)
    regions = _regions(path, index, task, ignore_warning)
    return _rate(path, [(place, region, _keys(path, place, region)) for place, region in regions], video,
                 ignore_warning)


def _tasks(path: Path, data: Any) -> list[Any]:
    """The tasks of the file: a list of tasks, one task, or one video's annotations (or predictions, or bare
    results) wrapped as its one task."""
    items = data if isinstance(data, list) else [data]
    if not items:
        raise InputError(path, "no tasks: the export is an empty list")
    mappings = [item for item in items if isinstance(item, Mapping)]
    if mappings and len(mappings) == len(items):
        if all("type" in item and "value" in item for item in mappings):  # bare results
            return [{"annotations": [{"result": items}], _SHAPE: "results"}]
        if all("result" in item and "data" not in item for item in mappings):  # annotations or predictions
            return [{"annotations": items, _SHAPE: "annotations"}]
    return items


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
                regions.append((_place(task, index, key, j), value))
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


def _keys(path: Path, place: str, region: Mapping[str, Any]) -> list[_Key]:
    sequence = region.get("sequence")
    if not isinstance(sequence, list):
        raise InputError(path, "the box has no sequence of keyframes", place=place)
    keys = []
    for k, item in enumerate(sequence):
        where = f"{place}.sequence[{k}]"
        if not isinstance(item, Mapping):
            raise InputError(path, "a keyframe must be an object", place=where)
        frame = parse_int(path, where, "frame", item.get("frame"))
        if frame < 1:
            raise InputError(path, f"frame {frame} is not a frame (Label Studio counts from 1)", place=where)
        x, y, w, h = (parse_float(path, where, key, item.get(key)) for key in ("x", "y", "width", "height"))
        if w < 0:  # drawn leftwards
            x, w = x + w, -w
        if h < 0:  # drawn upwards
            y, h = y + h, -h
        rotation = parse_float(path, where, "rotation", item.get("rotation") or 0)
        enabled = item.get("enabled", True)
        if not isinstance(enabled, bool):
            raise InputError(path, f"enabled must be true or false, got {enabled!r}", place=where)
        time = item.get("time")
        seconds = parse_float(path, where, "time", time) if time is not None else None
        keys.append(_Key(where, frame, x, y, w, h, rotation, enabled, seconds))
    keys.sort(key=lambda key: key.frame)
    for a, b in pairwise(keys):
        if a.frame == b.frame:
            raise InputError(path, f"two keyframes for frame {a.frame}", place=place)
    return keys


def _rate(path: Path, regions: list[tuple[str, Mapping[str, Any], list[_Key]]], video: VideoInfo, warn: Warn
          ) -> float:
    """The annotation's frame rate, read from the regions (see the module docstring)."""
    rates: list[tuple[float, str, str]] = []  # rate, how it was read, where
    for place, region, keys in regions:
        timed = [(key.frame, key.time) for key in keys if key.time is not None and key.time > 0]
        if timed:
            rates.append((_rate_of_times(timed), "its keyframes' time", place))
        count, duration = region.get("framesCount"), region.get("duration")
        if count is not None and duration is not None:
            frames = parse_float(path, place, "framesCount", count)
            seconds = parse_float(path, place, "duration", duration)
            if frames > 0 and seconds > 0:
                rates.append((frames / seconds, f"framesCount / duration = {frames:g} / {seconds:g}", place))
                if abs(seconds * video.fps - video.frame_count) > max(0.05 * video.frame_count, 0.5 * video.fps):
                    warn(f"{path}:{place}: annotated on a video of {seconds:g} s; {Path(video.path).name} lasts "
                         f"{video.frame_count / video.fps:g} s (another cut of the video?)")
    if not rates:
        return video.fps
    snapped = [(_snap(rate, video.fps), how, place) for rate, how, place in rates]
    first = snapped[0]
    for other in snapped[1:]:
        if abs(other[0] - first[0]) > 0.02 * first[0]:
            raise InputError(path, f"the annotation's frame rate is ambiguous: {first[0]:g} fps from {first[1]} at "
                             f"{first[2]}, {other[0]:g} fps from {other[1]} at {other[2]}; {FPS_HINT}")
    return first[0]


def _rate_of_times(timed: list[tuple[int, float]]) -> float:
    """Frames per second from (frame, time) pairs: the slope of frame over time, or frame / time for one."""
    if len({frame for frame, _ in timed}) < 2:
        frame, time = timed[0]
        return frame / time
    (f0, t0), (f1, t1) = timed[0], timed[-1]
    return (f1 - f0) / (t1 - t0) if t1 != t0 else f1 / t1


def _snap(rate: float, video_fps: float) -> float:
    if abs(rate - video_fps) <= 0.02 * video_fps:
        return video_fps
    nearest = min(STANDARD_RATES, key=lambda standard: abs(rate - standard))
    return nearest if abs(rate - nearest) <= 0.01 * nearest else rate


def _keyframes(path: Path, place: str, keys: list[_Key], video: VideoInfo, count: int, rate: float
               ) -> list[_Keyframe]:
    """The keyframes on the video's 0-based frames, in its pixels."""
    scale = video.fps / rate
    keyframes: list[_Keyframe] = []
    for key in keys:
        frame = round((key.frame - 1) * scale)
        if frame >= count:
            # At another rate, a frame that starts within the video may round to just past its end.
            if scale == 1 or (key.frame - 1) / rate >= count / video.fps:
                at = f" (at {rate:g} fps: {(key.frame - 1) / rate:.1f} s)" if scale != 1 else ""
                raise InputError(path, f"frame {key.frame}{at} lies past the end of the video "
                                 f"{Path(video.path).name} ({count} frames, {count / video.fps:.1f} s, "
                                 f"1-{round(count / scale)} as Label Studio counts at {rate:g} fps); if the "
                                 f"annotation's rate is wrong, {FPS_HINT}", place=key.where)
            frame = count - 1
        keyframes.append((frame, _box(key, video), key.enabled))
    for (a, _, _), (b, _, _) in pairwise(keyframes):
        if a == b:
            raise InputError(path, f"two keyframes fall on video frame {a} (the annotation's rate, {rate:g} fps, is "
                             f"above the video's, {video.fps:g}): {FPS_HINT}", place=place)
    return keyframes


def _box(key: _Key, video: VideoInfo) -> Box:
    """The keyframe's box in pixels; a rotated one as the axis-aligned box around it."""
    x, y = key.x / 100 * video.width, key.y / 100 * video.height
    w, h = key.width / 100 * video.width, key.height / 100 * video.height
    if key.rotation == 0:
        return (x, y, x + w, y + h)
    c, s = math.cos(math.radians(key.rotation)), math.sin(math.radians(key.rotation))
    xs = [x + dx * c - dy * s for dx, dy in ((0, 0), (w, 0), (0, h), (w, h))]
    ys = [y + dx * s + dy * c for dx, dy in ((0, 0), (w, 0), (0, h), (w, h))]
    return (min(xs), min(ys), max(xs), max(ys))


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
