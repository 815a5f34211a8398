"""OpenPose JSON output: a folder of ``*_keypoints.json`` files (or, renamed, any ``*.json``), one per frame,
``people[]`` each with ``pose_keypoints_2d``, ``hand_left_keypoints_2d``, ``hand_right_keypoints_2d`` (flat
``x, y, confidence`` triples; confidence 0 means not found).

Which frame a file is: OpenPose run on a video writes ``NAME_000000000012_keypoints.json`` for frame 12 (a
12-digit counter from 0), so the number before ``_keypoints`` is the frame when the set of files reads like
that counter (the smallest is 0, or every number has its 12 digits); run on a folder of images it names each
file after its image (``im1010.jpg`` gives ``im1010_keypoints.json``), numbers that are the user's own, and
the video made of those images shows them in order: then a file's frame is its place in the order of the
numbers, with a warning (:mod:`wecook_core.formats.numbering`). OpenPose does not track people, so
identities are kept here:

1. frame by frame, detections are assigned to the persons seen so far by :func:`scipy.optimize.linear_sum_assignment`
   on the mean distance of the body keypoints confident in both (the body centres when none are shared),
   divided by the body size; a cost above ``max_distance`` body sizes starts a new person;
2. when that made more than ``max_persons`` persons, the longest ones are kept and each shorter one joins the
   kept person it does not overlap in time and lies closest to (within ``merge_distance`` body sizes), or is
   dropped with a warning;
3. persons are numbered P1, P2 from left to right by their mean body position.

A hand's centre and box come from its confident hand keypoints (at least ``min_hand_points``); otherwise
from the wrist of the body (the centre pushed a little past the wrist along the forearm); otherwise the hand
is missing in that frame. Left and right are the person's own, as OpenPose reports them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import linear_sum_assignment

from wecook_core.errors import InputError, load_json
from wecook_core.files import read_text
from wecook_core.formats.fields import MAX_COORDINATE, Warn, check_frame, ignore_warning
from wecook_core.formats.numbering import NumberingError, name_frames
from wecook_core.model import HandTrack

# BODY_25, COCO-18 and MPI-15 share these indices.
_R_ELBOW, _R_WRIST, _L_ELBOW, _L_WRIST = 3, 4, 6, 7
_INFEASIBLE = 1e9


@dataclass(frozen=True)
class OpenPoseParams:
    min_confidence: float = 0.2
    """Keypoints below this confidence are ignored."""
    max_distance: float = 1.0
    """Largest frame-to-frame move of a person, in body sizes (diagonal of the confident body keypoints)."""
    merge_distance: float = 2.0
    """Largest jump, in body sizes, across which a short person track joins a longer one."""
    max_persons: int = 2
    """Persons kept (wecook names hands of P1 and P2)."""
    min_hand_points: int = 3
    """Confident hand keypoints needed to place a hand from them rather than from the wrist."""


@dataclass(frozen=True, eq=False)
class _Detection:
    frame: int
    body: np.ndarray
    """(K, 3) x, y, confidence; K may be 0."""
    left: np.ndarray
    right: np.ndarray
    centre: np.ndarray
    scale: float


@dataclass(eq=False)
class _Person:
    detections: list[_Detection] = field(default_factory=list)

    @property
    def frames(self) -> set[int]:
        return {d.frame for d in self.detections}

    @property
    def last(self) -> _Detection:
        return self.detections[-1]


def read_openpose(
    path: str | Path, params: OpenPoseParams | None = None, *, frame_count: int | None = None,
    warn: Warn = ignore_warning,
) -> tuple[HandTrack, ...]:
    """Hand tracks ``LH_P1 RH_P1 LH_P2 RH_P2`` (those found) from an OpenPose JSON folder. ``frame_count``,
    the video's frames, helps tell a frame counter from image names (see the module docstring)."""
    params = params or OpenPoseParams()
    path = Path(path)
    frames = _frame_files(path, frame_count, warn)
    detections: list[list[_Detection]] = []
    unusable = crowded = 0
    for frame, file in frames:
        people = _people(file)
        found = [d for d in (_detection(file, frame, i, person, params) for i, person in people) if d]
        unusable += len(people) - len(found)
        crowded += len(found) > params.max_persons
        detections.append(found)
    persons = _track(detections, params)
    if not persons:
        raise InputError(path, f"no person with confident keypoints in any of the {len(frames)} frames")
    if unusable:
        warn(f"{path}: ignored {unusable} person detections without a confident keypoint")
    if crowded:
        warn(f"{path}: {crowded} frames show more than {params.max_persons} persons")
    persons = _keep(persons, params, path, warn)
    persons.sort(key=lambda p: float(np.mean([d.centre[0] for d in p.detections])))
    tracks = []
    from_wrist = 0
    for number, person in enumerate(persons, 1):
        for side in ("L", "R"):
            track, wrists = _hand_track(f"{side}H_P{number}", person, params)
            from_wrist += wrists
            if track is not None:
                tracks.append(track)
    if not tracks:
        raise InputError(path, "no hand found: no confident hand keypoints nor wrists in any frame")
    if from_wrist:
        warn(f"{path}: {from_wrist} hand positions placed from the wrist (hand keypoints not confident)")
    order = {name: i for i, name in enumerate(("LH_P1", "RH_P1", "LH_P2", "RH_P2"))}
    return tuple(sorted(tracks, key=lambda t: order[t.hand]))


