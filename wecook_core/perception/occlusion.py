"""Objects hidden by the hand that carries them: a jar in a fist is still in the fist.

On real footage an annotator (or a detector) stops boxing a small object once the hand that holds it covers
it: the seasoning jar is boxed while an unseen hand brings it in, and no longer once the hand shows up around
it. Left as it is, the hand then overlaps only the static pan under it, and the held-object decoder
(:mod:`wecook_core.perception.holding`) gives it the pan. But an object does not vanish inside a hand that was
carrying it: it is occluded, and it goes where the hand goes. So, per object, at each frame where its box stops
being seen (for longer than ``Params.fill_gap_s``):

- it was **carried** there: its centre travelled more than ``Params.moving_fraction`` of its box's diagonal
  over the ``Params.dwell_s`` before (as in :mod:`wecook_core.perception.unseen`: objects do not move by
  themselves), within one shot;
- a detected hand **covers** it there: at least ``Params.contain_fraction`` of its box lies in the hand's box
  (the hand is in front of it), and it is no bigger than that hand (a bowl is not hidden by a hand);

then its box is carried on with that hand's displacement, frame by frame, for as long as that hand is seen
(gaps of at most ``fill_gap_s`` bridged), in the same shot, until the object's own box is seen again or the
hand takes another object (another object no bigger than the hand moves while the hand overlaps it: the jar
was put down for the next one).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.perception.frame_links import box_area, box_centres, box_intersection, frame_boxes, video_diagonal
from wecook_core.perception.unseen import moving_objects, shot_index

if TYPE_CHECKING:
    from collections.abc import Sequence

    from wecook_core.model import Observations
    from wecook_core.perception.params import Params


def hidden_by_hands(obs: Observations, params: Params, shots: Sequence[int] = ()) -> Observations:
    """``obs`` with each object's track carried on where the hand carrying it hides it (module docstring);
    ``obs`` itself when no object is hidden so."""
    total = int(obs.video.frame_count)
    if total <= 1 or not obs.objects or not obs.hands:
        return obs
    rate = params.at(obs.video.fps)
    boxes = frame_boxes(obs, 0, total, rate.fill_gap)
    objects, hands = boxes.objects, boxes.hand_boxes
    shot = shot_index(total, shots)
    most = params.dwell_fraction * video_diagonal(obs)
    moving = moving_objects(objects, rate.dwell_frames, params.moving_fraction, shot, most)
    hand_centres = box_centres(hands)
    with np.errstate(invalid="ignore"):
        hand_size = np.hypot(hands[..., 2] - hands[..., 0], hands[..., 3] - hands[..., 1])
    takes_other = _takes_other(objects, hands, moving, hand_size)
    tracks = list(obs.objects)
    changed = False
    for k, track in enumerate(obs.objects):
        seen = np.isfinite(objects[:, k, 0])
        ends = np.flatnonzero(seen[:-1] & ~seen[1:])
        added_frames: list[int] = []
        added_boxes: list[np.ndarray] = []
        for last in ends:
            if not moving[last, k]:
                continue
            box = objects[last, k]
            area = float(box_area(box))
            size = float(np.hypot(box[2] - box[0], box[3] - box[1]))
            with np.errstate(invalid="ignore"):
                covered = np.nan_to_num(box_intersection(hands[last], box[None, :]) / max(area, 1e-9))
            covered[~(np.nan_to_num(hand_size[last]) >= size)] = 0.0
            hand = int(np.argmax(covered))
            if covered[hand] < params.contain_fraction:
                continue
            anchor = hand_centres[last, hand]
            frame = int(last) + 1
            while frame < total and not seen[frame] and shot[frame] == shot[last] \
                    and np.isfinite(hands[frame, hand, 0]) and not takes_other[frame, hand, k]:
                shift = hand_centres[frame, hand] - anchor
                added_frames.append(frame)
                added_boxes.append(box + np.array([shift[0], shift[1], shift[0], shift[1]]))
                frame += 1
        if added_frames:
            frames = np.concatenate([track.frames, np.asarray(added_frames, dtype=track.frames.dtype)])
            values = np.concatenate([track.boxes, np.round(np.asarray(added_boxes), 1)])
            order = np.argsort(frames, kind="stable")
            tracks[k] = replace(track, frames=frames[order], boxes=values[order])
            changed = True
    return replace(obs, objects=tuple(tracks)) if changed else obs


def _takes_other(objects: np.ndarray, hands: np.ndarray, moving: np.ndarray, hand_size: np.ndarray) -> np.ndarray:
    """bool ``(frames, hands, objects)``: on that frame the hand overlaps a moving object no bigger than it
    other than that object (the hand now carries something else)."""
    with np.errstate(invalid="ignore"):
        size = np.hypot(objects[..., 2] - objects[..., 0], objects[..., 3] - objects[..., 1])
        touching = box_intersection(hands[:, :, None, :], objects[:, None, :, :]) > 0
        small = size[:, None, :] <= hand_size[:, :, None]
    carrying = touching & small & moving[:, None, :]
    count = carrying.sum(axis=2, keepdims=True)
    return (count - carrying) > 0
