"""Where a held object lies at the ends of its hold: picked up from there, put down there.

A hand grasps an object where it lies, pauses, lifts it; at the end it sets it down, pauses, lets go. At
either end the object sits at its resting place, and whatever lies beside that place (the cup next to
where the bread lay, the plate beside the knife's home) comes within reach of it without being acted on:
bread lying next to a cup is not dipped into it, a knife laid down beside a plate does not cut it. So a
held object's link to an object it only touches from beside (their boxes do not overlap on most frames)
is dropped on a segment where the held object lies at either end of its hold: its box centre, on a
typical frame of the segment, within :data:`REST_FRACTION` of its own diagonal of where it was when the
hold began or where it is when the hold ends. Links to what it lies in or over (a spoon left in the pan,
taken up there to stir) are kept, and so is everything once it has been lifted away.

The hold is the run of the timeline's per-frame held labels (:attr:`~.associate.Timeline.held`) that the
segment lies in, joined across gaps shorter than ``Params.min_link_s`` and across gaps on which the hand is
not detected at all: a hand the detector loses has not let go (a salt glass shaken over a pot while the hand
is lost for a second is not put down where the hand was lost).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, Associations, Observations, Segment
from wecook_core.perception.geometry import box_diagonal, box_intersection
from wecook_core.perception.recognition.motion import median_of
from wecook_core.perception.recognition.transfers import hold_spans

if TYPE_CHECKING:
    from wecook_core.perception.association.associate import Timeline

REST_FRACTION = 0.25
"""A held object whose centre is within this fraction of its own diagonal of where its hold began or
ends lies at its resting place (a box's jitter is a few pixels; lifting moves it by its size)."""
BESIDE_SHARE = 0.5
"""Two boxes that overlap on fewer than this share of the frames both are seen lie beside each other."""

SpanCache = dict[tuple[int, int], list[tuple[int, int]]]


def hold_of(timeline: Timeline, hand: str, name: str, segment: Segment, min_frames: int,
            cache: SpanCache, seen: np.ndarray | None = None) -> tuple[int, int] | None:
    """Frames ``[start, end)`` of ``hand``'s hold of ``name`` that overlaps ``segment`` (gaps shorter than
    ``min_frames`` joined, and gaps where the hand is not detected at all: ``seen``, the frames it is, when
    given), None when it holds ``name`` there on no frame. ``cache``: spans already found for this timeline,
    by (hand column, object column)."""
    if name not in timeline.names or hand not in HANDS:
        return None
    key = (HANDS.index(hand), timeline.column(name))
    if key not in cache:
        spans = hold_spans(timeline.held[:, key[0]], key[1], min_frames)
        cache[key] = spans if seen is None else _unbroken(spans, seen)
    for start, end in cache[key]:
        if start < segment.end and segment.start < end:
            return start, end
    return None


def _unbroken(spans: list[tuple[int, int]], seen: np.ndarray) -> list[tuple[int, int]]:
    """``spans`` joined across the gaps on whose frames the hand is never detected (``seen``, sorted frame
    indices): a release is seen, a detector losing the hand is not one (the hold goes on where it was)."""
    joined: list[tuple[int, int]] = []
    for start, end in spans:
        if joined:
            lo, hi = np.searchsorted(seen, [joined[-1][1], start])
            if hi == lo:  # not one detection of the hand between the two holds
                joined[-1] = (joined[-1][0], end)
                continue
        joined.append((start, end))
    return joined


def _centres(boxes: np.ndarray) -> np.ndarray:
    return np.stack([(boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2], axis=1)


def at_rest(obs: Observations, name: str, hold: tuple[int, int], segment: Segment) -> bool:
    """``name`` lies, on a typical frame of ``segment``, where it was when ``hold`` began or where it is when
    it ends (within :data:`REST_FRACTION` of its own diagonal)."""
    try:
        track = obs.object(name)
    except KeyError:
        return False
    lo, hi, a, b = np.searchsorted(track.frames, [hold[0], hold[1], segment.start, segment.end])
    boxes = track.boxes
    # only the rows of the hold and of the segment are read (a track spans the whole video)
    during = np.flatnonzero(np.isfinite(boxes[a:b]).all(axis=1)) + a
    if not len(during):
        return False
    inside = np.flatnonzero(np.isfinite(boxes[lo:hi]).all(axis=1)) + lo
    if not len(inside):
        return False
    seen = boxes[during]
    centre = np.array([median_of((seen[:, 0] + seen[:, 2]) / 2), median_of((seen[:, 1] + seen[:, 3]) / 2)])
    ends = _centres(boxes[[inside[0], inside[-1]]])
    size = median_of(box_diagonal(seen))
    return bool(np.min(np.linalg.norm(ends - centre, axis=1)) <= REST_FRACTION * size)


def beside(obs: Observations, name: str, other: str, segment: Segment) -> bool:
    """The boxes of ``name`` and ``other`` overlap on fewer than :data:`BESIDE_SHARE` of the frames of
    ``segment`` where both are seen."""
    try:
        a, b = obs.object(name), obs.object(other)
    except KeyError:
        return False
    # frames are strictly increasing: the frames both are seen on in the segment, by binary search
    lo_a, hi_a = np.searchsorted(a.frames, [segment.start, segment.end])
    lo_b, hi_b = np.searchsorted(b.frames, [segment.start, segment.end])
    own, others = a.frames[lo_a:hi_a], b.frames[lo_b:hi_b]
    at = np.minimum(np.searchsorted(others, own), max(len(others) - 1, 0))
    both = np.flatnonzero(others[at] == own) if len(others) else np.zeros(0, dtype=np.int64)
    if not len(both):
        return False
    boxes_a = a.boxes[lo_a + both]
    boxes_b = b.boxes[lo_b + at[both]]
    with np.errstate(invalid="ignore"):
        overlap = box_intersection(boxes_a, boxes_b) > 0
    return bool(overlap.mean() < BESIDE_SHARE)


def acting_links(assoc: Associations, obs: Observations, timeline: Timeline | None, min_frames: int,
                 cache: SpanCache) -> Associations:
    """``assoc`` without the links of a held object, lying at its resting place, to what lies beside it
    (see the module)."""
    if timeline is None or not assoc.hand_object:
        return assoc
    from dataclasses import replace

    segment = assoc.segment
    links = dict(assoc.object_object)
    for hand, held in assoc.hand_object.items():
        near: Sequence[str] = links.get(held, ())
        if not near:
            continue
        track = obs.hand(hand)
        seen = track.frames if track is not None else np.zeros(0, dtype=np.int64)
        hold = hold_of(timeline, hand, held, segment, min_frames, cache, seen)
        if hold is None or not at_rest(obs, held, hold, segment):
            continue
        links[held] = tuple(o for o in near if not beside(obs, held, o, segment))
    if links == dict(assoc.object_object):
        return assoc
    return replace(assoc, object_object=links)
