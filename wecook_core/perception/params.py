"""Every tunable of the perception pipeline, in one frozen value recorded in a session's ``session.yaml``.

Durations are in seconds and sizes in fractions (of the image diagonal, of a box), never frames or pixels, so a
5 fps frame dump and a 60 fps recording are judged alike; :func:`frames` turns a duration into frames of one
video. Old session files that still name frame counts (``min_frames``, ``fill_gap``, ``dwell_frames``,
``handover_gap``, ``handover_overlap``) are read with those keys ignored (with a warning), so the defaults in
seconds apply.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError
from wecook_core.model import HANDS

DEFAULT_FPS = 30.0
"""Frame rate assumed when a video does not say its own."""
DECODE_S = 0.1
"""Seconds per bin of the held-object decoder (:func:`wecook_core.perception.association.holding.held_objects`): a
resolution of the computation, not a tunable."""


def frames(seconds: float, fps: float, least: int = 1) -> int:
    """``seconds`` as a whole number of frames at ``fps`` (at least ``least``)."""
    rate = fps if fps > 0 else DEFAULT_FPS
    return max(least, round(seconds * rate))


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
    min_link_s: float = 0.27
    """Seconds: an association is kept only when it holds this long without a break."""
    seed: int = 0
    """Seed for anything random in the pipeline."""
    smooth_s: float = 0.2
    """Seconds of running median over every box track before motion is read
    (:mod:`~wecook_core.perception.repairs.smoothing`): a detector's jitter is a frame's, motion lasts longer."""
    fill_gap_s: float = 0.34
    """Seconds: a box or hand missing for at most this long is interpolated (the detector missed it)."""
    contain_fraction: float = 0.5
    """An ingredient lies in a container when at least this fraction of its box is inside the container's box
    (among several such containers, the highest Jaccard index wins)."""
    pass_fraction: float = 0.5
    """An ingredient is not in a container it moves across by more than this fraction of the container's
    diagonal over ``dwell_s`` before and after (carried over it on the way somewhere)."""
    min_share: float = 0.3
    """An object-object link must also last this fraction of its segment (consecutively): a tool passing
    over a board on its way does not act on it."""
    near_fraction: float = 0.02
    """Object-object: a held object acts on objects whose boxes come within this fraction of the image diagonal."""
    dwell_s: float = 0.5
    """Seconds: a held object acts on another only while it dwells near it, moving less than
    ``dwell_fraction`` of the image diagonal between this long before and after; also the window over which
    a hand's and an object's motions are compared (:attr:`moving_fraction`)."""
    dwell_fraction: float = 0.05
    """See ``dwell_s``."""
    dwell_own_fraction: float = 0.5
    """A held object also dwells while it moves less than this fraction of its own box's diagonal (see
    ``dwell_s``): working strokes scale with the tool, and a close-up makes everything big."""
    moving_fraction: float = 0.25
    """A hand moves (over ``dwell_s`` before and after a frame) when its centre travels more than this
    fraction of its own box's diagonal; only then does it say which object moves along with it."""
    coherent_fraction: float = 0.5
    """An object moves with a moving hand when its displacement differs from the hand's by less than this
    fraction of the hand's displacement."""
    hold_switch_s: float = 0.3
    """Seconds of contrary motion evidence it takes the held-object smoother to change what a hand holds
    (the hysteresis of :mod:`wecook_core.perception.association.holding`)."""
    hand_share: float = 0.3
    """A held ingredient with nothing near is worked by the hand itself (squeeze) only when the hand verbs
    (squeeze, peel, roll, wrap) together get at least this share of P(A | ingredient), unless the hand stays
    put on it for ``min_action_s`` (then the hand verbs are the only candidates, whatever their share)."""
    still_fraction: float = 0.02
    """A hand holding an ingredient with nothing near works it by itself (squeeze) only when it stays put:
    moving less than this fraction of the image diagonal between ``dwell_s`` before and after, for
    ``min_link_s`` without a break; otherwise it only grasps it on the way somewhere."""
    mover_share: float = 0.5
    """A transfer's mover is a hand that touches the ingredient, or holds what carries it, on at least this
    share of the frames around the ingredient's change of container."""
    handover_gap_s: float = 1.0
    """Seconds: a handover's receiver grasps the object at most this long after the giver releases it."""
    handover_overlap_s: float = 2.0
    """Seconds: two persons holding one object longer than this together is a holding, not a handover."""
    seen_share: float = 0.5
    """A segment whose hands are detected on less than this share of its frames is marked unsure (the
    reviewer should look), and so is one where a hold was inferred from an object's own motion."""
    min_action_s: float = 1.0
    """Seconds: a bare hold (a grasp with no action) shorter than this, next to an action of the same hand,
    is part of that action's reach or release, not a tree, graph node or plan entry of its own."""
    rejoin_s: float = 1.0
    """Seconds: one person's same work with a tool or a hand (same verb, object and targets) broken for at most
    this long, within a shot, is one action (:func:`wecook_core.trees.graph.rejoined`): nobody passes the spoon
    to the other hand and back in the middle of a stir; the break is the detector's."""

    # One meaning each (issue 23): these were read from the parameter named in each docstring, which means
    # something else; their defaults are that parameter's, so the analysis is unchanged.
    moving_cap_fraction: float = 0.05
    """An object moves by itself (:mod:`~wecook_core.perception.repairs.unseen`,
    :mod:`~wecook_core.perception.repairs.occlusion`) when its centre travels more than ``moving_fraction`` of
    its own box's diagonal over ``dwell_s``, or more than this fraction of the image diagonal, whichever is
    less: a big bowl swung over a pan moves by less than a quarter of its own size. (Was ``dwell_fraction``.)"""
    cover_fraction: float = 0.5
    """An object whose box stops being seen is hidden by a detected hand no smaller than it when at least this
    fraction of its box lies in the hand's box: the hand is in front of it
    (:mod:`~wecook_core.perception.repairs.occlusion`). (Was ``contain_fraction``.)"""
    unseen_bridge_s: float = 1.0
    """Seconds: gaps shorter than this between an object's moving, unseen frames are bridged into one hold by
    an unseen hand: a stirring spoon's box does not travel far on every frame
    (:mod:`~wecook_core.perception.repairs.unseen`). (Was ``min_action_s``.)"""
    mover_window_s: float = 0.27
    """Seconds: a transfer's mover is looked for this long before the ingredient's last frame in its old
    container and after its first frame in the new one (``mover_share`` of those frames;
    :mod:`~wecook_core.perception.recognition.transfers`). (Was ``min_link_s``.)"""

    unseen_hand_s: float = 1.0
    """Seconds before and after a hold by an unseen hand in which the hand seen nearest the object is the one
    that moved it (:mod:`wecook_core.perception.repairs.unseen`)."""
    still_gap_s: float = 2.0
    """Seconds: a gap in a hand's detections at most this long, where the hand reappears where it was, is
    filled in: it stayed there (:mod:`~wecook_core.perception.repairs.still_hands`); longer, it may have gone
    and come back."""
    elsewhere_s: float = 0.2
    """Seconds: a hand detected away from an object while the object moves with no hand seen at it, for at
    least this long in all, is somewhere else and is not the unseen hand moving it
    (:mod:`~wecook_core.perception.repairs.unseen`); shorter, it may be a detector's stray box."""

    tool_reach_fraction: float = 0.5
    """A tool whose box stops short of a hand by at most this fraction of the hand's diagonal may be held by it
    (a long handle, a box drawn on the working end), but only where it moves with the hand
    (:func:`wecook_core.perception.association.frame_links.links_of`)."""

    def at(self, fps: float) -> FrameParams:
        """The durations of these parameters in frames of a video at ``fps``."""
        return FrameParams(
            min_frames=frames(self.min_link_s, fps),
            fill_gap=frames(self.fill_gap_s, fps, least=0),
            dwell_frames=frames(self.dwell_s, fps),
            handover_gap=frames(self.handover_gap_s, fps),
            handover_overlap=frames(self.handover_overlap_s, fps),
            min_action_frames=frames(self.min_action_s, fps),
            hold_switch_frames=self.hold_switch_s * (fps if fps > 0 else DEFAULT_FPS),
            decode_step=frames(DECODE_S, fps),
            min_segment=frames(self.min_segment_s, fps),
            rejoin=frames(self.rejoin_s, fps, least=0),
            unseen_bridge=frames(self.unseen_bridge_s, fps),
            unseen_hand=frames(self.unseen_hand_s, fps),
            elsewhere=frames(self.elsewhere_s, fps),
            still_gap=frames(self.still_gap_s, fps, least=0),
            mover_window=frames(self.mover_window_s, fps),
        )


