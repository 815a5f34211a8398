"""Object association per segment (paper, "Object Association"): ingredient-container, hand-object,
object-object.

Everything is computed per frame (:mod:`wecook_core.perception.association.frame_links`: dense arrays aligned on frame
index, one
row per frame, NaN where a box is absent; gaps of at most ``params.fill_gap_s`` interpolated), gathered in
blocks of :data:`~wecook_core.frame_links.BLOCK_FRAMES` so memory does not grow with the video, then summarised
per segment (here): a link is kept only when it holds for at least ``params.min_link_s`` without a break
inside the segment (a segment shorter than that is judged on the ``min_link_s`` around it).

- Ingredient-container: an ingredient lies in a container when most of its box is inside the container's box
  (``params.contain_fraction``); among several, the highest Jaccard index wins.
- Hand-object: among the objects whose boxes overlap the hand's box, the one that moves with the hand,
  smoothed over time by Viterbi (:mod:`wecook_core.perception.association.holding`: motion coherence of hand and box as
  the emission, a switching cost as hysteresis). The container under a held bottle, spoon or bread does not
  move with the hand: it is the held object's destination (object-object below), never the held object; a
  bowl carried with an ingredient in it is held rather than the ingredient.
- Object-object: from each held object to the containers and ingredients whose boxes come within
  ``params.near_fraction`` of the image diagonal of it while it dwells there (``params.dwell_*``: passing by
  is not acting), for ``min_link_s`` and ``params.min_share`` of the segment; closest first; never a tool.

:func:`associate_segments` also returns the :class:`Timeline`: the per-frame links of the whole video, which
transfer and collaboration detection track over time (:mod:`wecook_core.perception.recognition.actions`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, Associations, Category, Corrections, Observations, Segment, Segmentation
from wecook_core.perception.association.frame_links import (
    BLOCK_FRAMES,
    FrameBoxes,
    FrameLinks,
    crop,
    crop_links,
    frame_boxes,
    frame_links,
    links_of,
)
from wecook_core.perception.geometry import (
    box_area,
    box_centres,
    box_diagonal,
    box_gap,
    box_intersection,
    video_diagonal,
)
from wecook_core.perception.label_runs import NONE, dominant, kept_runs, longest_runs, runs
from wecook_core.perception.params import DEFAULT_FPS

if TYPE_CHECKING:
    from wecook_core.perception.association.frame_links import UnseenHold
    from wecook_core.perception.params import FrameParams, Params


# ------------------------------------------------------------------------------------------- segments


@dataclass(frozen=True, eq=False)
class Timeline:
    """Per-frame links of the whole video, row = frame index, before the ``min_link_s`` filter (what transfer
    and collaboration detection track over time), with a segment's corrected hand-object links written in."""

    names: tuple[str, ...]
    categories: tuple[Category, ...]
    container: np.ndarray
    """int16 ``(frames, objects)``: see :attr:`FrameLinks.container`."""
    held: np.ndarray
    """int16 ``(frames, hands)``: see :attr:`FrameLinks.held`; hands in :data:`HANDS` order."""
    fps: float = DEFAULT_FPS
    """The video's frame rate."""

    def column(self, name: str) -> int:
        return self.names.index(name)


