"""COCO-VID JSON (mmtracking's CocoVID, TAO): ``videos``, ``images``, ``annotations``, ``categories``.

- ``images[]``: ``id``, ``video_id``, and the 0-based frame index in ``frame_id`` (or TAO's ``frame_index``);
- ``annotations[]``: ``image_id``, ``category_id``, ``bbox`` ``[x, y, width, height]`` in pixels, and the
  track in ``instance_id`` (or ``track_id``);
- ``categories[]``: ``id``, ``name`` (the label).

A file with several videos needs ``video`` (a video id or name); without it, the video whose name has the
same stem as the video file is taken, else the error lists the names.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError, load_json
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


def read_cocovid(
    path: str | Path,
    *,
    video: str | int | None = None,
    video_path: str | Path | None = None,
    warn: Warn = ignore_warning,
) -> tuple[ObjectTrack, ...]:
    """Object tracks of one video of a COCO-VID file (see the module docstring for choosing the video)."""
    path = Path(path)
    data = _load(path)
    videos = _list(path, data, "videos", required=False)
    video_id = _choose_video(path, videos, video, video_path)
    categories: dict[int, str] = {}
    for i, category in enumerate(_list(path, data, "categories")):
        place = f"categories[{i}]"
        entry = _object(path, category, place)
        category_id = parse_int(path, place, "id", entry.get("id"))
        name = entry.get("name")
        if not isinstance(name, str) or not name.strip():
            raise InputError(path, "category has no name", place=place)
        categories[category_id] = name.strip()
    frames: dict[int, int] = {}
    every_image: set[int] = set()
    for i, image in enumerate(_list(path, data, "images")):
        place = f"images[{i}]"
        entry = _object(path, image, place)
        image_id = parse_int(path, place, "id", entry.get("id"))
        if image_id in every_image:
            raise InputError(path, f"image id {image_id} is used twice", place=place)
        every_image.add(image_id)
        if video_id is not None and entry.get("video_id") != video_id:
            continue
        frame_value = entry.get("frame_id", entry.get("frame_index"))
        if frame_value is None:
            raise InputError(path, "image has no frame_id (nor frame_index)", place=place)
        frame = parse_int(path, place, "frame_id", frame_value)
        frames[image_id] = check_frame(path, place, frame, "frame_id")
    rows: list[tuple[int, str, int, Box]] = []
    crowd = 0
    for i, annotation in enumerate(_list(path, data, "annotations")):
        place = f"annotations[{i}]"
        entry = _object(path, annotation, place)
        image_id = parse_int(path, place, "image_id", entry.get("image_id"))
        if image_id not in frames:
            if image_id not in every_image:
                raise InputError(path, f"image_id {image_id} is not among the images", place=place)
            continue  # an image of another video
        if entry.get("iscrowd"):
            crowd += 1
            continue
        track_value = entry.get("instance_id", entry.get("track_id"))
        if track_value is None:
            raise InputError(path, "annotation has no instance_id (nor track_id): not a video annotation",
                             place=place)
        track_id = check_id(path, place, parse_int(path, place, "instance_id", track_value), "instance_id")
        category_id = parse_int(path, place, "category_id", entry.get("category_id"))
        if category_id not in categories:
            raise InputError(path, f"category_id {category_id} is not among the categories", place=place)
        bbox = entry.get("bbox")
        if not isinstance(bbox, list) or len(bbox) != 4:
            raise InputError(path, f"bbox must be [x, y, width, height], got {bbox!r}", place=place)
        x, y, w, h = (parse_float(path, place, "bbox", v) for v in bbox)
        rows.append((track_id, categories[category_id], frames[image_id], check_box(path, place, x, y, x + w, y + h)))
    if crowd:
        warn(f"{path}: skipped {crowd} crowd annotations (iscrowd)")
    if not rows:
        raise InputError(path, "no boxes: the file has no annotations" + (" for this video" if videos else ""))
    return object_tracks(rows, path)


def _load(path: Path) -> Mapping[str, Any]:
    text = read_text(path, "COCO-VID JSON file")
    if not text.strip():
        raise InputError(path, "empty file: expected COCO-VID JSON")
    data = load_json(path, text)
    if not isinstance(data, dict):
        raise InputError(path, "expected a JSON object with videos, images, annotations, categories")
    return data


def _list(path: Path, data: Mapping[str, Any], key: str, *, required: bool = True) -> list[Any]:
    value = data.get(key)
    if value is None:
        if required:
            raise InputError(path, f"no {key!r} list: not a COCO-VID file")
        return []
    if not isinstance(value, list):
        raise InputError(path, f"{key!r} must be a list", place=key)
    return value


def _object(path: Path, value: Any, place: str) -> Mapping[str, Any]:
    if not isinstance(value, dict):
        raise InputError(path, f"expected a JSON object, got {type(value).__name__}", place=place)
    return value


def _choose_video(
    path: Path, videos: list[Any], video: str | int | None, video_path: str | Path | None
) -> int | None:
    """The id of the chosen video, or None when the file does not list videos (take every image)."""
    entries = []
    for i, value in enumerate(videos):
        entry = _object(path, value, f"videos[{i}]")
        entries.append((parse_int(path, f"videos[{i}]", "id", entry.get("id")), str(entry.get("name", ""))))
    if not entries:
        if video is not None:
            raise InputError(path, f"video {video!r} asked for, but the file lists no videos")
        return None
    if video is not None:
        for video_id, name in entries:
            if str(video) in (str(video_id), name, Path(name).stem):
                return video_id
        raise InputError(path, f"no video {video!r}; the file has {_names(entries)}")
    if len(entries) == 1:
        return entries[0][0]
    if video_path is not None:
        stem = Path(video_path).stem
        matches = [video_id for video_id, name in entries if Path(name).stem == stem]
        if len(matches) == 1:
            return matches[0]
    raise InputError(path, f"{len(entries)} videos in the file; choose one of {_names(entries)}")


def _names(entries: list[tuple[int, str]]) -> str:
    shown = ", ".join(f"{name or '?'} (id {video_id})" for video_id, name in entries[:8])
    return shown + (", ..." if len(entries) > 8 else "")
