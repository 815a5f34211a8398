"""Every importer, fed malformed variants of a good file, returns tracks or raises one InputError line naming
the file: never another exception, never a hang (Hypothesis generates the variants)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from contract import field_swapped, keeps_contract, mutated
from hypothesis import given
from hypothesis import strategies as st

from wecook_core.formats.cocovid import read_cocovid
from wecook_core.formats.cvat import read_cvat
from wecook_core.formats.detect import read_hands, read_objects
from wecook_core.formats.labelstudio import read_labelstudio
from wecook_core.formats.mot import read_mot
from wecook_core.formats.native import read_hands_csv, read_objects_csv
from wecook_core.formats.openpose import read_openpose
from wecook_core.model import VideoInfo

OBJECTS_CSV = "frame,track_id,label,x1,y1,x2,y2\n0,1,pot,10,10,20,20\n1,1,pot,11,10,21,20\n0,2,big bowl,40,30,90,60\n"
HANDS_CSV = "frame,hand,x,y,x1,y1,x2,y2\n0,LH_P1,5,5,1,1,9,9\n1,LH_P1,6,5,2,1,10,9\n0,RH_P1,50,5,46,1,54,9\n"
MOT = "1,1,10,10,10,10,1,1\n2,1,11,10,10,10,1,1\n1,2,40,30,50,30,0.9,2\n"
LABELS = "1,pot\n2,bowl\n"
CVAT = """<?xml version="1.0" encoding="utf-8"?>
<annotations>
  <meta><task><original_size><width>96</width><height>64</height></original_size></task></meta>
  <track id="0" label="pot">
    <box frame="0" outside="0" occluded="0" keyframe="1" xtl="10" ytl="10" xbr="20" ybr="20"/>
    <box frame="2" outside="0" occluded="0" keyframe="1" xtl="12" ytl="10" xbr="22" ybr="20"/>
    <box frame="3" outside="1" occluded="0" keyframe="1" xtl="12" ytl="10" xbr="22" ybr="20"/>
  </track>
  <track id="1" label="bowl"><polygon frame="0" points="1,1;2,2;3,1"/></track>
</annotations>
"""
COCO = json.dumps({
    "videos": [{"id": 1, "name": "take.mp4"}],
    "images": [{"id": 1, "video_id": 1, "frame_id": 0}, {"id": 2, "video_id": 1, "frame_id": 1}],
    "annotations": [{"id": 1, "image_id": 1, "category_id": 1, "instance_id": 1, "bbox": [10, 10, 10, 10]},
                    {"id": 2, "image_id": 2, "category_id": 1, "instance_id": 1, "bbox": [11, 10, 10, 10]}],
    "categories": [{"id": 1, "name": "pot"}]}, indent=1)
LABEL_STUDIO = json.dumps([{"id": 1, "data": {"video": "/videos/take.mp4"}, "annotations": [{"id": 7, "result": [
    {"type": "videorectangle", "id": "pot", "from_name": "box", "to_name": "video", "value": {
        "framesCount": 10, "labels": ["pot"], "sequence": [
            {"frame": 1, "enabled": True, "x": 10, "y": 10, "width": 20, "height": 20, "time": 0.0},
            {"frame": 5, "enabled": False, "x": 12, "y": 10, "width": 20, "height": 20, "time": 0.13}]}}]}]}],
    indent=1)
BODY = [v for x, y in [(0, -30), (0, -20), (-10, -20), (-12, -5), (-14, 8), (10, -20), (12, -5), (14, 8)]
        for v in (30 + x, 30 + y, 0.9)]
KEYPOINTS = json.dumps({"version": 1.3, "people": [{"pose_keypoints_2d": BODY, "hand_left_keypoints_2d": [],
                                                    "hand_right_keypoints_2d": [12.0, 20.0, 0.8] * 21}]})


def _write(folder: Path, name: str, data: bytes | str) -> Path:
    path = folder / name
    path.write_bytes(data.encode() if isinstance(data, str) else data)
    return path


@given(data=st.one_of(mutated(OBJECTS_CSV.encode()), field_swapped(OBJECTS_CSV).map(str.encode)))
@pytest.mark.slow
def test_objects_csv(tmp_path: Path, data: bytes) -> None:
    path = _write(tmp_path, "objects.csv", data)
    keeps_contract(lambda: read_objects_csv(path), path)
    keeps_contract(lambda: read_objects(path), path)


@given(data=st.one_of(mutated(HANDS_CSV.encode()), field_swapped(HANDS_CSV).map(str.encode)))
def test_hands_csv(tmp_path: Path, data: bytes) -> None:
    path = _write(tmp_path, "hands.csv", data)
    keeps_contract(lambda: read_hands_csv(path), path)
    keeps_contract(lambda: read_hands(path), path)


@given(data=st.one_of(mutated(MOT.encode()), field_swapped(MOT).map(str.encode)),
       labels=st.one_of(st.just(LABELS.encode()), mutated(LABELS.encode())))
def test_mot(tmp_path: Path, data: bytes, labels: bytes) -> None:
    path = _write(tmp_path, "gt.txt", data)
    _write(tmp_path, "labels.txt", labels)
    keeps_contract(lambda: read_mot(path), tmp_path)  # the error may name the MOT file or its labels file


@given(data=st.one_of(mutated(CVAT.encode()), field_swapped(CVAT, ' "\n').map(str.encode)))
def test_cvat(tmp_path: Path, data: bytes) -> None:
    path = _write(tmp_path, "annotations.xml", data)
    keeps_contract(lambda: read_cvat(path, frame_size=(96, 64)), path)


@given(data=st.one_of(mutated(COCO.encode()), field_swapped(COCO, ',:\n').map(str.encode)))
def test_cocovid(tmp_path: Path, data: bytes) -> None:
    path = _write(tmp_path, "instances.json", data)
    keeps_contract(lambda: read_cocovid(path, video_path="take.mp4"), path)
    keeps_contract(lambda: read_objects(path), path)


@given(data=st.one_of(mutated(KEYPOINTS.encode()), field_swapped(KEYPOINTS, ',:\n').map(str.encode)),
       name=st.sampled_from(["take_000000000001_keypoints.json", "take_x_keypoints.json",
                             "take_99999999999999999999_keypoints.json", "take_000000000000_keypoints.json"]))
def test_openpose(tmp_path: Path, data: bytes, name: str) -> None:
    folder = tmp_path / "openpose"
    folder.mkdir(exist_ok=True)
    for old in folder.iterdir():
        old.unlink()
    _write(folder, "take_000000000000_keypoints.json", KEYPOINTS)
    _write(folder, name, data)
    keeps_contract(lambda: read_openpose(folder), folder)
    keeps_contract(lambda: read_hands(folder), folder)


@given(data=st.one_of(mutated(LABEL_STUDIO.encode()), field_swapped(LABEL_STUDIO, ',:\n').map(str.encode)))
def test_labelstudio(tmp_path: Path, data: bytes) -> None:
    path = _write(tmp_path, "export.json", data)
    video = VideoInfo("/videos/take.mp4", 30.0, 10, 96, 64, 10)
    keeps_contract(lambda: read_labelstudio(path, video=video), path)
    keeps_contract(lambda: read_objects(path), path)
