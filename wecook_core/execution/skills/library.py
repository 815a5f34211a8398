"""The skill library (``wecook_core/assets/skills.yaml``): for each verb, transfer, handover and holding, the primitives
grasp / engage / actuate / place, their Task Space Regions and the actuation motions. Pure data and numpy:
nothing here touches the simulator, so skills are tested without it.

Frames and units are those of :mod:`wecook_core.execution.skills.tsr`; the YAML file documents its own fields.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from wecook_core.errors import InputError
from wecook_core.execution.skills.motions import AXIS_NAMES, MOTIONS
from wecook_core.execution.skills.motions import Waypoint as Waypoint  # re-exported: skills name their motions
from wecook_core.execution.skills.motions import actuation_path as actuation_path
from wecook_core.execution.skills.tsr import TSR
from wecook_core.model import VERBS, Category
from wecook_core.resources import ASSETS_DIR

SKILLS_PATH = ASSETS_DIR / "skills.yaml"
KINDS: tuple[str, ...] = ("tool", "ingredient", "tall", "open_container", "flat_container")
FRAME_RE = re.compile(r"^(object|facing):(tool|ingredient|location|source|object)$|^(meet|drop)$")
EXPR_RE = re.compile(r"^[0-9a-z_.+\-*/(), ]*$")
BOUND_KEYS: tuple[str, ...] = ("x", "y", "z", "roll", "pitch", "yaw")
"""A TSR spec's bounds, in the order of :attr:`TSRSpec.bounds`."""
ROLES: tuple[str, ...] = ("tool", "ingredient", "location", "source")
"""The objects an action names, as skills refer to them."""
Expr = float | str
"""A number, or an arithmetic expression over half extents (``"0.5*t.hx + 0.01"``)."""


@dataclass(frozen=True)
class Half:
    """Half extents of an object, metres."""

    hx: float = 0.0
    hy: float = 0.0
    hz: float = 0.0


def evaluate(expr: Expr, sizes: Mapping[str, Half]) -> float:
    """The value of a number or an expression over ``f t i l`` half extents (missing roles count as zeros)."""
    if isinstance(expr, int | float):
        return float(expr)
    names: dict[str, Any] = {k: sizes.get(k, Half()) for k in ("f", "t", "i", "l")}
    names.update(min=min, max=max)
    return float(eval(expr, {"__builtins__": {}}, names))


@dataclass(frozen=True)
class TSRSpec:
    frame: str
    """``object:<role>``, ``facing:<role>``, ``meet`` or ``drop``."""
    at: tuple[Expr, Expr, Expr]
    """Metres in the frame."""
    axes: tuple[tuple[str, tuple[float, float, float]], ...]
    """Two effector axes (``x``/``y``/``z``) and their directions in the frame."""
    bounds: tuple[tuple[float, float], ...] = ((0.0, 0.0),) * 6
    """x y z (metres), roll pitch yaw (radians)."""
    origin: tuple[Expr, Expr, Expr] = (0.0, 0.0, 0.0)
    """Metres in the frame: where the TSR frame really sits (rotations of the bounds turn about it)."""
    crowded: tuple[tuple[float, float], ...] | None = None
    """A grasp's looser bounds (as ``bounds``, each containing its own), for a crowded table: tried only when a
    neighbour blocked every sample of ``bounds`` (see :meth:`on_a_crowded_table`); None: the same bounds."""

    def on_a_crowded_table(self) -> TSRSpec:
        """The spec with its :attr:`crowded` bounds (itself when it has none)."""
        return self if self.crowded is None else replace(self, bounds=self.crowded, crowded=None)

    @property
    def role(self) -> str | None:
        return self.frame.split(":", 1)[1] if ":" in self.frame else None

    def rotation(self) -> np.ndarray:
        """3x3 effector orientation in the frame, from the two given axes (the first is kept exactly)."""
        (a, va), (b, vb) = self.axes
        u = np.array(va, dtype=float)
        u /= np.linalg.norm(u)
        w = np.array(vb, dtype=float)
        w = w - u * (u @ w)
        w /= np.linalg.norm(w)
        R = np.zeros((3, 3))
        ia, ib = AXIS_NAMES[a], AXIS_NAMES[b]
        ic = 3 - ia - ib
        R[:, ia], R[:, ib] = u, w
        third = np.cross(R[:, (ic + 1) % 3], R[:, (ic + 2) % 3])
        R[:, ic] = third
        return R

    def tsr(self, T0_w: np.ndarray, sizes: Mapping[str, Half]) -> TSR:
        shift = np.eye(4)
        shift[:3, 3] = [evaluate(v, sizes) for v in self.origin]
        T0_w = T0_w @ shift
        Tw_e = np.eye(4)
        Tw_e[:3, :3] = self.rotation()
        Tw_e[:3, 3] = [evaluate(v, sizes) for v in self.at]
        return TSR(T0_w=T0_w, Tw_e=Tw_e, Bw=np.array(self.bounds))


