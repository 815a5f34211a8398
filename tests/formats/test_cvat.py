from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.formats.cvat import read_cvat

GOOD = """<?xml version="1.0" encoding="utf-8"?>
<annotations>
  <version>1.1</version>
  <meta><task><original_size><width>640</width><height>480</height></original_size></task></meta>
  <track id="0" label="Chopping board" source="manual">
    <box frame="0" outside="0" occluded="0" keyframe="1" xtl="10" ytl="20" xbr="110" ybr="220" z_order="0"></box>
    <box frame="1" outside="0" occluded="1" keyframe="0" xtl="12" ytl="20" xbr="112" ybr="220" z_order="0"></box>
    <box frame="2" outside="1" occluded="0" keyframe="1" xtl="12" ytl="20" xbr="112" ybr="220" z_order="0"></box>
    <box frame="5" outside="0" occluded="0" keyframe="1" xtl="0" ytl="0" xbr="10" ybr="10" z_order="0"></box>
  </track>
  <track id="3" label="bowl" source="manual">
    <box frame="2" outside="0" occluded="0" keyframe="1" xtl="0" ytl="0" xbr="40" ybr="40" z_order="0">
      <attribute name="state">full</attribute>
    </box>
    <box frame="6" outside="0" occluded="0" keyframe="1" xtl="40" ytl="0" xbr="80" ybr="40" z_order="0"></box>
  </track>
  <track id="4" label="bowl" source="manual">
    <box frame="0" outside="0" occluded="0" keyframe="1" xtl="1" ytl="1" xbr="2" ybr="2"/>
  </track>
</annotations>
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "boxes.xml"
    path.write_text(text)
    return path


def test_tracks_boxes_outside_and_interpolation(tmp_path: Path) -> None:
    tracks = read_cvat(write(tmp_path, GOOD))
    board, bowl, bowl2 = tracks
    assert (board.track_id, board.label, board.name) == (0, "Chopping board", "chopping_board")
    assert board.frames.tolist() == [0, 1, 5]  # frames 2-4 are outside
    assert board.boxes[1].tolist() == [12, 20, 112, 220]
    assert (bowl.name, bowl2.name) == ("bowl", "bowl_2")
    # keyframes 2 and 6 interpolate linearly in between
    assert bowl.frames.tolist() == [2, 3, 4, 5, 6]
    np.testing.assert_allclose(bowl.boxes[:, 0], [0, 10, 20, 30, 40])
    assert bowl.boxes.dtype == np.float64 and bowl.frames.dtype == np.int64


def test_frame_size_must_match_the_annotation(tmp_path: Path) -> None:
    path = write(tmp_path, GOOD)
    assert len(read_cvat(path, frame_size=(640, 480))) == 3
    with pytest.raises(InputError, match="annotated on 640x480 frames but the video is 1280x720"):
        read_cvat(path, frame_size=(1280, 720))


def test_non_box_tracks_are_skipped_with_a_warning(tmp_path: Path) -> None:
    text = GOOD.replace("</annotations>", """<track id="9" label="spill"><polygon frame="0" outside="0"
     points="1,1;2,2;3,1"/></track></annotations>""")
    warnings: list[str] = []
    tracks = read_cvat(write(tmp_path, text), warn=warnings.append)
    assert len(tracks) == 3
    assert len(warnings) == 1 and "track 9" in warnings[0] and "polygon" in warnings[0]


@pytest.mark.parametrize(
    ("old", "new", "message", "line"),
    [
        ('xtl="12" ytl="20" xbr="112" ybr="220" z_order="0"></box>\n    <box frame="2"',
         'xtl="12" ytl="20" xbr="1" ybr="220" z_order="0"></box>\n    <box frame="2"', "negative width", 7),
        ('<box frame="1"', '<box frame="one"', "frame must be a number", 7),
        ('<box frame="1" outside="0" occluded="1" keyframe="0" xtl="12"',
         '<box frame="1" outside="0" occluded="1" keyframe="0" xtl="nan"', "finite", 7),
        ('<box frame="1" outside="0"', '<box frame="1" outside="maybe"', "outside must be", 7),
        ('<box frame="1" outside="0" occluded="1" keyframe="0" xtl="12" ytl="20" ',
         '<box frame="1" outside="0" occluded="1" keyframe="0" ytl="20" ', "missing xtl", 7),
        ('<box frame="5"', '<box frame="1"', "increasing frame order", 9),
        ('<track id="3" label="bowl"', '<track id="3" label=""', "no label", 11),
        ('<track id="4" label="bowl"', '<track id="0" label="bowl"', "used twice", 17),
    ],
)
def test_bad_elements_name_their_line(tmp_path: Path, old: str, new: str, message: str, line: int) -> None:
    assert old in GOOD
    text = GOOD.replace(old, new, 1)
    with pytest.raises(InputError, match=message) as error:
        read_cvat(write(tmp_path, text))
    assert f"line {line}:" in str(error.value)
    assert str(tmp_path / "boxes.xml") in str(error.value)


def test_malformed_xml_gives_line_and_column(tmp_path: Path) -> None:
    text = GOOD.replace('<box frame="5"', '<box frame="5" <oops', 1)
    with pytest.raises(InputError, match=r"line 9, column 20: malformed XML") as error:
        read_cvat(write(tmp_path, text))
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty file"),
        ("<tasks></tasks>", "root element is <tasks>"),
        ("<annotations><image id='0' name='a.jpg'><box label='x' xtl='0' ytl='0' xbr='1' ybr='1'/></image>"
         "</annotations>", "CVAT for images"),
        ("<annotations><track id='0' label='x'><box frame='0' outside='1' xtl='0' ytl='0' xbr='1' ybr='1'/>"
         "</track></annotations>", "no boxes"),
        ("<annotations><track label='x'></track></annotations>", "no id"),
    ],
)
def test_bad_files(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(InputError, match=message):
        read_cvat(write(tmp_path, text))


def test_missing_file_and_folder(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="not found"):
        read_cvat(tmp_path / "nope.xml")
    with pytest.raises(InputError, match="directory"):
        read_cvat(tmp_path)


KEYFRAMES = """<?xml version="1.0" encoding="utf-8"?>
<annotations>
  <version>1.1</version>
  <track id="3" label="spoon" source="manual">
    <box frame="0" keyframe="1" outside="0" occluded="0" xtl="0" ytl="0" xbr="10" ybr="10"></box>
    <box frame="{far}" keyframe="1" outside="0" occluded="0" xtl="100" ytl="0" xbr="110" ybr="10"></box>
    <box frame="{end}" keyframe="1" outside="1" occluded="0" xtl="100" ytl="0" xbr="110" ybr="10"></box>
  </track>
