"""Frozen dataclasses for every stage's result.

Conventions used throughout wecook:

- Frames are 0-based frame indices of the video. Ranges are ``[start, end)``: end exclusive.
- Image coordinates are pixels with the origin at the top-left corner, x to the right, y down.
- Boxes are ``(x1, y1, x2, y2)`` with ``x1 <= x2`` and ``y1 <= y2``.
- Hands are named ``LH_P1 RH_P1 LH_P2 RH_P2`` (left/right hand of person 1/2; persons numbered from left
  to right by their mean body position in the image).
- Objects are named by their *name*: the lowercase label with ``_`` for spaces, made unique within a
  video by a numeric suffix (``bowl``, ``bowl_2``) when two tracks share a label.

Per-frame data are numpy arrays held by frozen dataclasses (``eq=False``: arrays do not compare as
values); everything else compares by value. Stage functions never mutate their inputs.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

HANDS: tuple[str, ...] = ("LH_P1", "RH_P1", "LH_P2", "RH_P2")
"""Every hand name, in canonical order."""

PERSONS: tuple[str, ...] = ("P1", "P2")

VERBS: tuple[str, ...] = (
    "cut", "peel", "stir", "pour", "sprinkle", "roll", "spread", "squeeze", "wrap", "dip", "transfer",
)
"""The action vocabulary of the trees (DESIGN.md). ``transfer`` is detected, never recognised."""

COLLABORATIONS: tuple[str, ...] = ("handover", "holding")


def person_of(hand: str) -> str:
    """``"RH_P2" -> "P2"``."""
    return hand.split("_", 1)[1]


class Category(StrEnum):
    """The semantic class of an object (paper, Object Association)."""

    TOOL = "tool"
    """Manipulates other objects: knife, spoon, rolling pin. Never the receiver of an action."""
    CONTAINER = "container"
    """Can contain other objects: bowl, pot, chopping board."""
    INGREDIENT = "ingredient"
    """Cannot contain other objects: tomato, lemon, dough."""


# --------------------------------------------------------------------------------------------- inputs


@dataclass(frozen=True)
class VideoInfo:
    """What the video container says about itself, and what actually decodes."""

    path: str
    fps: float
    """Frames per second; times are ``frame / fps``."""
    frame_count: int
    """Frames the container declares."""
    width: int
    """Pixels."""
    height: int
    """Pixels."""
    decoded_frames: int | None = None
    """Frames that really decode, when counted; differs from ``frame_count`` on damaged files."""


@dataclass(frozen=True, eq=False)
class ObjectTrack:
    """One object's boxes over time (one track id of the box file)."""

    track_id: int
    label: str
    """As in the input file (``"chopping board"``)."""
    name: str
    """Unique lowercase name used in trees and plans (``"chopping_board"``, ``"bowl_2"``)."""
    frames: np.ndarray
    """int64 ``(n,)``, strictly increasing frame indices where the object is seen."""
    boxes: np.ndarray
    """float64 ``(n, 4)``, ``x1 y1 x2 y2`` pixels, one row per entry of ``frames``."""

    def box_at(self, frame: int) -> np.ndarray | None:
        i = int(np.searchsorted(self.frames, frame))
        if i < len(self.frames) and self.frames[i] == frame:
            return self.boxes[i]
        return None


@dataclass(frozen=True, eq=False)
class HandTrack:
    """One hand over time."""

    hand: str
    """One of :data:`HANDS`."""
    frames: np.ndarray
    """int64 ``(n,)``, strictly increasing frame indices where the hand was detected."""
    xy: np.ndarray
    """float64 ``(n, 2)``, hand centre in pixels."""
    boxes: np.ndarray
    """float64 ``(n, 4)``, hand box ``x1 y1 x2 y2`` in pixels."""


