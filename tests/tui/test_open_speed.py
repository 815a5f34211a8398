"""Opening shows the video first: the first picture does not wait for the boxes, hands and commonsense tables."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest
from tui_driving import pilot_test, wait_for
from tui_fake import fake_workspace

from wecook_tui.app import WecookApp
from wecook_tui.frames import FrameSource
from wecook_tui.widgets.frame_view import FrameView
from wecook_tui.workspace import open_video


@pilot_test
@pytest.mark.slow
async def test_the_video_shows_before_the_session_is_open(tmp_path: Path) -> None:
    opener, analyzer = fake_workspace(tmp_path)
    gate = threading.Event()
    given: list[FrameSource | None] = []

    def slow_opener(path: Path, frames: FrameSource | None = None):  # type: ignore[no-untyped-def]
        given.append(frames)
        gate.wait(10)  # importing the observations takes a while
        return opener(path)

    app = WecookApp(tmp_path / "kitchen", opener=slow_opener, analyzer=analyzer,
                    video_opener=lambda path: FrameSource(tmp_path / "video.avi"))
    async with app.run_test(size=(120, 40)) as pilot:
        view = app.main.query_one(FrameView)
        await wait_for(pilot, lambda: view.first_painted, 200)
        assert app.opened is None and app.analysis is None  # the picture came first
        assert view.shown == 0 and given and given[0] is view.source  # and the opener is handed the same video
        assert view.source is not None and view.source.cached(5) is None  # nothing decoded ahead meanwhile
        gate.set()
        await wait_for(pilot, lambda: app.analysis is not None, 400)
        assert app.opened is not None and view.overlay.boxes  # then the boxes, then the analysis
        await wait_for(pilot, lambda: view.source is not None and view.source.cached(5) is not None, 200)
        assert view.source.cached(5) is not None  # and decoding ahead


def test_open_video_reads_the_session_yaml_only(tmp_path: Path) -> None:
    from tui_fake import make_video

    from wecook_core.session.store import create_session

    inputs = tmp_path / "inputs"
    inputs.mkdir()
    video = make_video(inputs / "video.avi", frames=30)
    (inputs / "objects.csv").write_text("frame,track_id,label,x1,y1,x2,y2\n" + "".join(
        f"{f},1,bowl,10,10,50,50\n" for f in range(30)))
    (inputs / "hands.csv").write_text("frame,hand,x,y,x1,y1,x2,y2\n" + "".join(
        f"{f},RH_P1,100,100,90,90,110,110\n" for f in range(30)))
    session = Path(create_session(tmp_path / "sessions", "s", video, inputs / "objects.csv", inputs / "hands.csv"))
    frames = open_video(session)
    assert frames is not None and frames.ok and frames.path == video.resolve()
    assert open_video(tmp_path / "not-a-session") is None
    video.write_bytes(b"not a video")
    assert open_video(session) is None  # the full open says what is wrong