</annotations>
"""


def test_keyframes_only_are_interpolated_as_cvat_does(tmp_path: Path) -> None:
    (spoon,) = read_cvat(write(tmp_path, KEYFRAMES.format(far=10, end=11)), frame_count=20)
    assert spoon.frames.tolist() == list(range(11))  # outside from frame 11 on
    np.testing.assert_allclose(spoon.boxes[:, 0], np.arange(11) * 10.0)


def test_a_keyframe_far_past_the_video_is_refused_before_interpolating(tmp_path: Path) -> None:
    # Issue 13: boxes at frame 0 and 1,000,000,000 grew memory until the process was killed (that frame is past
    # MAX_FRAME now; one within it but far past the video must be refused before interpolating too).
    path = write(tmp_path, KEYFRAMES.format(far=9_000_000, end=9_000_001))
    with pytest.raises(InputError, match=r"boxes.xml:line 7: track 3 \(spoon\) has a box at frame 9000001, but "
                                         r"the video has frames 0-19") as error:
        read_cvat(path, frame_count=20)
    assert "\n" not in str(error.value)
    with pytest.raises(InputError, match="span more than 5,000,000 frames"):
        read_cvat(path)  # no video: the interpolation is bounded all the same


DATA = Path(__file__).parent / "data"


def test_skeleton_points_and_polyline_tracks_are_skipped_and_box_tracks_kept() -> None:
    # Shaped like an app.cvat.ai job export: a skeleton track (parts as <points> in <skeleton>), one whose parts
    # are nested <track> elements (an older export, which used to reject the whole file), a polyline track, and
    # box tracks.
    warnings: list[str] = []
    knife, knife_2 = read_cvat(DATA / "cvat_video_mixed.xml", frame_size=(640, 360), warn=warnings.append)
    skipped = [w for w in warnings if "skipped" in w]
    assert len(skipped) == 3
    assert any("line 78: track 1 (hand) holds skeleton, not boxes; skipped" in w for w in skipped)
    assert any("track 2 (hand) holds skeleton" in w for w in skipped)
    assert any("track 4 (board edge) holds polyline" in w for w in skipped)
    # The last keyframe (frame 4) is not outside: CVAT holds the box to the end of the job (stop_frame 11).
    assert knife.frames.tolist() == list(range(12))
    np.testing.assert_allclose(knife.boxes[2], [120, 50, 180, 70])  # interpolated between 0 and 4
    np.testing.assert_allclose(knife.boxes[11], [140, 50, 200, 70])
    # Rotated by 90 degrees about its centre (320, 110): the 40x20 box stands 20x40; outside from frame 8.
    assert knife_2.frames.tolist() == [6, 7]
    np.testing.assert_allclose(knife_2.boxes[0], [310, 90, 330, 130])
    assert any("2 rotated boxes taken as the axis-aligned boxes around them" in w for w in warnings)


def test_a_track_not_outside_at_its_end_holds_to_the_videos_last_frame(tmp_path: Path) -> None:
    # No <stop_frame> in the file: the video's frames bound the task.
    (spoon,) = read_cvat(write(tmp_path, KEYFRAMES.format(far=10, end=11).replace('outside="1"', 'outside="0"')),
                         frame_count=20)
    assert spoon.frames.tolist() == list(range(20))
    np.testing.assert_allclose(spoon.boxes[-1], [100, 0, 110, 10])
    (alone,) = read_cvat(write(tmp_path, KEYFRAMES.format(far=10, end=11).replace('outside="1"', 'outside="0"')))
    assert alone.frames.tolist() == list(range(12))  # no video, no stop_frame: ends at its last box
