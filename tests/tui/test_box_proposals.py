"""Pilot tests of box proposals in the box mode: p runs the COCO detector on the frame shown (in a worker), the
user keeps a proposal (a digit, a click, K for all), names it from its hint and tracks it like a drawn box; in the
workbench a session of a video alone opens the box mode with proposals ready. On tasty-a's real video, read in
place from the shared folder."""

from __future__ import annotations

from pathlib import Path

import pytest
from textual.app import App
from tui_driving import journal, pilot_test, settle, wait_for

from tests.square_video import moving_square
from wecook_core.errors import InputError
from wecook_core.formats.native import read_objects_csv
from wecook_core.observations.proposals import iou
from wecook_core.session.boxes import UNNAMED
from wecook_core.session.store import create_session
from wecook_tui import cli
from wecook_tui.app import WecookApp
from wecook_tui.screens import box_proposals
from wecook_tui.screens.boxes import BOX_BINDINGS, BoxScreen, BoxVideo, NameScreen
from wecook_tui.widgets.frame_view import FrameView

SIZE = (120, 45)
TASTY = (480, 480)


class BoxApp(App[None]):
    def __init__(self, screen: BoxScreen) -> None:
        super().__init__()
        self.box_screen = screen

    def on_mount(self) -> None:
        self.push_screen(self.box_screen)


def tasty(shared: Path) -> Path:
    return shared / "data" / "real" / "tasty-a"


def status(screen: BoxScreen) -> str:
    return str(screen.query_one("#box-status").render())


def drawn(screen: BoxScreen) -> list[str]:
    return [mark.name for mark in screen.query_one(FrameView).overlay.boxes]


def test_the_proposal_keys_have_ids_for_the_key_file() -> None:
    ids = {b.id for b in BOX_BINDINGS}
    assert {"boxes-propose", "boxes-keep-1", "boxes-keep-9", "boxes-keep-all"} <= ids
    assert len(ids) == len(BOX_BINDINGS)
    assert {b.key for b in BOX_BINDINGS if b.id == "boxes-propose"} == {"p"}


@pilot_test
@pytest.mark.slow
async def test_p_proposes_a_digit_keeps_n_names_from_the_hint_and_t_tracks(tmp_path: Path, shared: Path) -> None:
    folder = tasty(shared)
    (bowl,) = [t for t in read_objects_csv(folder / "objects.csv") if t.label == "bowl" and 210 in t.frames]
    truth = tuple(float(v) for v in bowl.boxes[list(bowl.frames).index(210)])
    screen = BoxScreen(BoxVideo(str(folder / "video.mp4"), TASTY, 5.0, 269), tmp_path / "out",
                       labels=lambda: ["bowl", "pan"], start=210)
    app = BoxApp(screen)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.pause()
        assert screen.proposals == {} and not any("?" in name for name in drawn(screen))  # nothing unasked
        await pilot.press("p")
        assert await wait_for(pilot, lambda: 210 in screen.proposals, 1500)
        await pilot.pause()
        shown = screen.shown_proposals()
        assert shown and "proposals: 1-9 or a click keeps one" in status(screen)
        number, proposal = max(shown, key=lambda item: iou(item[1].box, truth))
        assert iou(proposal.box, truth) >= 0.5 and proposal.hint == "bowl" and number <= 9
        assert f"{number} bowl?" in drawn(screen)  # drawn on the frame, numbered, with the hint
        # Another frame has none of them; back on frame 210 they are there again, without running again.
        await pilot.press("right")
        assert not any("?" in name for name in drawn(screen)) and "proposals" not in status(screen)
        await pilot.press("left")
        assert f"{number} bowl?" in drawn(screen)
        # The digit keeps it: a box at frame 210, the proposal's, unnamed; the proposal is no longer offered.
        await pilot.press(str(number))
        (track,) = screen.tracks
        assert track.label == UNNAMED and track.keyframes == {210: proposal.box}
        assert number not in dict(screen.shown_proposals()) and f"{number} bowl?" not in drawn(screen)
        # n asks for the name starting from the hint: enter takes it.
        await pilot.press("n")
        assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
        assert app.screen.query_one("#name-input").value == "bowl"  # type: ignore[attr-defined]
        await pilot.press("enter")
        assert await wait_for(pilot, lambda: app.screen is screen)
        assert screen.tracks[0].label == "bowl"
        await pilot.press("t")
        assert await wait_for(pilot, lambda: not screen.tracking, 3000)
        assert screen.tracks[0].tracked, "the tracker lost the kept box at once"
        # Undone back to before the keep, the proposal is offered again; p hides and shows them.
        await pilot.press("z", "z", "z")
        assert screen.tracks == [] and number in dict(screen.shown_proposals())
        await pilot.press("p")
        assert screen.shown_proposals() == [] and "proposals hidden" in status(screen)
        await pilot.press("p")
        assert number in dict(screen.shown_proposals())
        # K keeps every proposal shown.
        count = len(screen.shown_proposals())
        await pilot.press("K")
        assert len(screen.tracks) == count and screen.shown_proposals() == []
        assert f"all {count} proposals boxed" in status(screen)
        # A wrong hint is typed over: the prompt starts with it selected.
        assert screen.hints[screen.tracks[-1].track_id] == screen.proposals[210][-1].hint
        await pilot.press("n")
        assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
        await pilot.press(*"pan", "enter")
        assert await wait_for(pilot, lambda: app.screen is screen)
        assert screen.tracks[-1].label == "pan"


