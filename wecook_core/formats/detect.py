"""Which importer reads a file: detection from the content (not the name), or a format the user forces.

Objects: ``cvat`` (XML), ``mot`` (numeric rows, comma-separated, or space-separated as PathTrack's),
``cocovid`` (a JSON object: COCO-VID, TAO, YouTube-VIS, OVIS), ``labelstudio`` (Label Studio's video export:
a JSON list of tasks, or a task, with keyframe sequences; or a list of its annotations, predictions or
results), ``csv`` (wecook's native CSV with the header ``frame,track_id,label,x1,y1,x2,y2``). Hands:
``openpose`` (a folder of OpenPose JSON files, ``*_keypoints.json`` or any ``*.json``), ``csv`` (native, header
``frame,hand,x,y,x1,y1,x2,y2``).

Given the video, every box's frame is checked against its frame count before anything is interpolated (a box
at frame 1,000,000,000 is one line, not a run out of memory), and sparse tracks (a box only every so many
frames, as YouCook2-BB's one a second) are filled in between (:func:`wecook_core.formats.tracks.fill_sparse`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path

from wecook_core.errors import InputError
from wecook_core.files import regular_file
from wecook_core.formats.fields import Warn, ignore_warning
from wecook_core.formats.tracks import fill_sparse
from wecook_core.formats.video import usable_frames
from wecook_core.model import HandTrack, ObjectTrack, VideoInfo

OBJECT_FORMATS: tuple[str, ...] = ("cvat", "mot", "cocovid", "labelstudio", "csv")
HAND_FORMATS: tuple[str, ...] = ("openpose", "csv")

FRAME_BASE: dict[str, int] = {"mot": 1, "labelstudio": 1}
"""The number each format gives the video's first frame (others count from 0, as wecook does)."""


def file_frame(format: str, frame: int) -> str:
    """``"frame 24"``: wecook's 0-based ``frame`` as a file of ``format`` numbers it, for messages."""
    return f"frame {frame + FRAME_BASE.get(format, 0)}"


def frame_namer(format: str, path: str | Path, *, video: VideoInfo, select: str | None = None,
                fps: float | None = None) -> Callable[[int], str]:
    """Names wecook's 0-based video frames as the file of ``format`` at ``path`` numbers them, for messages
    (:func:`file_frame`; Label Studio's at its annotation's rate, read when first needed)."""
    if format != "labelstudio":
        return lambda frame: file_frame(format, frame)
    rates: list[float] = []

    def name(frame: int) -> str:
        if not rates:
            from wecook_core.formats.labelstudio import annotation_rate

            rates.append(annotation_rate(path, video=video, select=select, fps=fps))
        return f"frame {round(frame * rates[0] / video.fps) + 1}"

    return name


_MOT_ROW = re.compile(r"^\s*-?\d+(\.\d*)?\s*(,\s*-?[\d.eE+-]+\s*){5,}(,.*)?$")
_MOT_SPACED_ROW = re.compile(r"^\s*\d+(\.0*)?([ \t]+-?[\d.eE+-]+){5,}\s*$")
"""PathTrack's MOT ground truth: the same fields separated by spaces."""


def _head(path: Path, what: str) -> str:
    """The first few KB of ``path`` as text, stripped of a BOM and leading space."""
    if not path.exists() and not path.is_symlink():
        raise InputError(path, f"no such {what}")
    regular_file(path, what)
    try:
        with path.open("rb") as handle:
            data = handle.read(4096)
    except OSError as error:
        raise InputError(path, f"cannot read: {error.strerror}") from None
    if not data.strip():
        raise InputError(path, f"empty file: expected {what}")
    return data.decode("utf-8", errors="replace").lstrip("\ufeff \t\r\n")


def _first_line(text: str) -> str:
    for line in text.splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            return line.strip()
    return ""


def detect_objects_format(path: str | Path) -> str:
    """One of :data:`OBJECT_FORMATS`, from what the file holds."""
    path = Path(path)
    if path.is_dir():
        raise InputError(path, "is a folder; object boxes come in one file (CVAT .xml, MOT .txt, COCO-VID .json "
                         "or wecook .csv)")
    head = _head(path, "an object box file")
    if head.startswith("<"):
        return "cvat"
    if head.startswith(("{", "[")):
        from wecook_core.formats.labelstudio import looks_like_labelstudio

        return "labelstudio" if head.startswith("[") or looks_like_labelstudio(head) else "cocovid"
    line = _first_line(head)
    if line.replace(" ", "").lower().startswith("frame,track_id,label"):
        return "csv"
    if _MOT_ROW.match(line) or _MOT_SPACED_ROW.match(line):
        return "mot"
    raise InputError(path, "unknown object box format: expected CVAT video XML, MOT text, COCO-VID JSON, Label "
                     "Studio JSON or the "
                     "CSV header frame,track_id,label,x1,y1,x2,y2 (force one with --objects-format)",
                     place="line 1")


