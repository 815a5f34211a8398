"""The review's view model: what the screen shows for a cursor frame, and the corrections keys produce.

Pure functions of ``Observations`` and ``Analysis`` (no Textual here): which segment holds a frame, the lanes
of the timeline, the inspector's facts, the overlay of the frame, the picker candidates, and the correction
typed corrections that ``Session.record`` journals are built in :mod:`wecook_tui.edits`.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from wecook_core.model import (
    HANDS,
    Action,
    ActionKind,
    Associations,
    Category,
    Corrections,
    Observations,
    Segment,
    SegmentStatus,
    TreeSpan,
)
from wecook_core.session.boxes import OTHER_TYPES, Drawn, with_drawn
from wecook_tui.frames import BoxMark, HandMark, LinkMark, Overlay

NOTHING = "-"
"""Picker value meaning "no object" (a hand that holds nothing, an object that acts on nothing)."""

HAND_COLOURS: Mapping[str, tuple[int, int, int]] = {
    "LH_P1": (80, 200, 255), "RH_P1": (40, 120, 255), "LH_P2": (255, 190, 60), "RH_P2": (255, 110, 40),
}
CATEGORY_COLOURS: Mapping[str, tuple[int, int, int]] = {
    "tool": (240, 240, 90), "container": (120, 230, 120), "ingredient": (240, 120, 220),
}
ACTION_COLOURS: Mapping[str, str] = {
    "cut": "#e6194b", "peel": "#f58231", "stir": "#42d4f4", "pour": "#4363d8", "sprinkle": "#911eb4",
    "roll": "#9a6324", "spread": "#ffe119", "squeeze": "#bfef45", "wrap": "#469990", "dip": "#f032e6",
    "transfer": "#fabed4", "holding": "#3cb44b", "handover": "#aaffc3", "grasp": "#a9a9a9",
}
"""One colour per action, none alike (Trubetskoy's distinct colours)."""
STATUS_GLYPHS: Mapping[SegmentStatus, tuple[str, str]] = {
    SegmentStatus.UNREVIEWED: ("·", "#808080"),
    SegmentStatus.ACCEPTED: ("✓", "#4caf50"),
    SegmentStatus.CORRECTED: ("✎", "#ffb300"),
    SegmentStatus.REJECTED: ("✗", "#e53935"),
}


# ---------------------------------------------------------------------------------- observations

_shown: list[tuple[object, object, int, Drawn]] = []
"""The latest :func:`drawn_of` result with what it was made from (observations, session, journal version)."""


def drawn_of(opened: object | None) -> Drawn | None:
    """The :class:`wecook_core.session.boxes.Drawn` of an open session: its observations with the boxes drawn in
    the box mode and the categories the user gave (what the analysis runs on), and the drawn labels still
    unknown; kept until the journal changes. None before the session opened."""
    obs = getattr(opened, "observations", None)
    session = getattr(opened, "session", None)
    if obs is None or session is None:
        return None
    version = session.journal.version
    if _shown and _shown[0][0] is obs and _shown[0][1] is session and _shown[0][2] == version:
        return _shown[0][3]
    corrections = session.applied_corrections
    if any(isinstance(c, OTHER_TYPES) for c in corrections):
        drawn = with_drawn(obs, corrections, session.category_table())
    else:
        drawn = Drawn(obs, ())  # nothing drawn, no category given: the imported observations as they are
    _shown[:] = [(obs, session, version, drawn)]
    return drawn


def shown_observations(opened: object | None) -> Observations | None:
    """The observations the review shows and analyses (:func:`drawn_of`), None before the session opened."""
    drawn = drawn_of(opened)
    return drawn.observations if drawn is not None else None


def unknown_labels(opened: object | None) -> tuple[str, ...]:
    """Labels nothing categorises that the user has not answered yet: imported ones, then drawn ones."""
    session = getattr(opened, "session", None)
    drawn = drawn_of(opened)
    if session is None:
        return ()
    found = list(getattr(session, "uncategorised", ()))
    found += [label for label in (drawn.unknown if drawn is not None else ()) if label not in found]
    return tuple(found)


# --------------------------------------------------------------------------------------- segments


def segments(analysis: object | None, frame_count: int) -> tuple[Segment, ...]:
    """The analysis' segments, or one segment over the whole video before the analysis arrives."""
    if analysis is not None:
        found = tuple(analysis.segmentation.segments)  # type: ignore[attr-defined]
        if found:
            return found
    return (Segment(0, max(1, frame_count)),)


def segment_index(segs: tuple[Segment, ...], frame: int) -> int:
    """Index of the segment holding ``frame`` (clamped to the first / last)."""
    starts = [s.start for s in segs]
    return max(0, min(len(segs) - 1, bisect.bisect_right(starts, frame) - 1))


def status_of(corrections: Corrections | None, start: int) -> SegmentStatus:
    """The journaled status; a segment with a changed verb or link and no explicit status is "corrected"."""
    if corrections is None:
        return SegmentStatus.UNREVIEWED
    explicit = corrections.status.get(start)
    if explicit is not None:
        return SegmentStatus(explicit)
    changed = (*corrections.verbs, *corrections.hand_object, *corrections.object_object)
    if any(key[0] == start for key in changed):
        return SegmentStatus.CORRECTED
    return SegmentStatus.UNREVIEWED


UNSURE_GLYPH = ("?", "#ff7043")
"""The timeline's mark of an unsure segment still to review."""


def unsure_of(analysis: object | None, seg: Segment) -> str | None:
    """Why the evidence in ``seg`` is too thin to trust what was recognised there (``Analysis.unsure``), or
    None when it is not unsure."""
    reasons = getattr(analysis, "unsure", None) or {}
    return reasons.get(seg.start)


def to_review(corrections: Corrections | None, start: int, unsure: Mapping[int, str] | None = None) -> bool:
    """Whether the segment starting at ``start`` still needs the reviewer: unreviewed, or unsure (the evidence
    too thin) and neither accepted nor rejected, even if a verb or object there was corrected."""
    if status_of(corrections, start) is SegmentStatus.UNREVIEWED:
        return True
    return unsure is not None and start in unsure and (corrections is None or start not in corrections.status)


def next_unreviewed(segs: tuple[Segment, ...], corrections: Corrections | None, current: int,
                    direction: int = 1, unsure: Mapping[int, str] | None = None) -> int | None:
    """The first segment after ``current`` (before it: ``direction`` -1) still to review (:func:`to_review`:
    unsure ones until accepted or rejected), wrapping around; None when all are reviewed."""
    n = len(segs)
    for step in range(1, n + 1):
        index = (current + direction * step) % n
        if to_review(corrections, segs[index].start, unsure):
            return index
    return None


# ---------------------------------------------------------------------------------------- actions


def action_label(action: Action) -> str:
    if action.kind in (ActionKind.HOLDING, ActionKind.HANDOVER):
        return str(action.kind)
    if action.verb:
        return action.verb
    return str(action.kind)


def _segment_actions(analysis: object | None, index: int, seg: Segment) -> object | None:
    """The pipeline's per-segment record (``SegmentActions``) for ``seg``, if the analysis has one."""
    table = getattr(analysis, "segment_actions", None)
    if not table:
        return None
    if 0 <= index < len(table) and table[index].segment == seg:
        return table[index]
    return next((entry for entry in table if entry.segment == seg), None)


def actions_of(analysis: object | None, seg: Segment, index: int = -1) -> dict[str, Action]:
    """Hand -> the action it takes part in during ``seg`` (a collaboration counts for both hands)."""
    found: dict[str, Action] = {}
    if analysis is None:
        return found
    record = _segment_actions(analysis, index, seg)
    candidates = record.actions if record is not None else analysis.actions  # type: ignore[attr-defined]
    for action in candidates:
        if action is None or not (action.start < seg.end and seg.start < action.end):
            continue
        found.setdefault(action.hand, action)
        if action.partner is not None:
            found.setdefault(action.partner.hand, action)
    return found


def whole_action(analysis: object | None, seg: Segment, hand: str) -> Action | None:
    """The merged action (a tree's span) ``hand`` takes part in during ``seg``: what a correction of the whole
    action covers."""
    if analysis is None:
        return None
    for action in analysis.actions:  # type: ignore[attr-defined]
        hands = {action.hand, action.partner.hand if action.partner is not None else None}
        if hand in hands and action.start < seg.end and seg.start < action.end:
            return action
    return None


def verb_span(analysis: object | None, seg: Segment, hand: str) -> tuple[int, int] | None:
    """The frames of the whole action whose segments carry ``hand``'s verb: from the first to the last segment of
    its merged action where the hand's own action has a verb (reaching for a tool and putting it down have none,
    and keep none). None when the hand has no verb in ``seg``."""
    action = whole_action(analysis, seg, hand)
    if action is None:
        return None
    segs = segments(analysis, 0)
    run: list[Segment] = []
    for index, other in enumerate(segs):
        if not (other.start < action.end and action.start < other.end):
            continue
        own = actions_of(analysis, other, index).get(hand)
        if own is not None and own.verb and own.kind not in (ActionKind.GRASP, ActionKind.HOLDING):
            run.append(other)
        elif seg in run:
            break
        else:
            run = []
    if seg not in run:
        return None
    return run[0].start, run[-1].end


def ranking_of(analysis: object | None, seg: Segment, index: int, hand: str) -> tuple[tuple[str, float], ...]:
    """The commonsense ranking the pipeline computed for ``hand`` in ``seg`` (empty if none)."""
    record = _segment_actions(analysis, index, seg)
    if record is not None:
        ranking = record.rankings.get(hand)  # type: ignore[attr-defined]
        if ranking:
            return tuple(ranking)
    action = actions_of(analysis, seg, index).get(hand)
    return tuple(action.scores) if action is not None else ()


def associations_of(analysis: object | None, index: int, seg: Segment) -> Associations | None:
    if analysis is None:
        return None
    table = analysis.associations  # type: ignore[attr-defined]
    if 0 <= index < len(table) and table[index].segment == seg:
        return table[index]
    for assoc in table:
        if assoc.segment == seg:
            return assoc
    return None


def trees_of(analysis: object | None, seg: Segment) -> tuple[TreeSpan, ...]:
    if analysis is None:
        return ()
    return tuple(t for t in analysis.trees if t.start < seg.end and seg.start < t.end)  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Lane:
    """One hand's row of the timeline: (start, end, label) spans, label None where the hand is idle."""

    hand: str
    spans: tuple[tuple[int, int, str | None], ...]


def lanes(analysis: object | None, hands: Iterable[str], frame_count: int) -> tuple[Lane, ...]:
    segs = segments(analysis, frame_count)
    result = []
    for hand in hands:
        spans = []
        for index, seg in enumerate(segs):
            action = actions_of(analysis, seg, index).get(hand)
            spans.append((seg.start, seg.end, action_label(action) if action else None))
        result.append(Lane(hand, tuple(spans)))
    return tuple(result)


def hands_of(obs: Observations | None) -> tuple[str, ...]:
    if obs is None:
        return ()
    present = {track.hand for track in obs.hands}
    return tuple(hand for hand in HANDS if hand in present)


# --------------------------------------------------------------------------------------- geometry


def _at(frames: np.ndarray, values: np.ndarray, frame: int, seg: Segment | None) -> np.ndarray | None:
    """The value at ``frame``, else the nearest one inside ``seg`` (None if the track is absent there)."""
    if len(frames) == 0:
        return None
    i = int(np.searchsorted(frames, frame))
    if i < len(frames) and frames[i] == frame:
        return values[i]
    if seg is None:
        return None
    candidates = [j for j in (i - 1, i) if 0 <= j < len(frames) and seg.start <= frames[j] < seg.end]
    if not candidates:
        return None
    j = min(candidates, key=lambda j: abs(int(frames[j]) - frame))
    return values[j]


def hand_xy(obs: Observations, hand: str, frame: int, seg: Segment | None = None) -> tuple[float, float] | None:
    track = obs.hand(hand)
    if track is None:
        return None
    xy = _at(track.frames, track.xy, frame, seg)
    return None if xy is None else (float(xy[0]), float(xy[1]))


def object_box(obs: Observations, name: str, frame: int, seg: Segment | None = None) -> np.ndarray | None:
    try:
        track = obs.object(name)
    except KeyError:
        return None
    return _at(track.frames, track.boxes, frame, seg)


def _centre(box: np.ndarray) -> tuple[float, float]:
    return (float(box[0] + box[2]) / 2, float(box[1] + box[3]) / 2)


def _point_box_distance(p: tuple[float, float], box: np.ndarray) -> float:
    dx = max(float(box[0]) - p[0], 0.0, p[0] - float(box[2]))
    dy = max(float(box[1]) - p[1], 0.0, p[1] - float(box[3]))
    return math.hypot(dx, dy)


def _box_distance(a: np.ndarray, b: np.ndarray) -> float:
    dx = max(float(b[0]) - float(a[2]), 0.0, float(a[0]) - float(b[2]))
    dy = max(float(b[1]) - float(a[3]), 0.0, float(a[1]) - float(b[3]))
    return math.hypot(dx, dy)


def objects_near_hand(obs: Observations, hand: str, frame: int, seg: Segment) -> list[tuple[str, float]]:
    """Objects seen in ``seg`` with their pixel distance to the hand at ``frame``, closest first."""
    xy = hand_xy(obs, hand, frame, seg)
    found = []
    for track in obs.objects:
        box = _at(track.frames, track.boxes, frame, seg)
        if box is None:
            continue
        distance = _point_box_distance(xy, box) if xy is not None else math.inf
        found.append((track.name, distance))
    return sorted(found, key=lambda item: (item[1], item[0]))


def link_candidates(obs: Observations, held: str, frame: int, seg: Segment) -> list[tuple[str, float]]:
    """Containers and ingredients (never tools) by box distance to ``held``, closest first."""
    held_box = object_box(obs, held, frame, seg)
    found = []
    for track in obs.objects:
        if track.name == held or obs.categories.get(track.name) is Category.TOOL:
            continue
        box = _at(track.frames, track.boxes, frame, seg)
        if box is None:
            continue
        found.append((track.name, _box_distance(held_box, box) if held_box is not None else math.inf))
    return sorted(found, key=lambda item: (item[1], item[0]))


def overlay(obs: Observations | None, assoc: Associations | None, frame: int, selected: str | None) -> Overlay:
    """Boxes and labels of the objects at ``frame``, hand markers, and the segment's links."""
    if obs is None:
        return Overlay()
    held = set(assoc.hand_object.values()) if assoc else set()
    boxes = []
    centres: dict[str, tuple[float, float]] = {}
    for track in obs.objects:
        box = track.box_at(frame)
        if box is None:
            continue
        centres[track.name] = _centre(box)
        colour = CATEGORY_COLOURS.get(str(obs.categories.get(track.name, "")), (200, 200, 200))
        boxes.append(BoxMark(track.name, tuple(float(v) for v in box), colour, track.name in held))  # type: ignore[arg-type]
    hands = []
    hand_points: dict[str, tuple[float, float]] = {}
    for hand_track in obs.hands:
        hand = hand_track.hand
        xy = hand_xy(obs, hand, frame)
        if xy is None:
            continue
        hand_points[hand] = xy
        hands.append(HandMark(hand, xy, HAND_COLOURS.get(hand, (255, 255, 255)), hand == selected))
    links = []
    if assoc is not None:
        for hand, name in assoc.hand_object.items():
            if hand in hand_points and name in centres:
                links.append(LinkMark(hand_points[hand], centres[name], HAND_COLOURS.get(hand, (255, 255, 255))))
        for name, targets in assoc.object_object.items():
            for target in targets:
                if name in centres and target in centres:
                    links.append(LinkMark(centres[name], centres[target], (255, 255, 255)))
    return Overlay(tuple(boxes), tuple(hands), tuple(links))


def segment_objects(assoc: Associations | None, action: Action | None, hand: str | None) -> tuple[str, ...]:
    """The objects a hand deals with in a segment, for ranking verbs: held object, then its targets."""
    names: list[str] = []
    if assoc is not None and hand is not None:
        held = assoc.hand_object.get(hand)
        if held:
            names.append(held)
            names.extend(assoc.object_object.get(held, ()))
    if action is not None:
        if action.held:
            names.append(action.held)
        names.extend(action.targets)
    return tuple(dict.fromkeys(names))
