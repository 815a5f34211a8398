"""Everything the pipeline starts from, imported and checked: video facts, object boxes, hands, categories.

Checks, each an :class:`InputError` naming the file and the frame and track, unless said otherwise:

- every frame index lies in the video (``0 <= frame < frames that decode``);
- coordinates are pixels: boxes or hands all within ``[0, 1]`` are normalised coordinates, refused;
- an object box that overhangs the image is clipped to it, however far (people and objects entering or
  leaving the picture stick out of it in real ground truth: MOT's, Label Studio's own example); the count,
  the largest overhang and the first such box, in the file's own frame numbering, are a warning. A box that
  lies wholly outside the image shows nothing there and is dropped (also counted); when every box of the file
  lies outside, the boxes belong to another video (or another resolution): an error;
- a hand centre may lie outside the image by up to ``hand_tolerance`` of its size (clipped); farther out is
  an error; hand boxes are only clipped (they are derived from keypoints);
- gaps inside a hand track are by default not an error (a hand leaves the picture, a detector misses it; the
  segmentation interpolates): a gap longer than ``max_gap_seconds`` is reported as a warning and listed in
  :attr:`Imported.gaps` so the user sees what will be interpolated; one longer than ``gap_error_seconds``,
  when set (`wecook new --max-gap`), is an error;
- every object label gets a category (the shipped table plus the user's additions, else the commonsense corpus:
  :func:`wecook_core.knowledge.categories.categorise_labels`); a label nothing knows never stops the import:
  it is taken as an ingredient, listed in :attr:`Imported.uncategorised` and reported as a warning.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.errors import InputError
from wecook_core.formats.detect import file_frame, frame_namer, read_hands, read_objects
from wecook_core.formats.tracks import object_name
from wecook_core.formats.video import frame_count_note, probe_video, usable_frames
from wecook_core.model import Category, HandTrack, ObjectTrack, Observations, VideoInfo

if TYPE_CHECKING:
    from wecook_core.knowledge.categories import CategoryTable


@dataclass(frozen=True)
class InputChecks:
    """How forgiving the checks are."""

    hand_tolerance: float = 0.05
    """How far a hand centre may lie outside the image and still be clipped, as a fraction of the image width
    (for x) or height (for y). Object boxes are clipped however far they overhang."""
    max_gap_seconds: float = 2.0
    """A hand missing inside its track for longer than this is reported."""
    gap_error_seconds: float | None = None
    """A hand missing inside its track for longer than this is an error (None: gaps are never an error)."""


@dataclass(frozen=True)
class HandGap:
    """Frames ``[start, end)`` inside a hand's track where the hand is missing."""

    hand: str
    start: int
    end: int
    seconds: float


@dataclass(frozen=True, eq=False)
class Imported:
    """The observations and what the import found on the way."""

    observations: Observations
    objects_format: str
    hands_format: str
    warnings: tuple[str, ...] = ()
    """One line each: clipped boxes, long gaps, frame count disagreements, skipped rows..."""
    gaps: tuple[HandGap, ...] = ()
    """Gaps longer than ``InputChecks.max_gap_seconds``, by hand then frame."""
    missing: dict[str, int] = field(default_factory=dict)
    """Hand -> frames missing between its first and last detection (all gaps, short ones too)."""
    uncategorised: tuple[str, ...] = ()
    """Object labels that neither the category table nor the commonsense corpus knows (taken as ingredients
    until the user says)."""
    video_problem: str | None = None
    """Why the video itself could not be opened, when its recorded facts stood in (see
    :meth:`wecook_core.session.Session.import_observations`); None: the video was probed."""


NO_OBJECTS = "none"
"""The objects format of a session made from a video alone (no boxes imported)."""


def load_observations(
    video: str | Path,
    objects: str | Path,
    hands: str | Path,
    *,
    objects_format: str | None = None,
    hands_format: str | None = None,
    labels: str | Path | None = None,
    select: str | None = None,
    categories: CategoryTable | None = None,
    checks: InputChecks | None = None,
    video_facts: VideoInfo | None = None,
) -> Observations:
    """The checked observations of a video (see :func:`import_observations` for the warnings too)."""
    return import_observations(
        video, objects, hands, objects_format=objects_format, hands_format=hands_format, labels=labels,
        select=select, categories=categories, checks=checks, video_facts=video_facts,
    ).observations


