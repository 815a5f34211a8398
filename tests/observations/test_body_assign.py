"""Hands named by the arm they end, on synthetic skeletons (no model runs here): two people side by side, a
cook filmed from above with the arms entering from the bottom edge, crossing hands, two people across a table.
Each case gives the hands a handedness that is wrong or says nothing, so only the body can name them; each
also shows what the names were by position and handedness alone (the old code)."""

from __future__ import annotations

import numpy as np
import pytest

from wecook_core.observations.body_assign import BodyParams, Skeleton, arm_sides, hint_hands
from wecook_core.observations.hand_assign import AssignParams, HandDetection, assign_hands

FPS = 10.0
SIZE = (640, 480)
DIAGONAL = float(np.hypot(*SIZE))
Point = tuple[float, float]


def skeleton(frame: int, shoulders: tuple[Point, Point], elbows: tuple[Point, Point], wrists: tuple[Point, Point],
             seen: float = 0.9) -> Skeleton:
    """Joints given as (the model's left, the model's right)."""
    joints = np.array([shoulders[0], shoulders[1], elbows[0], elbows[1], wrists[0], wrists[1]], dtype=float)
    return Skeleton(frame, joints, np.full(6, seen))


def hand(frame: int, xy: Point, label: str = "Left", half: float = 25.0,
         pointing: Point | None = None) -> HandDetection:
    x, y = xy
    return HandDetection(frame, label, 0.9, (x, y), (x - half, y - half, x + half, y + half), pointing=pointing)


def centres(tracks) -> dict[str, tuple[float, float]]:
    return {t.hand: (float(t.xy[:, 0].mean()), float(t.xy[:, 1].mean())) for t in tracks}


def near(a: Point, b: Point, tolerance: float = 30.0) -> bool:
    return bool(np.hypot(a[0] - b[0], a[1] - b[1]) < tolerance)


def test_the_facing_decides_the_side_not_the_models_labels() -> None:
    params = BodyParams()
    # Facing the camera, hands below the shoulders: the right shoulder is on the image's left.
    front = skeleton(0, ((400, 100), (240, 100)), ((420, 200), (220, 200)), ((380, 300), (260, 300)))
    assert arm_sides(front, DIAGONAL, params) == ("LH", "RH")
    # Seen from above, arms entering from the bottom edge, the model labelling as for a front view (as it does
    # on top-down footage): its "right" shoulder, on the image's left, is the person's left.
    above = skeleton(0, ((400, 500), (240, 500)), ((420, 380), (220, 380)), ((380, 250), (260, 250)))
    assert arm_sides(above, DIAGONAL, params) == ("RH", "LH")
    assert arm_sides(above, DIAGONAL, params, mirrored=True) == ("LH", "RH")
    # Wrists level with the shoulders: no facing to read, the model's labels stay.
    level = skeleton(0, ((400, 100), (240, 100)), ((450, 100), (190, 100)), ((500, 102), (140, 102)))
    assert arm_sides(level, DIAGONAL, params) == ("LH", "RH")
    with pytest.raises(ValueError, match="6, 2"):
        Skeleton(0, np.zeros((5, 2)), np.zeros(6))


def test_a_hand_is_given_only_to_a_wrist_it_is_next_to_and_the_model_sees() -> None:
    body = skeleton(0, ((400, 100), (240, 100)), ((420, 200), (220, 200)), ((380, 300), (260, 300)))
    hands = [hand(0, (262, 318)), hand(0, (560, 300))]  # the second is 180 px from any wrist
    hinted = hint_hands(hands, [body], SIZE, BodyParams())
    assert hinted[0] is not None and hinted[0].side == "RH" and hinted[1] is None
    assert hinted[0].body == (320.0, 100.0)
    unseen = skeleton(0, ((400, 100), (240, 100)), ((420, 200), (220, 200)), ((380, 300), (260, 300)), seen=0.3)
    assert hint_hands(hands, [unseen], SIZE, BodyParams()) == [None, None]
    # A "body" imagined inside the hand (shoulders, elbows, wrists all within it): its arm is shorter than the
    # hand, so it is no arm.
    tiny = skeleton(0, ((265, 330), (255, 332)), ((266, 318), (258, 320)), ((264, 310), (259, 309)))
    assert hint_hands(hands[:1], [tiny], SIZE, BodyParams()) == [None]
    # Two hands by one wrist: only the nearer ends it.
    pair = hint_hands([hand(0, (250, 300)), hand(0, (275, 310))], [body], SIZE, BodyParams())
    assert pair[0] is not None and pair[1] is None


