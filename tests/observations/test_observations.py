from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from grey_video import write_grey_video

from wecook_core.errors import InputError
from wecook_core.knowledge.categories import CategoryTable, parse_categories
from wecook_core.model import Category, ObjectTrack
from wecook_core.observations.importer import InputChecks, import_observations, load_observations, unique_names

W, H, FRAMES, FPS = 160, 120, 30, 10.0
TABLE: CategoryTable = parse_categories("objects:\n  knife: tool\n  bowl: container\n  tomato: ingredient\n",
                                        "test-table")


def write_video(path: Path, frames: int = FRAMES) -> Path:
    return write_grey_video(path, frames, (W, H), FPS)


def write_inputs(tmp_path: Path, objects: list[str], hands: list[str]) -> tuple[Path, Path, Path]:
    video = write_video(tmp_path / "v.avi")
    (tmp_path / "objects.csv").write_text("frame,track_id,label,x1,y1,x2,y2\n" + "\n".join(objects) + "\n")
    (tmp_path / "hands.csv").write_text("frame,hand,x,y,x1,y1,x2,y2\n" + "\n".join(hands) + "\n")
    return video, tmp_path / "objects.csv", tmp_path / "hands.csv"


OBJECTS = ["0,1,Knife,10,10,30,20", "1,1,Knife,12,10,32,20", "0,2,bowl,50,50,90,90", "0,5,Bowl,100,50,140,90",
           "0,3,tomato,60,60,70,70"]
HANDS = [f"{f},RH_P1,20,15,15,10,25,20" for f in range(FRAMES)] + ["0,LH_P1,60,60,55,55,65,65"]


def test_import_names_categorises_and_records_the_video(tmp_path: Path) -> None:
    imported = import_observations(*write_inputs(tmp_path, OBJECTS, HANDS), categories=TABLE)
    obs = imported.observations
    assert (obs.video.fps, obs.video.width, obs.video.height, obs.video.frame_count) == (FPS, W, H, FRAMES)
    assert [(t.track_id, t.name) for t in obs.objects] == [(1, "knife"), (2, "bowl"), (3, "tomato"), (5, "bowl_2")]
    assert obs.categories == {"knife": Category.TOOL, "bowl": Category.CONTAINER, "bowl_2": Category.CONTAINER,
                              "tomato": Category.INGREDIENT}
    assert obs.object("knife").frames.tolist() == [0, 1]
    assert [t.hand for t in obs.hands] == ["LH_P1", "RH_P1"]
    assert (imported.objects_format, imported.hands_format) == ("csv", "csv")
    assert imported.warnings == () and imported.gaps == ()
    assert imported.missing == {"LH_P1": 0, "RH_P1": 0}
    assert load_observations(*write_inputs(tmp_path, OBJECTS, HANDS), categories=TABLE).objects[0].name == "knife"


def test_unique_names_skip_names_already_taken() -> None:
    tracks = [ObjectTrack(i, label, "x", np.array([0]), np.zeros((1, 4))) for i, label in
              [(1, "bowl"), (2, "Bowl 2"), (3, "bowl"), (4, "BOWL"), (5, "chopping  board!")]]
    assert [t.name for t in unique_names(tracks)] == ["bowl", "bowl_2", "bowl_3", "bowl_4", "chopping_board"]


def test_boxes_overhanging_the_frame_are_clipped_however_far(tmp_path: Path) -> None:
    # A person walking out of the picture: MOT ground truth keeps the whole body, 60 px (37 %) past the edge.
    objects = [*OBJECTS, "2,1,Knife,-5,110,30,125", "2,2,bowl,100,50,220,90", "1,2,bowl,170,50,200,90"]
    imported = import_observations(*write_inputs(tmp_path, objects, HANDS), categories=TABLE)
    knife, bowl = imported.observations.object("knife"), imported.observations.object("bowl")
    assert knife.boxes[2].tolist() == [0, 110, 30, H]
    assert bowl.frames.tolist() == [0, 2]  # frame 1's box lies wholly right of the image: dropped
    assert bowl.boxes[1].tolist() == [100, 50, W, 90]
    assert any("clipped 2 boxes that overhang the 160x120 image, by up to 60 px (track 2 (bowl) at frame 2)" in w
               for w in imported.warnings)
    assert any("dropped 1 boxes that lie wholly outside the 160x120 image (the first: track 2 (bowl) at frame 1)"
               in w for w in imported.warnings)