@pilot_test
async def test_a_failed_detector_says_why_in_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(path: str, frame: int) -> tuple[()]:
        raise InputError(None, "box proposals need onnxruntime: `pip install -e '.[proposals]'`")

    monkeypatch.setattr(box_proposals, "propose_at", broken)
    video = tmp_path / "square.avi"
    moving_square(video)
    screen = BoxScreen(BoxVideo(str(video), (320, 240), 10.0, 40), tmp_path / "out", labels=lambda: ["bowl"])
    app = BoxApp(screen)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("p")
        assert await wait_for(pilot, lambda: screen.proposing is None)
        await pilot.pause()
        assert any("Proposals failed: box proposals need onnxruntime" in str(n.message) for n in app._notifications)
        assert screen.proposals == {} and screen.tracks == []
        await pilot.press("1")  # nothing to keep: said, nothing made
        assert screen.tracks == []


@pilot_test
@pytest.mark.slow
async def test_a_session_of_a_video_alone_opens_box_mode_with_proposals_ready(
        tmp_path: Path, shared: Path, scenario_inputs: tuple[Path, Path, Path],
        capsys: pytest.CaptureFixture[str]) -> None:
    folder = tasty(shared)
    root = tmp_path / "sessions"
    assert cli.main(["new", "alone", "--video", str(folder / "video.mp4"), "--hands", str(folder / "hands.csv"),
                     "--root", str(root)]) == 0
    assert "objects  none yet: in the workbench's box mode (B) keep the boxes it proposes" in capsys.readouterr().out
    path = root / "alone"
    app = WecookApp(path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        assert app.obs.objects == ()
        await pilot.press("B")
        assert await wait_for(pilot, lambda: isinstance(app.screen, BoxScreen))
        screen = app.screen
        assert isinstance(screen, BoxScreen)
        assert await wait_for(pilot, lambda: screen.frame in screen.proposals, 1500)  # nobody pressed p
        await pilot.pause()
        shown = screen.shown_proposals()
        assert shown, "no proposal on the first frame"
        # A click on a proposal keeps it, journaled like a drawn box.
        _, proposal = min(shown, key=lambda item: (item[1].box[2] - item[1].box[0]) * (item[1].box[3] - item[1].box[1]))
        view = screen.query_one(FrameView)
        pad, columns, rows = view._layout()
        x, y = (proposal.box[0] + proposal.box[2]) / 2, (proposal.box[1] + proposal.box[3]) / 2
        await pilot.click(FrameView, offset=(pad + int(x / TASTY[0] * columns), int(y / TASTY[1] * rows)))
        assert await wait_for(pilot, lambda: len(screen.tracks) == 1)
        assert screen.tracks[0].keyframes == {screen.frame: proposal.box}
        assert [e["op"] for e in journal(path)] == ["box_keyframe"]
        await pilot.press("escape")
        assert await wait_for(pilot, lambda: app.screen is app.main)
    # A session with imported boxes opens the box mode without running the detector.
    video, objects, hands = scenario_inputs
    boxed = Path(create_session(root, "boxed", video, objects, hands))
    again = WecookApp(boxed)
    async with again.run_test(size=SIZE) as pilot:
        await settle(pilot, again)
        await pilot.press("B")
        assert await wait_for(pilot, lambda: isinstance(again.screen, BoxScreen))
        await pilot.pause(0.2)
        assert again.screen.proposals == {} and again.screen.proposing is None  # type: ignore[attr-defined]