def associations_of(
    links: FrameLinks,
    segment: Segment,
    params: Params,
    rate: FrameParams,
    video_diagonal: float,
    corrections: Corrections | None = None,
    window: Segment | None = None,
) -> Associations:
    """The links of one segment that last ``min_link_s`` consecutive frames, from its per-frame links, with
    the user's hand-object and object-object corrections for this segment applied. ``window``: the frames
    to summarise when not the segment's own (a segment shorter than ``min_link_s`` is judged on the
    ``min_link_s`` around it). A held ingredient that comes near nothing while it stays put (a jar shaken
    hard at 5 fps never does) acts on the container it lies over in the segment: the container under a held
    object is its destination."""
    window = window or segment
    lo, hi = window.start - links.start, window.end - links.start
    names = links.boxes.names
    min_frames = min(rate.min_frames, hi - lo)  # a link that lasts a whole short segment counts
    containment: dict[str, str] = {}
    for column, category in enumerate(links.boxes.categories):
        if category is Category.INGREDIENT:
            best = dominant(links.container[lo:hi, column], min_frames)
            if best != NONE:
                containment[names[column]] = names[best]
    rows = np.zeros(len(links.held), dtype=bool)
    rows[lo:hi] = True
    hand_object: dict[str, str] = {}
    object_object: dict[str, tuple[str, ...]] = {}
    for column, hand in enumerate(links.boxes.hands):
        best = dominant(links.held[lo:hi, column], min_frames)
        if corrections is not None and (segment.start, hand) in corrections.hand_object:
            chosen = corrections.hand_object[(segment.start, hand)]
            best = names.index(chosen) if chosen in names else NONE
        if best == NONE:
            continue
        name = names[best]
        hand_object[hand] = name
        if corrections is not None and (segment.start, name) in corrections.object_object:
            object_object[name] = tuple(corrections.object_object[(segment.start, name)])
        elif name not in object_object:
            near = near_objects(links, best, params, rate, rows, video_diagonal)
            object_object[name] = tuple(names[k] for k in near)
            if not near and name in containment:
                object_object[name] = (containment[name],)
    return Associations(segment, hand_object, object_object, containment)


