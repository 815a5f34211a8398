"""The whole perception pipeline as one pure function: observations + corrections -> trees and graph.

Each stage lives in its own module; this one only chains them and applies the user's corrections:
segment (:mod:`wecook_core.segment`) -> associate (:mod:`wecook_core.associate`) -> actions
(:mod:`wecook_core.actions`) -> merged trees and graph (:mod:`wecook_core.graph`).
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from wecook_core.model import (
    Action,
    ActionGraph,
    Associations,
    Corrections,
    Segment,
    Segmentation,
    SegmentStatus,
    TreeSpan,
)

if TYPE_CHECKING:
    from wecook_core.actions import SegmentActions
    from wecook_core.model import Observations
    from wecook_core.recognize import Knowledge


@dataclass(frozen=True)
class Params:
    """Every tunable of the pipeline, recorded in a session's `session.yaml`."""

    lamb: float = 1e-3
    """GGS covariance regularisation (on hand positions scaled to the unit square)."""
    k_max: int = 40
    """Most breakpoints GGS considers per hand."""
    k_per_minute: float = 30.0
    """Breakpoints GGS may consider per hand and minute of video: the pipeline raises ``k_max`` to this rate
    so a long video is cut as finely as a short one (BIC still chooses how many are used)."""
    k: dict[str, int] = field(default_factory=dict)
    """Hand -> number of breakpoints forced by the user (otherwise chosen automatically)."""
    min_segment_s: float = 0.3
    """Seconds: the hands' breakpoints closer than this merge into one cut of the union, so no segment of the
    video is a sliver between two hands' nearly simultaneous phase changes."""
    min_frames: int = 8
    """An association is kept only when it holds for at least this many consecutive frames."""
    seed: int = 0
    """Seed for anything random in the pipeline."""
    fill_gap: int = 10
    """Frames: a box or hand missing for at most this long is interpolated (the detector missed it)."""
    contain_fraction: float = 0.5
    """An ingredient lies in a container when at least this fraction of its box is inside the container's box
    (among several such containers, the highest Jaccard index wins)."""
    min_share: float = 0.3
    """An object-object link must also last this fraction of its segment (consecutively): a tool passing
    over a board on its way does not act on it."""
    near_fraction: float = 0.02
    """Object-object: a held object acts on objects whose boxes come within this fraction of the image diagonal."""
    dwell_frames: int = 15
    """Object-object: a held object acts on another only while it dwells near it, moving less than
    ``dwell_fraction`` of the image diagonal between this many frames before and after."""
    dwell_fraction: float = 0.05
    """See ``dwell_frames``."""
    hand_share: float = 0.3
    """A held ingredient with nothing near is worked by the hand itself (squeeze) only when the hand verbs
    (squeeze, peel, roll, wrap) together get at least this share of P(A | ingredient)."""
    still_fraction: float = 0.02
    """A hand holding an ingredient with nothing near works it by itself (squeeze) only when it stays put:
    moving less than this fraction of the image diagonal between ``dwell_frames`` before and after, for
    ``min_frames`` consecutive frames; otherwise it only grasps it on the way somewhere."""
    handover_gap: int = 30
    """Frames: a handover's receiver grasps the object at most this long after the giver releases it."""
    handover_overlap: int = 60
    """Frames: two persons holding one object longer than this together is a holding, not a handover."""


@dataclass(frozen=True)
class Analysis:
    """The result of every stage for one video, after corrections."""

    segmentation: Segmentation
    """Segments after the user's splits and merges (``per_hand`` stays GGS's own breakpoints)."""
    associations: tuple[Associations, ...]
    """One per segment, in order (corrected hand-object and object-object links applied)."""
    segment_actions: tuple[SegmentActions, ...]
    """One per segment, in order: each hand's action there and its commonsense ranking."""
    actions: tuple[Action, ...]
    """Merged actions (consecutive compatible segments joined, grasp to release), by start frame; rejected
    segments give none."""
    trees: tuple[TreeSpan, ...]
    """The tree of each of ``actions``, same order."""
    graph: ActionGraph
    corrections: Corrections = field(default_factory=Corrections)
    seconds: Mapping[str, float] = field(default_factory=dict)
    """Wall time of each stage (``segment``, ``associate``, ``actions``, ``graph``), seconds."""

    def segment_index(self, frame: int) -> int | None:
        """Index of the segment holding ``frame``, None outside the video."""
        import bisect

        segments = self.segmentation.segments
        i = bisect.bisect_right([s.start for s in segments], frame) - 1
        if 0 <= i < len(segments) and segments[i].start <= frame < segments[i].end:
            return i
        return None


def apply_cuts(segmentation: Segmentation, corrections: Corrections) -> Segmentation:
    """The segments with the user's splits added and merged breakpoints removed."""
    if not segmentation.segments:
        return segmentation
    start, end = segmentation.segments[0].start, segmentation.segments[-1].end
    cuts = {s.start for s in segmentation.segments[1:]}
    cuts |= {f for f in corrections.splits if start < f < end}
    cuts -= set(corrections.merges)
    edges = [start, *sorted(cuts), end]
    segments = tuple(Segment(a, b) for a, b in itertools.pairwise(edges))
    if segments == segmentation.segments:
        return segmentation
    return Segmentation(segmentation.per_hand, segments, segmentation.interpolated)


def segmentation_params(obs: Observations, params: Params) -> Params:
    """``params`` with ``k_max`` raised to ``k_per_minute`` times the video's length in minutes."""
    import math

    fps = obs.video.fps if obs.video.fps > 0 else 30.0
    minutes = obs.video.frame_count / fps / 60.0
    k_max = max(params.k_max, math.ceil(params.k_per_minute * minutes))
    return params if k_max == params.k_max else replace(params, k_max=k_max)


def analyze(
    obs: Observations,
    knowledge: Knowledge,
    params: Params | None = None,
    corrections: Corrections | None = None,
    *,
    segmentation: Segmentation | None = None,
) -> Analysis:
    """Every stage on one video, with the user's corrections applied.

    ``segmentation``: reuse a segmentation already computed for these observations and ``params`` (the
    workbench does, since corrections never change GGS's own result); otherwise GGS runs.
    """
    from wecook_core.actions import recognize_actions
    from wecook_core.associate import associate_segments
    from wecook_core.graph import build_graph, merge_actions, tree_spans
    from wecook_core.segment import segment_hands

    params = params or Params()
    corrections = corrections or Corrections()
    seconds: dict[str, float] = {}
    clock = time.perf_counter()
    if segmentation is None:
        segmentation = segment_hands(obs, segmentation_params(obs, params))
    segmentation = apply_cuts(segmentation, corrections)
    seconds["segment"] = time.perf_counter() - clock

    clock = time.perf_counter()
    associations, timeline = associate_segments(obs, segmentation.segments, params, corrections)
    seconds["associate"] = time.perf_counter() - clock

    clock = time.perf_counter()
    segment_actions = recognize_actions(obs, segmentation, associations, knowledge, params, corrections, timeline)
    seconds["actions"] = time.perf_counter() - clock

    clock = time.perf_counter()
    rejected = {start for start, status in corrections.status.items() if status is SegmentStatus.REJECTED}
    actions = merge_actions(segment_actions, obs.categories, rejected)
    trees = tree_spans(actions)
    graph = build_graph(actions)
    seconds["graph"] = time.perf_counter() - clock
    return Analysis(segmentation, associations, segment_actions, actions, trees, graph, corrections, seconds)
