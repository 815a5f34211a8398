"""Sparse boxes (YouCook2-BB style: one box a second or less) are filled within a track; frames are checked
against the video before anything is filled or interpolated (issue 13)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.grey_video import write_grey_video
from wecook_core.errors import InputError
from wecook_core.formats.detect import read_objects
from wecook_core.formats.tracks import fill_sparse
from wecook_core.model import ObjectTrack, VideoInfo
from wecook_core.observations.importer import import_observations
from wecook_tui.cli import main


def csv(path: Path, rows: list[tuple[int, int, str, float]]) -> Path:
    lines = ["frame,track_id,label,x1,y1,x2,y2"]
    lines += [f"{f},{t},{label},{x},10,{x + 20},30" for f, t, label, x in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_box_a_second_is_filled_between_and_a_missed_sample_stays_a_gap(tmp_path: Path) -> None:
    # 30 fps, a box every 30 frames; the sample at frame 120 is missing (the object was away).
    frames = [0, 30, 60, 90, 150, 180]
    path = csv(tmp_path / "sparse.csv", [(f, 1, "pan", float(f)) for f in frames]
               + [(f, 2, "spoon", 5.0) for f in range(0, 40)])
    video = VideoInfo("v.mp4", 30.0, 200, 640, 360, 200)
    warnings: list[str] = []
    (pan, spoon), _ = read_objects(path, video=video, warn=warnings.append)
    assert pan.frames.tolist() == list(range(0, 91)) + list(range(150, 181))
    np.testing.assert_allclose(pan.boxes[:91, 0], np.arange(91.0))  # linear between the samples
    assert spoon.frames.tolist() == list(range(40))  # dense: as it was
    assert warnings == [f"{path}: track 1 (pan) has a box every 30 frames; interpolated to 122 frames"]


def test_the_same_sampling_at_5_fps_fills_the_same_seconds() -> None:
    # One box a second at 5 fps is a box every 5 frames: the same rule, relative to the track's own step.
    track = ObjectTrack(1, "pan", "pan", np.array([0, 5, 10, 20], dtype=np.int64),
                        np.array([[0, 0, 10, 10]] * 4, dtype=np.float64))
    (filled,) = fill_sparse([track])
    assert filled.frames.tolist() == [*range(11), 20]


def test_frames_past_the_video_are_one_line_before_filling(tmp_path: Path) -> None:
    path = csv(tmp_path / "far.csv", [(0, 1, "pan", 0.0), (9_000_000, 1, "pan", 5.0)])
    video = VideoInfo("v.mp4", 30.0, 200, 640, 360, 200)
    with pytest.raises(InputError, match=r"far.csv:frame 9000000: track 1 \(pan\) is in frame 9000000, but the "
                                         r"video v.mp4 has frames 0-199"):
        read_objects(path, video=video)


@pytest.mark.parametrize("kind", ["csv", "cvat"])
def test_wecook_new_refuses_a_box_far_past_the_video(tmp_path: Path, capsys, kind: str) -> None:
    video = write_grey_video(tmp_path / "v.avi", 10, (64, 48), 5.0)
    hands = tmp_path / "hands.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n0,RH_P1,20,20,10,10,30,30\n")
    if kind == "csv":
        boxes = csv(tmp_path / "boxes.csv", [(0, 1, "pan", 0.0), (9_000_000, 1, "pan", 5.0)])
    else:
        boxes = tmp_path / "boxes.xml"
        boxes.write_text('<annotations><track id="1" label="pan"><box frame="0" outside="0" xtl="0" ytl="0" '
                         'xbr="9" ybr="9"/><box frame="9000000" outside="0" xtl="0" ytl="0" xbr="9" ybr="9"/>'
                         "</track></annotations>")
    code = main(["new", "s", "--video", str(video), "--objects", str(boxes), "--hands", str(hands),
                 "--root", str(tmp_path / "sessions")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.count("\n") == 0 and "9000000" in err and "frames 0-9" in err
    assert not (tmp_path / "sessions" / "s").exists()


def test_a_5_fps_video_with_sparse_boxes_imports(tmp_path: Path) -> None:
    video = write_grey_video(tmp_path / "v.avi", 25, (64, 48), 5.0)
    boxes = csv(tmp_path / "boxes.csv", [(f, 1, "bowl", 2.0) for f in (0, 5, 10, 15, 20)])
    hands = tmp_path / "hands.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n" + "".join(f"{f},RH_P1,20,20,10,10,30,30\n" for f in range(25)))
    imported = import_observations(video, boxes, hands)
    (bowl,) = imported.observations.objects
    assert bowl.frames.tolist() == list(range(21))
