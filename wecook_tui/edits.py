"""The corrections the review's keys make (typed: :mod:`wecook_core.session.corrections`), and how their
one-line answers say where they apply."""

from __future__ import annotations

from wecook_core.model import Segment, SegmentStatus
from wecook_core.session.corrections import (
    Correction,
    Merge,
    SetHandObject,
    SetObjectObject,
    SetStatus,
    SetVerb,
    Split,
    covered,
)


def span_of(span: tuple[int, int] | None, seg: Segment) -> tuple[int, int | None]:
    """(segment, end) a correction records: the whole action's ``span``, or ``seg`` alone (end None)."""
    if span is None:
        return seg.start, None
    return span


def where(correction: Correction, segments: tuple[Segment, ...] | None) -> str:
    """Where a correction applies, for its one-line answer: `` at [30, 66), 2 segments``."""
    if not isinstance(correction, SetHandObject | SetObjectObject | SetVerb | SetStatus):
        return ""  # cuts say their frame; boxes and categories have no segment
    spread = covered(correction, segments)
    end = correction.end
    if end is None:
        end = next((s.end for s in segments or () if s.start == correction.segment), None)
    count = f", {len(spread)} segments" if len(spread) > 1 else ""
    return f" at [{correction.segment}, {end}){count}" if end is not None else f" at frame {correction.segment}"


def set_status(seg: Segment, status: SegmentStatus) -> SetStatus:
    return SetStatus(seg.start, SegmentStatus(status))


def set_verb(seg: Segment, hand: str, verb: str, span: tuple[int, int] | None = None) -> SetVerb:
    """The verb of ``hand`` in ``seg``, or over the whole action's ``span`` when given."""
    start, end = span_of(span, seg)
    return SetVerb(start, hand, verb, end)


def set_hand_object(seg: Segment, hand: str, name: str | None,
                    span: tuple[int, int] | None = None) -> SetHandObject:
    start, end = span_of(span, seg)
    return SetHandObject(start, hand, name, end)


def set_object_object(seg: Segment, held: str, targets: tuple[str, ...],
                      span: tuple[int, int] | None = None) -> SetObjectObject:
    start, end = span_of(span, seg)
    return SetObjectObject(start, held, tuple(targets), end)


def split(frame: int) -> Split:
    return Split(frame)


def merge(next_start: int) -> Merge:
    return Merge(next_start)
