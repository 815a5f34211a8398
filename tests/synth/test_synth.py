"""Synthetic scenarios: the truth is consistent with what the detectors report, every tree case appears,
seeds reproduce, files round-trip through wecook's own readers."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from functools import cache
from pathlib import Path

import cv2
import numpy as np
import pytest

from wecook_core.formats.native import read_hands_csv, read_objects_csv
from wecook_core.formats.openpose import read_openpose
from wecook_core.model import HANDS, Action, ActionKind, Category
from wecook_core.synth import DEMO_SEED, demo_dir, synthesize, write_scenario
from wecook_core.synth.motion import Move, minimum_jerk, phase_positions
from wecook_core.synth.scenario import Scenario
from wecook_core.trees.notation import action_of, format_tree, has_action, parse_tree
from wecook_core.trees.treefile import dump_tree_spans, read_tree_file

SEEDS = (1, 2, 3)


@cache
def scenario(seed: int, persons: int = 2) -> Scenario:
    return synthesize(seed, persons)


def held_by_hands(action: Action) -> list[tuple[str, str, int, int]]:
    """(hand, object, start, end) for every object a hand holds in an action (partner included)."""
    pairs = []
    if action.kind is ActionKind.HAND:
        pairs.append((action.hand, action.targets[0], action.start, action.end))
    elif action.held is not None:
        pairs.append((action.hand, action.held, action.start, action.end))
    if action.partner is not None:
        pairs += held_by_hands(action.partner)
    return pairs


def case(action: Action, categories: dict[str, Category]) -> str:
    if action.kind is ActionKind.TRANSFER:
        held = categories[action.held or ""]
        return "transfer_by_tool" if held is Category.TOOL else "transfer_by_tipping"
    if action.kind is ActionKind.TOOL:
        if action.verb in ("pour", "sprinkle"):
            return action.verb
        if len(action.targets) == 2:
            return "tool_in_container"
        return "tool_on_ingredient" if categories[action.targets[0]] is Category.INGREDIENT else "tool_on_container"
    return str(action.kind)


# ------------------------------------------------------------------------------------------- the truth


@pytest.mark.parametrize("seed", SEEDS)
def test_every_truth_tree_parses_and_matches_its_action(seed: int) -> None:
    s = scenario(seed)
    assert len(s.truth) == len(s.actions) >= 11
    for span, action in zip(s.truth, s.actions, strict=True):
        text = format_tree(span.tree)
        assert format_tree(parse_tree(text)) == text
        assert (span.start, span.end) == (action.start, action.end)
        assert 0 <= span.start < span.end <= s.frames
        again = action_of(span.tree, span.start, span.end)
        assert (again.kind, again.hand, again.verb, again.held, again.targets) == (
            action.kind, action.hand, action.verb, action.held, action.targets)
    assert [t.start for t in s.truth] == sorted(t.start for t in s.truth)


@pytest.mark.parametrize("seed", SEEDS)
def test_every_case_of_the_design_table_appears_with_two_persons(seed: int) -> None:
    s = scenario(seed)
    categories = dict(s.observations.categories)
    cases = {case(a, categories) for a in s.actions}
    assert cases >= {
        "tool_in_container", "tool_on_ingredient", "hand", "transfer_by_tool", "transfer_by_tipping", "pour",
        "sprinkle", "tool_on_container", "holding", "handover",
    }
    verbs = {a.verb for a in s.actions} | {a.partner.verb for a in s.actions if a.partner is not None}
    assert verbs >= {"cut", "peel", "roll", "squeeze", "transfer", "pour", "sprinkle", "stir"}
    handover = next(a for a in s.actions if a.kind is ActionKind.HANDOVER)
    assert handover.partner is not None and handover.partner.kind is ActionKind.GRASP
    assert handover.hand[-2:] != handover.partner.hand[-2:]
    assert handover.partner.start < handover.end  # the receiver takes it before the giver lets go
    holding = next(a for a in s.actions if a.kind is ActionKind.HOLDING)
    assert holding.partner is not None and holding.hand[-2:] != holding.partner.hand[-2:]
    assert holding.start < holding.partner.start and holding.partner.end > holding.start
    tipping = next(a for a in s.actions if case(a, categories) == "transfer_by_tipping")
    assert tipping.held == tipping.targets[1]  # the carried container is the source


def test_the_tree_notation_of_the_design_table() -> None:
    s = scenario(1)
    texts = [format_tree(t.tree) for t in s.truth]
    assert any("(AP (A cut) (OP (O tomato) (O chopping_board)))" in t for t in texts)
    assert any(t.startswith("(HP (H ") and "(AP (A squeeze) (O lemon))" in t for t in texts)
    assert any("(AP (A transfer) (OP (O " in t and "(OP (O bowl) (O pot)))))" in t for t in texts)
    assert any("(CP (C handover) (HP (H " in t for t in texts)
    assert any("(CP (C holding) (HP (HP (H " in t for t in texts)


@pytest.mark.parametrize("seed", SEEDS)
def test_held_objects_overlap_the_hand_and_are_its_nearest_overlap(seed: int) -> None:
    s = scenario(seed)
    obs = s.observations
    for action in s.actions:
        for hand, name, start, end in held_by_hands(action):
            hands, obj = obs.hand(hand), obs.object(name)
            assert hands is not None
            frames, hi, oi = np.intersect1d(hands.frames, obj.frames, return_indices=True)
            inside = (frames >= start) & (frames < end)
            hb, ob = hands.boxes[hi][inside], obj.boxes[oi][inside]
            assert len(hb) >= 0.8 * (end - start), (hand, name)
            overlap = (np.minimum(hb[:, 2], ob[:, 2]) > np.maximum(hb[:, 0], ob[:, 0])) & (
                np.minimum(hb[:, 3], ob[:, 3]) > np.maximum(hb[:, 1], ob[:, 1]))
            assert overlap.all(), f"{hand} lets go of {name} inside its tree {start}-{end}"


@pytest.mark.parametrize("seed", SEEDS)
def test_the_pipelines_associations_find_the_held_object(seed: int) -> None:
    from wecook_core.perception.association.associate import frame_links
    from wecook_core.perception.params import Params

    s = scenario(seed)
    links = frame_links(s.observations, 0, s.frames, Params())
    names = links.boxes.names
    for action in s.actions:
        for hand, name, start, end in held_by_hands(action):
            held = links.held[start:end, HANDS.index(hand)]
            assert np.mean(held == names.index(name)) >= 0.8, (seed, hand, name, start, end)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_hand_does_one_thing_at_a_time_and_holds_nothing_in_between(seed: int) -> None:
    from wecook_core.perception.association.associate import NONE, frame_links
    from wecook_core.perception.params import Params

    s = scenario(seed)
    spans: dict[str, list[tuple[int, int]]] = {hand: [] for hand in HANDS}
    for action in s.actions:
        if action.kind is ActionKind.GRASP:
            continue  # a receiver's carry: already inside the handover's partner
        for hand, _, start, end in held_by_hands(action):
            spans[hand].append((start, end))
    for hand, ranges in spans.items():
        ranges.sort()
        for (_, end), (start, _) in itertools.pairwise(ranges):
            assert end <= start, hand
    links = frame_links(s.observations, 0, s.frames, Params())
    for hand, ranges in spans.items():
        idle = np.ones(s.frames, dtype=bool)
        for start, end in ranges:  # reaching for it and coming back are not idle either
            idle[max(0, start - 45) : end + 45] = False
        assert idle.sum() > 100
        assert np.mean(links.held[idle, HANDS.index(hand)] == NONE) > 0.97, hand


@pytest.mark.parametrize("seed", SEEDS)
def test_transferred_ingredients_end_up_in_the_destination_then_are_stirred_in(seed: int) -> None:
    s = scenario(seed)
    obs = s.observations
    for action in s.actions:
        if action.kind is not ActionKind.TRANSFER:
            continue
        ingredient, _, destination = action.targets
        ing, dest = obs.object(ingredient), obs.object(destination)
        after = ing.frames[(ing.frames > action.start) & (ing.frames < action.end + 60)]
        shared = np.intersect1d(after, dest.frames)
        boxes_i = np.array([ing.box_at(int(f)) for f in shared])
        boxes_d = np.array([dest.box_at(int(f)) for f in shared])
        inside = np.all((boxes_i[:, :2] >= boxes_d[:, :2] - 2) & (boxes_i[:, 2:] <= boxes_d[:, 2:] + 2), axis=1)
        assert inside.sum() >= 15, f"{ingredient} never lies in {destination}"
        gone = np.setdiff1d(np.arange(action.end, min(action.end + 150, s.frames)), ing.frames)
        assert len(gone) >= 30, f"{ingredient} is not stirred in"


# ---------------------------------------------------------------------------------------------- motion


def test_minimum_jerk_reach_is_smooth_with_a_bell_shaped_speed() -> None:
    move = Move(0, 30, (0.0, 0.0), (120.0, 0.0), bulge=6.0)
    path = phase_positions(move, 30.0)
    speed = np.linalg.norm(np.diff(path, axis=0), axis=1)
    peak = int(np.argmax(speed))
    assert 8 < peak < 22
    assert speed[0] < 0.2 * speed[peak] and speed[-1] < 0.2 * speed[peak]
    assert abs(path[15, 1]) > 3  # a curved path
    assert np.allclose(minimum_jerk(np.array([0.0, 0.5, 1.0])), [0.0, 0.5, 1.0])


@pytest.mark.parametrize("seed", SEEDS)
def test_hands_never_jump_and_never_stand_perfectly_still(seed: int) -> None:
    s = scenario(seed)
    for track in s.observations.hands:
        steps = np.diff(track.frames)
        moves = np.linalg.norm(np.diff(track.xy, axis=0), axis=1)[steps == 1]
        assert moves.max() < 30, track.hand
        assert np.mean(moves < 1e-9) < 0.1, track.hand  # positions are rounded to 0.1 pixel
        assert len(track.frames) < s.frames  # sometimes undetected
    for person in s.scene.persons:
        for arm in person.arms:
            true_moves = np.linalg.norm(np.diff(arm.centre, axis=0), axis=1)
            assert true_moves.min() > 1e-6, arm.hand  # not piecewise constant, even at rest
    assert any(len(t.frames) < s.frames for t in s.observations.objects)  # boxes drop out now and then


def test_objects_jitter_a_little_when_they_lie_still() -> None:
    s = scenario(1)
    board = s.observations.object("chopping_board")
    first = board.boxes[:20]
    assert 0 < float(np.std(first[:, 0])) < 2.0


# ---------------------------------------------------------------------------------------- seeds, sizes


@pytest.mark.slow
def test_the_same_seed_gives_the_same_scenario_and_another_seed_another_script() -> None:
    a, b = synthesize(5), synthesize(5)
    assert a.tasks == b.tasks
    assert dump_tree_spans(a.truth) == dump_tree_spans(b.truth)
    for x, y in zip(a.observations.objects, b.observations.objects, strict=True):
        assert x.name == y.name and np.array_equal(x.frames, y.frames) and np.array_equal(x.boxes, y.boxes)
    for x, y in zip(a.observations.hands, b.observations.hands, strict=True):
        assert np.array_equal(x.xy, y.xy) and np.array_equal(x.boxes, y.boxes)
    c = synthesize(6)
    assert (c.tasks, dump_tree_spans(c.truth)) != (a.tasks, dump_tree_spans(a.truth))


def test_one_person_works_alone() -> None:
    s = scenario(4, 1)
    assert {t.hand for t in s.observations.hands} == {"LH_P1", "RH_P1"}
    assert s.actions and all(a.kind not in (ActionKind.HOLDING, ActionKind.HANDOVER) for a in s.actions)
    assert any(a.verb == "cut" for a in s.actions)
    assert all(a.hand.endswith("P1") for a in s.actions)


def test_persons_are_numbered_left_to_right() -> None:
    s = scenario(1)
    p1, p2 = (p for p in s.scene.persons)
    assert (p1.person, p2.person) == ("P1", "P2")
    assert p1.neck[:, 0].mean() < p2.neck[:, 0].mean()
    # a person's own left hand: P1 faces right, so its left hand is the upper one at rest
    left, right = p1.arms
    assert np.median(left.shoulder[:, 1]) < np.median(right.shoulder[:, 1])


@pytest.mark.slow
def test_a_ten_minute_scenario_is_generated_quickly() -> None:
    import time

    started = time.perf_counter()
    s = synthesize(11, duration_s=600)
    elapsed = time.perf_counter() - started
    assert s.frames == 18000 and len(s.observations.hands) == 4
    assert 10 <= len(s.observations.objects) <= 18
    counted = [t for t in s.truth if has_action(t.tree)]
    assert len(counted) > 80 and max(t.end for t in s.truth) <= 18000
    assert elapsed < 15  # seconds, generously (about 1 s on one core)


def test_other_sizes_scale_the_boxes() -> None:
    small = synthesize(3, size=(320, 180), duration_s=10)
    big = synthesize(3, size=(640, 360), duration_s=10)
    assert small.observations.video.width == 320
    a, b = small.observations.object("pot"), big.observations.object("pot")
    assert np.allclose(a.boxes[:10] * 2, b.boxes[:10], atol=6)


def test_bad_arguments_are_refused() -> None:
    with pytest.raises(ValueError):
        synthesize(1, persons=3)
    with pytest.raises(ValueError):
        synthesize(1, fps=0)


# ----------------------------------------------------------------------------------------------- files


@pytest.mark.slow
def test_write_scenario_round_trips_through_the_readers(tmp_path: Path) -> None:
    s = synthesize(8, duration_s=7)
    out = write_scenario(s, tmp_path / "scenario", openpose=False)
    objects = read_objects_csv(out / "objects.csv")
    assert [t.name for t in objects] == [t.name for t in s.observations.objects]
    for x, y in zip(objects, s.observations.objects, strict=True):
        assert np.array_equal(x.frames, y.frames) and np.allclose(x.boxes, y.boxes, atol=0.01)
    hands = read_hands_csv(out / "hands.csv")
    for x, y in zip(hands, s.observations.hands, strict=True):
        assert x.hand == y.hand and np.allclose(x.xy, y.xy, atol=0.01)
    truth = read_tree_file(out / "truth.yaml")
    assert [format_tree(t.tree) for t in truth] == [format_tree(t.tree) for t in s.truth]
    capture = cv2.VideoCapture(str(out / "video.mp4"))
    decoded = 0
    while True:
        ok, image = capture.read()
        if not ok:
            break
        assert image.shape == (360, 640, 3)
        decoded += 1
    assert decoded == s.frames


@pytest.mark.slow
def test_video_frames_draw_the_scene_the_same_with_and_without_the_cache() -> None:
    from wecook_core.synth.render import frames, render_frame

    s = synthesize(10, duration_s=9)
    for frame, image in enumerate(frames(s)):
        if frame % 45 == 0:
            assert np.array_equal(image, render_frame(s, frame)), frame
    tomato = next(p for p in s.scene.objects if p.name == "tomato")
    x, y = (int(v) for v in tomato.centre[0])
    assert render_frame(s, 0)[y, x + 7, 2] > 150  # a red tomato where the scene says it lies


@pytest.mark.slow
def test_the_openpose_folder_describes_the_same_hands(tmp_path: Path) -> None:
    s = synthesize(9, duration_s=8)
    out = write_scenario(s, tmp_path / "op", video=False)
    files = sorted((out / "openpose").glob("*_keypoints.json"))
    assert len(files) == s.frames
    assert files[12].name == "video_000000000012_keypoints.json"
    first_person_x = []
    for file in files[:40]:
        people = json.loads(file.read_text())["people"]
        assert len(people) == 2
        for person in people:
            assert len(person["pose_keypoints_2d"]) == 75
            assert len(person["hand_left_keypoints_2d"]) == len(person["hand_right_keypoints_2d"]) == 63
        first_person_x.append(people[0]["pose_keypoints_2d"][3])
    assert min(first_person_x) < 320 < max(first_person_x)  # persons listed in random order
    imported = read_openpose(out / "openpose")
    for x, y in zip(imported, s.observations.hands, strict=True):
        assert x.hand == y.hand
        common, i, j = np.intersect1d(x.frames, y.frames, return_indices=True)
        assert len(common) >= 0.95 * len(y.frames)
        assert np.abs(x.xy[i] - y.xy[j]).max() < 0.5
        assert np.abs(x.boxes[i] - y.boxes[j]).max() < 3.0


def test_the_synth_command_writes_a_scenario(tmp_path: Path) -> None:
    from wecook_tui.cli import main

    assert main(["synth", str(tmp_path / "a"), "--seed", "3", "--duration", "6", "--no-video"]) == 0
    assert {p.name for p in (tmp_path / "a").iterdir()} == {"objects.csv", "hands.csv", "truth.yaml", "openpose"}
    assert main(["synth", str(tmp_path / "b"), "--size", "big"]) == 2


def test_the_synth_command_is_listed() -> None:
    result = subprocess.run([sys.executable, "-m", "wecook_tui.cli", "--help"], capture_output=True, text=True,
                            check=True)
    assert "synth" in result.stdout


# ------------------------------------------------------------------------------------------------ demo


@pytest.mark.slow
def test_the_bundled_demo_is_what_its_seed_generates() -> None:
    folder = demo_dir()
    for name in ("video.mp4", "objects.csv", "hands.csv", "truth.yaml", "README.md"):
        assert (folder / name).is_file(), f"{folder / name} is missing: regenerate it (see README.md there)"
    assert str(DEMO_SEED) in (folder / "README.md").read_text()
    demo = scenario(DEMO_SEED)
    assert (folder / "truth.yaml").read_text() == dump_tree_spans(demo.truth)
    objects = read_objects_csv(folder / "objects.csv")
    assert [t.name for t in objects] == [t.name for t in demo.observations.objects]
    assert all(np.allclose(x.boxes, y.boxes, atol=0.01) for x, y in zip(objects, demo.observations.objects,
                                                                         strict=True))
    assert 40 * 30 <= demo.frames <= 60 * 30
    size = sum(p.stat().st_size for p in folder.iterdir() if p.is_file())
    assert size < 3.6e6
