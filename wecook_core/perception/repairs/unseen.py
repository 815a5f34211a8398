"""Holds by hands the detector does not see: an object that moves by itself is being moved by a hand.

On real footage hand detectors miss hands most of the time (MediaPipe finds a partly visible hand on well
under half of the frames of a recipe video); interpolating a hand across such gaps puts it where it was not.
But objects in a kitchen do not move on their own: a spoon sweeping through a pan, a bowl swinging over it, a
salt glass jerking above it are in a hand, seen or not. So, per object and frame (never comparing positions
across a shot cut, :mod:`wecook_core.perception.segmentation.shots`):

- it **moves** when its centre travels more than ``Params.moving_fraction`` of its own box's diagonal over
  the ``Params.dwell_s`` before or after the frame (jitter of the boxes is far smaller than that), or more
  than ``Params.moving_cap_fraction`` of the image diagonal (a big bowl swung over a pan moves by less than a
  quarter of its size);
- an ingredient that overlaps a moving container rides in it (the container is what the hand holds: found
  on tasty-a, the squash in the tipped bowl, frames 10-27), and one that overlaps a moving tool is being
  stirred or scooped by it;
- it is **unseen** when no detected hand's box comes within :data:`SEEN_WITHIN` of the object's own diagonal
  of it then (otherwise the held-object decoder of :mod:`wecook_core.perception.association.holding` judges it
  from the hand it sees, and an onion sliding off a plate that a seen hand tips is moved by the plate).

Runs of moving, unseen frames at least ``Params.min_link_s`` long (gaps shorter than
``Params.unseen_bridge_s`` bridged: a stirring spoon's box does not travel far on every frame) become
:class:`UnseenHold` s, given to the hand seen nearest the object just before the hold or just after it (within
``Params.unseen_hand_s``, in the same shot: hands do not jump, so the hand that let go of it or takes it back
moved it), else the hand that travels farthest while seen over the video (the cook's working hand; the other
steadies what it works on, and keeping still is often seen more), else the right hand of the video's first
person. Either way a hand detected away from the object while it moves unseen, for ``Params.elsewhere_s`` in
all, is passed over: a hand is in one place at a time. The pipeline cuts its segments where such a hold
starts and ends, and writes it into the timeline where that hand holds nothing.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, Category, Observations, person_of
from wecook_core.perception.association.frame_links import UnseenHold, frame_boxes
from wecook_core.perception.geometry import box_centres, box_diagonal, box_gap, box_intersection, video_diagonal
from wecook_core.perception.label_runs import runs

if TYPE_CHECKING:
    from wecook_core.perception.params import FrameParams, Params

SEEN_WITHIN = 1.0
"""A moving object is seen by a detected hand whose box comes within this many of the object's own box
diagonals of it: a hand that near is the one moving it (the decoder judges it from that hand), farther away it
is some other hand's work."""


def shot_index(length: int, shots: Sequence[int]) -> np.ndarray:
    """int ``(length,)``: which shot each frame belongs to (0 before the first cut)."""
    return np.searchsorted(np.asarray(sorted(shots), dtype=np.int64), np.arange(length), side="right")


def moving_objects(objects: np.ndarray, window: int, fraction: float, shot: np.ndarray, most: float) -> np.ndarray:
    """bool ``(frames, objects)``: the object's centre travels more than ``fraction`` of its box's diagonal
    (but never more than ``most`` pixels are asked: a big bowl swung over a pan moves less than a quarter of
    its size) over the ``window`` frames before or after, both ends in the frame's shot and seen."""
    length = len(objects)
    index = np.arange(length)
    centre = box_centres(objects)
    with np.errstate(invalid="ignore"):
        size = box_diagonal(objects)
    moving = np.zeros(objects.shape[:2], dtype=bool)
    for a, b in ((np.maximum(index - window, 0), index), (index, np.minimum(index + window, length - 1))):
        same = (shot[a] == shot[b])[:, None]
        with np.errstate(invalid="ignore"):
            travelled = np.linalg.norm(centre[b] - centre[a], axis=-1)
            moving |= same & (travelled > np.minimum(fraction * size, most))
    return moving


