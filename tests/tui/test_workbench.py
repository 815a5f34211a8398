"""Pilot tests: every key path of the review screen on a real session, asserting on state and on the journal."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import journal, pick, pilot_test, settle, wait_for

from wecook_core.model import SegmentStatus
from wecook_core.trees.treefile import read_tree_file
from wecook_tui import review
from wecook_tui.app import WecookApp
from wecook_tui.screens.help import HelpScreen
from wecook_tui.screens.links import LinkPickerScreen
from wecook_tui.screens.main import MAIN_BINDINGS
from wecook_tui.screens.picker import PickerScreen
from wecook_tui.widgets.frame_view import FrameView
from wecook_tui.widgets.inspector import SegmentTree
from wecook_tui.widgets.timeline import Timeline

SIZE = (150, 45)


def ops(session: Path) -> list[str]:
    return [entry["op"] for entry in journal(session)]


@pilot_test
@pytest.mark.slow
async def test_opens_with_frame_timeline_and_inspector(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        view = app.main.query_one(FrameView)
        assert view.shown == 0 and view.message is None
        assert len(view._strips) > 10
        timeline = app.main.query_one(Timeline)
        assert [lane.hand for lane in timeline.lanes] == list(review.hands_of(app.obs))
        assert {"LH_P1", "RH_P1"} <= {lane.hand for lane in timeline.lanes}
        segs = app.analysis.segmentation.segments
        assert len(segs) >= 3 and timeline.segments == segs
        tree = app.main.query_one(SegmentTree)
        assert len(tree.root.children) == len(review.trees_of(app.analysis, segs[0]))
        hands = review.hands_of(app.obs)
        acting = [h for h in hands if h in review.actions_of(app.analysis, segs[0], 0)]
        assert app.main.selected_hand == (acting or list(hands))[0]  # the first hand acting in the segment


@pilot_test
@pytest.mark.slow
async def test_frame_stepping_keys(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("right", "right", "l")
        assert app.main.frame == 3
        await pilot.press("left")
        assert app.main.frame == 2
        await pilot.press("shift+right")
        assert app.main.frame == 12
        await pilot.press("L")
        assert app.main.frame == 22
        await pilot.press("shift+left", "H", "H", "H")
        assert app.main.frame == 0  # clamped at the first frame
        app.main.frame = app.frame_count - 15
        await pilot.press("L", "L")
        assert app.main.frame == app.frame_count - 1  # clamped at the last frame
        await settle(pilot, app)
        view = app.main.query_one(FrameView)
        assert view.shown == app.frame_count - 1


@pilot_test
@pytest.mark.slow
async def test_segment_keys_and_next_unreviewed(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        await pilot.press("down")
        assert app.main.frame == segs[1].start
        await pilot.press("n")
        assert app.main.frame == segs[2].start
        await pilot.press("up")
        assert app.main.frame == segs[1].start
        await pilot.press("p", "p")
        assert app.main.frame == 0
        await pilot.press("a")  # accept segment 0, then accept segment 1
        await pilot.press("down", "a")
        await pilot.press("up", "u")
        assert app.main.frame == segs[2].start  # the first unreviewed after segment 0


@pilot_test
@pytest.mark.slow
async def test_accept_and_reject_are_journaled_and_shown(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        await pilot.press("a")
        assert journal(session_path)[-1] | {} == {**journal(session_path)[-1], "op": "set_status",
                                                 "segment": 0, "status": "accepted"}
        timeline = app.main.query_one(Timeline)
        assert timeline.status[0] is SegmentStatus.ACCEPTED  # shown at once, before the analysis returns
        await pilot.press("down", "x")
        entry = journal(session_path)[-1]
        assert (entry["op"], entry["segment"], entry["status"]) == ("set_status", segs[1].start, "rejected")
        await settle(pilot, app)
        assert app.analysis.corrections.status == {0: SegmentStatus.ACCEPTED, segs[1].start: SegmentStatus.REJECTED}
        assert timeline.status[segs[1].start] is SegmentStatus.REJECTED
        written = read_tree_file(session_path / "trees.yaml")  # the results on disk follow the corrections
        assert [(t.start, t.end) for t in written] == [(t.start, t.end) for t in app.analysis.trees]
        assert (session_path / "graph.yaml").is_file()


@pilot_test
@pytest.mark.slow
async def test_change_action_picker_ranked_by_commonsense(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        index = next(i for i, seg in enumerate(segs) if review.ranking_of(app.analysis, seg, i, "RH_P1"))
        last = segs[index]
        app.main.frame = last.start
        app.main.selected_hand = "RH_P1"
        await pilot.press("c")
        screen = app.screen
        assert isinstance(screen, PickerScreen)
        ranking = review.ranking_of(app.analysis, last, index, "RH_P1")
        offered = [value for value, _ in screen.options]
        assert offered[: len(ranking)] == [verb for verb, _ in ranking]
        await pick(pilot, app, "peel")
        entry = journal(session_path)[-1]
        assert entry["op"] == "set_verb" and entry["verb"] == "peel" and entry["hand"] == "RH_P1"
        assert entry["segment"] == last.start
        await settle(pilot, app)
        index = review.segment_index(app.analysis.segmentation.segments, last.start)
        action = review.actions_of(app.analysis, last, index)["RH_P1"]
        assert action.verb == "peel"
        assert review.status_of(app.corrections, last.start) is SegmentStatus.CORRECTED


@pilot_test
@pytest.mark.slow
async def test_change_object_picker_closest_first(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        app.main.frame = 40
        app.main.selected_hand = "RH_P1"
        await pilot.press("o")
        screen = app.screen
        assert isinstance(screen, PickerScreen)
        index, seg = app.main.current()
        near = review.objects_near_hand(app.obs, "RH_P1", 40, seg)
        distances = [d for _, d in near]
        assert near and distances == sorted(distances)
        assert [v for v, _ in screen.options][:-1] == [name for name, _ in near]
        held = review.associations_of(app.analysis, index, seg).hand_object.get("RH_P1")
        chosen = next(name for name, _ in near if name != held)
        await pick(pilot, app, chosen)
        entry = journal(session_path)[-1]
        assert (entry["op"], entry["hand"], entry["object"]) == ("set_hand_object", "RH_P1", chosen)
        await settle(pilot, app)
        index, seg = app.main.current()
        assert review.associations_of(app.analysis, index, seg).hand_object["RH_P1"] == chosen
        await pilot.press("o")
        await pick(pilot, app, review.NOTHING)
        assert journal(session_path)[-1]["object"] is None


@pilot_test
@pytest.mark.slow
async def test_change_object_object_link(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        index = next(i for i, seg in enumerate(segs)
                     if review.associations_of(app.analysis, i, seg).hand_object.get("RH_P1"))
        held = review.associations_of(app.analysis, index, segs[index]).hand_object["RH_P1"]
        app.main.frame = segs[index].start
        app.main.selected_hand = "RH_P1"
        await pilot.press("k")
        screen = app.screen
        assert isinstance(screen, LinkPickerScreen)
        offered = [v for v, _ in screen.options]
        tools = {name for name, category in app.obs.categories.items() if category == "tool"}
        assert held not in offered and not tools & set(offered)  # never the held object itself, never a tool
        current = review.associations_of(app.analysis, index, segs[index]).object_object.get(held, ())
        # toggle off whatever is linked now, toggle on the two closest candidates, confirm
        for row, value in enumerate(offered):
            if (value in current) != (row < 2):
                await pilot.press("home", *(["down"] * row), "space")
        await pilot.press("enter")
        await pilot.pause()
        targets = offered[:2]
        entry = journal(session_path)[-1]
        assert (entry["op"], entry["object"], entry["targets"]) == ("set_object_object", held, targets)
        await settle(pilot, app)
        assoc = review.associations_of(app.analysis, index, segs[index])
        assert assoc.object_object[held] == tuple(targets)
        await pilot.press("k", "escape")  # cancelling records nothing
        assert len(journal(session_path)) == 1


@pilot_test
@pytest.mark.slow
async def test_picker_escape_records_nothing(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("c", "escape", "o", "escape")
        assert app.screen is app.main
        assert journal(session_path) == []


@pilot_test
@pytest.mark.slow
async def test_split_and_merge(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        before = app.analysis.segmentation.segments
        index, seg = next((i, s) for i, s in enumerate(before[:-1]) if len(s) >= 6)
        app.main.frame = seg.start
        await pilot.press("s")  # at a segment's first frame: refused, nothing journaled
        assert journal(session_path) == []
        await pilot.press("right", "right", "right", "s")
        cut = seg.start + 3
        assert journal(session_path)[-1] == {**journal(session_path)[-1], "op": "split", "frame": cut}
        await settle(pilot, app)
        after = app.analysis.segmentation.segments
        assert len(after) == len(before) + 1 and after[index + 1].start == cut
        await pilot.press("m")  # merge [cut, ...) with the next segment
        assert journal(session_path)[-1]["op"] == "merge"
        assert journal(session_path)[-1]["frame"] == after[index + 2].start
        await settle(pilot, app)
        assert len(app.analysis.segmentation.segments) == len(after) - 1


@pilot_test
@pytest.mark.slow
async def test_undo_redo_unlimited_and_journaled(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        await pilot.press("a", "down", "a", "down", "x")
        await pilot.press("z", "z", "z")
        assert ops(session_path) == ["set_status"] * 3 + ["undo"] * 3
        assert app.corrections.status == {}
        await pilot.press("z")  # nothing left: nothing journaled
        assert len(journal(session_path)) == 6
        await pilot.press("y", "ctrl+y")
        assert ops(session_path)[-2:] == ["redo", "redo"]
        assert app.corrections.status == {0: SegmentStatus.ACCEPTED, segs[1].start: SegmentStatus.ACCEPTED}
        await settle(pilot, app)
        assert app.analysis.corrections.status == app.corrections.status


@pilot_test
@pytest.mark.slow
async def test_play_pause(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("space")
        assert app.main.playing
        await pilot.pause(0.4)
        await pilot.press("space")
        assert not app.main.playing
        stopped = app.main.frame
        assert stopped > 0
        await pilot.pause(0.2)
        assert app.main.frame == stopped


@pilot_test
@pytest.mark.slow
async def test_next_hand_changes_what_pickers_act_on(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        index, seg = max(enumerate(segs), key=lambda item: len(review.actions_of(app.analysis, item[1], item[0])))
        acting = list(review.actions_of(app.analysis, seg, index))
        app.main.frame = seg.start
        await pilot.pause()
        first = app.main.selected_hand
        assert first in acting  # the acting hand is selected on arriving in a segment
        hands = list(review.hands_of(app.obs))
        await pilot.press("t")
        assert app.main.selected_hand == hands[(hands.index(first) + 1) % len(hands)]
        while app.main.selected_hand not in acting or app.main.selected_hand == first:
            if len(acting) == 1 and app.main.selected_hand == first:
                break
            await pilot.press("t")
        await pilot.press("c")
        await pick(pilot, app, "stir")
        assert journal(session_path)[-1]["hand"] == app.main.selected_hand


@pilot_test
@pytest.mark.slow
async def test_a_verb_for_a_hand_holding_nothing_is_refused_with_a_reason(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        hands = review.hands_of(app.obs)
        _, seg, idle = next((i, s, h) for i, s in enumerate(segs) for h in hands
                                if h not in review.actions_of(app.analysis, s, i)
                                and not review.associations_of(app.analysis, i, s).hand_object.get(h))
        app.main.frame = seg.start
        await pilot.pause()
        while app.main.selected_hand != idle:
            await pilot.press("t")
        await pilot.press("c")
        assert app.screen is app.main and journal(session_path) == []  # no picker, nothing journaled
        assert any("holds nothing" in n.message for n in app._notifications)


@pilot_test
@pytest.mark.slow
async def test_help_screen_and_command_palette_list_every_binding(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("question_mark")
        assert isinstance(app.screen, HelpScreen)
        ids = {row for row in app.screen.bindings_}
        assert len(ids) == len(MAIN_BINDINGS)
        await pilot.press("escape")
        assert app.screen is app.main
        titles = {command.title for command in app.get_system_commands(app.main)}
        assert {b.description for b in MAIN_BINDINGS} <= titles
        assert len({b.id for b in MAIN_BINDINGS}) == len(MAIN_BINDINGS)


@pilot_test
@pytest.mark.slow
async def test_keys_remapped_from_the_key_file(session_path: Path, tmp_path: Path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    keys = tmp_path / "keys.toml"
    keys.write_text('[keys]\naccept = "enter"\nno-such-binding = "f5"\n')
    monkeypatch.setenv("WECOOK_KEYS", str(keys))
    app = WecookApp(session_path)
    assert app.keys.keymap == {"accept": "enter"}
    assert any("no-such-binding" in problem for problem in app.keys.problems)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("a")
        assert journal(session_path) == []  # "a" no longer accepts
        await pilot.press("enter")
        assert ops(session_path) == ["set_status"]


@pilot_test
@pytest.mark.slow
async def test_reopen_restores_corrections_undo_and_redo(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("a", "down", "x", "z")
    again = WecookApp(session_path)
    async with again.run_test(size=SIZE) as pilot:
        await settle(pilot, again)
        assert again.corrections.status == {0: SegmentStatus.ACCEPTED}
        await pilot.press("y")  # the redo stack survived the reopen
        segs = again.analysis.segmentation.segments
        assert again.corrections.status == {0: SegmentStatus.ACCEPTED, segs[1].start: SegmentStatus.REJECTED}


@pilot_test
@pytest.mark.slow
async def test_command_palette_runs_a_review_command(session_path: Path) -> None:
    app = WecookApp(session_path)
    async with app.run_test(size=SIZE) as pilot:
        await settle(pilot, app)
        await pilot.press("ctrl+p")
        await pilot.pause(0.2)
        await pilot.press(*"Reject")
        await pilot.pause(0.5)
        await pilot.press("enter")
        await wait_for(pilot, lambda: bool(journal(session_path)), 100)
        assert ops(session_path) == ["set_status"] and journal(session_path)[0]["status"] == "rejected"
