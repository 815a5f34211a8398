"""Shot cuts: the histogram test, and the grey-level spike test for a cut between two shots of the same counter
(issue 23, class 7)."""

from __future__ import annotations

import json

import cv2
import numpy as np

from wecook_core.perception.segmentation.shots import cuts_of, frame_changes, shot_cuts

SIZE = 96
COUNTER = np.random.default_rng(0).integers(150, 200, (SIZE, SIZE, 3), dtype=np.uint8)  # a speckled worktop
BOWL, HAND = (60, 60, 60), (120, 160, 220)


def _scene(bowl_x: int, hand_x: int, bowl_y: int = 30) -> np.ndarray:
    image = COUNTER.copy()
    cv2.circle(image, (bowl_x, bowl_y + 20), 20, BOWL, -1)
    image[60:80, hand_x : hand_x + 14] = HAND
    return image


def _write(path, frames) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 10.0, (SIZE, SIZE))
    for image in frames:
        writer.write(image)
    writer.release()


def test_a_cut_between_two_shots_of_the_same_counter_is_found_though_its_colours_do_not_change(tmp_path):
    # the same worktop, bowl and hand before and after frame 15; after the cut the bowl and the hand are
    # elsewhere (a minute later): the mix of colours is the same, where they are is not
    frames = [_scene(28, 20 + frame) for frame in range(15)] + [_scene(66, 60 - frame) for frame in range(15)]
    path = tmp_path / "same_counter.mp4"
    _write(path, frames)
    distances, _, _ = frame_changes(path)
    assert 15 not in cuts_of(distances)  # the histogram test alone misses it
    assert shot_cuts(path) == (15,)


def test_a_bowl_swept_across_over_several_frames_is_motion_not_a_cut(tmp_path):
    # the bowl is carried 8 px a frame for eight frames: many pixels change, but on every one of those frames
    frames = [_scene(20, 30) for _ in range(10)] + [_scene(20 + 8 * k, 30) for k in range(1, 9)]
    frames += [_scene(84, 30) for _ in range(10)]
    path = tmp_path / "swept.mp4"
    _write(path, frames)
    assert shot_cuts(path) == ()


def test_a_small_change_in_a_still_picture_is_not_a_cut(tmp_path):
    # a nearly still rendered scene: a jar appears at frame 12; it stands out of the still frames' differences
    # but changes a few pixels, not the picture
    frames = []
    for frame in range(25):
        image = _scene(30, 40)
        if frame >= 12:
            image[10:16, 80:86] = (20, 20, 20)
        frames.append(image)
    path = tmp_path / "jar.mp4"
    _write(path, frames)
    assert shot_cuts(path) == ()


def test_cuts_cached_by_an_older_detection_are_found_again(tmp_path):
    from wecook_core.workflows import SHOTS_FILE, cached_shot_cuts

    frames = [_scene(28, 20 + frame) for frame in range(15)] + [_scene(66, 60 - frame) for frame in range(15)]
    video = tmp_path / "v.mp4"
    _write(video, frames)
    assert cached_shot_cuts(tmp_path, str(video)) == (15,)
    data = json.loads((tmp_path / SHOTS_FILE).read_text())
    older = {key: value for key, value in data.items() if key != "detector"}  # written before the spike test
    (tmp_path / SHOTS_FILE).write_text(json.dumps({**older, "cuts": []}))
    assert cached_shot_cuts(tmp_path, str(video)) == (15,)
