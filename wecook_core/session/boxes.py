"""Boxes drawn in the workbench and categories the user gives, as corrections of the journal.

The box mode (``wecook_tui.screens.boxes``) edits :class:`~wecook_core.observations.tracking.BoxTrack` values
through four typed operations, journaled like every other correction (so undone, redone and kept across
sessions by the same code): a keyframe drawn or moved (:class:`SetBoxKeyframe`), a track named
(:class:`SetBoxLabel`), a keyframe dropped (:class:`DropBoxKeyframe`; dropping the only one removes the box) and
what OpenCV's tracker found after the last keyframe (:class:`SetBoxTracked`). :func:`fold_boxes` replays them.
:class:`SetCategory` records the category the user gives a label nothing categorises.

:func:`with_drawn` is what the analysis starts from: the imported observations with the drawn tracks added (named
after the imported ones, so corrections naming imported objects keep their meaning) and the user's categories
applied.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, ClassVar

from wecook_core.model import Category, Observations
from wecook_core.observations.tracking import Box, BoxTrack

if TYPE_CHECKING:
    from wecook_core.knowledge.categories import CategoryTable

UNNAMED = "object"
"""The label of a drawn box not named yet (never asked about as an unknown label)."""

DECIMALS = 1
"""Box coordinates are journaled to a tenth of a pixel."""


def rounded(box: Iterable[float]) -> Box:
    x1, y1, x2, y2 = (round(float(v), DECIMALS) for v in box)
    return (x1, y1, x2, y2)


@dataclass(frozen=True)
class SetBoxKeyframe:
    """The user's box of drawn track ``track`` at ``frame`` (a new track when ``track`` is not drawn yet; it
    takes ``label``, or ``object`` without one)."""

    op: ClassVar[str] = "box_keyframe"
    track: int
    frame: int
    box: Box
    label: str | None = None


@dataclass(frozen=True)
class SetBoxLabel:
    op: ClassVar[str] = "box_label"
    track: int
    label: str


@dataclass(frozen=True)
class DropBoxKeyframe:
    """The keyframe at ``frame`` removed; the track with it when it was its only one."""

    op: ClassVar[str] = "box_drop"
    track: int
    frame: int


@dataclass(frozen=True)
class SetBoxTracked:
    """The tracker's boxes after the track's last keyframe, and the frame it lost the object at."""

    op: ClassVar[str] = "box_tracked"
    track: int
    frames: tuple[int, ...]
    boxes: tuple[Box, ...]
    lost_at: int | None = None


@dataclass(frozen=True)
class SetCategory:
    """The category of every object labelled ``label`` (what the user answers for a label nothing knows)."""

    op: ClassVar[str] = "set_category"
    label: str
    category: Category


BoxCorrection = SetBoxKeyframe | SetBoxLabel | DropBoxKeyframe | SetBoxTracked
OtherCorrection = BoxCorrection | SetCategory
OTHER_TYPES: tuple[type[OtherCorrection], ...] = (SetBoxKeyframe, SetBoxLabel, DropBoxKeyframe, SetBoxTracked,
                                                  SetCategory)

def tracked(track_id: int, result: BoxTrack) -> SetBoxTracked:
    """The correction recording what the tracker found for a track (boxes rounded as journaled)."""
    frames = tuple(sorted(result.tracked))
    return SetBoxTracked(track_id, frames, tuple(rounded(result.tracked[f]) for f in frames), result.lost_at)


def fold_boxes(corrections: Iterable[object]) -> tuple[BoxTrack, ...]:
    """The drawn tracks the box corrections among ``corrections`` give, applied in order, by track id."""
    tracks: dict[int, BoxTrack] = {}
    for c in corrections:
        if isinstance(c, SetBoxKeyframe):
            track = tracks.get(c.track) or BoxTrack(c.track, c.label or UNNAMED)
            if c.label and track.label != c.label:
                track = replace(track, label=c.label)
            tracks[c.track] = track.with_keyframe(c.frame, c.box)
        elif isinstance(c, SetBoxLabel) and c.track in tracks:
            tracks[c.track] = replace(tracks[c.track], label=c.label)
        elif isinstance(c, DropBoxKeyframe) and c.track in tracks and c.frame in tracks[c.track].keyframes:
            if len(tracks[c.track].keyframes) == 1:
                del tracks[c.track]
            else:
                tracks[c.track] = tracks[c.track].without_keyframe(c.frame)
        elif isinstance(c, SetBoxTracked) and c.track in tracks:
            last = max(tracks[c.track].keyframes)
            run = {f: b for f, b in zip(c.frames, c.boxes, strict=True) if f > last}
            tracks[c.track] = replace(tracks[c.track], tracked=run, lost_at=c.lost_at)
    return tuple(tracks[k] for k in sorted(tracks))


def categories_given(corrections: Iterable[object]) -> dict[str, Category]:
    """Label -> the category the user gave it (the latest answer wins)."""
    return {c.label: c.category for c in corrections if isinstance(c, SetCategory)}


@dataclass(frozen=True)
class Drawn:
    """Observations with the drawn boxes and the user's categories."""

    observations: Observations
    unknown: tuple[str, ...]
    """Labels of drawn boxes that nothing categorises and the user has not answered (taken as ingredients)."""


def with_drawn(obs: Observations, corrections: Sequence[object],
               table: CategoryTable | None = None) -> Drawn:
    """``obs`` with the tracks drawn in the box mode added and the categories the user gave applied (``obs``
    itself when the corrections hold neither). A drawn label is categorised as an imported one would be (the
    category table ``table``, then the commonsense corpus), an imported label's category reused."""
    drawn = [t for t in fold_boxes(corrections) if t.keyframes]
    given = categories_given(corrections)
    if not drawn and not given:
        return Drawn(obs, ())
    from wecook_core.formats.tracks import object_name

    base = max((int(t.track_id) for t in obs.objects), default=0)
    taken = {t.name for t in obs.objects}
    added = []
    for track in drawn:
        name, count = object_name(track.label), 1
        while name in taken:  # imported names never change: corrections name them
            count += 1
            name = f"{object_name(track.label)}_{count}"
        taken.add(name)
        added.append(replace(track.object_track(name), track_id=base + track.track_id))
    objects = (*obs.objects, *added)
    label_category = {t.label: obs.categories[t.name] for t in obs.objects if t.name in obs.categories}
    new_labels = [t.label for t in added if t.label not in label_category and t.label not in given
                  and t.label != UNNAMED]
    unknown: tuple[str, ...] = ()
    from wecook_core.knowledge.categories import DEFAULT_CATEGORY, categorise_labels

    if new_labels:
        found = categorise_labels(new_labels, table)
        label_category.update(found.categories)
        unknown = tuple(found.unknown)
    label_category.setdefault(UNNAMED, DEFAULT_CATEGORY)  # a box not named yet: as an unknown label, unasked
    label_category.update(given)
    categories: Mapping[str, Category] = {**obs.categories, **{t.name: label_category[t.label] for t in objects
                                                                if t.label in label_category}}
    return Drawn(replace(obs, objects=objects, categories=categories), unknown)
