"""Corrections as typed operations, and the one fold that turns them into :class:`Corrections`.

A person's corrections are values of frozen dataclasses (:data:`Correction`): six about segments and their
cuts, here, and the boxes drawn in the box mode and categories given to unknown labels
(:mod:`wecook_core.session.boxes`, replayed by its own fold). The journal stores each as
a JSON object (:func:`to_record`; :func:`parse` reads one back and says what is wrong with a bad one), the
workbench builds them from keys, and :func:`fold` applies a sequence of them, later ones winning.

Segment operations name a segment by its start frame (``segment``). They may also carry ``end``: the span
``[segment, end)`` of the whole action the correction was made on. Folded against a segmentation, a span
correction applies to every segment of the span, so it acts on the whole action and survives a change of
segmentation (a split, a merge, other parameters); without a segmentation, or without ``end``, it applies to
the segment starting at ``segment`` (what journals written before spans existed mean).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import MISSING, dataclass, fields
from typing import Any, ClassVar, get_args, get_type_hints

from wecook_core.formats.fields import MAX_FRAME
from wecook_core.model import HANDS, VERBS, Category, Corrections, Segment, SegmentStatus
from wecook_core.session import boxes
from wecook_core.session.boxes import (
    DropBoxKeyframe,
    OtherCorrection,
    SetBoxKeyframe,
    SetBoxLabel,
    SetBoxTracked,
    SetCategory,
)

MAX_NAME_CHARS = 200
"""The longest object name a correction may carry."""


@dataclass(frozen=True)
class SetHandObject:
    """What ``hand`` holds in the segment (None: nothing)."""

    op: ClassVar[str] = "set_hand_object"
    segment: int
    hand: str
    object: str | None
    end: int | None = None


@dataclass(frozen=True)
class SetObjectObject:
    """What the held ``object`` acts on in the segment."""

    op: ClassVar[str] = "set_object_object"
    segment: int
    object: str
    targets: tuple[str, ...]
    end: int | None = None


@dataclass(frozen=True)
class SetVerb:
    """The verb of ``hand``'s action in the segment."""

    op: ClassVar[str] = "set_verb"
    segment: int
    hand: str
    verb: str
    end: int | None = None


@dataclass(frozen=True)
class SetStatus:
    """The review status of the segment."""

    op: ClassVar[str] = "set_status"
    segment: int
    status: SegmentStatus
    end: int | None = None


@dataclass(frozen=True)
class Split:
    """A new breakpoint at ``frame``."""

    op: ClassVar[str] = "split"
    frame: int


@dataclass(frozen=True)
class Merge:
    """The breakpoint at ``frame`` removed (a merge of a split frame cancels the split)."""

    op: ClassVar[str] = "merge"
    frame: int


Correction = SetHandObject | SetObjectObject | SetVerb | SetStatus | Split | Merge | OtherCorrection
SegmentCorrection = SetHandObject | SetObjectObject | SetVerb | SetStatus

TYPES: dict[str, type[Correction]] = {t.op: t for t in (SetHandObject, SetObjectObject, SetVerb, SetStatus,
                                                         Split, Merge, *boxes.OTHER_TYPES)}
"""Operation name -> its type."""

@dataclass(frozen=True)
class _Field:
    """One field of an operation as the journal checks it."""

    name: str
    check: Callable[[Any], Any]
    """The value checked and converted (a list to a tuple, a string to its enum), or :class:`_Bad`."""
    required: bool
    """It has no default: a record must give it."""
    nullable: bool
    """Its type admits None: a record may give null."""


class _Bad(ValueError):
    """A value not of its field's kind; ``expected`` says what the field takes."""

    def __init__(self, expected: str) -> None:
        super().__init__(expected)
        self.expected = expected


def _is_frame(value: Any) -> bool:
    return not isinstance(value, bool) and isinstance(value, int) and 0 <= value <= MAX_FRAME


def _is_name(value: Any) -> bool:
    return isinstance(value, str) and bool(value) and len(value) <= MAX_NAME_CHARS


def _frame(value: Any) -> int:
    if not _is_frame(value):
        raise _Bad(f"a frame index (int from 0 to {MAX_FRAME})")
    return int(value)


def _frames(value: Any) -> tuple[int, ...]:
    if not isinstance(value, list | tuple) or not all(_is_frame(v) for v in value):
        raise _Bad("a list of frame indices")
    return tuple(value)


