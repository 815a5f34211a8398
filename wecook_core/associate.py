"""Object association per segment (paper, "Object Association"): ingredient-container, hand-object,
object-object.

Everything is computed per frame on dense arrays aligned on frame index (one row per frame, NaN where a box
is absent; gaps of at most ``params.fill_gap`` frames interpolated), gathered in blocks of
:data:`BLOCK_FRAMES` so memory does not grow with the video, then summarised per segment: a link is kept
only when it holds for at least ``params.min_frames`` consecutive frames inside the segment (a segment
shorter than that is judged on the ``min_frames`` around it).

- Ingredient-container: an ingredient lies in a container when most of its box is inside the container's box
  (``params.contain_fraction``); among several, the highest Jaccard index wins.
- Hand-object: the objects whose boxes overlap the hand's box; among several, the one overlapped longest
  without a break (a grasp persists while the hand carries the object over others), then the closest box
  centre; a contained ingredient is replaced by its container.
- Object-object: from each held object to the containers and ingredients whose boxes come within
  ``params.near_fraction`` of the image diagonal of it while it dwells there (``params.dwell_*``: passing by
  is not acting), for ``min_frames`` and ``params.min_share`` of the segment; closest first; never a tool.

:func:`associate_segments` also returns the :class:`Timeline`: the per-frame links of the whole video, which
transfer and collaboration detection track over time (:mod:`wecook_core.actions`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, Associations, Category, Corrections, Observations, Segment, Segmentation

if TYPE_CHECKING:
    from wecook_core.pipeline import Params

NONE = -1
"""Index meaning "no object" in the per-frame label arrays."""


# ------------------------------------------------------------------------------------------ frame data


@dataclass(frozen=True, eq=False)
class FrameBoxes:
    """Every object's and hand's box on the frames ``[start, end)``, one row per frame."""

    start: int
    end: int
    """Frames ``[start, end)``: row ``i`` is frame ``start + i``."""
    names: tuple[str, ...]
    """Object names, the column order of ``objects``."""
    categories: tuple[Category, ...]
    """Category of each object of ``names``."""
    objects: np.ndarray
    """float64 ``(frames, objects, 4)``: ``x1 y1 x2 y2`` pixels, NaN where the object is not seen."""
    hands: tuple[str, ...]
    """Hand names (always :data:`HANDS`), the column order of ``hand_boxes``."""
    hand_boxes: np.ndarray
    """float64 ``(frames, hands, 4)``: pixels, NaN where the hand is not detected."""


def frame_boxes(obs: Observations, start: int, end: int, fill: int = 0) -> FrameBoxes:
    """Dense boxes of every object and hand on ``[start, end)`` (cost: the tracks' entries in the range),
    gaps of at most ``fill`` frames interpolated."""
    length = max(0, end - start)
    names = tuple(track.name for track in obs.objects)
    categories = tuple(Category(obs.categories.get(name, Category.INGREDIENT)) for name in names)
    objects = np.full((length, len(names), 4), np.nan)
    for column, track in enumerate(obs.objects):
        _scatter(objects[:, column], track.frames, track.boxes, start, end, fill)
    hand_boxes = np.full((length, len(HANDS), 4), np.nan)
    for hand_track in obs.hands:
        if hand_track.hand in HANDS:
            _scatter(hand_boxes[:, HANDS.index(hand_track.hand)], hand_track.frames, hand_track.boxes, start, end,
                     fill)
    return FrameBoxes(start, end, names, categories, objects, HANDS, hand_boxes)


def _scatter(out: np.ndarray, frames: np.ndarray, values: np.ndarray, start: int, end: int, fill: int) -> None:
    """Write a track's entries on ``[start, end)`` into ``out`` (row = frame - start), interpolating linearly
    across gaps of at most ``fill`` frames (a detector missing a few frames)."""
    lo, hi = np.searchsorted(frames, [start, end])
    if hi > lo:
        out[frames[lo:hi] - start] = values[lo:hi]
    if fill <= 0 or len(frames) < 2:
        return
    a, b = max(lo - 1, 0), min(hi + 1, len(frames))  # the entries just outside the range bound its gaps
    near_frames, near_values = frames[a:b], values[a:b]
    if len(near_frames) < 2:
        return
    gaps = np.diff(near_frames)
    if not ((gaps > 1) & (gaps <= fill + 1)).any():
        return
    missing = np.arange(start, end)
    position = np.searchsorted(near_frames, missing)
    inside = (position > 0) & (position < len(near_frames))
    before = near_frames[np.clip(position - 1, 0, len(near_frames) - 1)]
    after = near_frames[np.clip(position, 0, len(near_frames) - 1)]
    todo = inside & (after != missing) & (after - before <= fill + 1)
    if todo.any():
        t = missing[todo]
        for k in range(values.shape[1]):
            out[todo, k] = np.interp(t, near_frames, near_values[:, k])


def _area(boxes: np.ndarray) -> np.ndarray:
    return np.clip(boxes[..., 2] - boxes[..., 0], 0, None) * np.clip(boxes[..., 3] - boxes[..., 1], 0, None)


def _intersection(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Intersection areas of broadcast box arrays ``a[..., 4]`` and ``b[..., 4]`` (NaN where either is absent)."""
    width = np.minimum(a[..., 2], b[..., 2]) - np.maximum(a[..., 0], b[..., 0])
    height = np.minimum(a[..., 3], b[..., 3]) - np.maximum(a[..., 1], b[..., 1])
    return np.clip(width, 0, None) * np.clip(height, 0, None)


def box_gap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance between two boxes' closest points (0 when they overlap); NaN where absent."""
    dx = np.clip(np.maximum(a[..., 0], b[..., 0]) - np.minimum(a[..., 2], b[..., 2]), 0, None)
    dy = np.clip(np.maximum(a[..., 1], b[..., 1]) - np.minimum(a[..., 3], b[..., 3]), 0, None)
    return np.hypot(dx, dy)


def _centre(boxes: np.ndarray) -> np.ndarray:
    return np.stack([(boxes[..., 0] + boxes[..., 2]) / 2, (boxes[..., 1] + boxes[..., 3]) / 2], axis=-1)


@dataclass(frozen=True, eq=False)
class FrameLinks:
    """Per-frame links on ``[start, end)``, before the ``min_frames`` filter."""

    boxes: FrameBoxes
    container: np.ndarray
    """int ``(frames, objects)``: column index of the container holding each ingredient, :data:`NONE` if none
    (always NONE for tools and containers)."""
    held: np.ndarray
    """int ``(frames, hands)``: column index of the object each hand holds, :data:`NONE` if none (a contained
    ingredient already replaced by its container)."""
    touched: np.ndarray
    """int ``(frames, hands)``: like ``held`` but before replacing a contained ingredient by its container."""
    since: np.ndarray
    """int64 ``(2, hands, objects)``: on the last frame, where each hand's current overlap with each object
    began and the last frame the hand carried it (:data:`NONE`: no overlap); pass it to the next range's
    :func:`frame_links`."""

    @property
    def start(self) -> int:
        return self.boxes.start

    @property
    def end(self) -> int:
        return self.boxes.end


def frame_links(
    obs: Observations, start: int, end: int, params: Params, since: np.ndarray | None = None,
    block: FrameBoxes | None = None,
) -> FrameLinks:
    """Ingredient-container and hand-object links of every frame of ``[start, end)``; ``since`` carries the
    hand-object overlaps on from the frame before ``start`` (:attr:`FrameLinks.since` of the previous range).
    ``block``: boxes already gathered for frames that include ``[start, end)``."""
    if block is not None and block.start <= start and end <= block.end:
        boxes = crop(block, start, end)
    else:
        boxes = frame_boxes(obs, start, end, params.fill_gap)
    return links_of(boxes, params, since)


def crop_links(links: FrameLinks, start: int, end: int) -> FrameLinks:
    """The rows of ``[start, end)`` (within ``links``' range), as views (``since`` is not cropped)."""
    a, b = start - links.start, end - links.start
    return FrameLinks(crop(links.boxes, start, end), links.container[a:b], links.held[a:b], links.touched[a:b],
                      links.since)


BLOCK_FRAMES = 2048
"""Frames of boxes gathered at once while associating: bounds memory whatever the video's length."""


def crop(boxes: FrameBoxes, start: int, end: int) -> FrameBoxes:
    """The rows of ``[start, end)`` (within ``boxes``' range), as views."""
    a, b = start - boxes.start, end - boxes.start
    return FrameBoxes(start, end, boxes.names, boxes.categories, boxes.objects[a:b], boxes.hands,
                      boxes.hand_boxes[a:b])


def links_of(boxes: FrameBoxes, params: Params, since: np.ndarray | None = None) -> FrameLinks:
    cats = np.array([str(c) for c in boxes.categories])
    length, n_objects = boxes.objects.shape[:2]
    objects = boxes.objects

    # ingredient-container: the containers covering most of the ingredient's box, best Jaccard index first.
    container = np.full((length, n_objects), NONE, dtype=np.int32)
    ingredients = np.flatnonzero(cats == Category.INGREDIENT)
    containers = np.flatnonzero(cats == Category.CONTAINER)
    if len(ingredients) and len(containers) and length:
        ing = objects[:, ingredients, None, :]
        con = objects[:, None, containers, :]
        inter = _intersection(ing, con)
        ing_area = _area(ing)
        with np.errstate(invalid="ignore", divide="ignore"):
            jaccard = inter / (ing_area + _area(con) - inter)
            inside = inter / ing_area
        ok = (inside >= params.contain_fraction) & (jaccard > 0)
        score = np.where(ok, jaccard, -1.0)
        best = np.argmax(score, axis=2)
        found = np.take_along_axis(score, best[..., None], axis=2)[..., 0] > 0
        container[:, ingredients] = np.where(found, containers[best], NONE)

    # hand-object: overlapping boxes. Among several: first those the hand has carried (moved along with it)
    # since it began to overlap them, then the one overlapped longest without a break (a grasp persists: a
    # hand carrying a spoon over a rolling pin still holds the spoon), then the closest centre.
    hands = boxes.hand_boxes
    held = np.full((length, len(boxes.hands)), NONE, dtype=np.int32)
    touched = held.copy()
    last = np.full((2, len(boxes.hands), n_objects), NONE, dtype=np.int64)
    if n_objects and length:
        inter = _intersection(hands[:, :, None, :], objects[:, None, :, :])
        overlap = inter > 0
        before = np.empty_like(overlap)
        before[0] = since[0] >= 0 if since is not None else False
        before[1:] = overlap[:-1]
        frames = np.arange(boxes.start, boxes.end, dtype=np.int64)[:, None, None]
        began = np.where(overlap & ~before, frames, NONE)
        if since is not None:
            began[0] = np.where(overlap[0] & before[0], since[0], began[0])
        run_start = np.maximum.accumulate(began, axis=0)
        carried = overlap & _moving_together(hands, objects, params.dwell_frames)
        last_carried = np.where(carried, frames, NONE)
        if since is not None:
            last_carried[0] = np.maximum(last_carried[0], since[1])
        last_carried = np.maximum.accumulate(last_carried, axis=0)
        carried_since = overlap & (last_carried >= run_start)
        hand_centres, object_centres = _centre(hands), _centre(objects)
        distance = np.linalg.norm(hand_centres[:, :, None, :] - object_centres[:, None, :, :], axis=-1)
        finite = distance[np.isfinite(distance)]
        scale = float(finite.max()) + 1.0 if finite.size else 1.0
        later = float(boxes.end + 1)  # ranks every carried object before any other
        key = np.where(carried_since, 0.0, later) + run_start + np.nan_to_num(distance, nan=0.0) / scale
        best = np.argmin(np.where(overlap, key, np.inf), axis=2)
        any_overlap = overlap.any(axis=2)
        last = np.stack([np.where(overlap[-1], run_start[-1], NONE), np.where(overlap[-1], last_carried[-1], NONE)])
        touched = np.where(any_overlap, best, NONE).astype(np.int32)
        rows = np.arange(length)[:, None]
        redirect = np.where(touched >= 0, container[rows, np.maximum(touched, 0)], NONE)
        held = np.where(redirect >= 0, redirect, touched).astype(np.int32)
    return FrameLinks(boxes, container, held, touched, last)


def _moving_together(hands: np.ndarray, objects: np.ndarray, window: int) -> np.ndarray:
    """``(frames, hands, objects)``: the hand moves (more than a quarter of its box's diagonal between
    ``window`` frames before and after) and the object's box moves along with it (by the same displacement,
    give or take half of it)."""
    length = hands.shape[0]
    index = np.arange(length)
    after, before = np.minimum(index + window, length - 1), np.maximum(index - window, 0)
    hand_centres, object_centres = _centre(hands), _centre(objects)
    hand_step = hand_centres[after] - hand_centres[before]
    object_step = object_centres[after] - object_centres[before]
    with np.errstate(invalid="ignore"):
        hand_size = np.hypot(hands[..., 2] - hands[..., 0], hands[..., 3] - hands[..., 1])
        hand_move = np.linalg.norm(hand_step, axis=-1)
        moving = hand_move > 0.25 * hand_size
        apart = np.linalg.norm(object_step[:, None, :, :] - hand_step[:, :, None, :], axis=-1)
        return np.asarray(moving[:, :, None] & (apart < 0.5 * hand_move[:, :, None]))


# ----------------------------------------------------------------------------------------------- runs


def longest_runs(mask: np.ndarray) -> np.ndarray:
    """Longest run of consecutive True along axis 0 of a boolean ``(frames, k...)`` array, per column."""
    if mask.shape[0] == 0:
        return np.zeros(mask.shape[1:], dtype=np.int64)
    flat = mask.reshape(mask.shape[0], -1).astype(np.int8)
    padded = np.zeros((flat.shape[0] + 2, flat.shape[1]), dtype=np.int8)
    padded[1:-1] = flat
    change = np.diff(padded, axis=0)
    out = np.zeros(flat.shape[1], dtype=np.int64)
    columns_start, rows_start = np.nonzero(change.T == 1)
    _, rows_end = np.nonzero(change.T == -1)
    if len(rows_start):
        np.maximum.at(out, columns_start, rows_end - rows_start)
    return out.reshape(mask.shape[1:])


def runs(labels: np.ndarray) -> list[tuple[int, int, int]]:
    """``(start, end, value)`` runs of equal values of a 1-D label array (rows, end exclusive)."""
    if len(labels) == 0:
        return []
    cuts = np.flatnonzero(np.diff(labels)) + 1
    starts = np.concatenate([[0], cuts])
    ends = np.concatenate([cuts, [len(labels)]])
    return [(int(s), int(e), int(labels[s])) for s, e in zip(starts, ends, strict=True)]


def kept_runs(labels: np.ndarray, min_frames: int) -> list[tuple[int, int, int]]:
    """Runs of a label array that name an object and last at least ``min_frames`` rows."""
    return [r for r in runs(labels) if r[2] != NONE and r[1] - r[0] >= min_frames]


def dominant(labels: np.ndarray, min_frames: int) -> int:
    """The label with the most rows in kept runs (ties: the earliest), :data:`NONE` if no run is kept."""
    if len(labels) and labels[0] == labels[-1] and (labels == labels[0]).all():  # the common case, fast
        return int(labels[0]) if len(labels) >= min_frames else NONE
    totals: dict[int, int] = {}
    for start, end, value in kept_runs(labels, min_frames):
        totals[value] = totals.get(value, 0) + end - start
    if not totals:
        return NONE
    return max(totals, key=lambda value: totals[value])


# ------------------------------------------------------------------------------------------- segments


@dataclass(frozen=True, eq=False)
class Timeline:
    """Per-frame links of the whole video, row = frame index, before the ``min_frames`` filter (what transfer
    and collaboration detection track over time), with a segment's corrected hand-object links written in."""

    names: tuple[str, ...]
    categories: tuple[Category, ...]
    container: np.ndarray
    """int16 ``(frames, objects)``: see :attr:`FrameLinks.container`."""
    held: np.ndarray
    """int16 ``(frames, hands)``: see :attr:`FrameLinks.held`; hands in :data:`HANDS` order."""
    touched: np.ndarray
    """int16 ``(frames, hands)``: see :attr:`FrameLinks.touched`."""

    def column(self, name: str) -> int:
        return self.names.index(name)


def associations_of(
    links: FrameLinks,
    segment: Segment,
    params: Params,
    video_diagonal: float,
    corrections: Corrections | None = None,
    window: Segment | None = None,
) -> Associations:
    """The links of one segment that last ``min_frames`` consecutive frames, from its per-frame links, with
    the user's hand-object and object-object corrections for this segment applied. ``window``: the frames
    to summarise when not the segment's own (a segment shorter than ``min_frames`` is judged on the
    ``min_frames`` around it)."""
    window = window or segment
    lo, hi = window.start - links.start, window.end - links.start
    names = links.boxes.names
    min_frames = min(params.min_frames, hi - lo)  # a link that lasts a whole short segment counts
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
            near = near_objects(links, best, params, rows, video_diagonal)
            object_object[name] = tuple(names[k] for k in near)
    return Associations(segment, hand_object, object_object, containment)


def near_objects(
    links: FrameLinks, held: int, params: Params, rows: np.ndarray, video_diagonal: float
) -> tuple[int, ...]:
    """Containers and ingredients near object column ``held`` for ``min_frames`` consecutive frames (and at
    least ``min_share`` of the frames) among ``rows`` (a boolean mask over the rows of ``links``), closest
    first (mean box gap).

    Near means a box gap of at most ``params.near_fraction * video_diagonal`` pixels while the held object
    dwells there (:func:`dwelling`): passing by on the way somewhere is not acting. Tools and the held object
    itself are never linked."""
    boxes = links.boxes
    gap = box_gap(boxes.objects[:, held : held + 1, :], boxes.objects)
    near = (gap <= params.near_fraction * video_diagonal) & rows[:, None] & dwelling(
        boxes.objects[:, held, :], params.dwell_frames, params.dwell_fraction * video_diagonal)[:, None]
    for column, category in enumerate(boxes.categories):
        if category is Category.TOOL or column == held:
            near[:, column] = False
    longest = longest_runs(near)
    frames = int(rows.sum())
    needed = max(min(params.min_frames, frames), params.min_share * frames)
    keep = np.flatnonzero((longest >= needed) & (longest > 0))
    if not len(keep):
        return ()
    with np.errstate(invalid="ignore"):
        sums = np.where(near[:, keep], gap[:, keep], 0.0).sum(axis=0)
    mean_gap = sums / np.maximum(near[:, keep].sum(axis=0), 1)
    order = np.lexsort((keep, mean_gap))
    return tuple(int(keep[i]) for i in order)


def dwelling(boxes: np.ndarray, window: int, distance: float) -> np.ndarray:
    """Frames where a box stays put: its centre moves less than ``distance`` pixels between ``window`` frames
    before and ``window`` frames after (clipped to the rows given). Working strokes (sawing, stirring) stay
    put; carrying an object past others does not. False where the box is absent."""
    return dwelling_points(_centre(boxes), window, distance)


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


def video_diagonal(obs: Observations) -> float:
    """Image diagonal in pixels (from the video's size, else from the boxes' extent)."""
    if obs.video.width > 0 and obs.video.height > 0:
        return float(np.hypot(obs.video.width, obs.video.height))
    width, height = 1.0, 1.0
    for boxes in [t.boxes for t in obs.objects] + [t.boxes for t in obs.hands]:
        if len(boxes):
            width = max(width, float(np.max(boxes[:, 2])))
            height = max(height, float(np.max(boxes[:, 3])))
    return float(np.hypot(width, height))


def frame_count(obs: Observations, segments: Sequence[Segment] = ()) -> int:
    """Frames of the video: the declared count, extended to cover every segment and every track entry."""
    count = max(obs.video.frame_count, 0)
    if segments:
        count = max(count, max(s.end for s in segments))
    for frames in [t.frames for t in obs.objects] + [t.frames for t in obs.hands]:
        if len(frames):
            count = max(count, int(frames[-1]) + 1)
    return count


def associate_segments(
    obs: Observations,
    segments: Sequence[Segment],
    params: Params,
    corrections: Corrections | None = None,
) -> tuple[tuple[Associations, ...], Timeline]:
    """Associations of each segment, with the user's corrections applied, and the whole video's per-frame
    links. Works one segment at a time: memory holds one segment's boxes, not the video's."""
    diagonal = video_diagonal(obs)
    names = tuple(track.name for track in obs.objects)
    categories = tuple(Category(obs.categories.get(name, Category.INGREDIENT)) for name in names)
    total = frame_count(obs, segments)
    container = np.full((total, len(names)), NONE, dtype=np.int16)
    held = np.full((total, len(HANDS)), NONE, dtype=np.int16)
    touched = held.copy()
    associations: list[Associations | None] = []
    since = None
    previous_end = None
    first = 0
    while first < len(segments):  # blocks of consecutive segments, about BLOCK_FRAMES long
        last = first
        while last + 1 < len(segments) and segments[last + 1].end - segments[first].start <= BLOCK_FRAMES:
            last += 1
        start, end = segments[first].start, segments[last].end
        links = frame_links(obs, start, end, params, since if previous_end == start else None)
        since, previous_end = links.since, end
        rows = slice(start, end)
        container[rows] = links.container
        held[rows] = links.held
        touched[rows] = links.touched
        for segment in segments[first : last + 1]:
            # a segment too short to hold a link of min_frames is judged on the min_frames around it, once
            # the frames after it are known
            short = len(segment) < params.min_frames
            associations.append(None if short else associations_of(
                crop_links(links, segment.start, segment.end), segment, params, diagonal, corrections))
        first = last + 1
    for i, segment in enumerate(segments):
        if associations[i] is None:
            pad = (params.min_frames - len(segment) + 1) // 2
            window = Segment(max(0, segment.start - pad), min(total, segment.end + pad))
            rows = slice(window.start, window.end)
            boxes = frame_boxes(obs, window.start, window.end, params.fill_gap)
            around = FrameLinks(boxes, container[rows].astype(np.int32), held[rows].astype(np.int32),
                                touched[rows].astype(np.int32),
                                np.full((2, len(HANDS), len(names)), NONE, dtype=np.int64))
            associations[i] = associations_of(around, segment, params, diagonal, corrections, window)
    done = tuple(a for a in associations if a is not None)
    if corrections is not None:
        for segment, association in zip(segments, done, strict=True):
            for column, hand in enumerate(HANDS):
                if (segment.start, hand) in corrections.hand_object:
                    chosen = association.hand_object.get(hand)
                    held[segment.start : segment.end, column] = names.index(chosen) if chosen is not None else NONE
    return done, Timeline(names, categories, container, held, touched)


def associate(
    obs: Observations, segmentation: Segmentation, params: Params, corrections: Corrections | None = None
) -> tuple[Associations, ...]:
    """One :class:`Associations` per segment of ``segmentation``, in order."""
    return associate_segments(obs, segmentation.segments, params, corrections)[0]
