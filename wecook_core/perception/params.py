"""Every tunable of the perception pipeline, in one frozen value recorded in a session's ``session.yaml``."""

from __future__ import annotations

from dataclasses import dataclass, field


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
