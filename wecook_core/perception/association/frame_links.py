"""Per-frame boxes and links of a stretch of video, on dense arrays aligned on frame index (one row per frame,
NaN where a box is absent; gaps of at most ``params.fill_gap_s`` interpolated): which container holds
each ingredient, which object each hand touches and holds. :mod:`wecook_core.perception.association.associate`
summarises them per
segment."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, Category, Observations
from wecook_core.perception.association.holding import held_objects
from wecook_core.perception.geometry import box_area, box_centres, box_diagonal, box_gap, box_intersection
from wecook_core.perception.label_runs import NONE
from wecook_core.perception.params import DEFAULT_FPS

if TYPE_CHECKING:
    from wecook_core.perception.params import FrameParams, Params


@dataclass(frozen=True)
class UnseenHold:
    """An object moved by a hand that is not seen (found by :mod:`wecook_core.perception.repairs.unseen`), over frames
    ``[start, end)``."""

    hand: str
    obj: str
    start: int
    end: int


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
    fps: float = DEFAULT_FPS
    """The video's frame rate (durations in :class:`Params` are seconds)."""


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
    return FrameBoxes(start, end, names, categories, objects, HANDS, hand_boxes, obs.video.fps or DEFAULT_FPS)


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



@dataclass(frozen=True, eq=False)
class FrameLinks:
    """Per-frame links on ``[start, end)``, before the ``min_frames`` filter."""

    boxes: FrameBoxes
    container: np.ndarray
    """int ``(frames, objects)``: column index of the container holding each ingredient, :data:`NONE` if none
    (always NONE for tools and containers)."""
    held: np.ndarray
    """int ``(frames, hands)``: column index of the object each hand holds, :data:`NONE` if none: what moves with
    the hand among the boxes it overlaps (:mod:`wecook_core.perception.association.holding`)."""
    since: np.ndarray | None
    """float64 ``(hands, 1 + objects)``: the held-object smoother's forward costs on the last frame
    (:func:`wecook_core.perception.association.holding.held_objects`); pass it to the next range's
    :func:`frame_links`."""

    @property
    def start(self) -> int:
        return self.boxes.start

    @property
    def end(self) -> int:
        return self.boxes.end


def frame_links(
    obs: Observations, start: int, end: int, params: Params, since: np.ndarray | None = None,
    block: FrameBoxes | None = None, shots: Sequence[int] = (), rate: FrameParams | None = None,
) -> FrameLinks:
    """Ingredient-container and hand-object links of every frame of ``[start, end)``; ``since`` carries the
    held-object smoother's state on from the frame before ``start`` (:attr:`FrameLinks.since` of the previous range).
    ``block``: boxes already gathered for frames that include ``[start, end)``."""
    rate = rate or params.at(obs.video.fps)
    if block is not None and block.start <= start and end <= block.end:
        boxes = crop(block, start, end)
    else:
        boxes = frame_boxes(obs, start, end, rate.fill_gap)
    return links_of(boxes, params, rate, since, shots)


def crop_links(links: FrameLinks, start: int, end: int) -> FrameLinks:
    """The rows of ``[start, end)`` (within ``links``' range), as views (``since`` is not cropped)."""
    a, b = start - links.start, end - links.start
    return FrameLinks(crop(links.boxes, start, end), links.container[a:b], links.held[a:b],
                      links.since)


BLOCK_FRAMES = 2048
"""Frames of boxes gathered at once while associating: bounds memory whatever the video's length."""


def crop(boxes: FrameBoxes, start: int, end: int) -> FrameBoxes:
    """The rows of ``[start, end)`` (within ``boxes``' range), as views."""
    a, b = start - boxes.start, end - boxes.start
    return FrameBoxes(start, end, boxes.names, boxes.categories, boxes.objects[a:b], boxes.hands,
                      boxes.hand_boxes[a:b], boxes.fps)


