from __future__ import annotations

from pathlib import Path

import pytest
from grey_video import write_grey_video

from wecook_core.errors import InputError
from wecook_core.formats.video import frame_count_note, probe_video, usable_frames


def write_video(path: Path, frames: int = 40, size: tuple[int, int] = (64, 48), fps: float = 10.0) -> Path:
    return write_grey_video(path, frames, size, fps)


def test_probe_reads_fps_size_and_checks_the_declared_count(tmp_path: Path) -> None:
    info = probe_video(write_video(tmp_path / "v.avi", frames=40, size=(64, 48), fps=12.5))
    assert (info.fps, info.frame_count, info.width, info.height) == (12.5, 40, 64, 48)
    assert info.decoded_frames == 40
    assert usable_frames(info) == 40
    assert frame_count_note(info) is None


def test_truncated_video_reports_the_frames_that_decode(tmp_path: Path) -> None:
    whole = write_video(tmp_path / "whole.avi", frames=50)
    data = whole.read_bytes()
    cut = tmp_path / "cut.avi"
    cut.write_bytes(data[: int(len(data) * 0.6)])
    info = probe_video(cut)
    assert info.frame_count == 50
    assert info.decoded_frames is not None and 20 <= info.decoded_frames < 40
    counted = probe_video(cut, count_frames=True)
    assert counted.decoded_frames == info.decoded_frames  # the cheap search agrees with decoding everything
    note = frame_count_note(info)
    assert note is not None and "declares 50 frames" in note and str(cut) in note
    assert usable_frames(info) == info.decoded_frames


def test_count_frames_decodes_everything(tmp_path: Path) -> None:
    info = probe_video(write_video(tmp_path / "v.avi", frames=17), count_frames=True)
    assert info.decoded_frames == 17


@pytest.mark.parametrize("content", [b"", b"this is not a video at all\n" * 10])
def test_a_file_that_is_not_a_video_is_an_input_error(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "bad.mp4"
    path.write_bytes(content)
    with pytest.raises(InputError) as error:
        probe_video(path)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


def test_missing_video_and_folder(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such video"):
        probe_video(tmp_path / "nope.mp4")
    with pytest.raises(InputError, match="directory"):
        probe_video(tmp_path)
