"""Pilot tests of boxes drawn in the workbench: journaled like every correction, undone and redone from the review
screen, kept across quitting and reopening, and analysed (a session of a video and hands alone gets its trees
from them); labels nothing categorises are asked about and the answers journaled."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import journal, pick, pilot_test, settle, wait_for
from tui_scenario import hand_path

from wecook_core.model import Category
from wecook_core.session.boxes import fold_boxes
from wecook_core.session.store import create_session
from wecook_tui.app import WecookApp
from wecook_tui.screens.boxes import BoxScreen, NameScreen
from wecook_tui.screens.help import HelpScreen
from wecook_tui.screens.picker import PickerScreen

SIZE = (150, 45)


def video_alone(tmp_path: Path, scenario_inputs: tuple[Path, Path, Path]) -> Path:
    video, _, hands = scenario_inputs
    return Path(create_session(tmp_path / "sessions", "alone", video, None, hands))


async def name(pilot, app, label: str) -> None:  # type: ignore[no-untyped-def]
    assert await wait_for(pilot, lambda: isinstance(app.screen, NameScreen))
    await pilot.press(*label, "enter")
    assert await wait_for(pilot, lambda: isinstance(app.screen, BoxScreen))


@pilot_test
@pytest.mark.slow
async def test_boxes_drawn_in_the_workbench_are_journaled_undone_from_review_and_give_trees(
        tmp_path: Path, scenario_inputs: tuple[Path, Path, Path]) -> None:
    path = video_alone(tmp_path, scenario_inputs)
    app = WecookApp(path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        assert app.obs.objects == () and app.analysis.trees == ()
        await pilot.press("B")
        assert await wait_for(pilot, lambda: isinstance(app.screen, BoxScreen))
        screen = app.screen
        assert isinstance(screen, BoxScreen)
        # The board: drawn (b, named), fitted, tracked by OpenCV through the video.
        await pilot.press("b", "n")
        await name(pilot, app, "chopping board")
        screen.set_keyframe((120.0, 70.0, 230.0, 150.0))
        await pilot.press("t")
        assert await wait_for(pilot, lambda: not screen.tracking, 3000)  # OpenCV in a worker: slow on a busy machine
        assert screen.tracks[0].tracked, "the tracker lost the box at once"
        assert len(screen.tracks[0].boxes()) > 80
        # The knife: carried by the hand, so keyframed every few frames (interpolated between).
        right = hand_path()
        screen.add_box((35.0, 54.0, 65.0, 64.0), "knife")
        for frame in range(12, 90, 4):
            screen.frame = frame
            hx, hy = right[frame]
            screen.set_keyframe((hx - 25, hy - 6, hx + 5, hy + 4))
        ops = [e["op"] for e in journal(path)]
        assert ops.count("box_keyframe") == 2 + 1 + len(range(12, 90, 4)) and "box_tracked" in ops
        assert "box_label" in ops  # the board was named at the prompt
        await pilot.press("escape")
        assert await wait_for(pilot, lambda: app.screen is app.main)
        await settle(pilot, app)
        assert {t.name for t in app.obs.objects} == {"chopping_board", "knife"}
        assert app.obs.categories["knife"] is Category.TOOL
        trees = [str(t.tree) for t in app.analysis.trees]
        assert any("knife" in t and "RH_P1" in t for t in trees), trees
        # Undo from the review screen takes the last keyframe back; redo brings it again.
        before = fold_boxes(app.session.applied_corrections)
        await pilot.press("z")
        assert "Undone: box 2" in app.last_message
        assert fold_boxes(app.session.applied_corrections) != before
        await pilot.press("y")
        assert "Redone: box 2" in app.last_message
        assert fold_boxes(app.session.applied_corrections) == before
        await settle(pilot, app)
        await pilot.press("q")
    again = WecookApp(path)
    async with again.run_test(size=SIZE) as pilot:
        await settle(pilot, again)
        assert fold_boxes(again.session.applied_corrections) == before
        assert [str(t.tree) for t in again.analysis.trees] == trees
        assert (path / "trees.yaml").read_text().count("knife") >= 1
        await pilot.press("B")
        assert await wait_for(pilot, lambda: isinstance(again.screen, BoxScreen))
        assert [t.label for t in again.screen.tracks] == ["chopping board", "knife"]  # type: ignore[attr-defined]


@pilot_test
@pytest.mark.slow
async def test_the_help_lists_the_box_mode(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=(150, 60)) as pilot:
        await settle(pilot, app)
        await pilot.press("question_mark")
        assert await wait_for(pilot, lambda: isinstance(app.screen, HelpScreen))
        screen = app.screen
        assert isinstance(screen, HelpScreen)
        assert {"box-mode", "categorise-labels"} <= {b.id for b in screen.bindings_}
        (boxes,) = [bindings for title, bindings in screen.more.items() if title.startswith("Box mode")]
        assert {"boxes-new", "boxes-track", "boxes-undo", "boxes-redo", "boxes-export"} <= {b.id for b in boxes}
        assert len(screen.query(".help-more")) == len(screen.more)  # each drawn as a table


@pilot_test
@pytest.mark.slow
async def test_labels_nothing_categorises_are_asked_and_the_answer_is_journaled(
        tmp_path: Path, scenario_inputs: tuple[Path, Path, Path]) -> None:
    video, objects, hands = scenario_inputs
    odd = tmp_path / "objects.csv"
    odd.write_text(objects.read_text().replace(",tomato,", ",zorblax,"))
    path = Path(create_session(tmp_path / "sessions", "odd", video, odd, hands))
    app = WecookApp(path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        assert app.obs.categories["zorblax"] is Category.INGREDIENT
        assert any("zorblax" in str(n.message) and "Press N" in str(n.message) for n in app._notifications)
        before = app.analysis
        await pilot.press("N")
        assert await wait_for(pilot, lambda: isinstance(app.screen, PickerScreen))
        await pick(pilot, app, "container")
        assert await wait_for(pilot, lambda: app.screen is app.main)
        assert journal(path)[-1] == {**journal(path)[-1], "op": "set_category", "label": "zorblax",
                                     "category": "container"}
        assert "zorblax is a container" in app.last_message
        await settle(pilot, app)
        assert app.analysis is not before and app.obs.categories["zorblax"] is Category.CONTAINER
        await pilot.press("N")  # nothing left to ask
        await pilot.pause()
        assert app.screen is app.main
        # Undone, the answer is asked again; a drawn box with a label nothing knows is asked about too, and
        # with several labels the label is picked first, then each remaining one is asked in turn.
        await pilot.press("z")
        assert app.obs.categories["zorblax"] is Category.INGREDIENT
        await pilot.press("B")
        assert await wait_for(pilot, lambda: isinstance(app.screen, BoxScreen))
        app.screen.add_box((10.0, 10.0, 40.0, 40.0), "quux")  # type: ignore[attr-defined]
        await pilot.press("escape")
        assert await wait_for(pilot, lambda: app.screen is app.main)
        assert any("quux" in str(n.message) for n in app._notifications)
        await pilot.press("N")
        assert await wait_for(pilot, lambda: isinstance(app.screen, PickerScreen))
        assert [v for v, _ in app.screen.options] == ["zorblax", "quux"]  # type: ignore[attr-defined]
        await pick(pilot, app, "quux")
        assert await wait_for(pilot, lambda: "'quux'" in app.screen.title_text)  # type: ignore[attr-defined]
        await pick(pilot, app, "tool")
        assert await wait_for(pilot, lambda: "'zorblax'" in getattr(app.screen, "title_text", ""))
        await pilot.press("escape")
        assert await wait_for(pilot, lambda: app.screen is app.main)
        await settle(pilot, app)
        assert app.obs.categories["quux"] is Category.TOOL
        assert [e["op"] for e in journal(path)][-2:] == ["box_keyframe", "set_category"]
