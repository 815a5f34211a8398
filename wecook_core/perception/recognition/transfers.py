"""Transfers and handovers, tracked over the whole video's timeline of per-frame links (paper, "Action
Recognition"): an ingredient whose container changes while a hand, or the object it holds, moves it; an object
that passes from one person's hand to the other's. :mod:`wecook_core.perception.recognition.actions` turns them into
actions."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import HANDS, Category, Observations, person_of
from wecook_core.perception.association.associate import Timeline
from wecook_core.perception.association.frame_links import frame_boxes
from wecook_core.perception.geometry import box_gap, video_diagonal
from wecook_core.perception.label_runs import NONE, kept_runs

if TYPE_CHECKING:
    from wecook_core.perception.params import FrameParams, Params


@dataclass(frozen=True)
class TransferEvent:
    """An ingredient moved from one container to another by a hand, found on the whole video's timeline."""

    ingredient: str
    source: str
    destination: str
    hand: str
    carrier: str | None
    """What the hand holds while moving it (spoon, the tipped bowl); None when the hand carries it directly."""
    start: int
    end: int
    """Frames ``[start, end)`` the hand's segments take the transfer: from the carrier's grasp to the arrival."""


@dataclass(frozen=True)
class HandoverEvent:
    """An object passed from one person's hand to the other person's."""

    obj: str
    giver: str
    receiver: str
    start: int
    end: int
    """Frames ``[start, end)`` of the exchange: the receiver's grasp to the giver's release."""
    grasped: int = -1
    """The frame the giver grasped the object in the hold that ends with the exchange (``start`` when not
    known): from there the giver holds it to pass it on."""


def hold_spans(labels: np.ndarray, value: int, min_frames: int) -> list[tuple[int, int]]:
    """Frames ``[start, end)`` where ``labels == value``, runs joined across gaps shorter than ``min_frames``,
    keeping spans of at least ``min_frames``."""
    mask = labels == value
    if not mask.any():
        return []
    padded = np.concatenate([[False], mask, [False]])
    change = np.flatnonzero(np.diff(padded.astype(np.int8)))
    starts, ends = change[0::2], change[1::2]
    spans: list[list[int]] = []
    for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
        if spans and start - spans[-1][1] < min_frames:
            spans[-1][1] = end
        else:
            spans.append([start, end])
    return [(s, e) for s, e in spans if e - s >= min_frames]


def transfer_events(obs: Observations, timeline: Timeline, params: Params, rate: FrameParams | None = None,
                    ) -> tuple[TransferEvent, ...]:
    """Every change of an ingredient's container that a hand caused, over the whole video: the hand that
    touches it, or holds what carries it (within ``near_fraction`` of the image diagonal of it), on
    ``mover_share`` of the frames from ``mover_window_s`` before it leaves its container to ``mover_window_s``
    after it enters the next."""
    diagonal = video_diagonal(obs)
    near = params.near_fraction * diagonal
    rate = rate or params.at(obs.video.fps)
    window = rate.mover_window
    events = []
    total = len(timeline.held)
    for column, category in enumerate(timeline.categories):
        if category is not Category.INGREDIENT:
            continue
        kept = kept_runs(timeline.container[:, column], rate.min_frames)
        for (_, end1, source), (start2, _, destination) in itertools.pairwise(kept):
            if source == destination:
                continue
            lo = max(0, end1 - window)
            hi = min(total, start2 + window)
            event = _mover(obs, timeline, column, lo, hi, near, params, rate, source, destination)
            if event is None:
                continue
            hand, carrier, span_start, span_end = event
            # a carrier's transfer ends when it leaves what it delivered; a hand's own when it lets go
            end = _arrival_end(obs, column, carrier, start2, span_end, near, rate.fill_gap) \
                if carrier != NONE else span_end
            events.append(TransferEvent(
                timeline.names[column], timeline.names[source], timeline.names[destination], HANDS[hand],
                timeline.names[carrier] if carrier != NONE else None, span_start, max(hi, end),
            ))
    return tuple(events)