@dataclass(frozen=True)
class Step:
    primitive: str
    """``engage`` or ``actuate`` (grasp and place are added around every skill by the executor)."""
    tsr: TSRSpec | None = None
    motion: str | None = None
    params: Mapping[str, Expr] = field(default_factory=dict)
    contacts: tuple[tuple[str, str], ...] = ()
    """Pairs of roles that touch during the actuation (their collisions are switched off meanwhile); the first
    is the motion's own: its second role is ``f`` in the parameters and the frame the motion's axes face."""
    attach: tuple[str, ...] = ()
    release: tuple[str, ...] = ()

    @property
    def contact(self) -> tuple[str, str] | None:
        """The motion's own contact pair (the first), if any."""
        return self.contacts[0] if self.contacts else None


@dataclass(frozen=True)
class Skill:
    name: str
    carry: str
    """Role of the object the arm grasps first: ``tool`` or ``ingredient``."""
    steps: tuple[Step, ...]


@dataclass(frozen=True)
class SkillLibrary:
    grasps: Mapping[str, tuple[TSRSpec, ...]]
    grip: Mapping[str, Expr]
    skills: Mapping[str, Skill]
    meet: TSRSpec
    drop: TSRSpec
    meet_height: float = 0.32
    approach_distance: float = 0.08
    lift: float = 0.12
    receiver_clearance: float = 0.09
    drop_distance: float = 0.32
    hold_time: float = 0.5


# ------------------------------------------------------------------------------------------- loading


def _bad(path: Path, place: str, message: str) -> InputError:
    return InputError(path, message, place=place)


def _expr(value: Any, path: Path, place: str) -> Expr:
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise _bad(path, place, f"expected a number or an expression, got {value!r}")
    if isinstance(value, str):
        if not EXPR_RE.match(value):
            raise _bad(path, place, f"bad expression {value!r}")
        try:
            evaluate(value, {})
        except Exception as error:
            raise _bad(path, place, f"bad expression {value!r}: {error}") from None
        return value
    return float(value)


def _direction(value: Any, path: Path, place: str) -> tuple[float, float, float]:
    if isinstance(value, str):
        m = re.fullmatch(r"([+-]?)([xyz])", value.strip())
        if not m:
            raise _bad(path, place, f"expected an axis like -z or a vector, got {value!r}")
        v = [0.0, 0.0, 0.0]
        v[AXIS_NAMES[m.group(2)]] = -1.0 if m.group(1) == "-" else 1.0
        return v[0], v[1], v[2]
    if isinstance(value, list) and len(value) == 3 and all(isinstance(x, int | float) for x in value):
        if np.linalg.norm(value) < 1e-9:
            raise _bad(path, place, "zero direction")
        return float(value[0]), float(value[1]), float(value[2])
    raise _bad(path, place, f"expected an axis like -z or a vector [a, b, c], got {value!r}")