@dataclass(frozen=True)
class FrameParams:
    """:class:`Params`' durations in frames of one video (:meth:`Params.at`); never stored. The pipeline
    converts once per analysis and hands this to every stage (``rate=``); a stage called alone converts
    itself."""

    min_frames: int
    fill_gap: int
    dwell_frames: int
    handover_gap: int
    handover_overlap: int
    min_action_frames: int
    hold_switch_frames: float
    decode_step: int
    """Frames per bin of the held-object decoder (:data:`DECODE_S`)."""
    min_segment: int = 1
    rejoin: int = 0
    unseen_bridge: int = 1
    unseen_hand: int = 1
    elsewhere: int = 1
    still_gap: int = 0
    mover_window: int = 1


MAX_BREAKPOINTS = 1000
"""The most breakpoints per hand ``k_max`` and ``k`` may ask for (GGS's time grows with it)."""
MAX_BREAKPOINTS_PER_MINUTE = 600.0
"""The largest ``k_per_minute`` (ten breakpoints a second)."""
MAX_PARAM_FRAMES = 10**6
"""The largest value of a whole-number parameter."""
_FRACTIONS = frozenset({"contain_fraction", "min_share", "near_fraction", "dwell_fraction", "hand_share",
                        "still_fraction", "dwell_own_fraction", "moving_fraction", "coherent_fraction",
                        "mover_share", "seen_share", "tool_reach_fraction", "moving_cap_fraction", "cover_fraction"})