def links_of(boxes: FrameBoxes, params: Params, rate: FrameParams, since: np.ndarray | None = None,
             shots: Sequence[int] = ()) -> FrameLinks:
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
        inter = box_intersection(ing, con)
        ing_area = box_area(ing)
        with np.errstate(invalid="ignore", divide="ignore"):
            jaccard = inter / (ing_area + box_area(con) - inter)
            inside = inter / ing_area
        ok = (inside >= params.contain_fraction) & (jaccard > 0)
        score = np.where(ok, jaccard, -1.0)
        best = np.argmax(score, axis=2)
        found = np.take_along_axis(score, best[..., None], axis=2)[..., 0] > 0
        container[:, ingredients] = np.where(found, containers[best], NONE)
        _drop_passing(container, objects, rate.dwell_frames, params.pass_fraction)

    # hand-object: what moves with the hand among the boxes it overlaps, smoothed over time
    # (wecook_core.perception.association.holding)
    hands = boxes.hand_boxes
    held = np.full((length, len(boxes.hands)), NONE, dtype=np.int32)
    last = since
    if n_objects and length:
        shot = np.searchsorted(np.asarray(sorted(shots), dtype=np.int64), np.arange(boxes.start, boxes.end),
                               side="right")
        seen = np.isfinite(hands[:, :, None, 0]) & np.isfinite(objects[:, None, :, 0])
        overlap = bridged(box_intersection(hands[:, :, None, :], objects[:, None, :, :]) > 0, seen, rate.fill_gap,
                          shot)
        reach_only = _tools_within_reach(hands, objects, cats, overlap, params.tool_reach_fraction)
        held, last = held_objects(
            hands, objects, overlap, container, window=rate.dwell_frames, moving_fraction=params.moving_fraction,
            coherent_fraction=params.coherent_fraction, switch=rate.hold_switch_frames, start=since,
            step=rate.decode_step, shot=shot, reach_only=reach_only)
    return FrameLinks(boxes, container, held, last)


def bridged(overlap: np.ndarray, seen: np.ndarray, gap: int, shot: np.ndarray) -> np.ndarray:
    """``overlap`` (bool ``(frames, ...)``) with every run of at most ``gap`` frames where it is False but both
    boxes are ``seen``, between two frames where it is True in the same shot, made True (R1a): boxes that
    part for a frame or two and touch again are the detector's and the annotator's noise (a box a few pixels
    short, a hand box that jitters), as a box missing for that long is (R1); a grasp does not end and start
    again there."""
    length = len(overlap)
    if gap <= 0 or length < 3:
        return overlap
    index = np.arange(length).reshape(-1, *([1] * (overlap.ndim - 1)))
    last = np.maximum.accumulate(np.where(overlap, index, -1), axis=0)  # the latest True at or before each frame
    following = np.where(overlap, index, length)[::-1]
    following = np.minimum.accumulate(following, axis=0)[::-1]  # the earliest True at or after each frame
    inside = ~overlap & (last >= 0) & (following < length) & (following - last - 1 <= gap)
    if not inside.any():
        return overlap
    same = shot[np.clip(last, 0, length - 1)] == shot[np.clip(following, 0, length - 1)]
    return overlap | (inside & same & seen)


def _tools_within_reach(hands: np.ndarray, objects: np.ndarray, cats: np.ndarray, overlap: np.ndarray,
                        fraction: float) -> np.ndarray | None:
    """bool ``(frames, hands, objects)``: tools whose box does not overlap the hand's but comes within
    ``fraction`` of the hand's diagonal of it, added to ``overlap`` in place. A tool is held by its handle, and
    its box may stop short of the hand (a long handle, a box drawn on the blade or the spatula's head): what
    moves with the hand is held, and the decoder allows such a tool only where it does. None when there is none."""
    tools = np.flatnonzero(cats == Category.TOOL)
    if not len(tools) or fraction <= 0:
        return None
    with np.errstate(invalid="ignore"):
        near = box_gap(hands[:, :, None, :], objects[:, None, tools, :]) <= fraction * box_diagonal(hands)[:, :, None]
    reach_only = np.zeros_like(overlap)
    reach_only[:, :, tools] = near & ~overlap[:, :, tools]
    if not reach_only.any():
        return None
    overlap |= reach_only
    return reach_only


def _drop_passing(container: np.ndarray, objects: np.ndarray, window: int, fraction: float) -> None:
    """Unlink (in place) an ingredient from a container it only passes over: one it moves across by more
    than ``fraction`` of the container's diagonal between ``window`` frames before and after (a tomato
    carried from the pan to the plate over the pot is never in the pot). An ingredient riding in a bowl
    moves with the bowl, one stirred in a pan stays inside it: both stay linked."""
    rows, columns = np.nonzero(container >= 0)
    if not len(rows):
        return
    length = len(container)
    holders = container[rows, columns]
    before, after = np.maximum(rows - window, 0), np.minimum(rows + window, length - 1)
    centre = box_centres(objects)
    relative = (centre[after, columns] - centre[after, holders]) - (centre[before, columns] - centre[before, holders])
    box = objects[rows, holders]
    with np.errstate(invalid="ignore"):
        size = box_diagonal(box)
        passing = np.linalg.norm(relative, axis=1) > fraction * size
    container[rows[passing], columns[passing]] = NONE
