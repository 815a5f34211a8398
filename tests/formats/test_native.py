from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.formats.native import read_hands_csv, read_objects_csv, write_hands_csv, write_objects_csv

OBJECTS = """frame,track_id,label,x1,y1,x2,y2
0,1,Chopping Board,10,20,110,80
0,2,bowl,200,20,260,70
1,1,Chopping Board,11,20,111,80
0,3,bowl,300,20,360,70
2,1,Chopping Board,12,21,112,81
"""

HANDS = """frame,hand,x,y,x1,y1,x2,y2
0,RH_P1,50.5,60,40,50,61,70
1,RH_P1,51,60,41,50,62,70
0,LH_P2,400,60,390,50,410,70
"""


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_objects_grouped_by_track_and_named_uniquely(tmp_path: Path) -> None:
    tracks = read_objects_csv(write(tmp_path, "o.csv", OBJECTS))
    assert [t.name for t in tracks] == ["chopping_board", "bowl", "bowl_2"]
    board = tracks[0]
    assert board.label == "Chopping Board"
    assert board.frames.tolist() == [0, 1, 2]
    assert board.boxes[2].tolist() == [12, 21, 112, 81]
    assert board.box_at(1) is not None and board.box_at(5) is None


def test_objects_round_trip(tmp_path: Path) -> None:
    tracks = read_objects_csv(write(tmp_path, "o.csv", OBJECTS))
    out = tmp_path / "out.csv"
    write_objects_csv(out, tracks)
    again = read_objects_csv(out)
    assert [t.name for t in again] == [t.name for t in tracks]
    for a, b in zip(tracks, again, strict=True):
        assert np.array_equal(a.frames, b.frames) and np.allclose(a.boxes, b.boxes)


def test_hands_round_trip(tmp_path: Path) -> None:
    tracks = read_hands_csv(write(tmp_path, "h.csv", HANDS))
    assert [t.hand for t in tracks] == ["RH_P1", "LH_P2"]
    assert tracks[0].xy[0].tolist() == [50.5, 60]
    out = tmp_path / "out.csv"
    write_hands_csv(out, tracks)
    again = read_hands_csv(out)
    assert np.allclose(again[0].xy, tracks[0].xy) and np.allclose(again[1].boxes, tracks[1].boxes)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("", "empty file"),
        ("frame,track_id,label,x1,y1,x2,y2\n", "no boxes"),
        ("frame,id,label,x1,y1,x2,y2\n0,1,a,0,0,1,1\n", "line 1: expected the header"),
        ("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,1\n", "line 2: expected 7 fields"),
        ("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,1,1\nx,1,knife,0,0,1,1\n",
         "line 3: frame must be an integer"),
        ("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,abc,1\n", "line 2: x2 must be a number"),
        ("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,5,0,1,1\n", "line 2: box has x2 < x1"),
        ("frame,track_id,label,x1,y1,x2,y2\n-1,1,knife,0,0,1,1\n", "line 2: frame must not be negative"),
        ("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,1,1\n0,1,knife,0,0,2,2\n", "frame 0: track 1 has two boxes"),
        ("frame,track_id,label,x1,y1,x2,y2\n0,1,knife,0,0,1,1\n1,1,fork,0,0,2,2\n", "labelled both"),
    ],
)
def test_bad_object_files_name_the_place(tmp_path: Path, text: str, expected: str) -> None:
    path = write(tmp_path, "bad.csv", text)
    with pytest.raises(InputError) as error:
        read_objects_csv(path)
    assert str(path) in str(error.value)
    assert expected in str(error.value)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="file not found"):
        read_objects_csv(tmp_path / "nope.csv")


def test_unknown_hand(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="line 2: hand must be one of"):
        read_hands_csv(write(tmp_path, "h.csv", "frame,hand,x,y,x1,y1,x2,y2\n0,RH_P3,1,1,0,0,2,2\n"))
