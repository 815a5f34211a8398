"""Pilot tests of the box mode: draw (keys and mouse), name, track with OpenCV, correct, undo, export."""

from __future__ import annotations

from pathlib import Path

import pytest
from textual.app import App
from tui_driving import pilot_test, wait_for

from tests.square_video import moving_square
from wecook_core.formats.cvat import read_cvat
from wecook_core.formats.native import read_objects_csv
from wecook_tui.screens.boxes import BoxScreen, BoxVideo, NameScreen

SIZE = (100, 40)
LABELS = ["tomato", "knife", "bowl"]


class BoxApp(App[None]):
    def __init__(self, screen: BoxScreen) -> None:
        super().__init__()
        self.box_screen = screen

    def on_mount(self) -> None:
        self.push_screen(self.box_screen)


def make(tmp_path: Path) -> tuple[BoxApp, BoxScreen, list[tuple[float, float, float, float]]]:
    video = tmp_path / "square.avi"
    truth = moving_square(video)
    screen = BoxScreen(BoxVideo(str(video), (320, 240), 10.0, 40), tmp_path / "out", labels=lambda: LABELS)
    return BoxApp(screen), screen, truth


@pilot_test
@pytest.mark.slow
async def test_draw_with_keys_name_track_and_export(tmp_path: Path) -> None:
    app, screen, truth = make(tmp_path)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("b", "n")  # a box in the middle; n asks for its name
        assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
        await pilot.press(*"tomato", "enter")
        assert await wait_for(pilot, lambda: app.screen is screen)
        (track,) = screen.tracks
        assert track.label == "tomato" and list(track.keyframes) == [0]
        # Keys move and resize the box onto the square (its frame-0 box is 30,80-70,120).
        before = track.keyframes[0]
        await pilot.press("a", "a", "W")
        moved = screen.tracks[0].keyframes[0]
        assert moved[0] < before[0] and moved[3] < before[3]
        assert moved[2] - moved[0] == pytest.approx(before[2] - before[0])  # journaled to 0.1 px
        screen.set_keyframe(truth[0])  # the box fitted exactly at frame 0 (a keyframe)
        await pilot.press("t")
        assert await wait_for(pilot, lambda: not screen.tracking, 3000)  # OpenCV in a worker: slow on a busy machine
        assert screen.tracks[0].tracked, "the tracker lost the box at once"
        tracked = screen.tracks[0]
        assert len(tracked.tracked) >= 20 and tracked.lost_at is not None  # the square vanishes at frame 30
        await pilot.press("right", "right", "right")
        assert screen.frame == 3
        # A correction at frame 3 is a keyframe; frames 1-2 are interpolated; undo brings the track back.
        await pilot.press("s")
        assert sorted(screen.tracks[0].keyframes) == [0, 3] and not screen.tracks[0].tracked
        await pilot.press("z")
        assert screen.tracks[0] == tracked
        await pilot.press("e")
        (back,) = read_cvat(tmp_path / "out" / "boxes.xml", frame_size=(320, 240), frame_count=40)
        assert back.label == "tomato" and back.frames.tolist() == tracked.object_track().frames.tolist()
        (csv,) = read_objects_csv(tmp_path / "out" / "boxes.csv")
        assert len(csv.frames) == len(back.frames)


@pilot_test
@pytest.mark.slow
async def test_a_mouse_drag_draws_a_box_and_a_second_box_is_separate(tmp_path: Path) -> None:
    app, screen, _ = make(tmp_path)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.pause()
        await pilot.mouse_down("#box-frame", offset=(40, 5))
        await pilot.mouse_up("#box-frame", offset=(60, 15))
        await pilot.press("n")
        assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
        await pilot.press("escape")
        assert await wait_for(pilot, lambda: app.screen is screen)
        (track,) = screen.tracks
        x1, y1, x2, y2 = track.keyframes[0]
        assert x2 - x1 > 10 and y2 - y1 > 10  # drawn by the drag, in video pixels
        assert track.label == "object"  # the name prompt was cancelled
        await pilot.press("b", "n")
        assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
        await pilot.press(*"bowl", "enter")
        assert await wait_for(pilot, lambda: app.screen is screen)
        assert [t.label for t in screen.tracks] == ["object", "bowl"] and screen.selected == 1
        await pilot.press("x")  # dropping its only keyframe removes the box
        assert [t.label for t in screen.tracks] == ["object"]


@pilot_test
@pytest.mark.slow
async def test_the_workbench_opens_box_mode_on_its_video(session_path: Path) -> None:
    from tui_driving import settle

    from wecook_tui.app import WecookApp

    app = WecookApp(session_path)
    async with app.run_test(size=(150, 45)) as pilot:
        await settle(pilot, app)
        await pilot.press("B")
        assert await wait_for(pilot, lambda: isinstance(app.screen, BoxScreen))
        screen = app.screen
        assert isinstance(screen, BoxScreen)
        assert screen.video.path == app.obs.video.path and screen.out_dir == session_path / "boxes"
        await pilot.press("escape")
        assert await wait_for(pilot, lambda: app.screen is app.main)


def status(screen: BoxScreen) -> str:
    return str(screen.query_one("#box-status").render())


@pilot_test
async def test_keys_typed_after_b_fit_the_box_and_name_it_only_when_asked(tmp_path: Path) -> None:
    """A new user's first keys after b are WASD, to move the box: they move it (the screen keeps the keys), and
    the box is named only when n asks for the name."""
    app, screen, _ = make(tmp_path)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("b")
        await pilot.pause()
        assert app.screen is screen
        (track,) = screen.tracks
        before = track.keyframes[0]
        await pilot.press("d", "d", "s", "w", "s")
        await pilot.pause()
        assert app.screen is screen, "the keys went to a prompt"
        (track,) = screen.tracks
        assert track.label == "object" and "unnamed: n names it" in status(screen)
        after = track.keyframes[0]
        assert after[0] == pytest.approx(before[0] + 2 * 0.02 * 320, abs=0.1)
        assert after[1] == pytest.approx(before[1] + 0.02 * 240, abs=0.1)
        await pilot.press("n")
        assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
        await pilot.press(*"knife", "enter")
        assert await wait_for(pilot, lambda: app.screen is screen)
        assert [t.label for t in screen.tracks] == ["knife"]
        await pilot.press("a")  # the keys act on the box again once the name is given
        assert screen.tracks[0].keyframes[0][0] == pytest.approx(after[0] - 0.02 * 320, abs=0.1)


@pilot_test
async def test_box_mode_counts_frames_from_zero_as_the_review_screen(tmp_path: Path) -> None:
    app, screen, _ = make(tmp_path)
    async with app.run_test(size=SIZE) as pilot:
        await pilot.pause()
        assert status(screen).startswith("frame 0/39 (0.00 s)")
        await pilot.press("b", "right", "right", "s")
        await pilot.pause()
        assert screen.frame == 2 and status(screen).startswith("frame 2/39 (0.20 s)")
        assert "keyframes 0, 2;" in status(screen)