def _arrival_end(
    obs: Observations, ingredient: int, carrier: int, arrival: int, hold_end: int, near: float, fill: int
) -> int:
    """First frame after ``arrival`` where the carrier has left the ingredient it delivered (within its hold)."""
    if hold_end <= arrival:
        return arrival
    boxes = frame_boxes(obs, arrival, hold_end, fill)
    with np.errstate(invalid="ignore"):
        close = box_gap(boxes.objects[:, carrier, :], boxes.objects[:, ingredient, :]) <= near
    away = np.flatnonzero(~close)
    return arrival + int(away[0]) if len(away) else hold_end


def _mover(
    obs: Observations, timeline: Timeline, ingredient: int, lo: int, hi: int, near: float, params: Params,
    rate: FrameParams, source: int = NONE, destination: int = NONE,
) -> tuple[int, int, int, int] | None:
    """(hand column, carrier column or NONE, start and end of the carrier's hold) of the hand that moved an
    ingredient during ``[lo, hi)``, or None when no hand did. Where the ingredient is not seen it rides in
    the container it left (``source``): a hand holding that container carries it there (the rule of
    :mod:`~wecook_core.perception.repairs.occlusion`: a hidden ingredient rides in the container it lies in;
    found on tasty-a, the garlic hidden in the small dish the hand brings over the pan, frames 63-78). What
    receives the ingredient (``destination``) did not carry it there: a hand holding the destination (steadying
    the bowl it is emptied into) is not the mover by that hold (kfc-b 739-781: the cauliflower tipped from the
    strainer into the bowl a hand was taken to hold came out "carried by the bowl")."""
    if hi <= lo:
        return None
    boxes = frame_boxes(obs, lo, hi, rate.fill_gap)
    ingredient_boxes = boxes.objects[:, ingredient, :]
    hidden = ~np.isfinite(ingredient_boxes[:, 0])
    rows = np.arange(hi - lo)
    best: tuple[float, int, int] | None = None
    for hand in range(len(HANDS)):
        held = timeline.held[lo:hi, hand].astype(np.int64)
        direct = held == ingredient
        carried_box = boxes.objects[rows, np.maximum(held, 0), :]
        with np.errstate(invalid="ignore"):
            via = (held != NONE) & (held != ingredient) & (held != destination) & \
                (box_gap(carried_box, ingredient_boxes) <= near)
        via |= hidden & (held == source) & (source != NONE)
        score = float(np.mean(direct | via))
        if score < params.mover_share:
            continue
        if via.sum() >= direct.sum():
            values, counts = np.unique(held[via], return_counts=True)
            carrier = int(values[np.argmax(counts)])
        else:
            carrier = NONE
        if best is None or score > best[0]:
            best = (score, hand, carrier)
    if best is None:
        return None
    _, hand, carrier = best
    label = timeline.held[:, hand]
    value = carrier if carrier != NONE else ingredient
    start, end = lo, hi
    for span_start, span_end in hold_spans(label, value, rate.min_frames):
        if span_start < hi and lo < span_end:
            start, end = min(span_start, lo), max(span_end, hi)
            break
    return hand, carrier, start, end


def handover_events(timeline: Timeline, params: Params, rate: FrameParams | None = None) -> tuple[HandoverEvent, ...]:
    """Every object that passed from one person's hand to the other's over the whole video."""
    events = []
    rate = rate or params.at(timeline.fps)
    for column in range(len(timeline.names)):
        spans = [
            (hand, start, end)
            for hand in range(len(HANDS))
            for start, end in hold_spans(timeline.held[:, hand], column, rate.min_frames)
        ]
        spans.sort(key=lambda s: s[1])
        for giver, g_start, g_end in spans:
            for receiver, r_start, r_end in spans:
                if person_of(HANDS[giver]) == person_of(HANDS[receiver]):
                    continue
                if not (g_start < r_start <= g_end + rate.handover_gap and r_end > g_end):
                    continue
                if g_end - r_start > rate.handover_overlap:
                    continue  # both held it a long time: a holding, not a handover
                start, end = min(r_start, g_end - 1), max(g_end, r_start + 1)
                events.append(HandoverEvent(timeline.names[column], HANDS[giver], HANDS[receiver], start, end,
                                            min(g_start, start)))
                break
    return tuple(events)
