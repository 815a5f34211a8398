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
    ({"frame": 101, "time": 101 / 30}, r"sequence\[0\]: frame 101 lies past the end of the video kitchen.mp4 "
                                       r"\(100 frames"),
    ({"frame": 1_000_000_000, "time": 1e9 / 30}, r"frame 1000000000 lies past the end"),
    ({"frame": 0}, r"frame 0 is not a frame \(Label Studio counts from 1\)"),
    ({"x": "left"}, r"x must be a number"),
    ({"rotation": "left"}, r"rotation must be a number"),
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


def test_the_frontends_own_example_a_bare_list_of_results(tmp_path: Path) -> None:
    # The shape of label-studio-frontend's video example (simpleVideoResult): results alone, no task around them,
    # framesCount 131 over 5.425 s and keyframe times frame / 24, on its 24 fps opossum clip.
    results = [{"value": {"framesCount": 131, "duration": 5.425, "sequence": [
        {"frame": 1, "enabled": True, "rotation": 0, "x": 20.54721030042918, "y": 15.665236051502147,
         "width": 58.90557939914163, "height": 68.6695278969957, "time": 0.041666666666666664},
        {"x": 20.54721030042918, "y": 15.665236051502147, "width": 58.90557939914163, "height": 68.6695278969957,
         "rotation": 0, "enabled": False, "frame": 3, "time": 0.125}], "labels": ["Label 1"]},
        "id": "RRxnu061g3", "from_name": "box", "to_name": "video", "type": "videorectangle", "origin": "manual"}]
    path = write(tmp_path / "result.json", results)
    assert detect_objects_format(path) == "labelstudio"
    warnings: list[str] = []
    (box,) = read_labelstudio(path, video=VideoInfo("/v/opossum_intro.webm", 24.0, 131, 466, 466), warn=warnings.append)
    assert box.label == "Label 1" and box.frames.tolist() == [0, 1, 2]
    np.testing.assert_allclose(box.boxes[0], [95.75, 73.0, 370.25, 393.0], atol=0.01)
    assert not any("fps" in w for w in warnings)  # 131 / 5.425 = 24.15: the video's 24 fps


def test_a_list_of_predictions_is_one_videos_annotation(tmp_path: Path) -> None:
    # A tracker's predictions as imported into Label Studio: a list of {model_version, score, result}.
    predictions = [{"model_version": "bytetrack-v1", "score": 0.81, "result": [
        region(f"Item {i}", key(1 + i, i, 10, 5, 5), key(20 + i, i + 10, 10, 5, 5)) for i in range(16)]}]
    (*tracks,) = read_labelstudio(write(tmp_path / "predictions.json", predictions), video=VIDEO)
    assert len(tracks) == 16 and tracks[3].label == "Item 3" and tracks[3].frames[0] == 3


def test_frames_of_another_frame_rate_are_mapped_by_time(tmp_path: Path) -> None:
    # Label Studio's <Video> counts 24 fps unless told; the kitchen video plays at 30 fps (and at 12).
    def keyed(frame: int, x: float) -> dict[str, object]:
        return {**key(frame, x, 10, 10, 10), "time": frame / 24}

    region_24 = region("Pan", keyed(1, 0), keyed(121, 50))
    region_24["value"].update(framesCount=240, duration=10.0)  # type: ignore[union-attr]
    path = write(tmp_path / "export.json", [task("kitchen.mp4", region_24)])
    warnings: list[str] = []
    (pan,) = read_labelstudio(path, video=VideoInfo("/v/kitchen.mp4", 30.0, 300, 200, 100), warn=warnings.append)
    assert pan.frames[0] == 0 and pan.box_at(150) is not None  # 5 s in: frame 121 at 24 fps, 150 at 30
    np.testing.assert_allclose(pan.box_at(150), [100, 10, 120, 20])  # type: ignore[arg-type]
    assert pan.frames[-1] == 299  # the last keyframe held to the end
    assert any("annotated at 24 fps, the video kitchen.mp4 plays at 30 fps" in w for w in warnings)
    (slow,) = read_labelstudio(path, video=VideoInfo("/v/kitchen.mp4", 12.0, 120, 200, 100))
    np.testing.assert_allclose(slow.box_at(60), [100, 10, 120, 20])  # type: ignore[arg-type]


def test_an_ambiguous_frame_rate_is_refused_naming_fps(tmp_path: Path) -> None:
    keyframe = {**key(121, 50, 10, 10, 10), "time": 121 / 24}  # 24 fps by its time
    region_30 = region("Pan", keyframe)
    region_30["value"].update(framesCount=300, duration=10.0)  # type: ignore[union-attr]  # 30 fps by its count
    path = write(tmp_path / "export.json", [task("kitchen.mp4", region_30)])
    video = VideoInfo("/v/kitchen.mp4", 30.0, 300, 200, 100)
    with pytest.raises(InputError, match=r"frame rate is ambiguous: 24 fps from its keyframes' time .*, 30 fps "
                                         r"from framesCount / duration = 300 / 10 .*--annotation-fps") as error:
        read_labelstudio(path, video=video)
    assert "\n" not in str(error.value)
    (pan,) = read_labelstudio(path, video=video, fps=24)
    assert pan.frames[0] == 150


def test_boxes_drawn_upwards_are_normalised_and_rotated_ones_bounded(tmp_path: Path) -> None:
    upwards = key(1, 30, 40, -10, -20, enabled=False)  # drawn from (30%, 40%) up and left
    turned = {**key(1, 10, 10, 10, 20, enabled=False), "rotation": 90}  # clockwise about its top-left corner
    path = write(tmp_path / "export.json", [task("kitchen.mp4", region("Lid", upwards), region("Spoon", turned))])
    warnings: list[str] = []
    lid, spoon = read_labelstudio(path, video=VIDEO, warn=warnings.append)
    np.testing.assert_allclose(lid.boxes[0], [40, 20, 60, 40])
    np.testing.assert_allclose(spoon.boxes[0], [0, 10, 20, 30], atol=1e-9)
    assert any("1 rotated keyframes" in w for w in warnings)


def test_errors_in_a_bare_list_of_results_name_the_files_own_place(tmp_path: Path) -> None:
    path = write(tmp_path / "result.json", [region("Pan", key(1, 0, 0, 5, 5)), region("Pot", {**key(2, 0, 0, 5, 5),
                                                                                              "x": "?"})])
    with pytest.raises(InputError, match=r"result\.json:\[1\]\.sequence\[0\]: x must be a number"):
        read_labelstudio(path, video=VIDEO)
    path = write(tmp_path / "predictions.json", [{"result": [region("Pan", {**key(1, 0, 0, 5, 5), "x": "?"})]}])
    with pytest.raises(InputError, match=r"predictions\.json:\[0\]\.result\[0\]\.sequence\[0\]: x must be a number"):
        read_labelstudio(path, video=VIDEO)