def _track(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_TRACK:
        raise _Bad(f"a drawn track id (int from 1 to {MAX_TRACK})")
    return value


def _one_of(choices: Sequence[str], convert: Callable[[str], Any] = str) -> Callable[[Any], Any]:
    def check(value: Any) -> Any:
        if value not in choices:
            raise _Bad("one of " + " ".join(choices))
        return convert(value)
    return check


def _name(value: Any) -> str:
    if not _is_name(value):
        raise _Bad("an object name")
    return str(value)


def _names(value: Any) -> tuple[str, ...]:
    if not isinstance(value, list | tuple) or not all(_is_name(v) for v in value):
        raise _Bad("a list of object names")
    return tuple(value)


def _box(value: Any) -> tuple[float, float, float, float]:
    """A box ``[x1, y1, x2, y2]`` of finite pixels with x1 < x2 and y1 < y2."""
    if not isinstance(value, list | tuple) or len(value) != 4 or not all(
            not isinstance(v, bool) and isinstance(v, int | float) and math.isfinite(v) and abs(v) < MAX_PIXEL
            for v in value):
        raise _Bad("a box [x1, y1, x2, y2] of pixels")
    x1, y1, x2, y2 = (float(v) for v in value)
    if not (x1 < x2 and y1 < y2):
        raise _Bad("a box with x1 < x2 and y1 < y2")
    return (x1, y1, x2, y2)


def _boxes(value: Any) -> tuple[tuple[float, float, float, float], ...]:
    if not isinstance(value, list | tuple):
        raise _Bad("a list of boxes")
    return tuple(_box(v) for v in value)


MAX_TRACK = 1 << 20
"""The largest id of a drawn track."""
MAX_PIXEL = 1e6
"""The largest coordinate of a drawn box, pixels (in either direction)."""

CHECKS: dict[str, Callable[[Any], Any]] = {
    "segment": _frame, "end": _frame, "frame": _frame, "lost_at": _frame, "frames": _frames,
    "hand": _one_of(HANDS), "verb": _one_of(VERBS),
    "status": _one_of([s.value for s in SegmentStatus], SegmentStatus),
    "category": _one_of([c.value for c in Category], Category),
    "object": _name, "label": _name, "targets": _names,
    "track": _track, "box": _box, "boxes": _boxes,
}
"""How the value of each field of the operations is checked, by the field's name (the same name means the same
kind of value in every operation); whether it may be absent or null comes from the dataclass."""


def _fields(kind: type[Correction]) -> tuple[_Field, ...]:
    hints = get_type_hints(kind)
    return tuple(_Field(f.name, CHECKS[f.name],
                        required=f.default is MISSING and f.default_factory is MISSING,
                        nullable=type(None) in get_args(hints[f.name])) for f in fields(kind))


FIELDS: dict[str, tuple[_Field, ...]] = {op: _fields(kind) for op, kind in TYPES.items()}
"""Each operation's fields as a record gives them, read off its dataclass."""


def parse(record: Mapping[str, Any]) -> Correction:
    """The correction a record ``{"op": ..., fields}`` describes, or ValueError saying what is wrong."""
    op = record.get("op")
    if op not in FIELDS:
        raise ValueError(f"unknown correction op {op!r}; expected one of {', '.join(FIELDS)}")
    spec = FIELDS[op]
    extra = set(record) - {f.name for f in spec} - {"op"}
    if extra:
        raise ValueError(f"{op}: unexpected fields {', '.join(sorted(extra))}")
    values: dict[str, Any] = {}
    for field in spec:
        if field.name not in record:
            if not field.required:
                continue
            raise ValueError(f"{op}: missing field {field.name!r}")
        values[field.name] = _check_value(op, field, record[field.name])
    end = values.get("end")
    if end is not None and end <= values["segment"]:
        raise ValueError(f"{op}: end must be after segment, got [{values['segment']}, {end})")
    return TYPES[op](**values)


def _check_value(op: str, field: _Field, value: Any) -> Any:
    if value is None and field.nullable:
        return None
    try:
        return field.check(value)
    except _Bad as bad:
        raise ValueError(f"{op}: {field.name} must be {bad.expected}, got {value!r}") from None


def to_record(correction: Correction) -> dict[str, Any]:
    """The JSON object the journal stores for ``correction`` (``end`` only when it has one)."""
    record: dict[str, Any] = {"op": correction.op}
    for f in fields(correction):
        value = getattr(correction, f.name)
        if f.name == "end" and value is None:
            continue
        if isinstance(value, SegmentStatus | Category):
            value = value.value
        elif isinstance(value, tuple):
            value = [list(v) if isinstance(v, tuple) else v for v in value]
        record[f.name] = value
    return record


def covered(correction: SegmentCorrection, segments: Sequence[Segment] | None) -> tuple[int, ...]:
    """Start frames of the segments ``correction`` applies to: with a span and a segmentation, the segment
    holding its start and every segment lying mostly inside ``[segment, end)``; else its own segment."""
    start, end = correction.segment, correction.end
    if end is None or not segments:
        return (start,)
    starts = []
    for seg in segments:
        inside = min(seg.end, end) - max(seg.start, start)
        if seg.start <= start < seg.end or 2 * inside > seg.end - seg.start:
            starts.append(seg.start)
    return tuple(starts) or (start,)


def fold(corrections: Iterable[Correction], segments: Sequence[Segment] | None = None) -> Corrections:
    """The :class:`Corrections` of ``corrections`` applied in order, later ones winning; span corrections are
    spread over ``segments`` (the segmentation after the splits and merges) when given."""
    splits: set[int] = set()
    merges: set[int] = set()
    hand_object: dict[tuple[int, str], str | None] = {}
    object_object: dict[tuple[int, str], tuple[str, ...]] = {}
    verbs: dict[tuple[int, str], str] = {}
    status: dict[int, SegmentStatus] = {}
    for c in corrections:
        if isinstance(c, SetBoxKeyframe | SetBoxLabel | DropBoxKeyframe | SetBoxTracked | SetCategory):
            continue  # boxes and categories: folded by wecook_core.session.boxes
        if isinstance(c, Split):
            if c.frame in merges:
                merges.discard(c.frame)
            else:
                splits.add(c.frame)
        elif isinstance(c, Merge):
            if c.frame in splits:
                splits.discard(c.frame)
            else:
                merges.add(c.frame)
        else:
            for start in covered(c, segments):
                if isinstance(c, SetHandObject):
                    hand_object[(start, c.hand)] = c.object
                elif isinstance(c, SetObjectObject):
                    object_object[(start, c.object)] = c.targets
                elif isinstance(c, SetVerb):
                    verbs[(start, c.hand)] = c.verb
                else:
                    status[start] = c.status
    return Corrections(frozenset(splits), frozenset(merges), hand_object, object_object, verbs, status)


def describe(correction: Correction) -> str:
    """A short phrase for messages: ``verb of RH_P1 -> cut``."""
    if isinstance(correction, SetVerb):
        return f"verb of {correction.hand} -> {correction.verb}"
    if isinstance(correction, SetHandObject):
        return f"{correction.hand} holds {correction.object or 'nothing'}"
    if isinstance(correction, SetObjectObject):
        return f"{correction.object} acts on {', '.join(correction.targets) or 'nothing'}"
    if isinstance(correction, SetStatus):
        return f"segment {correction.status.value}"
    if isinstance(correction, Split):
        return f"split at frame {correction.frame}"
    if isinstance(correction, Merge):
        return f"merge at frame {correction.frame}"
    if isinstance(correction, SetBoxKeyframe):
        x1, y1, x2, y2 = correction.box
        return f"box {correction.track} at frame {correction.frame}: {x1:.0f},{y1:.0f}-{x2:.0f},{y2:.0f}"
    if isinstance(correction, SetBoxLabel):
        return f"box {correction.track} named {correction.label}"
    if isinstance(correction, DropBoxKeyframe):
        return f"box {correction.track}: keyframe at frame {correction.frame} dropped"
    if isinstance(correction, SetBoxTracked):
        lost = f", lost at frame {correction.lost_at}" if correction.lost_at is not None else ""
        return f"box {correction.track} tracked over {len(correction.frames)} frames{lost}"
    return f"{correction.label} is a {correction.category.value}"


def span_of(correction: Correction) -> tuple[int, int | None] | None:
    """(first frame, end or None) the correction is about: where the workbench jumps to show it (None: no
    place, a category or a name)."""
    if isinstance(correction, Split | Merge | SetBoxKeyframe | DropBoxKeyframe):
        return correction.frame, None
    if isinstance(correction, SetBoxTracked):
        return (correction.frames[0], correction.frames[-1] + 1) if correction.frames else None
    if isinstance(correction, SetBoxLabel | SetCategory):
        return None
    return correction.segment, correction.end
