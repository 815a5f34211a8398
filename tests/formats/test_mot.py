from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.formats.mot import read_labels, read_mot

ROWS = """1,1,10,20,30,40,1,-1,-1,-1
2,1,12,20,30,40,1,-1,-1,-1
1,2,100,100,50,50,1,-1,-1,-1
3,3,0,0,5,5,1,-1,-1,-1
"""


def write(tmp_path: Path, rows: str = ROWS, labels: str | None = "1,knife\n2,bowl\n3,Bowl\n",
          name: str = "labels.txt") -> Path:
    path = tmp_path / "gt.txt"
    path.write_text(rows)
    if labels is not None:
        (tmp_path / name).write_text(labels)
    return path


def test_rows_become_tracks_with_0_based_frames_and_labels_by_id(tmp_path: Path) -> None:
    knife, bowl, bowl2 = read_mot(write(tmp_path))
    assert (knife.track_id, knife.name, knife.frames.tolist()) == (1, "knife", [0, 1])
    assert knife.boxes.tolist() == [[10, 20, 40, 60], [12, 20, 42, 60]]
    assert (bowl.name, bowl2.label, bowl2.name) == ("bowl", "Bowl", "bowl_2")


def test_labels_by_class_column_one_per_line(tmp_path: Path) -> None:
    rows = "1,7,0,0,10,10,1,2,1.0\n2,7,0,0,10,10,1,2,1.0\n1,8,5,5,10,10,1,1,0.5\n"
    path = write(tmp_path, rows, labels="# classes\nspoon\n\npot\n")
    pot, spoon = read_mot(path)
    assert (pot.track_id, pot.label, spoon.label) == (7, "pot", "spoon")


def test_labels_by_class_with_a_header_and_an_explicit_file(tmp_path: Path) -> None:
    rows = "1,7,0,0,10,10,1,12\n"
    write(tmp_path, rows, labels=None)
    other = tmp_path / "mine.txt"
    other.write_text("class,label\n12,lemon\n")
    (track,) = read_mot(tmp_path / "gt.txt", other)
    assert track.label == "lemon"


def test_rows_with_conf_0_are_skipped_with_a_warning(tmp_path: Path) -> None:
    warnings: list[str] = []
    tracks = read_mot(write(tmp_path, ROWS + "4,1,0,0,1,1,0,-1,-1,-1\n"), warn=warnings.append)
    assert tracks[0].frames.tolist() == [0, 1]
    assert len(warnings) == 1 and "1 rows with conf 0" in warnings[0]


@pytest.mark.parametrize(
    ("rows", "message", "place"),
    [
        ("1,1,10,20,30\n", "expected frame,id,left,top,width,height", "line 1"),
        ("1,1,10,20,30,40\nx,1,10,20,30,40\n", "frame must be a number", "line 2"),
        ("0,1,10,20,30,40\n", "MOT frames start at 1", "line 1"),
        ("1,-1,10,20,30,40\n", "detection file", "line 1"),
        ("1,1,10,20,-30,40\n", "negative width", "line 1"),
        ("1,1,10,20,30,40\n1,1,10,20,30,40\n", "second box in frame 1 .first on line 1", "line 2"),
        ("1,1,10,20,30,inf\n", "finite", "line 1"),
        ("1,1,10,20,30,40.5.1\n", "height must be a number", "line 1"),
    ],
)
def test_bad_rows_name_their_line(tmp_path: Path, rows: str, message: str, place: str) -> None:
    with pytest.raises(InputError, match=message) as error:
        read_mot(write(tmp_path, rows))
    assert f"gt.txt:{place}:" in str(error.value)


def test_a_track_without_a_label_names_the_labels_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"labels.txt: no label for id 3 \(used at .*gt.txt:line 4\)"):
        read_mot(write(tmp_path, labels="1,knife\n2,bowl\n"))


def test_a_track_whose_class_changes_is_refused(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="labelled both"):
        read_mot(write(tmp_path, "1,1,0,0,1,1,1,1\n2,1,0,0,1,1,1,2\n", labels="a\nb\n"))


