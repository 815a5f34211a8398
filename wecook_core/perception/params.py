"""Every tunable of the perception pipeline, in one frozen value recorded in a session's ``session.yaml``."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError
from wecook_core.model import HANDS


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


MAX_BREAKPOINTS = 1000
"""The most breakpoints per hand ``k_max`` and ``k`` may ask for (GGS's time grows with it)."""
MAX_BREAKPOINTS_PER_MINUTE = 600.0
"""The largest ``k_per_minute`` (ten breakpoints a second)."""
MAX_PARAM_FRAMES = 10**6
"""The largest value of a parameter counted in frames."""
_FRACTIONS = frozenset({"contain_fraction", "min_share", "near_fraction", "dwell_fraction", "hand_share",
                        "still_fraction"})
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