def near_objects(
    links: FrameLinks, held: int, params: Params, rate: FrameParams, rows: np.ndarray, video_diagonal: float
) -> tuple[int, ...]:
    """Containers and ingredients near object column ``held`` for ``min_link_s`` consecutive frames (and at
    least ``min_share`` of the frames) among ``rows`` (a boolean mask over the rows of ``links``), closest
    first (mean box gap, then the larger share of the other's box covered by the held one).

    Near means a box gap of at most ``params.near_fraction * video_diagonal`` pixels while the held object
    dwells there (:func:`dwelling`, within ``dwell_fraction`` of the diagonal or ``dwell_own_fraction`` of its
    own size (its box half way through), whichever is more: a big spoon's strokes in a close-up are long):
    passing by on the way somewhere is not acting. Tools and the held object itself are never linked."""
    boxes = links.boxes
    # only containers and ingredients other than the held object can be linked: the gaps of the rest are
    # never read
    candidates = np.array([column for column, category in enumerate(boxes.categories)
                           if category is not Category.TOOL and column != held], dtype=int)
    if not len(candidates):
        return ()
    gap = box_gap(boxes.objects[:, held : held + 1, :], boxes.objects[:, candidates, :])
    own = boxes.objects[:, held, :]
    seen = np.flatnonzero(rows & np.isfinite(own[:, 0]))
    middle = own[seen[len(seen) // 2]] if len(seen) else None
    size = float(box_diagonal(middle)) if middle is not None else 0.0
    stay = max(params.dwell_fraction * video_diagonal, params.dwell_own_fraction * size)
    near = (gap <= params.near_fraction * video_diagonal) & rows[:, None] & dwelling(
        own, rate.dwell_frames, stay)[:, None]
    longest = longest_runs(near)
    frames = int(rows.sum())
    needed = max(min(rate.min_frames, frames), params.min_share * frames)
    kept = np.flatnonzero((longest >= needed) & (longest > 0))  # positions in candidates
    if not len(kept):
        return ()
    keep = candidates[kept]  # columns of the objects
    with np.errstate(invalid="ignore"):
        sums = np.where(near[:, kept], gap[:, kept], 0.0).sum(axis=0)
    mean_gap = sums / np.maximum(near[:, kept].sum(axis=0), 1)
    # among boxes that touch it (gap 0), the one the held object covers most of, on average: a tool works
    # what it is in, not what it grazes at an edge (found on tasty-a, frames 238-254: a spoon stirring the
    # spinach just tipped over the squash covers more of the spinach's box)
    covered = np.zeros(len(keep))
    if len(keep) > 1 and len(np.unique(mean_gap)) < len(keep):  # only ties need it
        held_boxes = boxes.objects[:, held : held + 1, :]
        with np.errstate(invalid="ignore", divide="ignore"):
            share = box_intersection(held_boxes, boxes.objects[:, keep, :]) / box_area(boxes.objects[:, keep, :])
            covered = np.where(near[:, kept], np.nan_to_num(share), 0.0).sum(axis=0) / np.maximum(
                near[:, kept].sum(axis=0), 1)
    order = np.lexsort((keep, -covered, mean_gap))
    return tuple(int(keep[i]) for i in order)


def dwelling(boxes: np.ndarray, window: int, distance: float) -> np.ndarray:
    """Frames where a box stays put: its centre moves less than ``distance`` pixels between ``window`` frames
    before and ``window`` frames after (clipped to the rows given). Working strokes (sawing, stirring) stay
    put; carrying an object past others does not. False where the box is absent."""
    return dwelling_points(box_centres(boxes), window, distance)


def dwelling_points(centre: np.ndarray, window: int, distance: float) -> np.ndarray:
    """:func:`dwelling` of points ``(frames, 2)``."""
    length = len(centre)
    if length == 0:
        return np.zeros(0, dtype=bool)
    index = np.arange(length)
    before = centre[np.maximum(index - window, 0)]
    after = centre[np.minimum(index + window, length - 1)]
    with np.errstate(invalid="ignore"):
        return np.asarray(np.linalg.norm(after - before, axis=1) < distance)


def frame_count(obs: Observations, segments: Sequence[Segment] = ()) -> int:
    """Frames of the video: the declared count, extended to cover every segment and every track entry."""
    count = max(obs.video.frame_count, 0)
    if segments:
        count = max(count, max(s.end for s in segments))
    for frames in [t.frames for t in obs.objects] + [t.frames for t in obs.hands]:
        if len(frames):
            count = max(count, int(frames[-1]) + 1)
    return count


def _tipped_from(column: int, categories: Sequence[Category], container: np.ndarray, held: np.ndarray, lo: int,
                hi: int, reach: int) -> int:
    """What an unseen hand holds on rows ``[lo, hi)`` of a block where object ``column`` moves by itself: the
    object, or, for an ingredient lying in a container as the hold begins (within ``reach`` rows) that the same
    hand holds within ``reach`` rows before or after (``held``: its labels in the block), that container.
    An ingredient tipped out
    of a bowl moves more than the bowl tilting it out (the paper: a hand whose closest object is an ingredient
    in a container is associated with the container; "what is tipped over a container goes into it")."""
    if categories[column] is not Category.INGREDIENT:
        return column
    first = container[max(0, lo - reach) : min(hi, lo + max(reach, 1)), column]
    lying = [int(c) for c in np.unique(first[first != NONE])]
    if not lying:
        return column
    around = np.concatenate([held[max(0, lo - reach) : lo], held[hi : hi + reach]])
    for candidate in lying:
        if (around == candidate).any():
            return candidate
    return column


def associate_segments(
    obs: Observations,
    segments: Sequence[Segment],
    params: Params,
    corrections: Corrections | None = None,
    *,
    shots: Sequence[int] = (),
    unseen: Sequence[UnseenHold] = (),
    rate: FrameParams | None = None,
) -> tuple[tuple[Associations, ...], Timeline]:
    """Associations of each segment, with the user's corrections applied, and the whole video's per-frame
    links. Works one segment at a time: memory holds one segment's boxes, not the video's. ``shots``: shot
    cuts, across which no motion is compared; ``unseen``: holds by hands the detector missed
    (:mod:`wecook_core.perception.repairs.unseen`), written in where their hand holds nothing."""
    diagonal = video_diagonal(obs)
    rate = rate or params.at(obs.video.fps)
    names = tuple(track.name for track in obs.objects)
    categories = tuple(Category(obs.categories.get(name, Category.INGREDIENT)) for name in names)
    total = frame_count(obs, segments)
    container = np.full((total, len(names)), NONE, dtype=np.int16)
    held = np.full((total, len(HANDS)), NONE, dtype=np.int16)
    associations: list[Associations | None] = []
    since = None
    previous_end = None
    first = 0
    while first < len(segments):  # blocks of consecutive segments, about BLOCK_FRAMES long
        last = first
        while last + 1 < len(segments) and segments[last + 1].end - segments[first].start <= BLOCK_FRAMES:
            last += 1
        start, end = segments[first].start, segments[last].end
        links = frame_links(obs, start, end, params, since if previous_end == start else None, shots=shots,
                            rate=rate)
        since, previous_end = links.since, end
        written = None  # the block's held labels with the unseen holds written in (a new array: links stay frozen)
        # the holds of ingredients last: one may turn out to be its container's, held by the same hand around it
        for hold in sorted(unseen, key=lambda h: categories[names.index(h.obj)] is Category.INGREDIENT
                           if h.obj in names else False):
            lo, hi = max(hold.start, start), min(hold.end, end)
            if lo < hi and hold.obj in names:
                written = links.held.copy() if written is None else written
                column = HANDS.index(hold.hand)
                unseen_rows = written[lo - start : hi - start, column]
                what = _tipped_from(names.index(hold.obj), categories, links.container, written[:, column],
                                    lo - start, hi - start, rate.unseen_hand)
                unseen_rows[unseen_rows == NONE] = what
        if written is not None:
            links = replace(links, held=written)
        rows = slice(start, end)
        container[rows] = links.container
        held[rows] = links.held
        for segment in segments[first : last + 1]:
            # a segment too short to hold a link of min_frames is judged on the min_frames around it, once
            # the frames after it are known
            short = len(segment) < rate.min_frames
            associations.append(None if short else associations_of(
                crop_links(links, segment.start, segment.end), segment, params, rate, diagonal, corrections))
        first = last + 1
    for i, segment in enumerate(segments):
        if associations[i] is None:
            pad = (rate.min_frames - len(segment) + 1) // 2
            window = Segment(max(0, segment.start - pad), min(total, segment.end + pad))
            rows = slice(window.start, window.end)
            boxes = frame_boxes(obs, window.start, window.end, rate.fill_gap)
            around = FrameLinks(boxes, container[rows].astype(np.int32), held[rows].astype(np.int32), None)
            associations[i] = associations_of(around, segment, params, rate, diagonal, corrections, window)
    done = tuple(a for a in associations if a is not None)
    if corrections is not None:
        for segment, association in zip(segments, done, strict=True):
            for column, hand in enumerate(HANDS):
                if (segment.start, hand) in corrections.hand_object:
                    chosen = association.hand_object.get(hand)
                    held[segment.start : segment.end, column] = names.index(chosen) if chosen is not None else NONE
    return done, Timeline(names, categories, container, held, obs.video.fps or DEFAULT_FPS)


def associate(
    obs: Observations, segmentation: Segmentation, params: Params, corrections: Corrections | None = None
) -> tuple[Associations, ...]:
    """One :class:`Associations` per segment of ``segmentation``, in order."""
    return associate_segments(obs, segmentation.segments, params, corrections)[0]


__all__ = [
    "BLOCK_FRAMES",
    "NONE",
    "FrameBoxes",
    "FrameLinks",
    "Timeline",
    "associate",
    "associate_segments",
    "associations_of",
    "box_gap",
    "crop",
    "crop_links",
    "dominant",
    "dwelling",
    "dwelling_points",
    "frame_boxes",
    "frame_count",
    "frame_links",
    "kept_runs",
    "links_of",
    "longest_runs",
    "near_objects",
    "runs",
    "video_diagonal",
]