# ------------------------------------------------------------------------------------------- reading


def json_files(folder: Path) -> list[Path]:
    """The OpenPose files of a folder: its ``*_keypoints.json``, else (renamed output) its ``*.json``."""
    files = sorted(folder.glob("*_keypoints.json"))
    return files or sorted(folder.glob("*.json"))


def _frame_files(path: Path, frame_count: int | None, warn: Warn) -> list[tuple[int, Path]]:
    if not path.exists():
        raise InputError(path, "no such folder")
    if not path.is_dir():
        raise InputError(path, "expected a folder of OpenPose *_keypoints.json files")
    files = json_files(path)
    if not files:
        raise InputError(path, "no *_keypoints.json files (nor any *.json) in the folder")
    try:
        numbers, note = name_frames([file.name for file in files], frame_count)
    except NumberingError as error:
        raise InputError(files[error.index], str(error)) from None
    if note:
        warn(f"{path}: {note}")
    for frame, file in zip(numbers, files, strict=True):
        check_frame(file, "file name", frame)
    return sorted(zip(numbers, files, strict=True))


def _people(file: Path) -> list[tuple[int, dict[str, object]]]:
    text = read_text(file, "OpenPose JSON file")
    if not text.strip():
        raise InputError(file, "empty file: expected OpenPose JSON")
    data = load_json(file, text)
    if not isinstance(data, dict) or not isinstance(data.get("people"), list):
        raise InputError(file, "expected an object with a 'people' list (OpenPose JSON)")
    people = []
    for i, person in enumerate(data["people"]):
        if not isinstance(person, dict):
            raise InputError(file, "expected an object", place=f"people[{i}]")
        people.append((i, person))
    return people


def _keypoints(file: Path, person: dict[str, object], index: int, key: str, expected: int | None) -> np.ndarray:
    value = person.get(key, [])
    place = f"people[{index}].{key}"
    if value is None:
        value = []
    try:
        array = np.asarray(value) if isinstance(value, list) else None
    except ValueError:  # ragged nesting
        array = None
    if array is None or array.ndim != 1 or (len(array) and array.dtype.kind not in "iuf"):
        raise InputError(file, "expected a flat list of numbers (x, y, confidence triples)", place=place)
    if len(array) % 3:
        raise InputError(file, f"{len(array)} numbers is not a whole number of x, y, confidence triples",
                         place=place)
    points = array.astype(np.float64).reshape(-1, 3)
    if expected is not None and len(points) not in (0, expected):
        raise InputError(file, f"{len(points)} keypoints, expected {expected}", place=place)
    if not np.isfinite(points).all():
        raise InputError(file, "a keypoint is not a finite number", place=place)
    if (np.abs(points[:, :2]) > MAX_COORDINATE).any():
        raise InputError(file, f"a keypoint lies beyond {MAX_COORDINATE:g} pixels: not a pixel position", place=place)
    return points