def _tsr_spec(data: Any, path: Path, place: str, may_crowd: bool = False) -> TSRSpec:
    """A TSR spec read and checked; ``may_crowd``: it is a grasp's, and may give bounds for a crowded table."""
    if not isinstance(data, dict):
        raise _bad(path, place, "expected a mapping {frame, at, axes, bounds}")
    frame = data.get("frame")
    if not isinstance(frame, str) or not FRAME_RE.match(frame):
        raise _bad(path, f"{place}.frame", f"unknown frame {frame!r}")
    at = data.get("at", [0, 0, 0])
    if not isinstance(at, list) or len(at) != 3:
        raise _bad(path, f"{place}.at", f"expected [x, y, z], got {at!r}")
    axes = data.get("axes")
    if not isinstance(axes, dict) or len(axes) != 2 or not set(axes) <= set(AXIS_NAMES):
        raise _bad(path, f"{place}.axes", f"expected two effector axes such as {{z: -z, y: x}}, got {axes!r}")
    pairs = tuple((str(k), _direction(v, path, f"{place}.axes.{k}")) for k, v in axes.items())
    cross = np.cross(pairs[0][1], pairs[1][1])
    if np.linalg.norm(cross) < 1e-6:
        raise _bad(path, f"{place}.axes", "the two axes are parallel")
    bounds = _bounds(data.get("bounds"), path, f"{place}.bounds")
    crowded = None
    if data.get("crowded") is not None:
        if not may_crowd:
            raise _bad(path, f"{place}.crowded", "only a grasp has bounds for a crowded table")
        crowded = _bounds(data["crowded"], path, f"{place}.crowded")
        for key, (lo, hi), (wide_lo, wide_hi) in zip(BOUND_KEYS, bounds, crowded, strict=True):
            if wide_lo > lo + 1e-12 or wide_hi < hi - 1e-12:
                raise _bad(path, f"{place}.crowded.{key}", "a crowded table's bounds must contain the bounds")
    origin = data.get("origin", [0, 0, 0])
    if not isinstance(origin, list) or len(origin) != 3:
        raise _bad(path, f"{place}.origin", f"expected [x, y, z], got {origin!r}")
    return TSRSpec(frame, tuple(_expr(v, path, f"{place}.at") for v in at),  # type: ignore[arg-type]
                   pairs, bounds, tuple(_expr(v, path, f"{place}.origin") for v in origin),  # type: ignore[arg-type]
                   crowded)


def _bounds(raw: Any, path: Path, place: str) -> tuple[tuple[float, float], ...]:
    """Bounds ``{x: [lo, hi], ..., yaw: [lo, hi]}`` (metres, degrees) as six (low, high) pairs (metres,
    radians); those not given are zero."""
    bounds = [(0.0, 0.0)] * 6
    raw = raw or {}
    if not isinstance(raw, dict):
        raise _bad(path, place, "expected a mapping")
    for key, value in raw.items():
        if key not in BOUND_KEYS:
            raise _bad(path, f"{place}.{key}", f"unknown bound, expected one of {', '.join(BOUND_KEYS)}")
        if not (isinstance(value, list) and len(value) == 2 and all(isinstance(v, int | float) for v in value)
                and value[0] <= value[1]):
            raise _bad(path, f"{place}.{key}", f"expected [low, high], got {value!r}")
        scale = 1.0 if BOUND_KEYS.index(key) < 3 else math.pi / 180
        bounds[BOUND_KEYS.index(key)] = (value[0] * scale, value[1] * scale)
    return tuple(bounds)


