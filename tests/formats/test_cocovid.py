from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import pytest

from wecook_core.errors import InputError
from wecook_core.formats.cocovid import read_cocovid

DATA: dict[str, Any] = {
    "videos": [{"id": 1, "name": "cooking/take1.mp4"}, {"id": 2, "name": "take2"}],
    "images": [
        {"id": 10, "video_id": 1, "frame_id": 0, "file_name": "a/0.jpg"},
        {"id": 11, "video_id": 1, "frame_id": 1, "file_name": "a/1.jpg"},
        {"id": 20, "video_id": 2, "frame_id": 0, "file_name": "b/0.jpg"},
    ],
    "annotations": [
        {"id": 1, "image_id": 10, "category_id": 3, "instance_id": 5, "bbox": [10, 20, 30, 40]},
        {"id": 2, "image_id": 11, "category_id": 3, "instance_id": 5, "bbox": [11, 20, 30, 40]},
        {"id": 3, "image_id": 11, "category_id": 4, "instance_id": 6, "bbox": [0, 0, 5, 5]},
        {"id": 4, "image_id": 20, "category_id": 4, "instance_id": 9, "bbox": [0, 0, 5, 5]},
    ],
    "categories": [{"id": 3, "name": "knife"}, {"id": 4, "name": "cutting board"}],
}


def write(tmp_path: Path, data: Any) -> Path:
    path = tmp_path / "ann.json"
    path.write_text(json.dumps(data, indent=1))
    return path


def test_one_video_by_id_name_or_video_file_stem(tmp_path: Path) -> None:
    path = write(tmp_path, DATA)
    knife, board = read_cocovid(path, video=1)
    assert (knife.track_id, knife.label, knife.frames.tolist()) == (5, "knife", [0, 1])
    assert knife.boxes.tolist() == [[10, 20, 40, 60], [11, 20, 41, 60]]
    assert (board.name, board.frames.tolist()) == ("cutting_board", [1])
    assert [t.track_id for t in read_cocovid(path, video="take2")] == [9]
    assert [t.track_id for t in read_cocovid(path, video_path="/videos/take1.mp4")] == [5, 6]


def test_several_videos_need_a_choice(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"2 videos in the file; choose one of cooking/take1.mp4 \(id 1\), take2"):
        read_cocovid(write(tmp_path, DATA))
    with pytest.raises(InputError, match="no video 'take3'"):
        read_cocovid(write(tmp_path, DATA), video="take3")


def test_track_id_and_frame_index_spellings_and_no_videos(tmp_path: Path) -> None:
    data = copy.deepcopy(DATA)
    del data["videos"]
    for image in data["images"]:
        image["frame_index"] = image.pop("frame_id")
    for annotation in data["annotations"]:
        annotation["track_id"] = annotation.pop("instance_id")
    data["annotations"].pop()  # the other video's box would collide in frame 0 with nothing: drop it anyway
    assert [t.track_id for t in read_cocovid(write(tmp_path, data))] == [5, 6]


def test_crowd_annotations_are_skipped(tmp_path: Path) -> None:
    data = copy.deepcopy(DATA)
    data["annotations"][2]["iscrowd"] = 1
    warnings: list[str] = []
    assert [t.track_id for t in read_cocovid(write(tmp_path, data), video=1, warn=warnings.append)] == [5]
    assert "1 crowd" in warnings[0]


def broken(path: tuple[Any, ...], value: Any) -> dict[str, Any]:
    data = copy.deepcopy(DATA)
    target: Any = data
    for key in path[:-1]:
        target = target[key]
    if value is KeyError:
        del target[path[-1]]
    else:
        target[path[-1]] = value
    return data


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (broken(("annotations", 1, "bbox"), [1, 2, 3]), r"annotations\[1\]: bbox must be \[x, y, width, height\]"),
        (broken(("annotations", 1, "bbox"), [1, 2, -3, 4]), r"annotations\[1\]: box .* negative width"),
        (broken(("annotations", 1, "bbox"), [1, 2, "a", 4]), r"annotations\[1\]: bbox must be a number"),
        (broken(("annotations", 1, "instance_id"), KeyError), r"annotations\[1\]: annotation has no instance_id"),
        (broken(("annotations", 1, "category_id"), 99), r"annotations\[1\]: category_id 99 is not among"),
        (broken(("annotations", 1, "image_id"), 99), r"annotations\[1\]: image_id 99 is not among"),
        (broken(("annotations", 1), "x"), r"annotations\[1\]: expected a JSON object"),
        (broken(("images", 1, "frame_id"), KeyError), r"images\[1\]: image has no frame_index"),
        (broken(("images", 1, "frame_id"), -2), r"images\[1\]: frame_id -2 is negative"),
        (broken(("images", 1, "id"), 10), r"images\[1\]: image id 10 is used twice"),
        (broken(("categories", 0, "name"), ""), r"categories\[0\]: category has no name"),
        (broken(("annotations",), KeyError), "no 'annotations' list"),
        (broken(("annotations",), {}), "'annotations' must be a list"),
        (broken(("annotations",), []), "no boxes"),
        (broken(("annotations", 1, "instance_id"), 6), "track 6 is labelled both"),
        ([1, 2], "expected a JSON object"),
    ],
)
def test_bad_content_names_the_place(tmp_path: Path, data: Any, message: str) -> None:
    with pytest.raises(InputError, match=message) as error:
        read_cocovid(write(tmp_path, data), video=1)
    assert str(tmp_path / "ann.json") in str(error.value)