def test_two_people_side_by_side_one_reaching_across() -> None:
    # Both face the camera. P1's right hand (image left of P1's body) stays home; P1's left hand reaches past
    # the middle into P2's half, where P2's own hands are; every handedness says "Left".
    frames, skeletons = [], {}
    for f in range(20):
        p1 = skeleton(f, ((230, 120), (110, 120)), ((250, 220), (90, 220)), ((370, 330), (100, 330)))
        p2 = skeleton(f, ((530, 120), (410, 120)), ((550, 220), (390, 220)), ((560, 320), (430, 320)))
        skeletons[f] = [p1, p2]
        frames.append([hand(f, (100, 345)), hand(f, (372, 345)), hand(f, (432, 338)), hand(f, (562, 338))])
    tracks, _ = assign_hands(frames, FPS, SIZE, skeletons=skeletons)
    got = centres(tracks)
    assert set(got) == {"RH_P1", "LH_P1", "RH_P2", "LH_P2"}
    assert near(got["RH_P1"], (100, 345)) and near(got["LH_P1"], (372, 345))
    assert near(got["RH_P2"], (432, 338)) and near(got["LH_P2"], (562, 338))
    old, _ = assign_hands(frames, FPS, SIZE)
    assert not near(centres(old).get("LH_P1", (0, 0)), (372, 345))  # by position it was P2's


def test_a_cook_filmed_from_above_with_the_arms_from_the_bottom_edge() -> None:
    # Shoulders below the frame; the model labels as for a front view; the hands' handedness is wrong too
    # (the hand on the image's right reported as the person's left).
    frames, skeletons = [], {}
    for f in range(15):
        dx = 3.0 * f
        skeletons[f] = [skeleton(f, ((420, 540), (220, 540)), ((460, 420), (180, 420)),
                                 ((400 + dx, 260), (240 - dx, 260)))]
        frames.append([hand(f, (405 + dx, 235), "Right"), hand(f, (235 - dx, 235), "Left")])
    tracks, _ = assign_hands(frames, FPS, SIZE, skeletons=skeletons)
    got = centres(tracks)
    assert set(got) == {"RH_P1", "LH_P1"}
    assert got["RH_P1"][0] > 320 and got["LH_P1"][0] < 320
    old, _ = assign_hands(frames, FPS, SIZE)
    assert centres(old)["RH_P1"][0] < 320


def test_a_body_imagined_facing_the_camera_over_forearms_from_the_bottom_edge_is_faced_by_its_hands() -> None:
    # As the pose model does on top-down footage with only the forearms in view (kfc-b): shoulders placed
    # mid-frame as for a body facing the camera (its "left" shoulder on the image's right) and wrists either
    # at the shoulders or guessed beyond the bottom edge, unseen. The hands point up, away from the cook at the
    # bottom edge: the hand on the image's right is the cook's right. The handedness says nothing.
    up = (0.0, -1.0)
    for wrists, seen in ((((400, 262), (240, 262)), 0.9), (((400, 560), (240, 560)), 0.1)):
        frames, skeletons = [], {}
        for f in range(15):
            body = skeleton(f, ((400, 250), (240, 250)), ((420, 400), (220, 400)), wrists)
            body = Skeleton(f, body.joints, np.array([0.95, 0.95, 0.6, 0.6, seen, seen]))
            skeletons[f] = [body]
            frames.append([hand(f, (400, 240), "Left", pointing=up), hand(f, (240, 240), "Left", pointing=up)])
        tracks, _ = assign_hands(frames, FPS, SIZE, skeletons=skeletons)
        got = centres(tracks)
        assert got["RH_P1"][0] > 320 and got["LH_P1"][0] < 320, wrists
    # Without the hands' pointing (the old code) the model's labels named them the mirror way.
    plain = [[hand(f, (400, 240)), hand(f, (240, 240))] for f in range(15)]
    old, _ = assign_hands(plain, FPS, SIZE, skeletons={f: [skeleton(f, ((400, 250), (240, 250)),
                                                                     ((420, 400), (220, 400)),
                                                                     ((400, 262), (240, 262)))]
                                                       for f in range(15)})
    assert centres(old)["RH_P1"][0] < 320


