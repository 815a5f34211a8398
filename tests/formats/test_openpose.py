from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.formats.openpose import OpenPoseParams, read_openpose

# A BODY_25-like skeleton around its centre: elbows 3 / 6 above the wrists 4 / 7.
OFFSETS = np.array([(0, -80), (0, -50), (-30, -50), (-35, -20), (-40, 10), (30, -50), (35, -20), (40, 10)]
                   + [(dx, 60) for dx in range(-17, 0)], dtype=float)


def body(cx: float, cy: float, confidence: float = 0.9) -> list[float]:
    points = np.add(OFFSETS, (cx, cy))
    return [v for x, y in points for v in (x, y, confidence)]


def hand(x: float, y: float, confidence: float = 0.8) -> list[float]:
    return [v for i in range(21) for v in (x + (i % 5) * 2, y + (i // 5) * 2, confidence)]


DX = float(np.mean([(i % 5) * 2 for i in range(21)]))
DY = float(np.mean([(i // 5) * 2 for i in range(21)]))
"""Mean offset of the hand keypoints from the first one."""


def person(cx: float, cy: float = 200, *, hands: bool = True, hand_confidence: float = 0.8) -> dict[str, Any]:
    entry: dict[str, Any] = {"person_id": [-1], "pose_keypoints_2d": body(cx, cy)}
    if hands:
        entry["hand_right_keypoints_2d"] = hand(cx - 45, cy + 15, hand_confidence)
        entry["hand_left_keypoints_2d"] = hand(cx + 35, cy + 15, hand_confidence)
    return entry


def write_frames(folder: Path, frames: dict[int, list[dict[str, Any]]], name: str = "take") -> Path:
    folder.mkdir(exist_ok=True)
    for frame, people in frames.items():
        (folder / f"{name}_{frame:012d}_keypoints.json").write_text(json.dumps({"version": 1.3, "people": people}))
    return folder


def test_two_persons_keep_their_identity_when_openpose_shuffles_them(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    frames = {}
    for f in range(30):
        people = [person(100 + f), person(400 - f)]
        rng.shuffle(people)  # type: ignore[arg-type]
        frames[f] = people
    tracks = read_openpose(write_frames(tmp_path / "op", frames))
    assert [t.hand for t in tracks] == ["LH_P1", "RH_P1", "LH_P2", "RH_P2"]
    lh1, rh1, lh2, rh2 = tracks
    for track in tracks:
        assert track.frames.tolist() == list(range(30))
    # P1 is the left person (x ~ 100 + f); a hand's centre is the mean of its keypoints
    np.testing.assert_allclose(lh1.xy[:, 0], 100 + np.arange(30) + 35 + DX)
    np.testing.assert_allclose(rh1.xy[:, 0], 100 + np.arange(30) - 45 + DX)
    np.testing.assert_allclose(lh2.xy[:, 0], 400 - np.arange(30) + 35 + DX)
    np.testing.assert_allclose(rh2.xy[:, 1], 200 + 15 + DY)
    assert (lh1.boxes[:, 0] <= lh1.xy[:, 0]).all() and (lh1.boxes[:, 2] >= lh1.xy[:, 0]).all()


def test_frame_index_comes_from_the_file_name_and_people_may_be_missing(tmp_path: Path) -> None:
    frames = {5: [person(100), person(400)], 6: [person(401)], 7: [], 9: [person(102), person(402)]}
    lh1, _, lh2, _ = read_openpose(write_frames(tmp_path / "op", frames))
    assert lh1.frames.tolist() == [5, 9]
    assert lh2.frames.tolist() == [5, 6, 9]


def test_low_confidence_hands_fall_back_to_the_wrist(tmp_path: Path) -> None:
    warnings: list[str] = []
    frames = {0: [person(100, hand_confidence=0.05)], 1: [person(100, hands=False)]}
    lh, rh = read_openpose(write_frames(tmp_path / "op", frames), warn=warnings.append)
    # left wrist (index 7) at (140, 210), elbow (135, 180): centre 0.35 forearm past the wrist
    np.testing.assert_allclose(lh.xy, [[141.75, 220.5], [141.75, 220.5]])
    np.testing.assert_allclose(rh.xy[0], [100 - 40 - 1.75, 220.5])
    forearm = np.hypot(5, 30)
    np.testing.assert_allclose(lh.boxes[0, 2] - lh.boxes[0, 0], 0.8 * forearm)
    assert any("4 hand positions placed from the wrist" in w for w in warnings)


def test_an_extra_detection_is_dropped_and_a_moved_person_rejoins(tmp_path: Path) -> None:
    frames: dict[int, list[dict[str, Any]]] = {}
    for f in range(30):
        people = [person(100)]
        if f < 10:
            people.append(person(400))
        elif f >= 20:
            people.append(person(600))  # jumped 200 px (more than a body size) after an absence
        frames[f] = people
    frames[15].append(person(900, 500))  # a passer-by, once, while P1 is there too
    warnings: list[str] = []
    tracks = read_openpose(write_frames(tmp_path / "op", frames), warn=warnings.append)
    lh1, _, lh2, _ = tracks
    assert len(tracks) == 4
    assert lh1.frames.tolist() == list(range(30))
    assert lh2.frames.tolist() == list(range(10)) + list(range(20, 30))
    assert any("dropped 1 extra person tracks" in w and "15-15" in w for w in warnings)


def test_a_jump_beyond_the_merge_distance_is_not_joined(tmp_path: Path) -> None:
    frames = {f: [person(100), person(300 if f < 10 else 900)] for f in range(20)}
    frames.update({f: [person(100)] for f in range(20, 25)})
    warnings: list[str] = []
    params = OpenPoseParams(max_persons=2, merge_distance=2.0)
    tracks = read_openpose(write_frames(tmp_path / "op", frames), params, warn=warnings.append)
    # person at 300 (frames 0-9) and at 900 (10-19) are two persons: the longest two are kept
    assert [t.frames.tolist() for t in tracks[::2]] == [list(range(25)), list(range(10))]
    assert any("dropped 1 extra" in w for w in warnings)


def test_only_one_person(tmp_path: Path) -> None:
    tracks = read_openpose(write_frames(tmp_path / "op", {0: [person(200)], 1: [person(201)]}))
    assert [t.hand for t in tracks] == ["LH_P1", "RH_P1"]


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("", "empty file"),
        ("{\n  people: []\n}", "line 2, column 3: malformed JSON"),
        ('{"version": 1.3}', "'people' list"),
        ('{"people": [3]}', r"people\[0\]: expected an object"),
        ('{"people": [{"pose_keypoints_2d": [1, 2]}]}', r"people\[0\].pose_keypoints_2d: 2 numbers"),
        ('{"people": [{"pose_keypoints_2d": [1, "a", 3]}]}', "flat list of numbers"),
        ('{"people": [{"pose_keypoints_2d": [1, [2], 3]}]}', "flat list of numbers"),
        ('{"people": [{"pose_keypoints_2d": [[1, 2, 3]]}]}', "flat list of numbers"),
        ('{"people": [{"pose_keypoints_2d": [1, null, 3]}]}', "flat list of numbers"),
        ('{"people": [{"pose_keypoints_2d": "1 2 3"}]}', "flat list of numbers"),
        ('{"people": [{"pose_keypoints_2d": [1, 2, 3], "hand_left_keypoints_2d": [1, 2, 3]}]}',
         "1 keypoints, expected 21"),
    ],
)
def test_bad_files_name_file_and_place(tmp_path: Path, content: str, message: str) -> None:
    folder = write_frames(tmp_path / "op", {0: [person(100)]})
    bad = folder / "take_000000000001_keypoints.json"
    bad.write_text(content)
    with pytest.raises(InputError, match=message) as error:
        read_openpose(folder)
    assert str(bad) in str(error.value)


def test_bad_folders(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such folder"):
        read_openpose(tmp_path / "nope")
    (tmp_path / "file.json").write_text("{}")
    with pytest.raises(InputError, match="expected a folder"):
        read_openpose(tmp_path / "file.json")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match=r"no \*_keypoints\.json files \(nor any \*\.json\)"):
        read_openpose(tmp_path / "empty")
    folder = write_frames(tmp_path / "op", {1: [person(100)]})
    (folder / "other_1_keypoints.json").write_text('{"people": []}')
    with pytest.raises(InputError, match="frame 1 again"):
        read_openpose(folder)
    (folder / "other_1_keypoints.json").unlink()
    (folder / "x_keypoints.json").write_text('{"people": []}')
    with pytest.raises(InputError, match="no frame number"):
        read_openpose(folder)


def test_nobody_confident_is_an_error(tmp_path: Path) -> None:
    quiet = {"pose_keypoints_2d": [v if i % 3 != 2 else 0.01 for i, v in enumerate(body(100, 100))]}
    with pytest.raises(InputError, match="no person with confident keypoints in any of the 2 frames"):
        read_openpose(write_frames(tmp_path / "op", {0: [quiet], 1: []}))


def test_image_folder_names_are_frames_in_order_not_their_numbers(tmp_path: Path) -> None:
    # OpenPose on a folder of images (im1010.jpg, im1011.jpg, ...) names each file after its image; the video
    # made of those images starts at im1010: frame 0, not 1010.
    folder = tmp_path / "op"
    folder.mkdir()
    for i, number in enumerate((1010, 1011, 1013)):
        (folder / f"im{number}_keypoints.json").write_text(json.dumps({"version": 1.3, "people": [person(100 + i)]}))
    warnings: list[str] = []
    tracks = read_openpose(folder, warn=warnings.append)
    assert [t.frames.tolist() for t in tracks] == [[0, 1, 2], [0, 1, 2]]
    assert any("numbered from 1010, not 0: frames taken in the order of those numbers (im1010_keypoints.json is "
               "frame 0)" in w for w in warnings)


def test_openpose_counter_names_are_the_frames_even_with_gaps(tmp_path: Path) -> None:
    # OpenPose on a video: a 12-digit counter; frames 0, 1 and 5 (files 2-4 removed: nobody there).
    warnings: list[str] = []
    tracks = read_openpose(write_frames(tmp_path / "op", {0: [person(100)], 1: [person(101)], 5: [person(102)]}),
                           warn=warnings.append)
    assert tracks[0].frames.tolist() == [0, 1, 5]
    assert any("number frames 0-5 with gaps: taken as the video's frames" in w for w in warnings)
    # --frame_first 300: the counter starts at 300 and is still the frame.
    later = read_openpose(write_frames(tmp_path / "late", {300: [person(100)], 301: [person(101)]}))
    assert later[0].frames.tolist() == [300, 301]


def test_renamed_output_files_are_read(tmp_path: Path) -> None:
    # A project that renamed OpenPose's output to frame_0001.json ...: any *.json with people[] in the folder.
    from wecook_core.formats.detect import detect_hands_format

    folder = tmp_path / "poses"
    folder.mkdir()
    for number in (1, 2, 3):
        (folder / f"frame_{number:04d}.json").write_text(json.dumps({"people": [person(100)]}))
    assert detect_hands_format(folder) == "openpose"
    tracks = read_openpose(folder)
    assert tracks[0].frames.tolist() == [0, 1, 2]  # counted from 1: images in order
    # With the video: numbers within it from 0 are frames; ones past its end while the files fit are images.
    for number in (0, 4):
        (folder / f"frame_{number:04d}.json").write_text(json.dumps({"people": [person(100)]}))
    assert read_openpose(folder)[0].frames.tolist() == [0, 1, 2, 3, 4]
    (folder / "frame_0004.json").unlink()
    (folder / "frame_0400.json").write_text(json.dumps({"people": [person(100)]}))
    assert read_openpose(folder)[0].frames.tolist() == [0, 1, 2, 3, 400]
    assert read_openpose(folder, frame_count=10)[0].frames.tolist() == [0, 1, 2, 3, 4]
