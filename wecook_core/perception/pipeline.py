"""The whole perception pipeline as one pure function: observations + corrections -> trees and graph.

Each stage lives in its own module; this one only chains them and applies the user's corrections:
segment (:mod:`wecook_core.perception.segmentation`, GGS on the hands, plus cuts at the video's shot cuts,
:mod:`wecook_core.perception.segmentation.shots`, and where objects start and stop moving in hands the detector does not
see, :mod:`wecook_core.perception.repairs.unseen`; objects hidden by the hand that carries them are carried on with it
first, :mod:`wecook_core.perception.repairs.occlusion`) -> associate
(:mod:`wecook_core.perception.association.associate`, what each
hand holds decoded by :mod:`wecook_core.perception.association.holding`) -> actions
(:mod:`wecook_core.perception.recognition.actions`,
with the held object's own motion, :mod:`wecook_core.perception.recognition.motion`) -> merged trees and graph
(:mod:`wecook_core.trees.graph`). Segments whose evidence is thin are marked unsure with the reason
(:attr:`Analysis.unsure`), and bare holds there are not emitted.
"""

from __future__ import annotations

import bisect
import itertools
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from wecook_core.model import (
    Action,
    ActionGraph,
    ActionKind,
    Associations,
    Corrections,
    Observations,
    Segment,
    Segmentation,
    SegmentStatus,
    TreeSpan,
)
from wecook_core.perception.association.frame_links import UnseenHold
from wecook_core.perception.params import DEFAULT_FPS, FrameParams, Params, frames

if TYPE_CHECKING:
    from wecook_core.knowledge.recognize import Knowledge
    from wecook_core.model import SegmentActions


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
    shots: tuple[int, ...] = ()
    """First frames of the video's shots after the first (:mod:`wecook_core.perception.segmentation.shots`): segments
    end
    there."""
    unseen: tuple[UnseenHold, ...] = ()
    """Objects moved by hands the detector did not see (:mod:`wecook_core.perception.repairs.unseen`)."""
    unsure: Mapping[int, str] = field(default_factory=dict)
    """Segment start -> why the evidence there is too thin to trust what was recognised (for the reviewer):
    the hands are seen on too few of its frames, or what a hand holds was inferred from the object's own
    motion."""
    observations: Observations | None = None
    """The observations the stages read: the input's, with the boxes of objects hidden by the hand carrying them
    carried on (:mod:`wecook_core.perception.repairs.occlusion`), for the workbench to show."""

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


def with_cuts(segmentation: Segmentation, cuts: Sequence[int], least: int) -> Segmentation:
    """The segments also cut at ``cuts`` (shot cuts, starts and ends of unseen holds), each skipped when
    within ``least`` frames of an existing edge (no sliver segments)."""
    if not segmentation.segments or not cuts:
        return segmentation
    start, end = segmentation.segments[0].start, segmentation.segments[-1].end
    edges = sorted({start, end, *(s.start for s in segmentation.segments[1:])})
    for cut in sorted(set(cuts)):
        if not start < cut < end:
            continue
        i = bisect.bisect_left(edges, cut)
        if min(abs(cut - edges[i - 1]), abs(edges[i] - cut) if i < len(edges) else least) >= least:
            edges.insert(i, cut)
    segments = tuple(Segment(a, b) for a, b in itertools.pairwise(edges))
    if segments == segmentation.segments:
        return segmentation
    return Segmentation(segmentation.per_hand, segments, segmentation.interpolated)


def final_segments(segmentation: Segmentation, shots: Sequence[int], unseen: Sequence[UnseenHold],
                   params: Params, fps: float, corrections: Corrections) -> Segmentation:
    """Every cut the analysis makes, in one place: GGS's ``segmentation`` also cut at the shot cuts and at the
    starts and ends of holds by unseen hands (each skipped within ``params.min_segment_s`` of an edge), then the
    user's splits added and merges removed. The segments every stage, and every span correction, works on."""
    extra = [*shots, *(f for hold in unseen for f in (hold.start, hold.end))]
    return apply_cuts(with_cuts(segmentation, extra, frames(params.min_segment_s, fps)), corrections)


@dataclass(frozen=True)
class Repaired:
    """The observations as the stages read them, and the cuts the video itself makes."""

    observations: Observations
    """With the boxes of objects hidden by the hand carrying them carried on with it
    (:mod:`wecook_core.perception.repairs.occlusion`)."""
    shots: tuple[int, ...]
    unseen: tuple[UnseenHold, ...]