def _step(data: Any, path: Path, place: str) -> Step:
    if not isinstance(data, dict) or data.get("primitive") not in ("engage", "actuate"):
        raise _bad(path, place, "expected a step {primitive: engage | actuate, ...}")
    if data["primitive"] == "engage":
        return Step("engage", tsr=_tsr_spec(data.get("tsr"), path, f"{place}.tsr"))
    motion = data.get("motion")
    if motion not in MOTIONS:
        raise _bad(path, f"{place}.motion", f"unknown motion {motion!r}, expected one of {', '.join(MOTIONS)}")
    params: dict[str, Expr] = {}
    for k, v in (data.get("params") or {}).items():
        if k == "axis":  # one axis, or for a tilt a list of axes to choose from in order ("-x": the other way)
            options = v if isinstance(v, list) and motion == "tilt" else [v]
            if not options or any(not isinstance(o, str) or o.lstrip("-") not in AXIS_NAMES for o in options):
                raise _bad(path, f"{place}.params.axis", f"expected x, y or z (a tilt: a list of them), got {v!r}")
            params[k] = options[0] if len(options) == 1 else ",".join(options)
        else:
            params[str(k)] = _expr(v, path, f"{place}.params.{k}")
    contact = data.get("contact") or []
    pairs = contact if contact and all(isinstance(c, list) for c in contact) else [contact] if contact else []
    for k, pair in enumerate(pairs):
        if not (isinstance(pair, list) and len(pair) == 2 and all(r in ROLES for r in pair)):
            raise _bad(path, f"{place}.contact" + (f"[{k}]" if len(pairs) > 1 else ""),
                       f"expected two roles of {', '.join(ROLES)} (or a list of such pairs), got {pair!r}")
    return Step("actuate", motion=motion, params=params, contacts=tuple((a, b) for a, b in pairs),
                attach=tuple(data.get("attach") or ()), release=tuple(data.get("release") or ()))


def load_skills(path: str | Path = SKILLS_PATH) -> SkillLibrary:
    """Read and check the skill library; problems raise :class:`InputError` naming the place."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise InputError(path, f"cannot read the skill library ({error})") from None
    if not isinstance(data, dict):
        raise _bad(path, "top", "expected a mapping")
    grasps = {}
    for kind in (*KINDS, "hold_rim", "hold_flat"):
        specs = (data.get("grasps") or {}).get(kind)
        if not specs:
            raise _bad(path, f"grasps.{kind}", "missing")
        grasps[kind] = tuple(_tsr_spec(s, path, f"grasps.{kind}[{k}]", may_crowd=True) for k, s in enumerate(specs))
    grip = {kind: _expr((data.get("grip") or {}).get(kind, 0.0), path, f"grip.{kind}") for kind in KINDS}
    skills = {}
    for name, raw in (data.get("verbs") or {}).items():
        if not isinstance(raw, dict) or raw.get("carry") not in ("tool", "ingredient"):
            raise _bad(path, f"verbs.{name}.carry", "expected tool or ingredient")
        steps = tuple(_step(s, path, f"verbs.{name}.steps[{k}]") for k, s in enumerate(raw.get("steps") or []))
        skills[name] = Skill(name, raw["carry"], steps)
    missing = [v for v in (*VERBS, "transfer_tipping", "transfer_by_hand") if v not in skills]
    if missing:
        raise _bad(path, "verbs", f"no skill for {', '.join(missing)}")
    collab = data.get("collaborations") or {}
    handover = collab.get("handover") or {}
    return SkillLibrary(
        grasps=grasps, grip=grip, skills=skills,
        meet=_tsr_spec(handover.get("meet"), path, "collaborations.handover.meet"),
        drop=_tsr_spec(handover.get("drop"), path, "collaborations.handover.drop"),
        meet_height=float(data.get("meet_height", 0.32)), approach_distance=float(data.get("approach_distance", 0.08)),
        lift=float(data.get("lift", 0.12)), receiver_clearance=float(handover.get("receiver_clearance", 0.09)),
        drop_distance=float(handover.get("drop_distance", 0.32)),
        hold_time=float((collab.get("holding") or {}).get("hold_time", 0.5)))


# ------------------------------------------------------------------------------------- choosing skills


def object_kind(category: Category, size: Sequence[float], open_top: bool) -> str:
    """Which grasp an object gets."""
    if category is Category.TOOL:
        return "tool"
    if category is Category.CONTAINER:
        return "open_container" if open_top else "flat_container"
    return "tall" if size[2] > 0.08 else "ingredient"


def skill_name(verb: str, tool: str | None, tool_category: Category | None) -> str:
    """The skill of an individual action: the verb's, except transfers by tipping a container or by hand."""
    if verb == "transfer":
        if tool is None:
            return "transfer_by_hand"
        if tool_category is Category.CONTAINER:
            return "transfer_tipping"
    return verb