def _detection(file: Path, frame: int, index: int, person: dict[str, object], params: OpenPoseParams
               ) -> _Detection | None:
    body = _keypoints(file, person, index, "pose_keypoints_2d", None)
    left = _keypoints(file, person, index, "hand_left_keypoints_2d", 21)
    right = _keypoints(file, person, index, "hand_right_keypoints_2d", 21)
    confident = body[body[:, 2] >= params.min_confidence, :2]
    if len(confident) == 0:  # no body: place the person by its hands, if any
        hands = np.concatenate([left, right]) if len(left) or len(right) else np.zeros((0, 3))
        confident = hands[hands[:, 2] >= params.min_confidence, :2]
        if len(confident) == 0:
            return None
    extent = confident.max(axis=0) - confident.min(axis=0)
    scale = max(float(np.hypot(*extent)), 20.0)
    return _Detection(frame, body, left, right, confident.mean(axis=0), scale)


# ------------------------------------------------------------------------------------------ tracking


def _distance(a: _Detection, b: _Detection, min_confidence: float) -> float:
    """Mean distance of the body keypoints confident in both, else of the centres, in body sizes."""
    scale = max(a.scale, b.scale)
    if len(a.body) == len(b.body) and len(a.body):
        both = (a.body[:, 2] >= min_confidence) & (b.body[:, 2] >= min_confidence)
        if both.any():
            return float(np.linalg.norm(a.body[both, :2] - b.body[both, :2], axis=1).mean()) / scale
    return float(np.linalg.norm(a.centre - b.centre)) / scale


def _costs(last: list[_Detection], detections: list[_Detection], params: OpenPoseParams) -> np.ndarray:
    """:func:`_distance` of every (person, detection) pair, skipping pairs whose centres alone rule them out.

    A centroid of some of a skeleton's keypoints lies within its bounding box, so centres farther apart than
    ``max_distance + 2`` body sizes cannot have keypoints within ``max_distance`` body sizes on average.
    """
    centres = np.array([d.centre for d in last])[:, None, :] - np.array([d.centre for d in detections])[None]
    scales = np.maximum(np.array([d.scale for d in last])[:, None], np.array([d.scale for d in detections])[None])
    possible = np.linalg.norm(centres, axis=2) <= (params.max_distance + 2) * scales
    cost = np.full(possible.shape, _INFEASIBLE)
    for i, j in zip(*np.nonzero(possible), strict=True):
        cost[i, j] = _distance(last[i], detections[j], params.min_confidence)
    return cost


def _track(frames: list[list[_Detection]], params: OpenPoseParams) -> list[_Person]:
    persons: list[_Person] = []
    for detections in frames:
        if not detections:
            continue
        assigned: set[int] = set()
        if persons:
            cost = _costs([p.last for p in persons], detections, params)
            cost[cost > params.max_distance] = _INFEASIBLE
            rows, cols = linear_sum_assignment(cost)
            for r, c in zip(rows, cols, strict=True):
                if cost[r, c] < _INFEASIBLE:
                    persons[r].detections.append(detections[c])
                    assigned.add(int(c))
        persons.extend(_Person([d]) for i, d in enumerate(detections) if i not in assigned)
    return persons


