"""Label Studio video object tracking exports (VideoRectangle), JSON and JSON-MIN. The files are written here in
the shape Label Studio exports them (1-based frames, percentages of the frame)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.formats.detect import detect_objects_format, read_objects
from wecook_core.formats.labelstudio import read_labelstudio
from wecook_core.model import VideoInfo

VIDEO = VideoInfo("/videos/kitchen.mp4", 30.0, 100, 200, 100, 100)


def key(frame: int, x: float, y: float, w: float, h: float, enabled: bool = True) -> dict[str, object]:
    return {"frame": frame, "enabled": enabled, "rotation": 0, "x": x, "y": y, "width": w, "height": h,
            "time": frame / 30}


def region(label: str, *keys: dict[str, object]) -> dict[str, object]:
    return {"value": {"framesCount": 100, "duration": 3.33, "sequence": list(keys), "labels": [label]},
            "id": label[:4], "from_name": "box", "to_name": "video", "type": "videorectangle", "origin": "manual"}


def task(video: str, *regions: dict[str, object], task_id: int = 1) -> dict[str, object]:
    return {"id": task_id, "data": {"video": video},
            "annotations": [{"id": 7, "result": [*regions, {"type": "labels", "value": {"labels": ["x"]}}]}]}


def write(path: Path, data: object) -> Path:
    path.write_text(json.dumps(data))
    return path


def test_keyframes_are_interpolated_and_percentages_become_pixels(tmp_path: Path) -> None:
    path = write(tmp_path / "export.json", [task(
        "/data/upload/1/3f2a9c-kitchen.mp4",
        region("Knife", key(1, 10, 20, 10, 20), key(11, 20, 20, 10, 20, enabled=False)),
        region("Cutting board", key(50, 0, 50, 50, 50), key(60, 50, 50, 50, 50)),
    )])
    assert detect_objects_format(path) == "labelstudio"
    warnings: list[str] = []
    knife, board = read_labelstudio(path, video=VIDEO, warn=warnings.append)
    assert knife.label == "Knife" and knife.frames.tolist() == list(range(0, 11))  # 1-based -> 0-based
    np.testing.assert_allclose(knife.boxes[0], [20, 20, 40, 40])  # 10% of 200 px wide, 20% of 100 px high
    np.testing.assert_allclose(knife.boxes[5], [30, 20, 50, 40])  # half way between the keyframes
    np.testing.assert_allclose(knife.boxes[10], [40, 20, 60, 40])  # disabled: shown on its frame, not after
    # The last keyframe, enabled, holds until the end of the video.
    assert board.frames.tolist() == list(range(49, 100))
    np.testing.assert_allclose(board.boxes[-1], [100, 50, 200, 100])
    assert any("labels" in w for w in warnings)  # the non-box result is named and skipped


def test_json_min_and_the_task_of_the_video(tmp_path: Path) -> None:
    minimal = [
        {"id": 1, "video": "/data/upload/1/other.mp4", "box": [{"sequence": [key(1, 0, 0, 10, 10)], "labels": ["x"]}]},
        {"id": 2, "video": "/data/upload/1/kitchen.mp4",
         "box": [{"sequence": [key(3, 0, 0, 10, 10, enabled=False)], "labels": ["Bowl"]}]},
    ]
    path = write(tmp_path / "min.json", minimal)
    (bowl,), chosen = read_objects(path, video=VIDEO)
    assert chosen == "labelstudio" and bowl.name == "bowl" and bowl.frames.tolist() == [2]
    (other,), _ = read_objects(path, video=VIDEO, select="1")
    assert other.label == "x"
    with pytest.raises(InputError, match=r"no task is of the video elsewhere.mp4; the tasks are 1: other.mp4"):
        read_labelstudio(path, video=VideoInfo("/v/elsewhere.mp4", 30.0, 100, 200, 100))


@pytest.mark.parametrize(("change", "message"), [
    ({"frame": 101}, r"sequence\[0\]: frame 101 lies past the end of the video kitchen.mp4 \(100 frames"),
    ({"frame": 1_000_000_000}, r"frame 1000000000 lies past the end"),
    ({"frame": 0}, r"frame 0 is not a frame \(Label Studio counts from 1\)"),
    ({"x": "left"}, r"x must be a number"),
    ({"width": -3}, r"negative width or height"),
    ({"enabled": "yes"}, r"enabled must be true or false"),
])
def test_bad_keyframes_are_one_line_naming_the_place(tmp_path: Path, change: dict[str, object], message: str) -> None:
    keyframe = {**key(1, 10, 10, 10, 10), **change}
    path = write(tmp_path / "bad.json", [task("kitchen.mp4", region("Knife", keyframe))])
    with pytest.raises(InputError, match=message) as error:
        read_labelstudio(path, video=VIDEO)
    assert "\n" not in str(error.value) and "task 0, annotations[0].result[0]" in str(error.value)


def test_bad_files(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="the video is needed"):
        read_labelstudio(write(tmp_path / "a.json", []), video=None)
    with pytest.raises(InputError, match="empty list"):
        read_labelstudio(tmp_path / "a.json", video=VIDEO)
    with pytest.raises(InputError, match="has no label"):
        read_labelstudio(write(tmp_path / "b.json", [task("kitchen.mp4", {
            "type": "videorectangle", "value": {"sequence": [key(1, 0, 0, 1, 1)], "labels": []}})]), video=VIDEO)
    with pytest.raises(InputError, match="no boxes"):
        read_labelstudio(write(tmp_path / "c.json", [task("kitchen.mp4")]), video=VIDEO)
    (tmp_path / "d.json").write_text('[{"id": 1,')
    with pytest.raises(InputError, match=r"d.json:line 1, column \d+: malformed JSON"):
        read_labelstudio(tmp_path / "d.json", video=VIDEO)