def _carried_containers(moving: np.ndarray, objects: np.ndarray, cats: Sequence[Category], containers: Sequence[int],
                        window: int, coherent_fraction: float, shot: np.ndarray) -> None:
    """Mark (in place) as moving a container that a moving ingredient overlaps and moves with: their
    displacements over the ``window`` frames before or after differ by less than ``coherent_fraction`` of the
    ingredient's (common fate). The yogurt poured out of a tipped measuring cup moves a good part of its own
    size while the cup, bigger, moves the same pixels and less than a quarter of its own: the cup is carried and
    the yogurt rides in it, so the hold is the cup's (the rule below then takes it off the yogurt)."""
    length = len(objects)
    if not length or not containers:
        return
    centre = box_centres(objects)
    for k, category in enumerate(cats):
        if category is not Category.INGREDIENT or not moving[:, k].any():
            continue
        rows = np.flatnonzero(moving[:, k])
        for c in containers:
            with np.errstate(invalid="ignore"):
                touching = box_intersection(objects[rows, k], objects[rows, c]) > 0
            near = rows[touching]
            if not len(near):
                continue
            together = np.zeros(len(near), dtype=bool)
            for a, b in ((np.maximum(near - window, 0), near), (near, np.minimum(near + window, length - 1))):
                own = centre[b, k] - centre[a, k]
                with np.errstate(invalid="ignore"):
                    apart = np.linalg.norm(centre[b, c] - centre[a, c] - own, axis=-1)
                    together |= (shot[a] == shot[b]) & (apart < coherent_fraction * np.linalg.norm(own, axis=-1))
            moving[near[together], c] = True


def unseen_holds(obs: Observations, params: Params, shots: Sequence[int] = (), *, rate: FrameParams | None = None,
                 ) -> tuple[UnseenHold, ...]:
    """Every hold of an object by a hand the detector does not see (see the module docstring)."""
    total = int(obs.video.frame_count)
    if total <= 0 or not obs.objects:
        return ()
    rate = rate or params.at(obs.video.fps)
    boxes = frame_boxes(obs, 0, total, rate.fill_gap)
    objects = boxes.objects
    shot = shot_index(total, shots)
    most = params.moving_cap_fraction * video_diagonal(obs)
    moving = moving_objects(objects, rate.dwell_frames, params.moving_fraction, shot, most)
    if not moving.any():
        return ()
    cats = boxes.categories
    # an ingredient overlapping a moving container rides in it (found on tasty-a: the squash in the tipped
    # bowl); one in a container that a moving tool overlaps is being stirred there: neither is in a hand of
    # its own
    containers = [k for k, c in enumerate(cats) if c is Category.CONTAINER]
    tools = [k for k, c in enumerate(cats) if c is Category.TOOL]
    _carried_containers(moving, objects, cats, containers, rate.dwell_frames, params.coherent_fraction, shot)
    for k, category in enumerate(cats):
        if category is not Category.INGREDIENT:
            continue
        rows = np.flatnonzero(moving[:, k])
        for c in (*containers, *tools):
            if not len(rows):
                break
            with np.errstate(invalid="ignore"):
                overlap = box_intersection(objects[rows, k], objects[rows, c]) > 0
            moving[rows[overlap & moving[rows, c]], k] = False
            rows = np.flatnonzero(moving[:, k])
    dominant = _dominant_hand(obs)
    # seen: a detected hand comes within SEEN_WITHIN of the object's own size (the decoder judges what that
    # hand holds; an onion sliding off a plate that a seen hand tips is moved by the plate, not by a hand of
    # its own)
    unseen = np.zeros_like(moving)
    away = np.zeros((*moving.shape, len(HANDS)), dtype=bool)  # a detected hand away from the unseen mover
    rows, columns = np.nonzero(moving)
    if len(rows):
        box = objects[rows, columns]
        with np.errstate(invalid="ignore"):
            size = box_diagonal(box)
            gap = box_gap(boxes.hand_boxes[rows], box[:, None, :])
            seen = (gap <= SEEN_WITHIN * size[:, None]).any(axis=1)
        unseen[rows[~seen], columns[~seen]] = True
        away[rows[~seen], columns[~seen]] = np.isfinite(gap[~seen])
    holds = []
    bridge, reach = rate.unseen_bridge, rate.unseen_hand
    for k, name in enumerate(boxes.names):
        spans = _spans(unseen[:, k], bridge, rate.min_frames)
        for start, end in spans:
            elsewhere = away[start:end, k].sum(axis=0) >= rate.elsewhere
            hand = _nearest_hand(objects[:, k], boxes.hand_boxes, start, end, shot, reach, elsewhere)
            holds.append(UnseenHold(hand or dominant.pick(elsewhere), name, start, end))
    return tuple(sorted(holds, key=lambda h: (h.start, h.obj)))