def test_class_labels_need_the_class_column(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no class"):
        read_mot(write(tmp_path, "1,1,0,0,1,1,1\n", labels="a\nb\n"))


def test_missing_labels_file_says_how_to_give_one(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="--labels"):
        read_mot(write(tmp_path, labels=None))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty labels file"),
        ("# only a comment\n", "empty labels file"),
        ("1,knife\nbowl\n", "line 2: expected ID,LABEL"),
        ("1,knife\n1,bowl\n", "line 2: id 1 is labelled twice"),
        ("1,\n", "line 1: no label"),
        ("id,label\n", "nothing else"),
    ],
)
def test_bad_labels_files(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "labels.txt"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_labels(path)


def test_empty_and_missing_mot_files(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="empty MOT file"):
        read_mot(write(tmp_path, "\n\n"))
    with pytest.raises(InputError, match="every row has conf 0"):
        read_mot(write(tmp_path, "1,1,0,0,1,1,0\n"))
    with pytest.raises(InputError, match="not found"):
        read_mot(tmp_path / "nope.txt", tmp_path / "labels.txt")
    (tmp_path / "bin.txt").write_bytes(b"\xff\xfe\x00")
    with pytest.raises(InputError, match="not a text file"):
        read_mot(tmp_path / "bin.txt", tmp_path / "labels.txt")


# PathTrack's ground truth: MOT's fields separated by spaces.
PATHTRACK = """1 1 845 298 49 125 1 -1 -1 -1
2 1 847 298 49 125 1 -1 -1 -1
2 2 101.5 80 40 110 1 -1 -1 -1
"""


def test_mot_with_spaces_is_recognised_and_read(tmp_path: Path) -> None:
    from wecook_core.formats.detect import detect_objects_format, read_objects
    from wecook_core.model import VideoInfo

    path = write(tmp_path, PATHTRACK, labels="1,person\n2,person\n")
    assert detect_objects_format(path) == "mot"
    (first, second), chosen = read_objects(path, video=VideoInfo("/v/seq.mp4", 30.0, 10, 1280, 720))
    assert chosen == "mot" and first.frames.tolist() == [0, 1] and first.boxes[1].tolist() == [847, 298, 896, 423]
    assert (second.name, second.boxes[0].tolist()) == ("person_2", [101.5, 80, 141.5, 190])
    with pytest.raises(InputError, match=r"gt.txt:line 2: expected frame,id,left,top,width,height"):
        short = PATHTRACK.replace("2 1 847 298 49 125 1 -1 -1 -1", "2 1 847 298")
        read_mot(write(tmp_path, short, labels="1,person\n2,p\n"))


def test_a_frame_past_the_video_is_named_as_mot_counts_at_its_line(tmp_path: Path) -> None:
    from wecook_core.formats.detect import read_objects
    from wecook_core.model import VideoInfo

    rows = ROWS + "24,1,12,20,30,40,1,-1,-1,-1\n"
    with pytest.raises(InputError, match=r"gt\.txt:line 5: id 1: frame 24 lies past the end of the video \(frames "
                                         r"1-23, as MOT counts\)"):
        read_objects(write(tmp_path, rows), video=VideoInfo("/v/seq.mp4", 30.0, 23, 640, 480))


def test_mot17_ground_truth_overhanging_the_frame_is_clipped(tmp_path: Path) -> None:
    # py-motmetrics' MOT17-05-SDP gt.txt, track 1 (640x480 at 14 fps): walking out at the bottom left, the
    # box reaches 140 px below the image (29 % of its height); the old 5 % tolerance refused the file.
    from grey_video import write_grey_video

    from wecook_core.observations.importer import import_observations

    rows = ("55,1,-6,-10,237,561,1,1,0.82897\n56,1,-9,-14,241,573,1,1,0.80168\n57,1,-18,-24,245,572,1,1,0.773\n"
            "58,1,-13,-18,246,620,1,1,0.72914\n59,1,-13,-17,246,619,1,1,0.73031\n")
    path = write(tmp_path, rows, labels="class,label\n1,pedestrian\n")
    video = write_grey_video(tmp_path / "MOT17-05.avi", 60, (640, 480), 14.0)
    hands = tmp_path / "hands.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n" + "".join(f"{f},RH_P1,20,15,15,10,25,20\n" for f in range(60)))
    imported = import_observations(video, path, hands)
    (person,) = imported.observations.objects
    assert person.frames.tolist() == [54, 55, 56, 57, 58]
    assert person.boxes[3].tolist() == [0, 0, 233, 480]
    assert any("clipped 5 boxes that overhang the 640x480 image, by up to 122 px (track 1 (pedestrian) at frame 58)"
               in w for w in imported.warnings)


def test_a_track_of_two_classes_is_named_at_the_files_frame(tmp_path: Path) -> None:
    rows = "1,7,0,0,10,10,1,2,1.0\n2,7,0,0,10,10,1,1,1.0\n"
    with pytest.raises(InputError, match=r"gt\.txt:frame 2: track 7 is labelled both 'pot' and 'spoon'"):
        read_mot(write(tmp_path, rows, labels="spoon\npot\n"))
