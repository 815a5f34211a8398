"""CVAT "for video 1.1" XML: ``<track id label>`` elements holding ``<box frame xtl ytl xbr ybr outside ...>``.

Semantics follow CVAT's interpolation mode: a box holds from its frame until the track's next box, with the
coordinates interpolated linearly in between (CVAT exports usually list every frame, so there is nothing to
fill); ``outside="1"`` means the object is absent from that frame on. A track whose last box is not
``outside`` holds that box to the end of the task, as CVAT plays it: to the task's ``<stop_frame>`` (from
``<meta>``), else to the video's last frame (without either, it ends at its last box). A box with a
``rotation`` (degrees, clockwise about its centre) becomes the axis-aligned box around the rotated one, with
a warning. Every box's frame is checked against the video's frame count (without a video, the
interpolation's size is bounded) before anything is interpolated.

Tracks of other shapes (polygons, polylines, points, skeletons...) are skipped with one warning each, never
failing the file: a skeleton track holds ``<skeleton>`` elements with ``<points>`` inside, and some exports
nest its parts as ``<track>`` elements inside it, which are skipped with it. A "CVAT for images" file (boxes
under ``<image>``) is refused with a hint. Errors name the line of the element and the track id.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from wecook_core.errors import InputError
from wecook_core.files import regular_file
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

_OTHER_SHAPES = frozenset({"polygon", "polyline", "points", "cuboid", "ellipse", "mask", "skeleton", "tag"})


@dataclass
class _Box:
    line: int
    frame: int
    box: Box
    outside: bool


@dataclass
class _Track:
    line: int
    track_id: int
    label: str
    boxes: list[_Box] = field(default_factory=list)
    other_shapes: set[str] = field(default_factory=set)
    rotated: int = 0
    """Boxes with a rotation, replaced by their axis-aligned bounding box."""


class _Reader:
    def __init__(self, path: Path) -> None:
        self.path = path
        self.parser = expat.ParserCreate()
        self.parser.StartElementHandler = self.start
        self.parser.EndElementHandler = self.end
        self.stack: list[str] = []
        self.tracks: list[_Track] = []
        self.current: _Track | None = None
        self.images = 0
        self.text_of: str | None = None
        self.text: list[str] = []
        self.size: dict[str, str] = {}
        """``<original_size>``'s width and height, and the task's (or job's) ``stop_frame``, as text."""
        self.nested = 0
        """Depth inside a ``<track>`` nested in a track (a skeleton's parts): everything there is skipped."""
        self.parser.CharacterDataHandler = self.characters

    def place(self) -> str:
        return f"line {self.parser.CurrentLineNumber}"

    def start(self, name: str, attrs: dict[str, str]) -> None:
        parent = self.stack[-1] if self.stack else None
        self.stack.append(name)
        if parent is None:
            if name != "annotations":
                raise InputError(self.path, f"not CVAT XML: the root element is <{name}>, expected <annotations>",
                                 place=self.place())
            return
        if self.nested:
            self.nested += 1
            return
        if name == "image" and parent == "annotations":
            self.images += 1
        elif name == "track" and parent == "annotations":
            self.start_track(attrs)
        elif name == "track" and self.current is not None:  # a skeleton's part, tracked on its own
            self.current.other_shapes.add("skeleton")
            self.nested = 1
        elif name == "track":
            raise InputError(self.path, f"<track> inside <{parent}>: tracks must be children of <annotations>",
                             place=self.place())
        elif name == "box" and parent == "track":
            self.add_box(attrs)
        elif parent == "track" and name in _OTHER_SHAPES and self.current is not None:
            self.current.other_shapes.add(name)
        elif self.wanted_text(name, parent):
            self.text_of, self.text = name, []

    def wanted_text(self, name: str, parent: str) -> bool:
        """Whether the element's text is one of :attr:`size`'s (the first task's or job's stop frame)."""
        if name in ("width", "height"):
            return parent == "original_size"
        return (name == "stop_frame" and parent in ("task", "job") and self.stack[:2] == ["annotations", "meta"]
                and "stop_frame" not in self.size)

    def characters(self, data: str) -> None:
        if self.text_of is not None:
            self.text.append(data)

    def end(self, name: str) -> None:
        self.stack.pop()
        if self.nested:
            self.nested -= 1
            return
        if name == "track":
            self.current = None
        if self.text_of is not None and name == self.text_of:
            self.size[name] = "".join(self.text).strip()
            self.text_of = None

    def start_track(self, attrs: dict[str, str]) -> None:
        place = self.place()
        if "id" not in attrs:
            raise InputError(self.path, "<track> has no id attribute", place=place)
        track_id = check_id(self.path, place, parse_int(self.path, place, "track id", attrs["id"]), "track id")
        label = attrs.get("label", "").strip()
        if not label:
            raise InputError(self.path, f"<track id={track_id}> has no label attribute", place=place)
        for other in self.tracks:
            if other.track_id == track_id:
                raise InputError(self.path, f"track id {track_id} is used twice (first at line {other.line})",
                                 place=place)
        self.current = _Track(self.parser.CurrentLineNumber, track_id, label)
        self.tracks.append(self.current)

    def add_box(self, attrs: dict[str, str]) -> None:
        assert self.current is not None
        place = self.place()
        frame = check_frame(self.path, place, parse_int(self.path, place, "frame", attrs.get("frame")))
        x1, y1, x2, y2 = (parse_float(self.path, place, key, attrs.get(key)) for key in ("xtl", "ytl", "xbr", "ybr"))
        outside = attrs.get("outside", "0").strip()
        if outside not in ("0", "1"):
            raise InputError(self.path, f'outside must be "0" or "1", got {outside!r}', place=place)
        box = check_box(self.path, place, x1, y1, x2, y2)
        if attrs.get("rotation", "0").strip() not in ("", "0", "0.0", "0.00"):
            box = _rotated(box, parse_float(self.path, place, "rotation", attrs["rotation"]))
            self.current.rotated += 1
        boxes = self.current.boxes
        if boxes and frame <= boxes[-1].frame:
            raise InputError(
                self.path,
                f"track {self.current.track_id}: box for frame {frame} after one for frame {boxes[-1].frame} "
                "(boxes must be in increasing frame order, one per frame)",
                place=place,
            )
        boxes.append(_Box(self.parser.CurrentLineNumber, frame, box, outside == "1"))


MAX_INTERPOLATED = 5_000_000
"""Most boxes interpolated when no video bounds the frames (days of video at 30 fps for a few tracks)."""


def read_cvat(
    path: str | Path, *, frame_size: tuple[int, int] | None = None, frame_count: int | None = None,
    warn: Warn = ignore_warning,
) -> tuple[ObjectTrack, ...]:
    """Object tracks of a CVAT for video XML file.

    ``frame_size`` (width, height) of the video, when given, must match the ``<original_size>`` the file was
    annotated on (boxes of another resolution would land in the wrong place). ``frame_count``, the frames of
    the video, bounds the frames of the boxes: one past it is an error, found before interpolating.
    """
    path = regular_file(path, "CVAT XML file")
    reader = _Reader(path)
    try:
        with path.open("rb") as handle:
            reader.parser.ParseFile(handle)
    except FileNotFoundError:
        raise InputError(path, "file not found") from None
    except IsADirectoryError:
        raise InputError(path, "is a directory, expected a CVAT XML file") from None
    except (LookupError, ValueError) as error:  # an unknown encoding in the XML declaration
        raise InputError(path, f"malformed XML ({error})", place="line 1") from None
    except expat.ExpatError as error:
        if error.code == expat.errors.codes[expat.errors.XML_ERROR_NO_ELEMENTS]:
            raise InputError(path, "empty file: expected CVAT for video XML") from None
        message = expat.ErrorString(error.code)
        raise InputError(path, f"malformed XML ({message})", place=f"line {error.lineno}, column {error.offset + 1}"
                         ) from None
    if reader.images and not reader.tracks:
        raise InputError(path, "this is CVAT for images XML (boxes under <image>); export the task as "
                         "'CVAT for video 1.1' so boxes come in tracks")
    _check_size(path, reader.size, frame_size)
    end = _task_end(path, reader.size.get("stop_frame"), frame_count)
    _check_frames(path, reader.tracks, frame_count, end)
    rows: list[tuple[int, str, int, Box]] = []
    rotated = 0
    for track in reader.tracks:
        if track.other_shapes and not track.boxes:
            warn(f"{path}:line {track.line}: track {track.track_id} ({track.label}) holds "
                 f"{', '.join(sorted(track.other_shapes))}, not boxes; skipped")
            continue
        rotated += track.rotated
        rows.extend((track.track_id, track.label, frame, box) for frame, box in _frames(track, end))
    if rotated:
        warn(f"{path}: {rotated} rotated boxes taken as the axis-aligned boxes around them")
    if not rows:
        raise InputError(path, "no boxes: no <track> holds a <box> that is not outside")
    return object_tracks(rows, path)


def _task_end(path: Path, stop_frame: str | None, frame_count: int | None) -> int | None:
    """The last frame of the task (a track not ``outside`` at its last box holds to it): the task's
    ``<stop_frame>`` within the video, else the video's last frame, else None (unknown)."""
    end = None
    if stop_frame is not None:
        end = check_frame(path, "<stop_frame>", parse_int(path, "<stop_frame>", "stop_frame", stop_frame),
                          "stop_frame")
    if frame_count is not None:
        end = frame_count - 1 if end is None else min(end, frame_count - 1)
    return end


def _check_frames(path: Path, tracks: list[_Track], frame_count: int | None, end: int | None) -> None:
    """Boxes within the video (boxes are in increasing frame order, so a track's last is its latest), and
    the interpolation bounded when there is no video."""
    total = 0
    for track in tracks:
        if not track.boxes:
            continue
        last = track.boxes[-1]
        # An outside box may sit on the frame just past the end (it closes a run that reaches the last frame).
        if frame_count is not None and last.frame >= frame_count + last.outside:
            raise InputError(path, f"track {track.track_id} ({track.label}) has a box at frame {last.frame}, but "
                             f"the video has frames 0-{frame_count - 1}", place=f"line {last.line}")
        held = end if end is not None and not last.outside and not track.other_shapes else last.frame
        total += max(held, last.frame) - track.boxes[0].frame + 1
        if frame_count is None and total > MAX_INTERPOLATED:
            raise InputError(path, f"the tracks span more than {MAX_INTERPOLATED:,} frames between their "
                             "keyframes; give the video so the frames can be checked", place=f"line {last.line}")


def _frames(track: _Track, end: int | None) -> list[tuple[int, Box]]:
    """Every frame where the track's object is present, interpolating between consecutive boxes; the last box,
    when not outside, held to ``end`` (the task's last frame, when known)."""
    result: list[tuple[int, Box]] = []
    for box, following in zip(track.boxes, [*track.boxes[1:], None], strict=True):
        if box.outside:
            continue
        result.append((box.frame, box.box))
        if following is None:
            if end is not None:
                result.extend((frame, box.box) for frame in range(box.frame + 1, end + 1))
            continue
        span = following.frame - box.frame
        for step in range(1, span):
            result.append((box.frame + step, _lerp(box.box, following.box, step / span)))
    return result


def _rotated(box: Box, degrees: float) -> Box:
    """The axis-aligned bounding box of ``box`` turned by ``degrees`` about its centre."""
    cx, cy = (box[0] + box[2]) / 2, (box[1] + box[3]) / 2
    w, h = box[2] - box[0], box[3] - box[1]
    c, s = abs(math.cos(math.radians(degrees))), abs(math.sin(math.radians(degrees)))
    half_w, half_h = (w * c + h * s) / 2, (w * s + h * c) / 2
    return (cx - half_w, cy - half_h, cx + half_w, cy + half_h)


def _lerp(a: Box, b: Box, t: float) -> Box:
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]), a[3] + t * (b[3] - a[3]))


def _check_size(path: Path, size: dict[str, str], frame_size: tuple[int, int] | None) -> None:
    if frame_size is None or "width" not in size or "height" not in size:
        return
    try:
        annotated = (int(size["width"]), int(size["height"]))
    except ValueError:
        return
    if annotated != tuple(frame_size):
        raise InputError(path, f"annotated on {annotated[0]}x{annotated[1]} frames but the video is "
                         f"{frame_size[0]}x{frame_size[1]}", place="<original_size>")