def _spans(mask: np.ndarray, bridge: int, least: int) -> list[tuple[int, int]]:
    """Runs of True joined across gaps shorter than ``bridge``, kept when at least ``least`` long."""
    spans: list[list[int]] = []
    for start, end, value in runs(mask.astype(np.int8)):
        if not value:
            continue
        if spans and start - spans[-1][1] < bridge:
            spans[-1][1] = end
        else:
            spans.append([start, end])
    return [(a, b) for a, b in spans if b - a >= least]


def _nearest_hand(track: np.ndarray, hands: np.ndarray, start: int, end: int, shot: np.ndarray,
                  reach: int, elsewhere: np.ndarray) -> str | None:
    """The hand seen nearest the object just before or after its unseen hold ``[start, end)``: within
    ``reach`` frames of either end, in the same shot as that end, the detected hand whose box comes closest
    to the object's, no farther than the object's own size, and not seen somewhere else during the hold
    (``elsewhere``, per hand of :data:`HANDS`). Hands do not jump: the hand that let go of the object, or that
    takes it back, moved it (the detector lost it, not the cook). None when no hand is seen there."""
    length = len(track)
    best: tuple[float, int] | None = None
    for lo, hi, edge in ((max(start - reach, 0), start, start), (end, min(end + reach, length), end - 1)):
        if hi <= lo:
            continue
        frames = np.arange(lo, hi)
        frames = frames[shot[frames] == shot[min(edge, length - 1)]]
        if not len(frames):
            continue
        box = track[frames]
        with np.errstate(invalid="ignore"):
            size = box_diagonal(box)
            gap = box_gap(hands[frames], box[:, None, :]) / size[:, None]
        gap = np.where(np.isfinite(gap) & (gap <= 1.0) & ~elsewhere, gap, np.inf)
        if not np.isfinite(gap).any():
            continue
        column = int(np.argmin(np.min(gap, axis=0)))
        near = float(np.min(gap[:, column]))
        if best is None or near < best[0]:
            best = (near, column)
    return HANDS[best[1]] if best is not None else None


def _travel(frames: np.ndarray, xy: np.ndarray) -> float:
    """Pixels a hand's centre travels between consecutive frames on which it is detected (no gap bridged:
    an interpolated hand moves where it was not seen)."""
    if len(frames) < 2:
        return 0.0
    step = np.diff(np.asarray(xy, dtype=np.float64), axis=0)
    consecutive = np.diff(np.asarray(frames)) == 1
    return float(np.hypot(step[consecutive, 0], step[consecutive, 1]).sum())


@dataclass(frozen=True)
class _Working:
    """The hands in the order the fallback of R7 tries them: farthest travelled while seen first."""

    order: tuple[str, ...]

    def pick(self, elsewhere: np.ndarray) -> str:
        """The first hand not seen somewhere else during the hold (``elsewhere`` per hand of :data:`HANDS`),
        else the first."""
        for hand in self.order:
            if hand not in HANDS or not elsewhere[HANDS.index(hand)]:
                return hand
        return self.order[0]


def _dominant_hand(obs: Observations) -> _Working:
    """The hand that travels farthest while the detector sees it over the whole video (the cook's working
    hand: it fetches, carries and stirs; the other steadies a bowl or a board, and, keeping still, is often
    the one the detector sees more), then the others by their travel, else the right hand of the video's first
    person."""
    travel = {t.hand: _travel(t.frames, t.xy) for t in obs.hands if t.hand in HANDS and len(t.frames)}
    if travel:
        return _Working(tuple(sorted(travel, key=lambda hand: (travel[hand], hand.startswith("RH")), reverse=True)))
    persons = sorted({person_of(t.hand) for t in obs.hands}) or ["P1"]
    return _Working((f"RH_{persons[0]}",))