def test_hands_pointing_opposite_ways_tell_no_facing() -> None:
    # A cook facing the camera, the hands pointing at each other (kneading): their mean pointing is short, so
    # the wrists (seen, below the shoulders) give the facing: the right shoulder is on the image's left.
    body = skeleton(0, ((400, 100), (240, 100)), ((420, 200), (220, 200)), ((380, 300), (260, 300)))
    hands = [hand(0, (262, 318), pointing=(1.0, 0.0)), hand(0, (378, 318), pointing=(-1.0, 0.0))]
    hinted = hint_hands(hands, [body], SIZE, BodyParams())
    assert [h.side if h else None for h in hinted] == ["RH", "LH"]


def test_crossing_hands_stay_on_their_arms() -> None:
    # From above, the right hand passes over the left one and back; the detector says "Left" for both, so
    # the handedness keeps nothing apart; the wrists do.
    frames, skeletons = [], {}
    for f in range(30):
        t = np.sin(np.pi * f / 29)  # 0 -> 1 -> 0
        right = (420 - 260 * t, 250 - 10 * t)
        left = (220 + 60 * t, 270)
        skeletons[f] = [skeleton(f, ((220, 540), (420, 540)), ((180, 420), (460, 420)), (left, right))]
        frames.append([hand(f, (right[0], right[1] - 20)), hand(f, (left[0], left[1] - 20))])
    params = AssignParams()
    tracks, assigned = assign_hands(frames, FPS, SIZE, params, skeletons=skeletons)
    assert {t.hand: len(t.frames) for t in tracks} == {"RH_P1": 30, "LH_P1": 30}
    for a in assigned:
        body = skeletons[a.detection.frame][0]
        wrist = body.joints[5] if a.hand == "RH_P1" else body.joints[4]
        assert near(a.detection.xy, (float(wrist[0]), float(wrist[1])))


def test_two_people_across_a_table_are_told_apart_by_their_shoulders() -> None:
    # From above: P1 at the bottom edge, P2 at the top edge facing down; all four hands mingle in the middle,
    # so their own places do not split the persons; the shoulders do. Persons still count from the left: the
    # bottom cook stands a little further left.
    frames, skeletons = [], {}
    for f in range(20):
        bottom = skeleton(f, ((200, 540), (360, 540)), ((180, 420), (380, 420)), ((260, 250), (330, 230)))
        top = skeleton(f, ((450, -60), (290, -60)), ((470, 60), (270, 60)), ((380, 210), (310, 250)))
        skeletons[f] = [bottom, top]
        frames.append([hand(f, (260, 232)), hand(f, (330, 212)), hand(f, (380, 228)), hand(f, (312, 268))])
    tracks, _ = assign_hands(frames, FPS, SIZE, skeletons=skeletons)
    got = centres(tracks)
    assert near(got["LH_P1"], (260, 232)) and near(got["RH_P1"], (330, 212))
    # The top cook faces down: their right is the image's left; the model's "right" wrist (image left) is it.
    assert near(got["RH_P2"], (312, 268)) and near(got["LH_P2"], (380, 228))
