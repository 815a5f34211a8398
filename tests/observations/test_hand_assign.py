"""Naming detected hands by tracking and position, on fabricated detections (no detector runs here)."""

from __future__ import annotations

import numpy as np

from wecook_core.observations.hand_assign import AssignParams, HandDetection, assign_hands, deduplicate

FPS = 10.0
SIZE = (640, 360)


def det(frame: int, x: float, y: float, label: str, score: float = 0.9, half: float = 20.0) -> HandDetection:
    return HandDetection(frame, label, score, (x, y), (x - half, y - half, x + half, y + half))


def names(tracks) -> dict[str, int]:
    return {t.hand: len(t.frames) for t in tracks}


def test_mediapipe_left_is_the_persons_right_hand_unless_mirrored() -> None:
    frames = [[det(f, 100 + f, 200, "Left"), det(f, 400 - f, 200, "Right")] for f in range(10)]
    tracks, _ = assign_hands(frames, FPS, SIZE)
    by_name = {t.hand: t for t in tracks}
    assert set(by_name) == {"LH_P1", "RH_P1"}
    assert by_name["RH_P1"].xy[0, 0] == 100  # MediaPipe's "Left" on an unmirrored image
    assert by_name["LH_P1"].xy[0, 0] == 400
    mirrored, _ = assign_hands(frames, FPS, SIZE, AssignParams(mirrored=True))
    assert {t.hand: t.xy[0, 0] for t in mirrored} == {"LH_P1": 100, "RH_P1": 400}


def test_one_hand_reported_twice_in_a_frame_is_one_hand() -> None:
    frame = [det(3, 100, 100, "Left", 0.95), det(3, 104, 102, "Right", 0.6), det(3, 400, 100, "Right")]
    kept = deduplicate(frame, 0.5)
    assert [(d.xy, d.label) for d in kept] == [((100, 100), "Left"), ((400, 100), "Right")]
    tracks, _ = assign_hands([frame], FPS, SIZE)
    assert names(tracks) == {"LH_P1": 1, "RH_P1": 1}


def test_both_hands_given_the_same_side_get_both_sides() -> None:
    # Every frame says "Left" for both hands; the steadier, higher scored one keeps the voted side.
    frames = [[det(f, 100, 200, "Left", 0.95), det(f, 450, 200, "Left", 0.55)] for f in range(8)]
    tracks, _ = assign_hands(frames, FPS, SIZE)
    by_name = {t.hand: t for t in tracks}
    assert set(by_name) == {"LH_P1", "RH_P1"}
    assert by_name["RH_P1"].xy[0, 0] == 100
    assert by_name["LH_P1"].xy[0, 0] == 450


def test_a_handedness_flip_in_one_frame_does_not_swap_the_hands() -> None:
    frames = []
    for f in range(20):
        left, right = ("Right", "Left") if f == 7 else ("Left", "Right")
        frames.append([det(f, 150 + 2 * f, 200, left), det(f, 450 - 2 * f, 210, right)])
    tracks, _ = assign_hands(frames, FPS, SIZE)
    by_name = {t.hand: t for t in tracks}
    assert len(by_name["RH_P1"].frames) == 20 and len(by_name["LH_P1"].frames) == 20
    assert (by_name["RH_P1"].xy[:, 0] < 320).all()
    assert (by_name["LH_P1"].xy[:, 0] > 320).all()


def test_four_hands_are_two_persons_numbered_from_the_left() -> None:
    frames = []
    for f in range(10):
        frames.append([
            det(f, 60, 150, "Left"), det(f, 140, 220, "Right"),  # the person on the left
            det(f, 500, 150, "Left"), det(f, 580, 220, "Right"),  # the person on the right
        ])
    tracks, _ = assign_hands(frames, FPS, SIZE)
    centres = {t.hand: tuple(t.xy[0]) for t in tracks}
    assert centres == {"RH_P1": (60, 150), "LH_P1": (140, 220), "RH_P2": (500, 150), "LH_P2": (580, 220)}
    one, _ = assign_hands(frames, FPS, SIZE, persons=1)  # forced: two hands per side, the best kept
    assert {t.hand for t in one} == {"LH_P1", "RH_P1"}


def test_a_far_jump_starts_another_hand_and_a_gap_is_allowed() -> None:
    # One right hand, missing for 0.5 s (within max_gap_seconds), then back near where it was.
    frames = [[det(f, 200, 200, "Left")] for f in range(5)] + [[det(f, 210, 200, "Left")] for f in range(10, 15)]
    tracks, assigned = assign_hands(frames, FPS, SIZE)
    assert names(tracks) == {"RH_P1": 10}
    assert len({a.tracklet for a in assigned}) == 1
    # A detection across the image 0.1 s later is not the same hand.
    jump = [[det(0, 50, 50, "Left")], [det(1, 600, 330, "Left"), det(1, 52, 50, "Left")]]
    _, assigned = assign_hands(jump, FPS, SIZE)
    assert len({a.tracklet for a in assigned}) == 2


def test_parameters_are_seconds_the_same_hands_at_another_frame_rate() -> None:
    # The same motion sampled at 5 fps (every other frame of 10 fps): the same names.
    fast = [[det(f, 100 + 6 * f, 200, "Left"), det(f, 500 - 6 * f, 200, "Right")] for f in range(20)]
    slow = [[det(f, 100 + 12 * f, 200, "Left"), det(f, 500 - 12 * f, 200, "Right")] for f in range(10)]
    tracks_fast, a_fast = assign_hands(fast, 10.0, SIZE)
    tracks_slow, a_slow = assign_hands(slow, 5.0, SIZE)
    assert names(tracks_fast) == {"LH_P1": 20, "RH_P1": 20}
    assert names(tracks_slow) == {"LH_P1": 10, "RH_P1": 10}
    assert len({a.tracklet for a in a_fast}) == len({a.tracklet for a in a_slow}) == 2


def test_a_short_lived_third_hand_is_no_second_person() -> None:
    # Two hands for 3 s, and for 0.5 s (a sixth of the frames) a ghost where they crossed.
    frames = [[det(f, 100, 200, "Left"), det(f, 450, 200, "Right")] for f in range(30)]
    for f in range(10, 15):
        frames[f].append(det(f, 280, 120, "Right", 0.7))
    tracks, _ = assign_hands(frames, FPS, SIZE)
    assert {t.hand for t in tracks} == {"LH_P1", "RH_P1"}
    assert len({t.hand for t in tracks if t.hand.endswith("P2")}) == 0


def test_crossing_hands_keep_their_names() -> None:
    # The hands pass each other at frame 10 (same place): the handedness keeps them apart, not the distance.
    frames = [[det(f, 100 + 20 * f, 200, "Left"), det(f, 500 - 20 * f, 205, "Right")] for f in range(21)]
    tracks, _ = assign_hands(frames, FPS, SIZE)
    by_name = {t.hand: t for t in tracks}
    assert np.all(np.diff(by_name["RH_P1"].xy[:, 0]) > 0)  # the "Left"-labelled one moves right throughout
    assert np.all(np.diff(by_name["LH_P1"].xy[:, 0]) < 0)