def detect_hands_format(path: str | Path) -> str:
    """One of :data:`HAND_FORMATS`, from what the file or folder holds."""
    path = Path(path)
    if path.is_dir():
        if next(path.glob("*.json"), None) is None:
            raise InputError(path, "folder without *_keypoints.json files (nor any *.json): expected OpenPose JSON "
                             "output")
        return "openpose"
    head = _head(path, "a hand track file")
    if _first_line(head).replace(" ", "").lower().startswith("frame,hand"):
        return "csv"
    if head.startswith("{"):
        raise InputError(path, "one JSON file: OpenPose output is a folder of *_keypoints.json files, give the "
                         "folder")
    raise InputError(path, "unknown hand format: expected an OpenPose JSON folder or the CSV header "
                     "frame,hand,x,y,x1,y1,x2,y2 (force one with --hands-format)", place="line 1")


def check_format(name: str, formats: tuple[str, ...], what: str) -> str:
    if name not in formats:
        raise InputError(None, f"unknown {what} format {name!r}; choose one of {', '.join(formats)}")
    return name


def read_objects(
    path: str | Path,
    format: str | None = None,
    *,
    labels: str | Path | None = None,
    video: VideoInfo | None = None,
    select: str | None = None,
    fps: float | None = None,
    warn: Warn = ignore_warning,
) -> tuple[tuple[ObjectTrack, ...], str]:
    """Object tracks of ``path`` and the format they were read as (``format`` forces one).

    ``labels`` is the MOT labels file; ``video`` lets CVAT check the annotated frame size and COCO-VID pick
    the video by name; ``select`` names the video (name or id) of a COCO-VID file that holds several; ``fps``
    is the frame rate a Label Studio annotation was made at (None: read from the file).
    """
    path = Path(path)
    chosen = check_format(format, OBJECT_FORMATS, "objects") if format else detect_objects_format(path)
    if labels is not None and chosen != "mot":
        warn(f"{labels}: a labels file only applies to MOT boxes; ignored for {chosen}")
    if select is not None and chosen not in ("cocovid", "labelstudio"):
        warn(f"choosing a video ({select!r}) only applies to COCO-VID boxes; ignored for {chosen}")
    if fps is not None and chosen != "labelstudio":
        warn(f"an annotation frame rate (--annotation-fps {fps:g}) only applies to Label Studio boxes; "
             f"ignored for {chosen}")
    if fps is not None and not (math.isfinite(fps) and fps > 0):
        raise InputError(None, f"--annotation-fps {fps:g}: expected a frame rate above 0")
    count = usable_frames(video) if video is not None else None
    if chosen == "cvat":
        from wecook_core.formats.cvat import read_cvat

        size = (video.width, video.height) if video is not None else None
        return read_cvat(path, frame_size=size, frame_count=count, warn=warn), chosen
    if chosen == "labelstudio":
        from wecook_core.formats.labelstudio import read_labelstudio

        return read_labelstudio(path, video=video, select=select, fps=fps, warn=warn), chosen
    if chosen == "mot":
        from wecook_core.formats.mot import read_mot

        tracks = read_mot(path, labels, frame_count=count, warn=warn)
    elif chosen == "cocovid":
        from wecook_core.formats.cocovid import read_cocovid

        tracks = read_cocovid(path, video=select, video_path=video.path if video else None, frame_count=count,
                              warn=warn)
    else:
        from wecook_core.formats.native import read_objects_csv

        tracks = read_objects_csv(path)
    if video is None:
        return tracks, chosen
    check_frame_range(path, tracks, video)
    return fill_sparse(tracks, warn=warn, source=path), chosen


def check_frame_range(path: str | Path, tracks: tuple[ObjectTrack, ...], video: VideoInfo) -> None:
    """InputError when a box lies in a frame the video does not have."""
    count = usable_frames(video)
    for track in tracks:
        if len(track.frames) and (track.frames[0] < 0 or track.frames[-1] >= count):
            bad = int(track.frames[-1] if track.frames[-1] >= count else track.frames[0])
            raise InputError(path, f"track {track.track_id} ({track.label}) is in frame {bad}, but the video "
                             f"{Path(video.path).name} has frames 0-{count - 1}", place=f"frame {bad}")


def read_hands(
    path: str | Path, format: str | None = None, *, frame_count: int | None = None, warn: Warn = ignore_warning
) -> tuple[tuple[HandTrack, ...], str]:
    """Hand tracks of ``path`` and the format they were read as (``format`` forces one); ``frame_count``, the
    video's frames, helps OpenPose tell its frame counter from image names."""
    path = Path(path)
    chosen = check_format(format, HAND_FORMATS, "hands") if format else detect_hands_format(path)
    if chosen == "openpose":
        from wecook_core.formats.openpose import read_openpose

        return read_openpose(path, frame_count=frame_count, warn=warn), chosen
    from wecook_core.formats.native import read_hands_csv

    if path.is_dir():
        raise InputError(path, "is a folder, expected a hand CSV file")
    return read_hands_csv(path), chosen