_UPPER: dict[str, float] = {"k_max": MAX_BREAKPOINTS, "k_per_minute": MAX_BREAKPOINTS_PER_MINUTE,
                            "seed": 2**63 - 1, "lamb": 1e6, "min_segment_s": 3600.0}


def params_from_dict(value: Any, path: str | Path | None = None, place: str = "params",
                     unknown: list[str] | None = None) -> Params:
    """The :class:`Params` of a ``params`` mapping, every value checked (type, sign, upper bound): a bad one is
    an :class:`InputError` at ``params.NAME``. Names that are not parameters are appended to ``unknown``."""
    if value is None:
        return Params()
    if not isinstance(value, Mapping):
        raise InputError(path, f"expected a mapping of parameter -> value, got {type(value).__name__}", place=place)
    known = {f.name: f for f in dataclasses.fields(Params)}
    values: dict[str, Any] = {}
    for name, item in value.items():
        if name not in known:
            if unknown is not None:
                unknown.append(str(name))
            continue
        values[name] = _check_param(str(name), item, path, f"{place}.{name}")
    return Params(**values)


def _check_param(name: str, value: Any, path: str | Path | None, place: str) -> Any:
    default = getattr(Params(), name)
    if name == "k":
        if not isinstance(value, Mapping):
            raise InputError(path, f"expected a mapping of hand -> breakpoints, got {value!r:.60}", place=place)
        for hand, k in value.items():
            if hand not in HANDS:
                raise InputError(path, f"unknown hand {hand!r:.40}, expected one of {' '.join(HANDS)}", place=place)
            if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k <= MAX_BREAKPOINTS:
                raise InputError(path, f"{hand}: expected a whole number of breakpoints from 0 to {MAX_BREAKPOINTS}, "
                                 f"got {k!r:.60}", place=place)
        return dict(value)
    whole = isinstance(default, int)
    if isinstance(value, bool) or not isinstance(value, int | float) or (whole and not isinstance(value, int)):
        raise InputError(path, f"expected {'a whole number' if whole else 'a number'}, got {value!r:.60}",
                         place=place)
    upper = _UPPER.get(name, 1.0 if name in _FRACTIONS else MAX_PARAM_FRAMES if whole else 1e6)
    number = float(value) if not whole else value
    if (not whole and not math.isfinite(number)) or number < 0 or number > upper or (name == "lamb" and number == 0):
        low = "above 0" if name == "lamb" else "from 0"
        raise InputError(path, f"expected a value {low} to {upper:g}, got {value!r:.60}", place=place)
    return value if whole else float(value)
