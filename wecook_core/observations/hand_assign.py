"""Naming detected hands ``LH_P1 RH_P1 LH_P2 RH_P2`` from per-frame detections, by the body they are on.

A hand detector (MediaPipe's) reports per frame a set of hands, each with a handedness guess and a score, but
no identity; its handedness assumes a mirrored (selfie) image and it sometimes reports one hand twice or both
hands with the same side. As OpenPose does for the paper, a hand is named by the arm it ends when a pose model
found the body (:mod:`~wecook_core.observations.body_assign`: the person and the arm's side), the handedness
being the tie-breaker where no arm claims it. The names are not taken from one frame but from the whole video:

1. **duplicates** in a frame (boxes overlapping by more than ``duplicate_iou``) are one hand: the best scored
   stays; **arms**: with the frame's skeletons, each hand is given the arm whose wrist it ends, if any;
2. **tracklets**: frame by frame, detections join the tracklets seen within ``max_gap_seconds`` by
   :func:`scipy.optimize.linear_sum_assignment` on the centre distance, plus ``arm_cost`` when the detection
   was found on the other side's arm than the tracklet so far, or (no arm to compare) ``label_cost`` when its
   handedness disagrees with the tracklet's: where hands cross, distance cannot tell them apart; a detection
   farther than the hand can move in the time since (``max_speed`` frame diagonals a second, at least its own
   size) starts a tracklet;
3. **persons**: two when at least ``two_person_fraction`` of the frames with hands show more than two hands
   that each last ``min_track_seconds``, else one (or as given); with two, tracklets are split by where their
   person is (the shoulders of the bodies they were found on, else the hand's own place) into the two groups
   that are tightest along the line the persons stand on (exact 1-D two-means), P1 the one further left, P2
   the other (DESIGN.md: persons from left to right);
4. **sides**: each tracklet's side is the visibility-weighted vote of the arms it was found on, else its
   score-weighted vote of handedness (un-mirrored unless the video is mirrored); tracklets are given sides
   most confident first (those on arms first), and one whose side is already taken at the same time by its
   person's other tracklet takes the other side;
5. per hand name and frame, the best scored detection stays.

Pure: detections in, :class:`~wecook_core.model.HandTrack` out; nothing here reads a video.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import linear_sum_assignment

from wecook_core.model import HANDS, HandTrack
from wecook_core.observations.body_assign import ArmHint, BodyParams, Skeleton, hint_hands

_INFEASIBLE = 1e9


@dataclass(frozen=True)
class HandDetection:
    """One hand the detector found in one frame."""

    frame: int
    label: str
    """The detector's handedness, ``"Left"`` or ``"Right"``, as it reports it (MediaPipe: of a mirrored image)."""
    score: float
    """The detector's confidence in the handedness, 0-1."""
    xy: tuple[float, float]
    """Centre, pixels."""
    box: tuple[float, float, float, float]
    """``x1 y1 x2 y2`` pixels."""
    arm: ArmHint | None = None
    """The body's arm this hand ends, when a pose model found one (:func:`~.body_assign.hint_hands`)."""
    pointing: tuple[float, float] | None = None
    """Unit vector from the wrist to the knuckle of the middle finger, in image coordinates: the way the hand
    points, away from its forearm (None when the detector gives no landmarks)."""


@dataclass(frozen=True)
class AssignParams:
    duplicate_iou: float = 0.5
    """Two detections of one frame overlapping more than this (intersection over union) are one hand."""
    max_speed: float = 1.5
    """Fastest a hand moves, in frame diagonals a second."""
    label_cost: float = 0.1
    """Matching a detection to a tracklet whose handedness so far disagrees with it costs as much as this
    distance, in frame diagonals: enough to keep crossing hands apart, too little to swap distant ones."""
    arm_cost: float = 0.3
    """Matching a detection found on one side's arm to a tracklet whose arms so far are the other side's costs
    as much as this distance, in frame diagonals: the body is surer than the handedness, so more."""
    max_gap_seconds: float = 1.0
    """A tracklet not seen for longer than this ends."""
    two_person_fraction: float = 0.05
    """Frames with more than two lasting hands, among frames with hands, from which on two persons are
    assumed."""
    min_track_seconds: float = 1.0
    """A hand seen for less than this (first to last detection) does not count towards a second person."""
    mirrored: bool = False
    """The video is mirrored (a selfie camera): the detector's handedness is then taken as it is, and the
    body's sides swap."""
    body: BodyParams = field(default_factory=BodyParams)
    """How hands are given to the arms of the bodies a pose model found."""


@dataclass(frozen=True)
class AssignedHand:
    """A detection with the hand name it was given (for the raw output and for tests)."""

    detection: HandDetection
    hand: str
    tracklet: int


