"""Which arm a detected hand is on: each hand given to a body's wrist, and that arm's side, from the skeleton.

The paper names hands from OpenPose's bodies: a hand belongs to the person and the side of the arm it ends. A
pose model (MediaPipe's, see :mod:`wecook_core.observations.pose_detect`) gives per frame each body's shoulders,
elbows and wrists; a hand detector gives hands with no person and a handedness guess. The rules, each physical:

1. **a hand is on the arm whose wrist it is next to**: a hand's centre lies about half a hand from its wrist, so
   a hand and a wrist within ``wrist_gate`` hand sizes (the hand box's diagonal) may go together, and the
   pairing of a frame's hands and wrists is the one of least total distance (each wrist ends one hand); a wrist
   the model itself sees less than ``min_visibility`` is no evidence (on top-down footage the model guesses
   arms it cannot see: on tasty-a it reports a body in 245 of 269 frames with only the arms in view, its
   wrists often a hand or more from any hand);
2. **an arm's side comes from where the body faces, not from the model's left and right labels**: the hands
   work in front of the body, so the body faces from its shoulders' midpoint towards its wrists' midpoint, and
   looking that way the right shoulder is on the right. In image coordinates (x right, y down) for a body seen
   from above or from the front, the right of a facing ``f`` is ``(-f_y, f_x)``: a cook filmed from above whose
   arms enter from the bottom edge has their right arm on the image's right, a cook facing the camera with the
   hands below the shoulders has it on the image's left. The pose model's labels assume a body seen from the
   front; on tasty-a (top-down, arms from the bottom edge) they gave 20 of the 21 hands on a well-seen wrist
   the other side than tasty-a's hands.csv, this rule 6 of 21. The hands themselves tell it better where the
   hand detector gives their landmarks: a working hand points away from its body (wrist to knuckles), so the
   body faces the way its hands point, when they agree (their mean unit vector at least ``min_pointing``
   long); the wrists' place is then not needed. On top-down footage with only the forearms in view the
   model places shoulders at the wrists or the wrists beyond the frame's edge, as a body facing the camera
   (kfc-b: both hands shown on 159 frames, and the model's labels named them the mirror way on all of them).
   Without the hands' pointing the facing is read from the wrists, when the model sees both and they lie at
   least ``min_facing`` shoulder widths in front of the shoulders. Only when neither tells, or the shoulders are
   seen edge-on (under ``min_shoulder_width`` of the frame diagonal apart), are the model's labels kept;
3. **an arm is longer than its hand**: upper arm and forearm (about 0.3 and 0.26 m) are each longer than a
   hand (about 0.19 m), so a shoulder-elbow-wrist path under ``min_arm`` hand sizes, even allowing for an arm
   pointing at the camera, is no arm but a body the model imagined in the hand itself (it does so in a video
   of two hand photos on a plain background: a "body" with shoulders 11 px apart inside a 100 px hand);
4. the arm's evidence weighs as much as the model sees its wrist (its visibility, 0-1); MediaPipe's handedness
   is left to :mod:`wecook_core.observations.hand_assign` as the tie-breaker of hands no arm claims.

Pure: landmark arrays in (a frozen :class:`Skeleton` per body and frame), hands with an :class:`ArmHint` out.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy.optimize import linear_sum_assignment

JOINTS = ("left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist")
"""The joints a :class:`Skeleton` holds, in this order; left and right as the pose model labels them."""
L_SHOULDER, R_SHOULDER, L_ELBOW, R_ELBOW, L_WRIST, R_WRIST = range(6)


class Hand(Protocol):
    """What is read of a detected hand (:class:`~.hand_assign.HandDetection` is one)."""

    @property
    def xy(self) -> tuple[float, float]: ...

    @property
    def box(self) -> tuple[float, float, float, float]: ...

    @property
    def pointing(self) -> tuple[float, float] | None: ...


@dataclass(frozen=True, eq=False)
class Skeleton:
    """One body in one frame: the pose model's arm joints."""

    frame: int
    joints: np.ndarray
    """(6, 2) pixels, in :data:`JOINTS` order; may lie outside the image (a shoulder beyond the edge)."""
    visibility: np.ndarray
    """(6,) the model's belief, 0-1, that each joint is in view."""

    def __post_init__(self) -> None:
        if np.shape(self.joints) != (6, 2) or np.shape(self.visibility) != (6,):
            raise ValueError(f"a skeleton needs (6, 2) joints and (6,) visibilities, got "
                             f"{np.shape(self.joints)} and {np.shape(self.visibility)}")

    @property
    def shoulder_centre(self) -> tuple[float, float]:
        x, y = (self.joints[L_SHOULDER] + self.joints[R_SHOULDER]) / 2
        return float(x), float(y)


@dataclass(frozen=True)
class ArmHint:
    """The arm a hand was found on."""

    side: str
    """``RH`` or ``LH``: the person's right or left."""
    weight: float
    """How much the pose model sees the wrist, 0-1."""
    body: tuple[float, float]
    """The body's shoulder centre, pixels: where the person is (for telling persons apart)."""