@dataclass(frozen=True, eq=False)
class Observations:
    """Everything the pipeline starts from: the video's facts, object boxes, hand tracks, categories."""

    video: VideoInfo
    objects: tuple[ObjectTrack, ...]
    hands: tuple[HandTrack, ...]
    categories: Mapping[str, Category]
    """Object *name* -> category, for every object in ``objects``."""

    def object(self, name: str) -> ObjectTrack:
        for track in self.objects:
            if track.name == name:
                return track
        raise KeyError(name)

    def hand(self, hand: str) -> HandTrack | None:
        for track in self.hands:
            if track.hand == hand:
                return track
        return None


# ---------------------------------------------------------------------------------------- segmentation


@dataclass(frozen=True)
class Segment:
    """A span of the video, ``[start, end)`` in frames."""

    start: int
    end: int

    def __post_init__(self) -> None:
        if not 0 <= self.start < self.end:
            raise ValueError(f"segment [{self.start}, {self.end}) is empty or negative")

    def __len__(self) -> int:
        return self.end - self.start

    def overlaps(self, other: Segment) -> bool:
        return self.start < other.end and other.start < self.end


@dataclass(frozen=True)
class GGSResult:
    """Greedy Gaussian Segmentation of one series, for every number of breakpoints up to ``k_max``."""

    breakpoints_by_k: tuple[tuple[int, ...], ...]
    """``[k]`` is the sorted *interior* breakpoints (sample indices where a new segment starts) after
    adding the k-th breakpoint and adjusting. ``[0] == ()``."""
    objective_by_k: tuple[float, ...]
    """Covariance-regularised log-likelihood of each ``breakpoints_by_k[k]``."""
    seconds: float
    """Wall time of the algorithm itself."""


@dataclass(frozen=True)
class Segmentation:
    """The video cut into segments: each hand's breakpoints and their union."""

    per_hand: Mapping[str, tuple[int, ...]]
    """Hand -> interior breakpoints chosen for it (frame indices where a new segment starts)."""
    segments: tuple[Segment, ...]
    """Contiguous segments covering ``[0, frame_count)``, cut at the union of all breakpoints."""
    interpolated: Mapping[str, int] = field(default_factory=dict)
    """Hand -> number of frames filled in by interpolation (gaps in its track)."""


# ---------------------------------------------------------------------------------------- associations


@dataclass(frozen=True)
class Associations:
    """What is linked to what during one segment (each link held for at least N consecutive frames)."""

    segment: Segment
    hand_object: Mapping[str, str]
    """Hand -> name of the object it holds (absent: the hand holds nothing)."""
    object_object: Mapping[str, tuple[str, ...]]
    """Held object's name -> names of containers / ingredients it acts on, closest first. Never a tool."""
    containment: Mapping[str, str]
    """Ingredient name -> name of the container that holds it (highest Jaccard index)."""


# --------------------------------------------------------------------------------------------- actions


class ActionKind(StrEnum):
    """The tree cases of DESIGN.md."""

    GRASP = "grasp"
    """A hand holds an object, no action: ``(HP (H h) (O o))``."""
    TOOL = "tool"
    """An action with a held tool or held object on targets (cut with knife, pour oil into pot)."""
    HAND = "hand"
    """An action by the hand itself (squeeze lemon)."""
    TRANSFER = "transfer"
    """An ingredient moves from one container to another, carried by a tool or by tipping a container."""
    HOLDING = "holding"
    """One person holds an object while the other acts on it."""
    HANDOVER = "handover"
    """An object passes from one person's hand to the other's."""


@dataclass(frozen=True)
class Action:
    """One recognised action of one segment (or of a merged run of segments)."""

    kind: ActionKind
    hand: str
    """The acting hand; for HOLDING the holder's hand, for HANDOVER the giver's hand."""
    start: int
    end: int
    """Frames ``[start, end)``."""
    verb: str | None = None
    """From :data:`VERBS`; None for GRASP, HOLDING, HANDOVER."""
    held: str | None = None
    """Object in ``hand`` (tool, carried container, held ingredient); None for HAND actions."""
    targets: tuple[str, ...] = ()
    """Objects acted on, outermost last: ``("tomato", "chopping_board")`` = tomato on the board.
    For TRANSFER: ``(ingredient, source_container, destination_container)``."""
    partner: Action | None = None
    """HOLDING: the other person's action on the held object. HANDOVER: the receiver's GRASP."""
    scores: tuple[tuple[str, float], ...] = ()
    """Commonsense ranking (verb, probability), best first, when the verb was recognised."""