def repaired(obs: Observations, params: Params, shots: Sequence[int] = (), *, rate: FrameParams | None = None,
             ) -> Repaired:
    """``obs`` repaired where real observations miss (:mod:`wecook_core.perception.repairs`), with the shot cuts
    and the holds of hands the detector did not see."""
    from wecook_core.perception.repairs.occlusion import hidden_by_hands
    from wecook_core.perception.repairs.smoothing import smoothed
    from wecook_core.perception.repairs.still_hands import with_still_hands
    from wecook_core.perception.repairs.unseen import unseen_holds
    from wecook_core.perception.segmentation.hands import GLITCH_FRAMES

    cuts = tuple(sorted(set(shots)))
    rate = rate or params.at(obs.video.fps)
    # the running median spans the detector's glitches (GLITCH_FRAMES, as for the segmentation's hand series),
    # never more than smooth_s of time: at 5 fps five frames are a second of real motion
    half = min(GLITCH_FRAMES // 2, frames(params.smooth_s / 2, obs.video.fps, least=0))
    still = with_still_hands(smoothed(obs, half), params, cuts, rate=rate)
    fixed = hidden_by_hands(still, params, cuts, rate=rate)
    return Repaired(fixed, cuts, tuple(unseen_holds(fixed, params, cuts, rate=rate)))


def unsure_segments(obs: Observations, segments: Sequence[Segment], unseen: Sequence[UnseenHold],
                    seen_share: float) -> dict[int, str]:
    """Segment start -> the reason its evidence is thin: its hands are detected on less than ``seen_share``
    of its frames while something moves, or a hold in it was inferred from an object's own motion."""
    import numpy as np

    seen = np.zeros(max(obs.video.frame_count, max((s.end for s in segments), default=0)), dtype=bool)
    for track in obs.hands:
        frames = track.frames[(track.frames >= 0) & (track.frames < len(seen))]
        seen[frames] = True
    reasons: dict[int, str] = {}
    for segment in segments:
        inferred = sorted({h.obj for h in unseen if h.start < segment.end and segment.start < h.end})
        share = float(seen[segment.start : segment.end].mean()) if len(segment) else 0.0
        parts = []
        if share < seen_share:
            parts.append(f"hands seen on {share:.0%} of its frames")
        if inferred:
            parts.append(f"held by a hand not seen, from the motion of {', '.join(inferred)}")
        if parts and (inferred or share < seen_share):
            reasons[segment.start] = "; ".join(parts)
    return reasons


def _without_thin_holds(actions: Sequence[Action], segments: Sequence[Segment], unsure: Mapping[int, str],
                        ) -> tuple[Action, ...]:
    """``actions`` without the bare holds that lie mostly in unsure segments: where the evidence is too thin,
    the segment says so (``Analysis.unsure``) instead of a hold standing in for an action."""
    if not unsure:
        return tuple(actions)
    thin = [s for s in segments if s.start in unsure]

    def covered(action: Action) -> int:
        return sum(max(0, min(s.end, action.end) - max(s.start, action.start)) for s in thin)

    return tuple(a for a in actions
                 if a.kind is not ActionKind.GRASP or 2 * covered(a) < a.end - a.start)


def segmentation_params(obs: Observations, params: Params) -> Params:
    """``params`` with ``k_max`` raised to ``k_per_minute`` times the video's length in minutes."""
    import math

    fps = obs.video.fps if obs.video.fps > 0 else DEFAULT_FPS
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
    shots: Sequence[int] = (),
    repairs: Repaired | None = None,
) -> Analysis:
    """Every stage on one video, with the user's corrections applied.

    ``segmentation``: reuse a segmentation already computed for these observations and ``params`` (the
    workbench does, since corrections never change GGS's own result); otherwise GGS runs.
    ``shots``: the video's shot cuts (:func:`wecook_core.perception.segmentation.shots.shot_cuts`, which reads the
    video;
    the caller decides whether that is worth it): segments end there, and no motion is read across them.
    Segments also end where an object starts or stops being moved by a hand the detector does not see
    (:mod:`wecook_core.perception.repairs.unseen`). ``repairs``: :func:`repaired` already computed for these
    observations, ``params`` and ``shots`` (then ``shots`` is not read): span corrections must be folded against
    :func:`final_segments` of it, which this makes again.
    """
    from wecook_core.perception.association.associate import associate_segments
    from wecook_core.perception.recognition.actions import recognize_actions
    from wecook_core.perception.segmentation import segment_hands
    from wecook_core.trees.graph import build_graph, merge_actions, tree_spans

    params = params or Params()
    corrections = corrections or Corrections()
    seconds: dict[str, float] = {}
    rate = params.at(obs.video.fps)  # every duration in frames, once per analysis, handed to every stage
    clock = time.perf_counter()
    if segmentation is None:
        segmentation = segment_hands(obs, segmentation_params(obs, params))
    if repairs is None:
        repairs = repaired(obs, params, shots, rate=rate)
    detected = obs  # what the detector saw: a hand filled in across a gap (R0b) is inferred, not seen
    obs, shots, unseen = repairs.observations, repairs.shots, repairs.unseen
    segmentation = final_segments(segmentation, shots, unseen, params, obs.video.fps, corrections)
    seconds["segment"] = time.perf_counter() - clock

    clock = time.perf_counter()
    associations, timeline = associate_segments(obs, segmentation.segments, params, corrections,
                                                shots=shots, unseen=unseen, rate=rate)
    seconds["associate"] = time.perf_counter() - clock

    clock = time.perf_counter()
    segment_actions = recognize_actions(obs, segmentation, associations, knowledge, params, corrections, timeline,
                                        rate=rate)
    seconds["actions"] = time.perf_counter() - clock

    clock = time.perf_counter()
    rejected = {start for start, status in corrections.status.items() if status is SegmentStatus.REJECTED}
    actions = merge_actions(segment_actions, obs.categories, rejected,
                            min_hold=rate.min_action_frames, rejoin=rate.rejoin, shots=shots)
    unsure = unsure_segments(detected, segmentation.segments, unseen, params.seen_share)
    actions = _without_thin_holds(actions, segmentation.segments, unsure)
    trees = tree_spans(actions)
    graph = build_graph(actions)
    seconds["graph"] = time.perf_counter() - clock
    return Analysis(segmentation, associations, segment_actions, actions, trees, graph, corrections, seconds,
                    shots, unseen, unsure, obs)