@dataclass(frozen=True)
class BodyParams:
    wrist_gate: float = 0.5
    """A hand goes with a wrist at most this many hand sizes (its box diagonal) from its centre: about where a
    hand's centre lies from its own wrist."""
    min_visibility: float = 0.8
    """A wrist the model sees less than this is no evidence (tasty-a, before the arm-length rule: at 0.5, 39
    of 62 hands on a wrist got hands.csv's side; at 0.8, 18 of 26)."""
    min_arm: float = 1.0
    """The shoulder-elbow-wrist path must be at least this many sizes of the hand it ends."""
    min_facing: float = 0.25
    """The wrists' midpoint must lie at least this many shoulder widths in front of the shoulders for the body's
    facing (and so its sides) to be read from them."""
    min_shoulder_width: float = 0.02
    """Shoulders closer than this fraction of the frame diagonal are seen edge-on: their order tells no side."""
    min_pointing: float = 0.5
    """The hands' mean pointing (unit vectors wrist to knuckles) must be at least this long to give the body's
    facing (rule 2): 0.5 is two hands at most 120 degrees apart."""


def arm_sides(skeleton: Skeleton, diagonal: float, params: BodyParams, mirrored: bool = False,
              pointing: np.ndarray | None = None) -> tuple[str, str]:
    """The person's side (``RH``/``LH``) of the arm ending at the model's left wrist and of the one ending at
    its right wrist (rule 2 of the module); in a ``mirrored`` video (a selfie camera) every side swaps.
    ``pointing``: the mean unit pointing vector of the hands at this body's wrists, None when unknown."""
    joints = skeleton.joints
    centre = (joints[L_SHOULDER] + joints[R_SHOULDER]) / 2
    across = joints[R_SHOULDER] - joints[L_SHOULDER]
    facing = (joints[L_WRIST] + joints[R_WRIST]) / 2 - centre
    width = float(np.hypot(*across))
    model_right_is_right = True
    if width >= params.min_shoulder_width * diagonal:
        wrists_seen = bool((skeleton.visibility[[L_WRIST, R_WRIST]] >= params.min_visibility).all())
        if pointing is not None and float(np.hypot(*pointing)) >= params.min_pointing:
            facing = np.asarray(pointing)
        elif not wrists_seen or float(np.hypot(*facing)) < params.min_facing * width:
            facing = None
        if facing is not None:
            right = np.array([-facing[1], facing[0]])
            model_right_is_right = float(np.dot(across, right)) > 0
    if mirrored:
        model_right_is_right = not model_right_is_right
    return ("LH", "RH") if model_right_is_right else ("RH", "LH")


def _pointing_at(hands: Sequence[Hand], skeleton: Skeleton, params: BodyParams) -> np.ndarray | None:
    """The mean unit pointing vector of the hands whose centre lies within ``wrist_gate`` hand sizes of one of
    the body's wrists (rule 1's gate, whatever the wrist's visibility), None when none is known."""
    found = []
    for hand in hands:
        if hand.pointing is None:
            continue
        x1, y1, x2, y2 = hand.box
        extent = float(np.hypot(x2 - x1, y2 - y1))
        for wrist in (skeleton.joints[L_WRIST], skeleton.joints[R_WRIST]):
            if float(np.hypot(hand.xy[0] - wrist[0], hand.xy[1] - wrist[1])) <= params.wrist_gate * extent:
                found.append(hand.pointing)
                break
    return np.mean(np.asarray(found, dtype=np.float64), axis=0) if found else None


def hint_hands(hands: Sequence[Hand], skeletons: Sequence[Skeleton], size: tuple[int, int],
               params: BodyParams, mirrored: bool = False) -> list[ArmHint | None]:
    """For each of one frame's hands, in order, the :class:`ArmHint` of the arm it ends, or None (rule 1);
    ``size`` is the frame's (width, height) pixels."""
    diagonal = float(np.hypot(*size))
    arms: list[tuple[np.ndarray, float, ArmHint]] = []
    for skeleton in skeletons:
        sides = arm_sides(skeleton, diagonal, params, mirrored, _pointing_at(hands, skeleton, params))
        j = skeleton.joints
        for (shoulder, elbow, wrist), side in (((L_SHOULDER, L_ELBOW, L_WRIST), sides[0]),
                                               ((R_SHOULDER, R_ELBOW, R_WRIST), sides[1])):
            seen = float(skeleton.visibility[wrist])
            length = float(np.hypot(*(j[elbow] - j[shoulder])) + np.hypot(*(j[wrist] - j[elbow])))
            if seen >= params.min_visibility:
                arms.append((j[wrist], length, ArmHint(side, seen, skeleton.shoulder_centre)))
    out: list[ArmHint | None] = [None] * len(hands)
    if not arms or not hands:
        return out
    cost = np.full((len(hands), len(arms)), np.inf)
    for i, hand in enumerate(hands):
        x1, y1, x2, y2 = hand.box
        extent = float(np.hypot(x2 - x1, y2 - y1))
        for k, (joint, length, _) in enumerate(arms):
            distance = float(np.hypot(hand.xy[0] - joint[0], hand.xy[1] - joint[1]))
            if distance <= params.wrist_gate * extent and length >= params.min_arm * extent:
                cost[i, k] = distance
    finite = np.where(np.isfinite(cost), cost, 1e12)
    rows, cols = linear_sum_assignment(finite)
    for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
        if np.isfinite(cost[i, j]):
            out[i] = arms[j][2]
    return out
