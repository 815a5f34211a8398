"""A missing or corrupt video, a changed input file, a torn journal line, a folder that is no session: the
workbench opens anyway (or says why not) with a clear notice, never a traceback."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from textual.notifications import Notify
from tui_driving import journal, pilot_test, settle

from wecook_core.model import SegmentStatus
from wecook_tui.app import WecookApp
from wecook_tui.messages import SessionFailed
from wecook_tui.widgets.frame_view import FrameView

SIZE = (150, 45)


@pytest.fixture
def own_session(tmp_path: Path, scenario_inputs: tuple[Path, Path, Path]) -> Path:
    """A session over private copies of the inputs, so a test may damage them."""
    from wecook_core.session.store import create_session

    folder = tmp_path / "inputs"
    folder.mkdir()
    copies = [Path(shutil.copy(path, folder / path.name)) for path in scenario_inputs]
    return Path(create_session(tmp_path / "sessions", "kitchen", *copies))


def video_of(session: Path) -> Path:
    return session.parent.parent / "inputs" / "video.mp4"


def collecting(notices: list[str]) -> Callable[[object], None]:
    """A message hook that appends each notice's text to ``notices`` (``FAILED ...`` when the session fails)."""

    def hook(message: object) -> None:
        if isinstance(message, Notify):
            notices.append(message.notification.message)
        elif isinstance(message, SessionFailed):
            notices.append("FAILED " + message.error)

    return hook


async def open_and_collect(session: Path) -> tuple[WecookApp, list[str]]:
    notices: list[str] = []
    app = WecookApp(session)
    async with app.run_test(size=SIZE, message_hook=collecting(notices)) as pilot:
        if "FAILED" not in " ".join(notices):
            await settle(pilot, app)
        await pilot.press("right", "a")  # keys still work (or are harmless) whatever is wrong
        await pilot.pause()
        notices.append("VIEW " + str(app.main.query_one(FrameView).message))
    return app, notices


@pilot_test
@pytest.mark.slow
async def test_missing_video_opens_with_a_notice_and_boxes(own_session: Path) -> None:
    video_of(own_session).unlink()
    app, notices = await open_and_collect(own_session)
    assert any("video" in n and "video.mp4" in n for n in notices), notices
    assert app.obs is not None and app.analysis is not None  # boxes and hands still analysed
    assert notices[-1] != "VIEW None"  # the frame view says why there is no picture
    assert journal(own_session)[-1]["op"] == "set_status"  # and corrections are still journaled


@pilot_test
@pytest.mark.slow
async def test_corrupt_video_opens_with_a_notice(own_session: Path) -> None:
    video_of(own_session).write_bytes(b"\x00garbage" * 1000)
    app, notices = await open_and_collect(own_session)
    assert any("video.mp4" in n for n in notices), notices
    assert app.analysis is not None
    assert notices[-1].startswith("VIEW") and "video.mp4" in notices[-1]


@pilot_test
@pytest.mark.slow
async def test_changed_input_file_is_reported(own_session: Path) -> None:
    objects = own_session.parent.parent / "inputs" / "objects.csv"
    objects.write_text(objects.read_text().replace("bowl", "pot"))
    app, notices = await open_and_collect(own_session)
    assert any("objects.csv" in n and "changed" in n for n in notices), notices
    assert app.analysis is not None


@pilot_test
@pytest.mark.slow
async def test_torn_journal_line_is_reported_and_skipped(own_session: Path) -> None:
    from wecook_core.session.store import open_session

    open_session(own_session).record({"op": "set_status", "segment": 0, "status": "accepted"})
    with (own_session / "journal.jsonl").open("a") as f:
        f.write('{"seq": 2, "time": "2026-01-01T00:00:00Z", "op": "set_st')
    app, notices = await open_and_collect(own_session)
    assert any("journal" in n for n in notices), notices
    assert app.corrections.status[0] is SegmentStatus.ACCEPTED


@pilot_test
@pytest.mark.slow
async def test_not_a_session_says_so(tmp_path: Path) -> None:
    folder = tmp_path / "nothing"
    folder.mkdir()
    notices: list[str] = []
    app = WecookApp(folder)
    async with app.run_test(size=SIZE, message_hook=lambda m: notices.append(m.error)
                            if isinstance(m, SessionFailed) else None) as pilot:
        await app.workers.wait_for_complete()
        await pilot.pause()
        await pilot.press("right", "a", "c", "e")
        assert app.screen is app.main
    assert notices and "session" in notices[0]


@pilot_test
@pytest.mark.slow
async def test_journal_written_by_another_wecook_is_refused_not_fatal(own_session: Path) -> None:
    from wecook_core.session.store import open_session

    notices: list[str] = []
    app = WecookApp(own_session)
    async with app.run_test(size=SIZE, message_hook=collecting(notices)) as pilot:
        await settle(pilot, app)
        open_session(own_session).record({"op": "set_status", "segment": 0, "status": "rejected"})
        await pilot.press("a")
        await pilot.pause()
        assert app.screen is app.main
    assert [e["status"] for e in journal(own_session)] == ["rejected"]  # nothing half-written
    assert any("Not recorded" in n and "journal" in n for n in notices), notices


@pilot_test
@pytest.mark.slow
async def test_undo_and_redo_refused_by_the_journal_are_notices_not_tracebacks(own_session: Path) -> None:
    from wecook_core.session.store import open_session

    notices: list[str] = []
    app = WecookApp(own_session)
    async with app.run_test(size=SIZE, message_hook=collecting(notices)) as pilot:
        await settle(pilot, app)
        await pilot.press("a", "z")  # accept, undo: the journal says so
        await settle(pilot, app)
        assert [e["op"] for e in journal(own_session)] == ["set_status", "undo"]
        open_session(own_session).record({"op": "set_status", "segment": 0, "status": "rejected"})
        await pilot.press("y")  # redo, but another wecook wrote the journal meanwhile
        await pilot.pause()
        assert app.screen is app.main
        assert [e["op"] for e in journal(own_session)] == ["set_status", "undo", "set_status"]
        assert any("journal" in n and "changed" in n for n in notices), notices

        def full_disk(op: str, fields: dict) -> None:
            raise OSError(28, "No space left on device")

        app.session.journal._append = full_disk  # type: ignore[method-assign]
        notices.clear()
        await pilot.press("y")  # redo again, and the disk refuses
        await pilot.pause()
        assert app.screen is app.main
        assert any("No space left" in n for n in notices), notices
