"""Issue 28, odd videos read right: a variable frame rate counted by decoding, a container rate of 0 refused
naming ``--fps`` (and the rate given taken), a resolution limit, a symbolic link loop named as one, and a session
made with relative paths found from any folder."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from odd_video import variable_rate_mp4, write_mp4, zero_rate_mp4

import wecook_core.formats.video as video
from wecook_core.errors import InputError
from wecook_core.formats.video import probe_video
from wecook_tui.cli import main


@pytest.mark.parametrize("rates", [(45, 24), (24, 45)])
def test_a_variable_frame_rate_is_counted_by_decoding(tmp_path: Path, rates: tuple[int, int]) -> None:
    """All 1,594 frames decoded in order, but seeking said 1,592 (45 fps then 24) or more than there are."""
    path = variable_rate_mp4(tmp_path / "vfr.mp4", 400, rates)
    info = probe_video(path)
    assert info.frame_count == 400 and info.decoded_frames == 400
    assert video.frame_count_note(info) is None  # no false "declared but decode" warning


def test_a_frame_rate_of_zero_is_refused_naming_fps(tmp_path: Path) -> None:
    """A media timescale of 0 was taken as 0.002 fps, with a false "declared but decode" warning."""
    path = zero_rate_mp4(tmp_path / "zero.mp4")
    with pytest.raises(InputError, match=r"no usable frame rate .*give the rate with --fps") as caught:
        probe_video(path)
    assert str(caught.value).startswith(str(path))
    info = probe_video(path, fps=24.0)
    assert info.fps == 24.0 and info.frame_count == info.decoded_frames  # counted, not derived from the header
    with pytest.raises(InputError, match="--fps 5000: expected a frame rate from 1 to 1000"):
        probe_video(path, fps=5000.0)


def test_new_says_fps_and_takes_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = zero_rate_mp4(tmp_path / "zero.mp4", frames=30)
    hands = tmp_path / "hands.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n0,RH_P1,20,20,15,15,25,25\n")
    argv = ["new", "z", "--root", str(tmp_path / "s"), "--video", str(path), "--hands", str(hands)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--fps" in err and str(path) in err
    assert main([*argv, "--fps", "12"]) == 0
    from wecook_core.session.store import open_session

    shutil.rmtree(tmp_path / "s" / "z" / "cache", ignore_errors=True)  # the video is probed again
    session = open_session(tmp_path / "s" / "z")
    assert session.video_fps == 12.0 and session.load_observations().video.fps == 12.0


def test_a_resolution_past_the_limit_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """An 8000x8000 video took 1.1 GB in ``hands``: frames past MAX_PIXELS are refused before one decodes."""
    path = write_mp4(tmp_path / "big.mp4", 3, size=(64, 48))
    assert video.MAX_PIXELS == 7680 * 4320
    monkeypatch.setattr(video, "MAX_PIXELS", 64 * 48 - 1)
    with pytest.raises(InputError, match=r"frames of 64x48 pixels are more than wecook reads .*scale the video"):
        probe_video(path)


def test_a_symbolic_link_loop_is_named_as_one(tmp_path: Path) -> None:
    """It said "no such video file"."""
    a, b = tmp_path / "a.mp4", tmp_path / "b.mp4"
    os.symlink(b, a)
    os.symlink(a, b)
    with pytest.raises(InputError, match="is a loop of symbolic links"):
        probe_video(a)


def test_a_session_made_with_relative_paths_is_analysed_from_anywhere(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """Analysed from another folder, it silently skipped its shot cuts: the cache kept the relative path."""
    from session_inputs import make_inputs

    make_inputs(tmp_path / "in")
    monkeypatch.chdir(tmp_path)
    assert main(["new", "rel", "--root", "sessions", "--video", "in/take.avi", "--objects", "in/objects.csv",
                 "--hands", "in/openpose"]) == 0
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    assert main(["analyze", str(tmp_path / "sessions" / "rel")]) == 0
    from wecook_core.session.store import open_session

    obs = open_session(tmp_path / "sessions" / "rel").load_observations()
    assert obs.video.path == str(tmp_path / "in" / "take.avi")
    assert (tmp_path / "sessions" / "rel" / "shots.json").is_file()  # the video was found, its cuts looked for