def _keep(persons: list[_Person], params: OpenPoseParams, path: Path, warn: Warn) -> list[_Person]:
    """The ``max_persons`` longest persons, with shorter fragments joined to them where they fit."""
    persons = sorted(persons, key=lambda p: (-len(p.detections), p.detections[0].frame))
    kept, rest = persons[: params.max_persons], persons[params.max_persons:]
    dropped = []
    for fragment in rest:
        best, best_distance = None, params.merge_distance
        for person in kept:
            if person.frames & fragment.frames:
                continue
            distance = min(_distance(_nearest(person, d.frame), d, params.min_confidence)
                           for d in (fragment.detections[0], fragment.detections[-1]))
            if distance <= best_distance:
                best, best_distance = person, distance
        if best is None:
            dropped.append(fragment)
        else:
            best.detections = sorted(best.detections + fragment.detections, key=lambda d: d.frame)
    if dropped:
        spans = ", ".join(f"{p.detections[0].frame}-{p.detections[-1].frame}" for p in dropped[:5])
        warn(f"{path}: dropped {len(dropped)} extra person tracks ({sum(len(p.detections) for p in dropped)} "
             f"detections, frames {spans}{', ...' if len(dropped) > 5 else ''})")
    return kept


def _nearest(person: _Person, frame: int) -> _Detection:
    return min(person.detections, key=lambda d: abs(d.frame - frame))


# --------------------------------------------------------------------------------------------- hands


def _hand_track(name: str, person: _Person, params: OpenPoseParams) -> tuple[HandTrack | None, int]:
    wrist, elbow = (_L_WRIST, _L_ELBOW) if name[0] == "L" else (_R_WRIST, _R_ELBOW)
    frames, centres, boxes = [], [], []
    from_wrist = 0
    for d in person.detections:
        keypoints = d.left if name[0] == "L" else d.right
        placed = _from_keypoints(keypoints, d, wrist, elbow, params)
        if placed is None:
            placed = _from_wrist(d, wrist, elbow, params)
            from_wrist += placed is not None
        if placed is not None:
            frames.append(d.frame)
            centres.append(placed[0])
            boxes.append(placed[1])
    if not frames:
        return None, 0
    return HandTrack(name, np.asarray(frames, dtype=np.int64), np.asarray(centres, dtype=np.float64),
                     np.asarray(boxes, dtype=np.float64)), from_wrist


def _hand_size(d: _Detection, wrist: int, elbow: int, min_confidence: float) -> float:
    """About a hand's length in pixels: 0.8 forearm when the arm is seen, else a fraction of the body."""
    body = d.body
    if len(body) > max(wrist, elbow) and body[wrist, 2] >= min_confidence and body[elbow, 2] >= min_confidence:
        return max(0.8 * float(np.linalg.norm(body[wrist, :2] - body[elbow, :2])), 8.0)
    return max(0.15 * d.scale, 8.0)


def _from_keypoints(points: np.ndarray, d: _Detection, wrist: int, elbow: int, params: OpenPoseParams
                    ) -> tuple[np.ndarray, np.ndarray] | None:
    confident = points[points[:, 2] >= params.min_confidence, :2] if len(points) else points
    if len(confident) < params.min_hand_points:
        return None
    low, high = confident.min(axis=0), confident.max(axis=0)
    centre = (low + high) / 2
    half = np.maximum((high - low) * 0.6, _hand_size(d, wrist, elbow, params.min_confidence) / 4)
    return confident.mean(axis=0), np.concatenate([centre - half, centre + half])


def _from_wrist(d: _Detection, wrist: int, elbow: int, params: OpenPoseParams
                ) -> tuple[np.ndarray, np.ndarray] | None:
    body = d.body
    if len(body) <= wrist or body[wrist, 2] < params.min_confidence:
        return None
    centre = body[wrist, :2].copy()
    if len(body) > elbow and body[elbow, 2] >= params.min_confidence:
        centre += 0.35 * (body[wrist, :2] - body[elbow, :2])
    half = _hand_size(d, wrist, elbow, params.min_confidence) / 2
    return centre, np.concatenate([centre - half, centre + half])