def import_observations(
    video: str | Path,
    objects: str | Path | None,
    hands: str | Path,
    *,
    objects_format: str | None = None,
    hands_format: str | None = None,
    labels: str | Path | None = None,
    select: str | None = None,
    annotation_fps: float | None = None,
    categories: CategoryTable | None = None,
    checks: InputChecks | None = None,
    video_facts: VideoInfo | None = None,
) -> Imported:
    """Import the video's facts, the object boxes (none when ``objects`` is None) and the hand tracks, name
    objects uniquely, categorise them and check everything against the video. ``labels`` is the labels file of
    MOT boxes; ``select`` the video (name or id) of a COCO-VID file that holds several; ``annotation_fps`` the
    frame rate a Label Studio annotation was made at (None: read from the file). ``video_facts``, when
    known (a session records them), stand in for probing ``video``, which is then not opened (it may be missing
    or damaged)."""
    checks = checks or InputChecks()
    warnings: list[str] = []
    info = video_facts if video_facts is not None else probe_video(video)
    note = frame_count_note(info)
    if note:
        warnings.append(note)
    object_tracks: Sequence[ObjectTrack] = ()
    if objects is None:  # a video alone: boxes are drawn in the workbench's box mode
        chosen_objects = NO_OBJECTS
    else:
        object_tracks, chosen_objects = read_objects(objects, objects_format, labels=labels, video=info,
                                                     select=select, fps=annotation_fps, warn=warnings.append)
    hand_tracks, chosen_hands = read_hands(hands, hands_format, frame_count=usable_frames(info),
                                           warn=warnings.append)
    namer = frame_namer(chosen_objects, objects, video=info, select=select, fps=annotation_fps) if objects else None
    checked_objects = _check_objects(Path(objects or video), unique_names(object_tracks), info,
                                     namer or (lambda frame: file_frame("csv", frame)), warnings)
    checked_hands = _check_hands(Path(hands), hand_tracks, info, checks)
    gaps, missing = hand_gaps(checked_hands, info.fps, checks.max_gap_seconds)
    if checks.gap_error_seconds is not None:
        for gap in hand_gaps(checked_hands, info.fps, checks.gap_error_seconds)[0]:
            raise InputError(hands, f"{gap.hand} is missing for {gap.seconds:.1f} s, frames {gap.start}-{gap.end - 1}"
                             f", longer than the {checks.gap_error_seconds:g} s allowed",
                             place=f"frame {gap.start}")
    for gap in gaps:
        warnings.append(f"{hands}: {gap.hand} is missing for {gap.seconds:.1f} s, frames {gap.start}-{gap.end - 1}"
                        " (interpolated)")
    names, unknown = _categorise(checked_objects, categories)
    if unknown:
        from wecook_core.knowledge.categories import DEFAULT_CATEGORY, EXTEND_HINT

        warnings.append(f"{objects}: no category known for {', '.join(repr(u) for u in unknown)}: taken as "
                        f"{DEFAULT_CATEGORY.value} for now; {EXTEND_HINT}")
    observations = Observations(info, tuple(checked_objects), tuple(checked_hands), names)
    return Imported(observations, chosen_objects, chosen_hands, tuple(warnings), tuple(gaps), missing,
                    uncategorised=unknown)


def unique_names(tracks: Iterable[ObjectTrack]) -> tuple[ObjectTrack, ...]:
    """Tracks renamed so names are unique: the label's name, then ``_2``, ``_3``... in track id order,
    skipping names already taken (a label ``"bowl 2"`` keeps ``bowl_2``; a second ``bowl`` becomes ``bowl_3``)."""
    ordered = sorted(tracks, key=lambda t: t.track_id)
    bases = [object_name(t.label) for t in ordered]
    taken: set[str] = set()
    counts: dict[str, int] = {}
    result = []
    # Names equal to their label's base go first so that a literal "bowl_2" label keeps its name.
    firsts: dict[str, int] = {}
    for track, base in zip(ordered, bases, strict=True):
        firsts.setdefault(base, track.track_id)
    taken.update(firsts)
    for track, base in zip(ordered, bases, strict=True):
        if firsts[base] == track.track_id:
            name = base
        else:
            count = counts.get(base, 1)
            while True:
                count += 1
                name = f"{base}_{count}"
                if name not in taken:
                    break
            counts[base] = count
            taken.add(name)
        result.append(track if track.name == name else replace(track, name=name))
    return tuple(result)


def hand_gaps(
    tracks: Sequence[HandTrack], fps: float, max_gap_seconds: float
) -> tuple[list[HandGap], dict[str, int]]:
    """Gaps longer than ``max_gap_seconds`` inside each track, and every track's missing frame count."""
    gaps = []
    missing = {}
    for track in tracks:
        frames = track.frames
        missing[track.hand] = int(frames[-1] - frames[0] + 1 - len(frames)) if len(frames) else 0
        steps = np.diff(frames)
        for i in np.flatnonzero(steps > 1):
            start, end = int(frames[i]) + 1, int(frames[i + 1])
            seconds = (end - start) / fps
            if seconds > max_gap_seconds:
                gaps.append(HandGap(track.hand, start, end, seconds))
    return gaps, missing


# ------------------------------------------------------------------------------------------ checks


def _check_frames(path: Path, what: str, frames: np.ndarray, info: VideoInfo,
                  name: Callable[[int], str] = lambda frame: file_frame("csv", frame)) -> None:
    """Frames within the video, an error in the file's own numbering (``name``: 1-based for MOT...)."""
    count = usable_frames(info)
    if len(frames) and (frames[0] < 0 or frames[-1] >= count):
        bad = name(int(frames[-1] if frames[-1] >= count else frames[0]))
        first, last = (name(f).split()[-1] for f in (0, count - 1))
        raise InputError(path, f"{what} is in {bad}, but the video {Path(info.path).name} has frames "
                         f"{first}-{last}", place=bad)


