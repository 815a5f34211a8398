from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.formats.detect import detect_hands_format, detect_objects_format, read_hands, read_objects


@pytest.mark.parametrize(
    ("name", "content", "expected"),
    [
        ("a.xml", '<?xml version="1.0"?>\n<annotations></annotations>', "cvat"),
        ("a.txt", "\ufeff<annotations></annotations>", "cvat"),
        ("a.json", '  {"videos": []}', "cocovid"),
        ("gt.txt", "1,1,10,20,30,40,1,-1,-1,-1\n", "mot"),
        ("gt.csv", "# MOT\n1, 1, 10.5, 20, 30, 40\n", "mot"),
        ("boxes.csv", "frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,1,1\n", "csv"),
        ("boxes.txt", "Frame, Track_ID, Label,x1,y1,x2,y2\n", "csv"),
    ],
)
def test_object_formats_are_detected_from_the_content(tmp_path: Path, name: str, content: str, expected: str) -> None:
    path = tmp_path / name
    path.write_text(content)
    assert detect_objects_format(path) == expected


@pytest.mark.parametrize(
    ("content", "message"),
    [("", "empty file"), ("   \n\n", "empty file"), ("hello,world\n", "unknown object box format"),
     ("1,2,3\n", "unknown object box format")],
)
def test_unknown_object_files(tmp_path: Path, content: str, message: str) -> None:
    path = tmp_path / "boxes.dat"
    path.write_text(content)
    with pytest.raises(InputError, match=message) as error:
        detect_objects_format(path)
    assert str(path) in str(error.value)


def test_object_paths_that_are_not_files(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="is a folder"):
        detect_objects_format(tmp_path)
    with pytest.raises(InputError, match="no such"):
        detect_objects_format(tmp_path / "missing.xml")


def test_hand_formats(tmp_path: Path) -> None:
    folder = tmp_path / "op"
    folder.mkdir()
    with pytest.raises(InputError, match=r"without \*_keypoints\.json"):
        detect_hands_format(folder)
    (folder / "v_000000000000_keypoints.json").write_text('{"people": []}')
    assert detect_hands_format(folder) == "openpose"
    csv = tmp_path / "hands.csv"
    csv.write_text("frame,hand,x,y,x1,y1,x2,y2\n")
    assert detect_hands_format(csv) == "csv"
    single = tmp_path / "one.json"
    single.write_text('{"people": []}')
    with pytest.raises(InputError, match="give the folder"):
        detect_hands_format(single)
    other = tmp_path / "hands.txt"
    other.write_text("x y\n")
    with pytest.raises(InputError, match="unknown hand format"):
        detect_hands_format(other)


def test_forced_formats(tmp_path: Path) -> None:
    path = tmp_path / "boxes.dat"
    path.write_text("frame,track_id,label,x1,y1,x2,y2\n3,1,Knife,0,0,10,10\n")
    tracks, chosen = read_objects(path, "csv")
    assert chosen == "csv" and tracks[0].name == "knife" and tracks[0].frames.tolist() == [3]
    with pytest.raises(InputError,
                       match="unknown objects format 'yolo'; choose one of cvat, mot, cocovid, labelstudio, csv"):
        read_objects(path, "yolo")
    with pytest.raises(InputError, match="malformed XML"):
        read_objects(path, "cvat")  # forcing a wrong format gives that format's error
    with pytest.raises(InputError, match="unknown hands format"):
        read_hands(path, "mediapipe")
    hands = tmp_path / "hands.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n0,RH_P1,5,5,0,0,10,10\n")
    (track,), chosen = read_hands(hands)
    assert chosen == "csv" and track.hand == "RH_P1"


def test_labels_are_passed_to_mot_and_ignored_otherwise(tmp_path: Path) -> None:
    mot = tmp_path / "gt.txt"
    mot.write_text("1,4,0,0,10,10\n")
    labels = tmp_path / "names.txt"
    labels.write_text("4,spoon\n")
    (track,), chosen = read_objects(mot, labels=labels)
    assert (chosen, track.label) == ("mot", "spoon")
    warnings: list[str] = []
    csv = tmp_path / "boxes.csv"
    csv.write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,1,1\n")
    read_objects(csv, labels=labels, warn=warnings.append)
    assert warnings and "only applies to MOT" in warnings[0]