# ----------------------------------------------------------------------------------------------- trees


@dataclass(frozen=True)
class Node:
    """A node of an action tree. Preterminals (H, O, A, C) carry a ``word`` and no children."""

    label: str
    """``HP AP CP OP`` for phrases, ``H O A C`` for preterminals."""
    children: tuple[Node, ...] = ()
    word: str | None = None


@dataclass(frozen=True)
class TreeSpan:
    """One action tree and the frames it covers; one entry of a tree file."""

    start: int
    end: int
    """Frames ``[start, end)``."""
    tree: Node


# ----------------------------------------------------------------------------------------------- graph


@dataclass(frozen=True)
class GraphNode:
    """One action of the action graph: a merged run of segments with identical trees."""

    id: str
    """Stable id, ``"a1"``, ``"a2"``, ... in order of start frame."""
    person: str
    """``P1`` or ``P2``: whose sequence it belongs to (the holder's / giver's for collaborations)."""
    span: TreeSpan
    action: Action


Ranking = tuple[tuple[str, float], ...]
"""Verbs with their probabilities, most likely first."""


@dataclass(frozen=True)
class SegmentActions:
    """What every hand does during one segment."""

    segment: Segment
    actions: tuple[Action, ...]
    """One per acting hand (GRASP included), in :data:`HANDS` order of ``Action.hand``. A hand whose action
    is the partner of a collaboration appears only inside it."""
    rankings: Mapping[str, Ranking] = field(default_factory=dict)
    """Hand -> the commonsense ranking of its individual action (empty when nothing was ranked)."""
    partners: tuple[str, ...] = ()
    """Hands whose action is the partner inside a collaboration of this segment."""

    def action_of(self, hand: str) -> Action | None:
        for action in self.actions:
            if action.hand == hand:
                return action
        return None


@dataclass(frozen=True)
class GraphEdge:
    source: str
    target: str
    kind: str
    """``"sequence"`` (next action of the same person) or a collaboration (``"handover"``, ``"holding"``)."""


@dataclass(frozen=True)
class ActionGraph:
    nodes: tuple[GraphNode, ...]
    sequences: Mapping[str, tuple[str, ...]]
    """Person -> node ids in order."""
    edges: tuple[GraphEdge, ...]


# ------------------------------------------------------------------------------------------ evaluation


@dataclass(frozen=True)
class Scores:
    """Tree precision / recall as DESIGN.md defines them."""

    precision: float
    recall: float
    correct: int
    predicted: int
    truth: int


# ----------------------------------------------------------------------------------------- corrections


class SegmentStatus(StrEnum):
    UNREVIEWED = "unreviewed"
    ACCEPTED = "accepted"
    CORRECTED = "corrected"
    REJECTED = "rejected"


@dataclass(frozen=True)
class Corrections:
    """What a person changed, folded from a session's journal. Keys name a segment by its start frame.

    The pipeline applies these on top of its own results; an empty ``Corrections()`` changes nothing.
    """

    splits: frozenset[int] = frozenset()
    """Frames where the user cut a segment (extra breakpoints)."""
    merges: frozenset[int] = frozenset()
    """Breakpoints the user removed (a segment merged with the one before)."""
    hand_object: Mapping[tuple[int, str], str | None] = field(default_factory=dict)
    """(segment start, hand) -> object name the hand holds, or None for nothing."""
    object_object: Mapping[tuple[int, str], tuple[str, ...]] = field(default_factory=dict)
    """(segment start, held object) -> objects it acts on."""
    verbs: Mapping[tuple[int, str], str] = field(default_factory=dict)
    """(segment start, hand) -> verb chosen by the user (from VERBS)."""
    status: Mapping[int, SegmentStatus] = field(default_factory=dict)
    """Segment start -> review status (absent: unreviewed)."""
