"""Objects hidden by the hand that carries them: a jar in a fist is still in the fist.

On real footage an annotator (or a detector) stops boxing a small object once the hand that holds it covers
it: the object is boxed while the hand bringing it in is not yet detected, and no longer once the hand shows
up around it (found on tasty-a: the italian seasoning and black pepper jars, frames 125-137 and 150-163).
Left as it is, the hand then overlaps only the static container under it, and the held-object decoder
(:mod:`wecook_core.perception.association.holding`) gives it the container. But an object does not vanish
inside a hand that was carrying it: it is occluded, and it goes where the hand goes. So, per object, at each
frame where its box stops being seen (for longer than ``Params.fill_gap_s``):

- it was **carried** there: its centre travelled more than ``Params.moving_fraction`` of its box's diagonal
  (or ``Params.moving_cap_fraction`` of the image diagonal, whichever is less) over a ``Params.dwell_s``
  ending in the ``dwell_s`` before (as in :mod:`wecook_core.perception.repairs.unseen`: objects do not move by
  themselves), within one shot;
- a detected hand **covers** it there, or shows up around it within ``fill_gap_s``: at least
  ``Params.cover_fraction`` of its box lies in the hand's box (the hand is in front of it), and it is no
  bigger than that hand (a bowl is not hidden by a hand);

then its box is carried on with that hand's displacement, frame by frame, for as long as that hand is seen
(gaps of at most ``fill_gap_s`` bridged), in the same shot, until the object's own box is seen again or the
hand takes another object (another object no bigger than the hand moves while the hand overlaps it: the jar
was put down for the next one). An ingredient hidden at the same frame as a container it lies in
(``Params.contain_fraction`` of its box) rides in that container, not in the hand.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import Category
from wecook_core.perception.association.frame_links import frame_boxes
from wecook_core.perception.geometry import box_area, box_centres, box_diagonal, box_intersection, video_diagonal
from wecook_core.perception.repairs.unseen import moving_objects, shot_index

if TYPE_CHECKING:
    from collections.abc import Sequence

    from wecook_core.model import Observations
    from wecook_core.perception.params import FrameParams, Params

MIN_AREA = 1e-9
"""Square pixels: the least area a box is divided by (a box of zero area covers nothing; not a tunable)."""
BOX_DECIMALS = 1
"""Carried-on boxes are rounded to this many decimals of a pixel: finer than any detector's or annotator's box."""


def hidden_by_hands(obs: Observations, params: Params, shots: Sequence[int] = (), *,
                    rate: FrameParams | None = None) -> Observations:
    """``obs`` with each object's track carried on where the hand carrying it hides it (module docstring);
    ``obs`` itself when no object is hidden so."""
    total = int(obs.video.frame_count)
    if total <= 1 or not obs.objects or not obs.hands:
        return obs
    rate = rate or params.at(obs.video.fps)
    boxes = frame_boxes(obs, 0, total, rate.fill_gap)
    objects, hands = boxes.objects, boxes.hand_boxes
    shot = shot_index(total, shots)
    most = params.moving_cap_fraction * video_diagonal(obs)
    moving = moving_objects(objects, rate.dwell_frames, params.moving_fraction, shot, most)
    hand_centres = box_centres(hands)
    with np.errstate(invalid="ignore"):
        hand_size = box_diagonal(hands)
    takes_other = _takes_other(objects, hands, moving, hand_size)
    carried: dict[int, list[tuple[int, list[int], list[np.ndarray]]]] = {}
    for k in range(len(obs.objects)):
        seen = np.isfinite(objects[:, k, 0])
        for last in (int(f) for f in np.flatnonzero(seen[:-1] & ~seen[1:])):
            if not moving[max(0, last - rate.dwell_frames) : last + 1, k].any():
                continue
            box = objects[last, k]
            after = [f for f in range(last, min(total, last + 1 + rate.fill_gap)) if shot[f] == shot[last]]
            found = _covering_hand(box, hands, hand_size, after, params.cover_fraction)
            if found is None:
                continue
            since, hand = found
            anchor = hand_centres[since, hand]
            frames, values = [], []
            frame = last + 1
            while frame < total and not seen[frame] and shot[frame] == shot[last] \
                    and (frame < since or np.isfinite(hands[frame, hand, 0])) and not takes_other[frame, hand, k]:
                shift = hand_centres[frame, hand] - anchor if frame >= since else np.zeros(2)
                frames.append(frame)
                values.append(box + np.array([shift[0], shift[1], shift[0], shift[1]]))
                frame += 1
            if frames:
                carried.setdefault(k, []).append((last, frames, values))
    # an ingredient hidden together with the container it lies in rides in it: it is not in the hand of its
    # own, and where it shows up again says where it went (found on tasty-a: the garlic in the small bowl the
    # hand brings over the pan, frames 63-78)
    containers = {k: {last for last, _, _ in runs} for k, runs in carried.items()
                  if boxes.categories[k] is Category.CONTAINER}
    tracks = list(obs.objects)
    for k, runs in carried.items():
        if boxes.categories[k] is Category.INGREDIENT:
            runs = [run for run in runs if not _rides(objects, k, run[0], containers, params.contain_fraction)]
        if not runs:
            continue
        track = obs.objects[k]
        joined = np.concatenate([track.frames, np.asarray([f for _, fs, _ in runs for f in fs], dtype=np.int64)])
        added = np.round(np.asarray([v for _, _, vs in runs for v in vs]), BOX_DECIMALS)
        joined_boxes = np.concatenate([track.boxes, added])
        order = np.argsort(joined, kind="stable")
        tracks[k] = replace(track, frames=joined[order].astype(track.frames.dtype), boxes=joined_boxes[order])
    changed = any(a is not b for a, b in zip(tracks, obs.objects, strict=True))
    return replace(obs, objects=tuple(tracks)) if changed else obs


def _rides(objects: np.ndarray, k: int, last: int, containers: dict[int, set[int]], least: float) -> bool:
    """Object column ``k`` lies (``least`` of its box) in a container whose box is hidden from the same
    frame ``last`` on."""
    box = objects[last, k]
    area = max(float(box_area(box)), MIN_AREA)
    return any(last in ends and float(np.nan_to_num(box_intersection(box, objects[last, c]))) >= least * area
               for c, ends in containers.items())


def _takes_other(objects: np.ndarray, hands: np.ndarray, moving: np.ndarray, hand_size: np.ndarray) -> np.ndarray:
    """bool ``(frames, hands, objects)``: on that frame the hand overlaps a moving object no bigger than it
    other than that object (the hand now carries something else)."""
    with np.errstate(invalid="ignore"):
        size = box_diagonal(objects)
        touching = box_intersection(hands[:, :, None, :], objects[:, None, :, :]) > 0
        small = size[:, None, :] <= hand_size[:, :, None]
    carrying = touching & small & moving[:, None, :]
    count = carrying.sum(axis=2, keepdims=True)
    return (count - carrying) > 0


def _covering_hand(box: np.ndarray, hands: np.ndarray, hand_size: np.ndarray, frames: Sequence[int], least: float,
                   ) -> tuple[int, int] | None:
    """``(frame, hand)``: the first of ``frames`` where a detected hand no smaller than ``box`` covers at least
    ``least`` of it (the hand that shows up around it), else None."""
    area = max(float(box_area(box)), MIN_AREA)
    size = float(box_diagonal(box))
    for frame in frames:
        with np.errstate(invalid="ignore"):
            covered = np.nan_to_num(box_intersection(hands[frame], box[None, :]) / area)
        covered[~(np.nan_to_num(hand_size[frame]) >= size)] = 0.0
        hand = int(np.argmax(covered))
        if covered[hand] >= least:
            return frame, hand
    return None
