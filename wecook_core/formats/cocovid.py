"""COCO-VID JSON (mmtracking's CocoVID, TAO): ``videos``, ``images``, ``annotations``, ``categories``; and
YouTube-VIS / OVIS JSON (``videos[].file_names``, one ``annotations[]`` entry per instance).

- ``images[]``: ``id``, ``video_id``, and the 0-based frame index in TAO's ``frame_index`` (the frame of the
  video) or else ``frame_id``. An image with both is placed by ``frame_index``: mmtracking's conversion of TAO
  adds ``frame_id`` as the image's index among the *annotated* frames (0, 1, 2... for frames 0, 30, 60),
  which is not the video's frame (a warning counts them);
- ``annotations[]``: ``image_id``, ``category_id``, ``bbox`` ``[x, y, width, height]`` in pixels, and the
  track in ``instance_id`` (or ``track_id``);
- ``categories[]``: ``id``, ``name`` (the label).

YouTube-VIS and OVIS have no ``images``: each video lists its frames' ``file_names``, and each annotation is
one instance over the whole video, ``bboxes`` holding one ``[x, y, width, height]`` per file name, ``null``
where the instance is absent; the track is the annotation's ``id``. Which video frame a file name stands for
is read as :mod:`wecook_core.formats.numbering` says: YouTube-VIS's ``00000.jpg, 00005.jpg...`` count the
30 fps video's frames from 0 (every fifth annotated; the frames in between are interpolated as any sparse
track), OVIS's ``img_0000001.jpg...`` are the images in order.

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
from wecook_core.formats.numbering import name_frames
from wecook_core.formats.tracks import object_tracks
from wecook_core.model import ObjectTrack


def read_cocovid(
    path: str | Path,
    *,
    video: str | int | None = None,
    video_path: str | Path | None = None,
    frame_count: int | None = None,
    warn: Warn = ignore_warning,
) -> tuple[ObjectTrack, ...]:
    """Object tracks of one video of a COCO-VID, TAO, YouTube-VIS or OVIS file (see the module docstring for
    choosing the video). ``frame_count``, the video's frames, helps read YouTube-VIS file names."""
    path = Path(path)
    data = _load(path)
    videos = _list(path, data, "videos", required=False)
    if "images" not in data and any(isinstance(v, dict) and "file_names" in v for v in videos):
        return _read_vis(path, data, videos, video, video_path, frame_count, warn)
    video_id = _choose_video(path, videos, video, video_path)
    categories = _categories(path, data)
    frames: dict[int, int] = {}
    keys: dict[int, tuple[str, int]] = {}  # image id -> (the frame's field, index in images)
    by_index = 0
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
        key = "frame_index" if entry.get("frame_index") is not None else "frame_id"
        if entry.get(key) is None:
            raise InputError(path, "image has no frame_index (nor frame_id)", place=place)
        frame = check_frame(path, place, parse_int(path, place, key, entry.get(key)), key)
        if key == "frame_index" and entry.get("frame_id") is not None and entry.get("frame_id") != frame:
            by_index += 1
        frames[image_id] = frame
        keys[image_id] = (key, i)
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
        if frame_count is not None and frames[image_id] >= frame_count:
            key, k = keys[image_id]
            raise InputError(path, f"instance {track_id} is on image {image_id} (images[{k}]), {key} "
                             f"{frames[image_id]}, but the video has frames 0-{frame_count - 1}", place=place)
        rows.append((track_id, categories[category_id], frames[image_id], check_box(path, place, x, y, x + w, y + h)))
    if by_index:
        warn(f"{path}: {by_index} images placed by frame_index (their frame in the video), not frame_id "
             "(mmtracking's index among the annotated frames)")
    if crowd:
        warn(f"{path}: skipped {crowd} crowd annotations (iscrowd)")
    if not rows:
        raise InputError(path, "no boxes: the file has no annotations" + (" for this video" if videos else ""))
    return object_tracks(rows, path)


def _categories(path: Path, data: Mapping[str, Any]) -> dict[int, str]:
    categories: dict[int, str] = {}
    for i, category in enumerate(_list(path, data, "categories")):
        place = f"categories[{i}]"
        entry = _object(path, category, place)
        category_id = parse_int(path, place, "id", entry.get("id"))
        name = entry.get("name")
        if not isinstance(name, str) or not name.strip():
            raise InputError(path, "category has no name", place=place)
        categories[category_id] = name.strip()
    return categories


def _read_vis(
    path: Path, data: Mapping[str, Any], videos: list[Any], video: str | int | None,
    video_path: str | Path | None, frame_count: int | None, warn: Warn,
) -> tuple[ObjectTrack, ...]:
    """YouTube-VIS / OVIS: per-video ``file_names``, per-instance ``bboxes`` (see the module docstring)."""
    video_id = _choose_video(path, videos, video, video_path)
    entry = next(_object(path, v, f"videos[{i}]") for i, v in enumerate(videos)
                 if isinstance(v, dict) and v.get("id") == video_id)
    index = videos.index(entry)
    names = entry.get("file_names")
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise InputError(path, "file_names must be a list of the video's frame files", place=f"videos[{index}]")
    frames, note = name_frames(names, frame_count)
    if note:
        warn(f"{path}:videos[{index}]: {note}")
    for frame in frames:
        check_frame(path, f"videos[{index}].file_names", frame)
    categories = _categories(path, data)
    rows: list[tuple[int, str, int, Box]] = []
    crowd = 0
    for i, annotation in enumerate(_list(path, data, "annotations")):
        place = f"annotations[{i}]"
        item = _object(path, annotation, place)
        if item.get("video_id") != video_id:
            continue
        if item.get("iscrowd"):
            crowd += 1
            continue
        track_id = check_id(path, place, parse_int(path, place, "id", item.get("id")), "id")
        category_id = parse_int(path, place, "category_id", item.get("category_id"))
        if category_id not in categories:
            raise InputError(path, f"category_id {category_id} is not among the categories", place=place)
        bboxes = item.get("bboxes")
        if not isinstance(bboxes, list) or len(bboxes) != len(names):
            raise InputError(path, f"bboxes must be a list of {len(names)} boxes (one per file name of video "
                             f"{video_id}, null where absent)", place=place)
        for k, bbox in enumerate(bboxes):
            if bbox is None:
                continue
            where = f"{place}.bboxes[{k}]"
            if not isinstance(bbox, list) or len(bbox) != 4:
                raise InputError(path, f"expected [x, y, width, height] or null, got {bbox!r}", place=where)
            x, y, w, h = (parse_float(path, where, "bbox", v) for v in bbox)
            if frame_count is not None and frames[k] >= frame_count:
                raise InputError(path, f"instance {track_id} is on {names[k]}, frame {frames[k]}, but the video has "
                                 f"frames 0-{frame_count - 1}", place=where)
            rows.append((track_id, categories[category_id], frames[k], check_box(path, where, x, y, x + w, y + h)))
    if crowd:
        warn(f"{path}: skipped {crowd} crowd annotations (iscrowd)")
    if not rows:
        raise InputError(path, f"no boxes: no annotation of video {video_id} has a box")
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
        name = entry.get("name")
        names = entry.get("file_names")
        if name is None and isinstance(names, list) and names and isinstance(names[0], str):
            name = Path(names[0]).parent.as_posix()  # YouTube-VIS: the frames' folder is the video's name
        entries.append((parse_int(path, f"videos[{i}]", "id", entry.get("id")), str(name or "")))
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