@dataclass
class _Tracklet:
    index: int
    detections: list[HandDetection] = field(default_factory=list)

    @property
    def last(self) -> HandDetection:
        return self.detections[-1]

    def frames(self) -> set[int]:
        return {d.frame for d in self.detections}

    def vote(self, mirrored: bool) -> float:
        """Positive: the person's right hand; negative: left; weighted by score."""
        total = 0.0
        for d in self.detections:
            right = d.label.lower() == "right"
            if not mirrored:
                right = not right
            total += d.score if right else -d.score
        return total

    def arm_vote(self) -> float:
        """Positive: found on the person's right arm; negative: left; weighted by the wrist's visibility."""
        return sum((d.arm.weight if d.arm.side == "RH" else -d.arm.weight) for d in self.detections
                   if d.arm is not None)

    def side_vote(self, mirrored: bool) -> tuple[float, float]:
        """(arm vote, handedness vote): the body decides; the handedness only where no arm was found."""
        return self.arm_vote(), self.vote(mirrored)

    def mean_x(self) -> float:
        return float(np.mean([d.xy[0] for d in self.detections]))

    def anchor(self) -> tuple[float, float]:
        """Where the tracklet's person is: the mean shoulder centre of the bodies it was found on, else the
        hand's own mean place."""
        bodies = [d.arm.body for d in self.detections if d.arm is not None]
        points = bodies or [d.xy for d in self.detections]
        x, y = np.mean(np.asarray(points, dtype=np.float64), axis=0)
        return float(x), float(y)


def iou(a: Sequence[float], b: Sequence[float]) -> float:
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    if w <= 0 or h <= 0:
        return 0.0
    inter = w * h
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def deduplicate(detections: Sequence[HandDetection], threshold: float) -> list[HandDetection]:
    """One frame's detections without repeats: of boxes overlapping more than ``threshold``, the best scored."""
    kept: list[HandDetection] = []
    for d in sorted(detections, key=lambda d: -d.score):
        if all(iou(d.box, k.box) <= threshold for k in kept):
            kept.append(d)
    return kept


def _diagonal(box: Sequence[float]) -> float:
    return float(np.hypot(box[2] - box[0], box[3] - box[1]))


def track(
    frames: Sequence[Sequence[HandDetection]], fps: float, size: tuple[int, int], params: AssignParams
) -> list[_Tracklet]:
    """Tracklets of the (deduplicated) detections of consecutive frames."""
    diagonal = float(np.hypot(*size))
    max_gap = params.max_gap_seconds * fps
    tracklets: list[_Tracklet] = []
    active: list[_Tracklet] = []
    for detections in frames:
        if not detections:
            continue
        frame = detections[0].frame
        active = [t for t in active if frame - t.last.frame <= max_gap]
        costs = np.full((len(active), len(detections)), _INFEASIBLE)
        for i, t in enumerate(active):
            seconds = (frame - t.last.frame) / fps
            for j, d in enumerate(detections):
                distance = float(np.hypot(d.xy[0] - t.last.xy[0], d.xy[1] - t.last.xy[1]))
                reach = max(params.max_speed * diagonal * seconds, _diagonal(d.box))
                if distance <= reach:
                    # Where hands cross, distance cannot tell them apart; the arm they end can, and else
                    # the detector's handedness.
                    arm = t.arm_vote()
                    if d.arm is not None and arm != 0:
                        penalty = params.arm_cost if (arm > 0) != (d.arm.side == "RH") else 0.0
                    else:
                        disagrees = (t.vote(True) >= 0) != (d.label.lower() == "right")
                        penalty = params.label_cost if disagrees else 0.0
                    costs[i, j] = distance / diagonal + penalty
        matched: set[int] = set()
        if active:
            rows, cols = linear_sum_assignment(costs)
            for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
                if costs[i, j] < _INFEASIBLE:
                    active[i].detections.append(detections[j])
                    matched.add(j)
        for j, d in enumerate(detections):
            if j not in matched:
                new = _Tracklet(len(tracklets), [d])
                tracklets.append(new)
                active.append(new)
    return tracklets


def count_persons(tracklets: Sequence[_Tracklet], fps: float, params: AssignParams) -> int:
    """Two when, in at least ``two_person_fraction`` of the frames with hands, more than two hands that each
    stay at least ``min_track_seconds`` are seen at once; else one. (A short-lived extra detection, such as a
    ghost MediaPipe's tracking leaves where two hands crossed, is no second person.)"""
    frames_with_hands: set[int] = set()
    lasting: dict[int, int] = {}
    for t in tracklets:
        frames = t.frames()
        frames_with_hands |= frames
        if (max(frames) - min(frames) + 1) / fps >= params.min_track_seconds:
            for f in frames:
                lasting[f] = lasting.get(f, 0) + 1
    if not frames_with_hands:
        return 1
    crowded = sum(1 for n in lasting.values() if n > 2)
    return 2 if crowded >= params.two_person_fraction * len(frames_with_hands) else 1


