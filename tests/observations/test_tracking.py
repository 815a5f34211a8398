"""Boxes drawn by the user and carried by OpenCV's tracker; keyframes interpolated as CVAT does; CVAT XML and
wecook CSV out."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.square_video import moving_square
from wecook_core.formats.cvat import read_cvat
from wecook_core.formats.cvat_write import write_cvat
from wecook_core.formats.native import read_objects_csv, write_objects_csv
from wecook_core.observations.hand_assign import iou
from wecook_core.observations.tracking import BoxTrack, TrackParams, available_trackers, track_from_last_keyframe


def test_mil_is_available() -> None:
    assert "MIL" in available_trackers()


@pytest.mark.slow
def test_a_drawn_box_is_followed_until_the_object_is_gone(tmp_path: Path) -> None:
    video = tmp_path / "square.avi"
    truth = moving_square(video)
    track = BoxTrack(1, "tomato").with_keyframe(0, truth[0])
    tracked = track_from_last_keyframe(video, track, 10.0)
    boxes = tracked.boxes()
    assert tracked.lost_at is not None and 29 <= tracked.lost_at <= 31  # lost when the square vanished
    followed = [f for f in range(1, 30) if f in boxes and iou(boxes[f], truth[f]) > 0.5]
    assert len(followed) >= 25
    assert max(boxes) < 31


def test_a_box_touching_the_frames_edge_is_tracked(tmp_path: Path) -> None:
    """MIL samples patches of the box's size around it, all inside the image: on a box touching the frame's
    edge it found none and OpenCV raised an assertion (kfc-b: the bowls filling the frame's height, the box
    mode's `t` on them). Tracked inset from the edge, the box keeps its full extent."""
    video = tmp_path / "square.avi"
    truth = moving_square(video, vanish=None, start=(0, 0))
    tracked = track_from_last_keyframe(video, BoxTrack(1, "bowl").with_keyframe(0, truth[0]), 10.0,
                                       TrackParams(max_seconds=2.0))
    boxes = tracked.boxes()
    assert tracked.lost_at is None and all(f in boxes for f in range(1, 20))
    # MIL samples at random from a generator OpenCV does not let us seed (OpenCV 5.1: cv2.setRNGSeed leaves its
    # tracks different from run to run): over 15 runs here the mean overlap was 0.63-0.86, single frames down to
    # 0.16 where it slipped a step behind
    overlaps = [iou(boxes[f], truth[f]) for f in range(1, 20)]
    assert float(np.mean(overlaps)) > 0.5, overlaps
    widths = [boxes[f][2] - boxes[f][0] for f in range(1, 20)]
    heights = [boxes[f][3] - boxes[f][1] for f in range(1, 20)]
    assert float(np.median(widths)) == float(np.median(heights)) == 40.0  # the drawn size, not the inset 36


@pytest.mark.slow
def test_max_seconds_bounds_the_tracking(tmp_path: Path) -> None:
    video = tmp_path / "square.avi"
    truth = moving_square(video, vanish=None)
    tracked = track_from_last_keyframe(video, BoxTrack(1, "x").with_keyframe(5, truth[5]), 10.0,
                                       TrackParams(max_seconds=1.0))
    assert max(tracked.tracked) == 15 and tracked.lost_at is None


def test_keyframes_interpolate_and_a_correction_drops_the_stale_run() -> None:
    track = BoxTrack(1, "bowl").with_keyframe(0, (0, 0, 10, 10))
    track = BoxTrack(1, "bowl", track.keyframes, {f: (f, 0, f + 10, 10) for f in range(1, 20)})
    assert track.boxes()[19] == (19, 0, 29, 10)
    corrected = track.with_keyframe(10, (20, 0, 30, 10))
    boxes = corrected.boxes()
    assert boxes[5] == (10.0, 0.0, 20.0, 10.0)  # half way between the keyframes
    assert max(boxes) == 10  # the tracker's run after the correction is stale: track again from it
    earlier = track.with_keyframe(19, (19, 0, 29, 10)).with_keyframe(5, (0, 0, 10, 10))
    assert sorted(earlier.keyframes) == [0, 5, 19]
    assert earlier.without_keyframe(5).boxes()[10] == (10.0, 0.0, 20.0, 10.0)


def test_cvat_and_csv_round_trip(tmp_path: Path) -> None:
    track = BoxTrack(3, "chopping board", {0: (0, 0, 10, 10), 4: (4, 0, 14, 10)},
                     {f: (4.0, 0.0, 14.0, 10.0) for f in range(5, 8)})
    objects = [track.object_track()]
    write_cvat(tmp_path / "boxes.xml", objects, size=(320, 240), keyframes={3: track.keyframes})
    (back,) = read_cvat(tmp_path / "boxes.xml", frame_size=(320, 240), frame_count=8)
    assert back.frames.tolist() == list(range(8)) and back.label == "chopping board"
    np.testing.assert_allclose(back.boxes, objects[0].boxes)
    write_objects_csv(tmp_path / "boxes.csv", objects)
    (csv,) = read_objects_csv(tmp_path / "boxes.csv")
    np.testing.assert_allclose(csv.boxes, objects[0].boxes)