def test_malformed_and_empty_json(tmp_path: Path) -> None:
    path = tmp_path / "ann.json"
    path.write_text('{\n "videos": [\n  {"id": 1,,}\n ]\n}\n')
    with pytest.raises(InputError, match=r"ann.json:line 3, column 12: malformed JSON"):
        read_cocovid(path)
    path.write_text("  \n")
    with pytest.raises(InputError, match="empty file"):
        read_cocovid(path)
    with pytest.raises(InputError, match="not found"):
        read_cocovid(tmp_path / "nope.json")


DATA_DIR = Path(__file__).parent / "data"


def test_tao_images_are_placed_by_frame_index_not_mmtrackings_frame_id() -> None:
    # mmtracking's TAO demo: frame_index 390 and 420 (the video's frames), frame_id 0 and 1 (its index among
    # the annotated frames). The boxes belong at 390 and 420.
    warnings: list[str] = []
    baby, bowl = read_cocovid(DATA_DIR / "tao_mmtracking.json", warn=warnings.append)
    assert (baby.track_id, baby.label, baby.frames.tolist()) == (1, "baby", [390, 420])
    assert bowl.boxes[1].tolist() == [332, 377, 440, 480]
    assert any("2 images placed by frame_index" in w for w in warnings)


def test_youtube_vis_file_names_and_bboxes_with_nulls() -> None:
    from wecook_core.formats.detect import detect_objects_format, read_objects
    from wecook_core.model import VideoInfo

    path = DATA_DIR / "youtube_vis_train.json"
    assert detect_objects_format(path) == "cocovid"
    sedan, person = read_cocovid(path, video="0043f083b5")
    # 00010.jpg is frame 10 of the 30 fps video (every fifth frame annotated); null boxes are absent frames.
    assert (sedan.track_id, sedan.label, sedan.frames.tolist()) == (1, "sedan", [10, 15, 20])
    assert sedan.boxes[0].tolist() == [1170, 310, 1209, 387]
    assert person.frames.tolist() == [0, 5, 10, 15, 20, 25, 30, 35]
    # With the video, the fifth frames are filled in between, as any sparse track.
    tracks, chosen = read_objects(path, video=VideoInfo("/v/0043f083b5.mp4", 30.0, 40, 1280, 720))
    assert chosen == "cocovid" and tracks[0].frames.tolist() == list(range(10, 21))
    with pytest.raises(InputError, match=r"2 videos in the file; choose one of 0043f083b5 \(id 1\), 00f88c4f0a"):
        read_cocovid(path)


def test_ovis_images_counted_from_one_are_the_frames_in_order(tmp_path: Path) -> None:
    names = [f"2524877e/img_{i:07d}.jpg" for i in range(1, 5)]
    data = {"videos": [{"id": 7, "width": 640, "height": 360, "length": 4, "file_names": names}],
            "categories": [{"id": 1, "name": "Person"}],
            "annotations": [{"id": 3, "video_id": 7, "category_id": 1, "iscrowd": 0, "length": 1, "width": 640,
                             "height": 360, "bboxes": [None, [1, 2, 3, 4], [2, 2, 3, 4], None],
                             "areas": [None, 12, 12, None], "segmentations": [None, {}, {}, None]}]}
    warnings: list[str] = []
    (person,) = read_cocovid(write(tmp_path, data), warn=warnings.append)
    assert person.frames.tolist() == [1, 2]  # img_0000002 is the second image: frame 1
    assert any("numbered from 1, not 0: frames taken in the order of those numbers (img_0000001.jpg is frame 0)"
               in w for w in warnings)
    data["annotations"][0]["bboxes"] = [None, [1, 2, 3, 4]]  # type: ignore[index]
    with pytest.raises(InputError, match=r"annotations\[0\]: bboxes must be a list of 4 boxes"):
        read_cocovid(write(tmp_path, data))


def test_a_frame_past_the_video_names_the_annotation_and_its_image() -> None:
    from wecook_core.formats.detect import read_objects
    from wecook_core.model import VideoInfo

    with pytest.raises(InputError, match=r"tao_mmtracking\.json:annotations\[2\]: instance 1 is on image 1 "
                                         r"\(images\[1\]\), frame_index 420, but the video has frames 0-399"):
        read_objects(DATA_DIR / "tao_mmtracking.json", video=VideoInfo("/v/v.mp4", 30.0, 400, 640, 480))
    # Eight files numbered 0-35 on a 5-frame video: neither the frames nor the files fit it.
    with pytest.raises(InputError, match=r"annotations\[0\]\.bboxes\[2\]: instance 1 is on 0043f083b5/00010\.jpg, "
                                         r"frame 10, but the video has frames 0-4"):
        read_objects(DATA_DIR / "youtube_vis_train.json", video=VideoInfo("/v/0043f083b5.mp4", 30.0, 5, 1280, 720))
    # On a video of its eight images (made from the JPEGs), the names are the images in order.
    tracks, _ = read_objects(DATA_DIR / "youtube_vis_train.json", video=VideoInfo("/v/0043f083b5.mp4", 6.0, 8, 1280,
                                                                                   720))
    assert tracks[0].frames.tolist() == [2, 3, 4]