def split_persons(tracklets: Sequence[_Tracklet], persons: int) -> dict[int, str]:
    """Tracklet index -> ``P1``/``P2``: the tightest split (weighted by length) of where their persons are
    (:meth:`_Tracklet.anchor`: the body's shoulders where one was found, which stay apart where the hands of
    two people reach past each other), along the line the persons are spread on (the anchors' principal axis:
    side by side, or across a table); P1 is the group further left in the image."""
    if persons == 1 or len(tracklets) < 2:
        return {t.index: "P1" for t in tracklets}
    anchors = np.array([t.anchor() for t in tracklets])
    weights_all = np.array([len(t.detections) for t in tracklets], dtype=np.float64)
    centred = anchors - np.average(anchors, axis=0, weights=weights_all)
    _, vectors = np.linalg.eigh((centred * weights_all[:, None]).T @ centred)
    axis = vectors[:, -1]
    projected = centred @ axis
    order = np.argsort(projected, kind="stable")
    ordered = [tracklets[i] for i in order.tolist()]
    xs = projected[order]
    weights = weights_all[order]
    best, best_cost = 1, np.inf
    for k in range(1, len(ordered)):
        cost = 0.0
        for part, w in ((xs[:k], weights[:k]), (xs[k:], weights[k:])):
            mean = np.average(part, weights=w)
            cost += float(np.sum(w * (part - mean) ** 2))
        if cost < best_cost:
            best, best_cost = k, cost
    first = float(np.average(anchors[order[:best], 0], weights=weights[:best]))
    second = float(np.average(anchors[order[best:], 0], weights=weights[best:]))
    left = ("P1", "P2") if first <= second else ("P2", "P1")
    return {t.index: (left[0] if i < best else left[1]) for i, t in enumerate(ordered)}


def assign_sides(tracklets: Sequence[_Tracklet], persons: dict[int, str], mirrored: bool) -> dict[int, str]:
    """Tracklet index -> hand name: each tracklet's voted side (its arms', else its handedness') unless its
    person's other tracklet holds that side at the same time; the most confident tracklets choose first, those
    found on an arm before those only the handedness names."""
    taken: dict[str, set[int]] = {}
    names: dict[int, str] = {}
    votes = {t.index: t.side_vote(mirrored) for t in tracklets}
    order = sorted(tracklets, key=lambda t: (-abs(votes[t.index][0]), -abs(votes[t.index][1]), t.index))
    for t in order:
        person = persons[t.index]
        arm, hand = votes[t.index]
        voted = "RH" if (arm > 0 if arm != 0 else hand >= 0) else "LH"
        other = "LH" if voted == "RH" else "RH"
        frames = t.frames()
        side = voted
        for candidate in (voted, other):
            if not taken.get(f"{candidate}_{person}", set()) & frames:
                side = candidate
                break
        name = f"{side}_{person}"
        taken.setdefault(name, set()).update(frames)
        names[t.index] = name
    return names


def assign_hands(
    frames: Sequence[Sequence[HandDetection]],
    fps: float,
    size: tuple[int, int],
    params: AssignParams | None = None,
    *,
    persons: int | None = None,
    skeletons: Mapping[int, Sequence[Skeleton]] | None = None,
) -> tuple[tuple[HandTrack, ...], tuple[AssignedHand, ...]]:
    """Hand tracks named by person and side from per-frame detections (``frames`` in frame order, one list
    per frame that was read), and every kept detection with its name. ``size`` is (width, height) pixels;
    ``persons`` (1 or 2) forces the number of persons; ``skeletons`` (frame -> the bodies a pose model found
    in it) gives hands to arms first (:mod:`~wecook_core.observations.body_assign`)."""
    params = params or AssignParams()
    clean = [deduplicate(f, params.duplicate_iou) for f in frames]
    if skeletons:
        clean = [[replace(d, arm=arm) for d, arm in
                  zip(f, hint_hands(f, skeletons.get(f[0].frame, ()), size, params.body, params.mirrored),
                      strict=True)] if f else f for f in clean]
    tracklets = track(clean, fps, size, params)
    count = persons if persons is not None else count_persons(tracklets, fps, params)
    if count not in (1, 2):
        raise ValueError(f"persons must be 1 or 2, got {count}")
    person_of = split_persons(tracklets, count)
    names = assign_sides(tracklets, person_of, params.mirrored)
    best: dict[tuple[str, int], tuple[HandDetection, int]] = {}
    for t in tracklets:
        name = names[t.index]
        for d in t.detections:
            key = (name, d.frame)
            if key not in best or d.score > best[key][0].score:
                best[key] = (d, t.index)
    assigned = tuple(AssignedHand(d, name, index) for (name, _), (d, index) in
                     sorted(best.items(), key=lambda item: (item[0][1], HANDS.index(item[0][0]))))
    tracks = []
    for hand in HANDS:
        mine = [a.detection for a in assigned if a.hand == hand]
        if not mine:
            continue
        tracks.append(HandTrack(
            hand,
            np.array([d.frame for d in mine], dtype=np.int64),
            np.array([d.xy for d in mine], dtype=np.float64).reshape(-1, 2),
            np.array([d.box for d in mine], dtype=np.float64).reshape(-1, 4),
        ))
    return tuple(tracks), assigned