def test_boxes_all_outside_the_image_are_of_another_video(tmp_path: Path) -> None:
    objects = ["0,1,Knife,200,10,230,20", "1,1,Knife,300,130,330,140"]
    with pytest.raises(InputError, match=r"every box lies outside the 160x120 image of v\.avi"):
        import_observations(*write_inputs(tmp_path, objects, HANDS), categories=TABLE)


def test_boxes_past_the_end_name_frame_and_track(tmp_path: Path) -> None:
    row = "30,2,bowl,10,10,20,20"
    with pytest.raises(InputError, match=r"frame 30: track 2 \(bowl\) is in frame 30, but the video "
                       r"v\.avi has frames 0-29") as error:
        import_observations(*write_inputs(tmp_path, [*OBJECTS, row], HANDS), categories=TABLE)
    assert str(error.value).startswith(str(tmp_path / "objects.csv"))


def test_hands_are_checked_and_their_boxes_clipped(tmp_path: Path) -> None:
    hands = [*HANDS[:-1], "0,LH_P1,159,60,150,55,170,65"]
    obs = load_observations(*write_inputs(tmp_path, OBJECTS, hands), categories=TABLE)
    assert obs.hand("LH_P1") is not None
    assert obs.hand("LH_P1").boxes[0].tolist() == [150, 55, W, 65]  # type: ignore[union-attr]
    far = [*HANDS[:-1], "3,LH_P1,300,60,290,55,310,65"]
    with pytest.raises(InputError, match=r"hands.csv:frame 3: hand LH_P1 at \(300, 60\) lies outside"):
        load_observations(*write_inputs(tmp_path, OBJECTS, far), categories=TABLE)
    late = [*HANDS, "31,LH_P1,30,60,25,55,35,65"]
    with pytest.raises(InputError, match=r"hands\.csv:frame 31: hand LH_P1 is in frame 31"):
        load_observations(*write_inputs(tmp_path, OBJECTS, late), categories=TABLE)


def test_long_hand_gaps_are_reported_not_fatal(tmp_path: Path) -> None:
    hands = [f"{f},RH_P1,20,15,15,10,25,20" for f in [*range(5), *range(26, 30)]]
    hands += [f"{f},LH_P1,20,15,15,10,25,20" for f in [0, 2, 4, 20, 21]]  # gaps of 1, 1 and 15 frames
    imported = import_observations(*write_inputs(tmp_path, OBJECTS, hands), categories=TABLE)
    assert [(g.hand, g.start, g.end) for g in imported.gaps] == [("RH_P1", 5, 26)]
    assert imported.gaps[0].seconds == pytest.approx(2.1)
    assert imported.missing == {"LH_P1": 17, "RH_P1": 21}
    assert any("RH_P1 is missing for 2.1 s, frames 5-25" in w for w in imported.warnings)
    stricter = import_observations(*write_inputs(tmp_path, OBJECTS, hands), categories=TABLE,
                                   checks=InputChecks(max_gap_seconds=1.0))
    assert [(g.hand, g.start) for g in stricter.gaps] == [("LH_P1", 5), ("RH_P1", 5)]


