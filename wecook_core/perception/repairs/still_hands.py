"""Hands the detector loses while they keep still (R0b): a hand seen at the same place before and after a gap in
its detections stayed there.

A hand that steadies a board or holds a pot's handle keeps still for many seconds, and a hand detector loses
such a hand for stretches (the other hand passes over it, it is half out of frame, a glove): on real footage
most frames have no box for it. Read as "no hand", a steady hold breaks into pieces and the holding is lost. But
a hand that keeps still does not vanish: when it is seen still just before a gap in its detections and just
after it (on every frame of ``Params.dwell_s`` on each side, travelling less than ``Params.moving_fraction`` of
its diagonal: the pipeline's own test of a hand that moves), and its box after the gap lies within that of
where it was before, in the same shot, and the gap is at most ``Params.still_gap_s`` long (longer, it may have
gone and come back), the hand's box is filled in across the gap, interpolated between the two ends. Seeing it
still on both sides matters: a stirring hand glimpsed on single frames comes back to the same place every
turn (kfc-b 1600-1651). A hand that
reappears elsewhere is left with its gap (interpolating it would put it where it was not, see
:mod:`~wecook_core.perception.repairs.unseen`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, HandTrack, Observations
from wecook_core.perception.association.frame_links import frame_boxes
from wecook_core.perception.geometry import box_diagonal, box_gap, video_diagonal
from wecook_core.perception.repairs.unseen import SEEN_WITHIN, moving_objects, shot_index

if TYPE_CHECKING:
    from wecook_core.perception.params import FrameParams, Params


def _moved_at(boxes: np.ndarray, frames: np.ndarray, column: int, objects: np.ndarray, moving: np.ndarray,
              hands: np.ndarray) -> bool:
    """Whether, on some of ``frames``, an object moves within reach of the filled-in hand ``boxes`` (as R5
    reads reach: :data:`~wecook_core.perception.repairs.unseen.SEEN_WITHIN` of the object's own diagonal) with
    no other hand (``hands``, column ``column`` being this one) seen within reach of it: then this hand may be
    the one moving it. An object another seen hand is at is that hand's work (a knife cutting beside the hand
    that steadies the board)."""
    box = objects[frames]
    with np.errstate(invalid="ignore"):
        reach = SEEN_WITHIN * box_diagonal(box)
        near = (box_gap(boxes[:, None, :], box) <= reach) & moving[frames]
        if not near.any():
            return False
        others = np.delete(hands[frames], column, axis=1)
        explained = (box_gap(others[:, :, None, :], box[:, None, :, :]) <= reach[:, None, :]).any(axis=1)
    return bool((near & ~explained).any())


def _filled(track: HandTrack, column: int, most: int, fraction: float, shot: np.ndarray, objects: np.ndarray,
            moving: np.ndarray, hands: np.ndarray) -> HandTrack:
    frames = track.frames
    if len(frames) < 2 or most <= 0:
        return track
    gap = np.diff(frames)
    inside = (frames[:-1] >= 0) & (frames[1:] < len(shot))
    candidates = np.flatnonzero((gap > 1) & (gap <= most + 1) & inside)
    if not len(candidates):
        return track
    a, b = candidates, candidates + 1
    with np.errstate(invalid="ignore"):
        size = (box_diagonal(track.boxes[a]) + box_diagonal(track.boxes[b])) / 2
        travel = np.hypot(*(track.xy[b] - track.xy[a]).T)
        still = (travel <= fraction * size) & (shot[frames[a]] == shot[frames[b]])
    new_frames, new_boxes, new_xy = [frames], [track.boxes], [track.xy]
    for i in candidates[still]:
        missing = np.arange(frames[i] + 1, frames[i + 1])
        t = ((missing - frames[i]) / (frames[i + 1] - frames[i]))[:, None]
        boxes = track.boxes[i] + t * (track.boxes[i + 1] - track.boxes[i])
        if _moved_at(boxes, missing, column, objects, moving, hands):  # the hand may be moving it
            continue
        new_frames.append(missing)
        new_boxes.append(boxes)
        new_xy.append(track.xy[i] + t * (track.xy[i + 1] - track.xy[i]))
    if len(new_frames) == 1:
        return track
    all_frames = np.concatenate(new_frames)
    order = np.argsort(all_frames, kind="stable")
    return replace(track, frames=all_frames[order].astype(np.int64), boxes=np.concatenate(new_boxes)[order],
                   xy=np.concatenate(new_xy)[order])


def with_still_hands(obs: Observations, params: Params, shots: Sequence[int] = (), *,
                     rate: FrameParams | None = None) -> Observations:
    """``obs`` with every hand's gaps of at most ``Params.still_gap_s`` filled where it reappears where it was
    and nothing under it moves meanwhile (module docstring); ``shots``: the video's cuts (never filled
    across)."""
    rate = rate or params.at(obs.video.fps)
    total = int(obs.video.frame_count)
    if rate.still_gap <= 0 or not obs.hands or total <= 0:
        return obs
    shot = shot_index(total, shots)
    boxes = frame_boxes(obs, 0, total, rate.fill_gap)
    objects = boxes.objects
    most = params.moving_cap_fraction * video_diagonal(obs)
    moving = moving_objects(objects, rate.dwell_frames, params.moving_fraction, shot, most)
    hands = tuple(t if t.hand not in HANDS else _filled(t, HANDS.index(t.hand), rate.still_gap,
                                                         params.moving_fraction, shot, objects, moving,
                                                         boxes.hand_boxes)
                  for t in obs.hands)
    return replace(obs, hands=hands)