def _outside(boxes: np.ndarray, info: VideoInfo, tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """(rows beyond the tolerance, rows needing a clip)."""
    tx, ty = tolerance * info.width, tolerance * info.height
    x1, y1, x2, y2 = boxes.T
    far = (x1 < -tx) | (y1 < -ty) | (x2 > info.width + tx) | (y2 > info.height + ty)
    near = (x1 < 0) | (y1 < 0) | (x2 > info.width) | (y2 > info.height)
    return far, near


def _clip(boxes: np.ndarray, info: VideoInfo) -> np.ndarray:
    limits = np.array([info.width, info.height, info.width, info.height], dtype=np.float64)
    return np.clip(boxes, 0.0, limits)


def _check_pixels(path: Path, what: str, values: Sequence[np.ndarray], info: VideoInfo) -> None:
    """Refuse coordinates that are all within [0, 1] on a real image: normalised, not pixels."""
    if min(info.width, info.height) < 16 or not values:
        return
    stacked = np.concatenate([v.reshape(-1) for v in values])
    if len(stacked) and np.abs(stacked).max() <= 1.0:
        raise InputError(path, f"every {what} coordinate lies within [0, 1]: normalised coordinates, but wecook "
                         f"needs pixels of the {info.width}x{info.height} video (OpenPose: --keypoint_scale 0)")


def _check_objects(
    path: Path, tracks: Sequence[ObjectTrack], info: VideoInfo, name: Callable[[int], str], warnings: list[str]
) -> list[ObjectTrack]:
    """Tracks with their boxes clipped to the image, boxes wholly outside it dropped (see the module
    docstring)."""
    _check_pixels(path, "box", [t.boxes for t in tracks], info)
    result = []
    clipped = dropped = total = 0
    worst = (0.0, "")
    first_dropped = ""
    for track in tracks:
        what = f"track {track.track_id} ({track.label})"
        _check_frames(path, what, track.frames, info, name)
        total += len(track.frames)
        x1, y1, x2, y2 = track.boxes.T
        inside = (x1 < info.width) & (x2 > 0) & (y1 < info.height) & (y2 > 0)
        over = np.maximum.reduce([-x1, -y1, x2 - info.width, y2 - info.height, np.zeros(len(x1))])
        near = inside & (over > 0)
        if near.any():
            clipped += int(near.sum())
            i = int(np.argmax(np.where(near, over, -1)))
            if over[i] > worst[0]:
                worst = (float(over[i]), f"{what} at {name(int(track.frames[i]))}")
            track = replace(track, boxes=_clip(track.boxes, info))
        if not inside.all():
            dropped += int((~inside).sum())
            if not first_dropped:
                first_dropped = f"{what} at {name(int(track.frames[~inside][0]))}"
            if not inside.any():
                continue
            track = replace(track, frames=track.frames[inside], boxes=track.boxes[inside])
        result.append(track)
    if total and dropped == total:
        raise InputError(path, f"every box lies outside the {info.width}x{info.height} image of "
                         f"{Path(info.path).name}: boxes of another video, or of another resolution")
    if clipped:
        warnings.append(f"{path}: clipped {clipped} boxes that overhang the {info.width}x{info.height} image, by "
                        f"up to {worst[0]:.0f} px ({worst[1]})")
    if dropped:
        warnings.append(f"{path}: dropped {dropped} boxes that lie wholly outside the {info.width}x{info.height} "
                        f"image (the first: {first_dropped})")
    return result


def _check_hands(path: Path, tracks: Sequence[HandTrack], info: VideoInfo, checks: InputChecks) -> list[HandTrack]:
    _check_pixels(path, "hand", [t.xy for t in tracks], info)
    result = []
    for track in tracks:
        _check_frames(path, f"hand {track.hand}", track.frames, info)
        points = np.concatenate([track.xy, track.xy], axis=1)
        far, near = _outside(points, info, checks.hand_tolerance)
        if far.any():
            i = int(np.flatnonzero(far)[0])
            raise InputError(path, f"hand {track.hand} at ({track.xy[i, 0]:g}, {track.xy[i, 1]:g}) lies outside "
                             f"the {info.width}x{info.height} image by more than {checks.hand_tolerance:.0%}",
                             place=f"frame {int(track.frames[i])}")
        xy = np.clip(track.xy, 0.0, [info.width, info.height]) if near.any() else track.xy
        boxes = _clip(track.boxes, info)
        result.append(replace(track, xy=xy, boxes=boxes))
    return result


def _categorise(
    tracks: Sequence[ObjectTrack], table: CategoryTable | None
) -> tuple[dict[str, Category], tuple[str, ...]]:
    from wecook_core.knowledge.categories import categorise_labels

    found = categorise_labels([t.label for t in tracks], table)
    return {t.name: found.categories[t.label] for t in tracks}, found.unknown