def test_hand_gaps_past_the_allowed_length_are_an_error_when_asked(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    hands = [f"{f},RH_P1,20,15,15,10,25,20" for f in [*range(5), *range(26, 30)]]  # missing 2.1 s
    inputs = write_inputs(tmp_path, OBJECTS, hands)
    with pytest.raises(InputError, match=r"hands\.csv:frame 5: RH_P1 is missing for 2\.1 s, frames 5-25, longer than"):
        import_observations(*inputs, categories=TABLE, checks=InputChecks(gap_error_seconds=2.0))
    import_observations(*inputs, categories=TABLE, checks=InputChecks(gap_error_seconds=3.0))  # within the limit

    from wecook_tui.cli import main

    video, objects, hands_csv = inputs
    args = ["new", "s", "--video", str(video), "--objects", str(objects), "--hands", str(hands_csv),
            "--root", str(tmp_path / "sessions"), "--max-gap", "1"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "RH_P1 is missing for 2.1 s" in err
    assert not (tmp_path / "sessions" / "s").exists()


def test_labels_the_table_lacks_never_stop_the_import(tmp_path: Path) -> None:
    # Neither this table nor the corpus says what a spatula or a gizmo is: taken as ingredients, and said.
    rows = [*OBJECTS, "0,9,spatula,0,0,5,5", "0,10,gizmo,0,0,5,5"]
    imported = import_observations(*write_inputs(tmp_path, rows, HANDS), categories=TABLE)
    assert imported.uncategorised == ("spatula", "gizmo")
    assert imported.observations.categories["gizmo"] == "ingredient"
    assert any("no category known for 'spatula', 'gizmo'" in w for w in imported.warnings)


def test_a_truncated_video_limits_the_frames_and_says_so(tmp_path: Path) -> None:
    video, objects, hands = write_inputs(tmp_path, OBJECTS, HANDS)
    data = video.read_bytes()
    video.write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match=r"but the video v\.avi has frames 0-"):
        load_observations(video, objects, hands, categories=TABLE)
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n" + "".join(f"{f},RH_P1,20,15,15,10,25,20\n" for f in range(5)))
    imported = import_observations(video, objects, hands, categories=TABLE)
    assert any("declares 30 frames" in w for w in imported.warnings)


def test_a_video_that_does_not_open(tmp_path: Path) -> None:
    _, objects, hands = write_inputs(tmp_path, OBJECTS, HANDS)
    (tmp_path / "bad.mp4").write_text("nope")
    with pytest.raises(InputError, match=r"bad\.mp4"):
        load_observations(tmp_path / "bad.mp4", objects, hands, categories=TABLE)


def test_normalised_coordinates_are_refused(tmp_path: Path) -> None:
    objects = ["0,1,Knife,0.1,0.1,0.3,0.2", "0,2,bowl,0.5,0.5,0.9,0.9"]
    with pytest.raises(InputError, match=r"objects\.csv: every box coordinate lies within \[0, 1\]"):
        load_observations(*write_inputs(tmp_path, objects, HANDS), categories=TABLE)
    hands = ["0,RH_P1,0.2,0.1,0.1,0.05,0.3,0.15"]
    with pytest.raises(InputError, match=r"hands\.csv: every hand coordinate lies within \[0, 1\].*keypoint_scale"):
        load_observations(*write_inputs(tmp_path, OBJECTS, hands), categories=TABLE)


def test_a_label_studio_annotation_at_another_rate_and_the_fps_flag(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    # The video plays at 10 fps; the annotation counted 20 fps by its keyframes' time but 10 by framesCount:
    # ambiguous, refused in one line naming --annotation-fps; with --annotation-fps 20 its frame 21 (1 s) is
    # video frame 10, also when the session is opened again.
    import json

    from wecook_core.session.store import open_session
    from wecook_tui.cli import main

    video, _, hands = write_inputs(tmp_path, OBJECTS, HANDS)
    sequence = [{"frame": 1, "x": 10, "y": 10, "width": 10, "height": 10, "enabled": False, "time": 1 / 20},
                {"frame": 21, "x": 20, "y": 10, "width": 10, "height": 10, "enabled": False, "time": 21 / 20}]
    result = [{"type": "videorectangle", "value": {"framesCount": 30, "duration": 3.0, "sequence": sequence,
                                                   "labels": ["Knife"]}}]
    objects = tmp_path / "ls.json"
    objects.write_text(json.dumps(result))
    base = ["new", "s", "--video", str(video), "--objects", str(objects), "--hands", str(hands), "--categories",
            str(tmp_path / "cats.yaml"), "--root", str(tmp_path / "sessions")]
    (tmp_path / "cats.yaml").write_text("objects:\n  knife: tool\n")
    assert main(base) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "frame rate is ambiguous" in err and "--annotation-fps" in err
    assert main([*base, "--annotation-fps", "20"]) == 0
    assert "fps: 20" in (tmp_path / "sessions" / "s" / "session.yaml").read_text()
    knife = open_session(tmp_path / "sessions" / "s").load_observations().object("knife")
    assert knife.frames.tolist() == [0, 10]


def test_clipped_label_studio_boxes_are_named_at_the_annotations_own_frame(tmp_path: Path) -> None:
    # Annotated at 20 fps (framesCount 60 over 3 s) on the 10 fps video: its frame 21 is video frame 10.
    import json

    video, _, hands = write_inputs(tmp_path, OBJECTS, HANDS)
    sequence = [{"frame": 21, "x": 90, "y": 10, "width": 20, "height": 10, "enabled": False, "time": 21 / 20}]
    objects = tmp_path / "ls.json"
    objects.write_text(json.dumps([{"type": "videorectangle", "value": {"framesCount": 60, "duration": 3.0,
                                                                          "sequence": sequence, "labels": ["Knife"]}}]))
    imported = import_observations(video, objects, hands, categories=TABLE)
    assert imported.observations.object("knife").frames.tolist() == [10]
    assert any("by up to 16 px (track 1 (Knife) at frame 21)" in w for w in imported.warnings)
