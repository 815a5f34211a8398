"""Plan YAML in and out, validation of every bad case, and building a plan from an action graph."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.model import (
    ActionGraph,
    Category,
    GraphEdge,
    GraphNode,
    HandTrack,
    ObjectTrack,
    Observations,
    TreeSpan,
    VideoInfo,
)
from wecook_core.plan import (
    Act,
    Agent,
    Plan,
    PlanAction,
    Scene,
    SceneObject,
    Table,
    action_objects,
    dump_plan,
    load_plan,
    object_dependencies,
    plan_from_graph,
    plan_problems,
    read_plan,
    validate,
    write_plan,
)
from wecook_core.trees.notation import action_of, parse_tree

TABLE = Table()


def small_plan() -> Plan:
    objects = (
        SceneObject("knife", Category.TOOL, "box", (0.2, 0.03, 0.025), -0.1, 0.1, math.pi / 2),
        SceneObject("tomato", Category.INGREDIENT, "sphere", (0.05, 0.05, 0.05), 0.0, 0.0),
        SceneObject("chopping_board", Category.CONTAINER, "box", (0.25, 0.18, 0.02), 0.0, 0.0),
        SceneObject("pot", Category.CONTAINER, "cylinder", (0.18, 0.18, 0.12), 0.1, -0.15),
        SceneObject("spoon", Category.TOOL, "box", (0.16, 0.03, 0.025), 0.15, 0.15),
    )
    actions = (
        PlanAction("a1", ("P1",), "cut", "knife", ("tomato",), "chopping_board", frames=(0, 40),
                   tree="(HP (HP (H RH_P1) (O knife)) (AP (A cut) (OP (O tomato) (O chopping_board))))"),
        PlanAction("a2", ("P1", "P2"), "handover", "knife", after=("a1",), frames=(40, 60)),
        PlanAction("a3", ("P2", "P1"), "holding", "pot",
                   partner=Act("stir", "spoon", (), "pot"), after=("a2",), frames=(60, 90)),
        PlanAction("a4", ("P2",), "transfer", "spoon", ("tomato",), "pot", "chopping_board", after=("a3",)),
    )
    agents = (Agent("P1", base_position=(-0.5, 0.0, 0.0)), Agent("P2", base_position=(0.5, 0.0, 0.0),
                                                                base_yaw=math.pi))
    return Plan(agents, Scene(TABLE, objects, (("tomato", "chopping_board"),)), actions)


def test_round_trip_write_read_is_identity(tmp_path: Path) -> None:
    plan = small_plan()
    path = write_plan(plan, tmp_path / "plans" / "plan.yaml")
    assert read_plan(path) == plan
    assert "wecook_plan: 1" in path.read_text()


def test_valid_plan_has_no_problems() -> None:
    assert plan_problems(small_plan()) == []


def _with_action(plan: Plan, index: int, **changes: object) -> Plan:
    actions = list(plan.actions)
    actions[index] = replace(actions[index], **changes)  # type: ignore[arg-type]
    return replace(plan, actions=tuple(actions))


@pytest.mark.parametrize(("change", "place", "words"), [
    (lambda p: _with_action(p, 0, verb="juggle"), "actions[0] (a1).verb", "unknown verb 'juggle'"),
    (lambda p: _with_action(p, 0, tool="fork"), "actions[0] (a1).tool", "'fork' is not in the scene"),
    (lambda p: _with_action(p, 3, ingredients=("onion",)), "actions[3] (a4).ingredients[0]", "not in the scene"),
    (lambda p: _with_action(p, 2, partner=Act("stir", "ladle", (), "pot")), "actions[2] (a3).partner.tool",
     "'ladle'"),
    (lambda p: _with_action(p, 0, pids=("P3",)), "actions[0] (a1).pid", "unknown pid 'P3'"),
    (lambda p: _with_action(p, 3, after=("a9",)), "actions[3] (a4).after", "unknown action id 'a9'"),
    (lambda p: _with_action(p, 1, id="a1"), "actions[1] (a1).id", "duplicate action id 'a1'"),
    (lambda p: replace(p, version=2), "wecook_plan", "unsupported plan version 2"),
    (lambda p: _with_action(p, 1, pids=("P1",)), "actions[1] (a2).pid", "two different agents"),
])
def test_each_bad_case_names_action_and_field(change, place: str, words: str) -> None:  # type: ignore[no-untyped-def]
    problems = plan_problems(change(small_plan()), "plan.yaml")
    assert problems, "the bad plan passed validation"
    assert any(e.place == place and words in e.message for e in problems), [str(e) for e in problems]
    with pytest.raises(InputError) as info:
        validate(change(small_plan()), "plan.yaml")
    assert str(info.value).startswith("plan.yaml:")


def test_cycle_in_after_is_named() -> None:
    plan = _with_action(small_plan(), 0, after=("a4",))
    problems = plan_problems(plan)
    cycles = [e for e in problems if "cycle" in e.message]
    assert len(cycles) == 1
    message = cycles[0].message
    assert "a1 -> a4 -> a3 -> a2 -> a1" in message or "a4 -> a3 -> a2 -> a1 -> a4" in message, message


def test_pose_off_the_table() -> None:
    plan = small_plan()
    objects = list(plan.scene.objects)
    objects[4] = replace(objects[4], x=0.6)
    problems = plan_problems(replace(plan, scene=replace(plan.scene, objects=tuple(objects))))
    assert [e.place for e in problems] == ["scene.objects[4] (spoon).pose"]
    assert "off the table" in problems[0].message


def test_object_beyond_the_arms_reach() -> None:
    plan = small_plan()
    objects = list(plan.scene.objects)
    objects[1] = replace(objects[1], x=0.45, y=0.3)  # the tomato, at P2's end: 1.0 m from P1's base
    problems = plan_problems(replace(plan, scene=replace(plan.scene, objects=tuple(objects))))
    places = [e.place for e in problems]
    assert places == ["actions[0] (a1).ingredients[0]"], [str(e) for e in problems]  # a4 is P2's: in reach
    assert "beyond the arm's reach (0.85 m)" in problems[0].message and "from P1's base" in problems[0].message


def test_reading_bad_yaml_names_the_place(tmp_path: Path) -> None:
    text = dump_plan(small_plan())
    with pytest.raises(InputError, match=r"p.yaml:actions\[0\] \(a1\).verb: unknown verb 'juggle'"):
        load_plan(text.replace("verb: cut", "verb: juggle"), "p.yaml")
    with pytest.raises(InputError, match="not a wecook plan"):
        load_plan("hello: 1\n", "p.yaml")
    with pytest.raises(InputError, match=r"scene.objects\[1\] \(tomato\).size: expected 3 numbers"):
        load_plan(text.replace("size: [0.05, 0.05, 0.05]", "size: [0.05]"), "p.yaml")
    with pytest.raises(InputError, match="line"):
        load_plan("wecook_plan: [1\n", "p.yaml")
    with pytest.raises(InputError, match="cannot read"):
        read_plan(tmp_path / "missing.yaml")


# ----------------------------------------------------------------------------------- from a graph

W, H = 640, 480


def track(tid: int, name: str, box: tuple[float, float, float, float], first: int = 0) -> ObjectTrack:
    frames = np.arange(first, first + 20, dtype=np.int64)
    return ObjectTrack(tid, name.replace("_", " "), name, frames, np.tile(np.array(box, dtype=float), (20, 1)))


def node(nid: str, person: str, start: int, end: int, tree: str) -> GraphNode:
    t = parse_tree(tree)
    return GraphNode(nid, person, TreeSpan(start, end, t), action_of(t, start, end))


def scenario() -> tuple[ActionGraph, Observations]:
    objects = (
        track(1, "knife", (100, 300, 220, 320)),
        track(2, "chopping_board", (90, 200, 300, 330)),       # the knife lies on the board in the image
        track(3, "tomato", (150, 230, 190, 270)),
        track(4, "pot", (400, 150, 520, 260)),
        track(5, "spoon", (420, 160, 470, 250), first=30),     # inside the pot's box, seen later
        track(6, "bowl", (380, 300, 470, 380)),
    )
    categories = {"knife": Category.TOOL, "chopping_board": Category.CONTAINER, "tomato": Category.INGREDIENT,
                  "pot": Category.CONTAINER, "spoon": Category.TOOL, "bowl": Category.CONTAINER}
    obs = Observations(VideoInfo("v.mp4", 30.0, 200, W, H), objects, (), categories)
    nodes = (
        node("a1", "P1", 0, 10, "(HP (H RH_P1) (O knife))"),
        node("a2", "P1", 10, 50, "(HP (HP (H RH_P1) (O knife)) (AP (A cut) (OP (O tomato) (O chopping_board))))"),
        node("a3", "P1", 50, 70, "(HP (HP (H RH_P1) (O knife)) (CP (C handover) (HP (H LH_P2) (O knife))))"),
        node("a4", "P2", 40, 60, "(HP (HP (H RH_P2) (O spoon)) (AP (A stir) (O pot)))"),
        node("a5", "P2", 80, 120, "(HP (HP (H LH_P2) (O knife)) (AP (A cut) (OP (O tomato) (O chopping_board))))"),
        node("a6", "P1", 90, 130, "(HP (HP (H LH_P1) (O pot)) (CP (C holding) "
                                  "(HP (HP (H RH_P2) (O spoon)) (AP (A stir) (O pot)))))"),
        node("a7", "P1", 140, 170, "(HP (HP (H RH_P1) (O spoon)) (AP (A transfer) "
                                   "(OP (O tomato) (OP (O chopping_board) (O pot)))))"),
    )
    sequences = {"P1": ("a1", "a2", "a3", "a6", "a7"), "P2": ("a4", "a5")}
    edges = (GraphEdge("a3", "a5", "handover"),)
    return ActionGraph(nodes, sequences, edges), obs


def test_plan_from_graph_actions_and_order() -> None:
    graph, obs = scenario()
    plan = plan_from_graph(graph, obs)
    validate(plan)
    by_id = {a.id: a for a in plan.actions}
    assert list(by_id) == ["a2", "a4", "a3", "a5", "a6", "a7"]  # grasp-only a1 left out, by start frame
    assert by_id["a2"] == replace(by_id["a2"], pids=("P1",), verb="cut", tool="knife", ingredients=("tomato",),
                                  location="chopping_board", source=None, frames=(10, 50))
    assert by_id["a3"].pids == ("P1", "P2") and by_id["a3"].verb == "handover" and by_id["a3"].tool == "knife"
    assert by_id["a3"].after == ("a2",)                    # the knife's last user; a4 (spoon, pot) is unrelated
    assert set(by_id["a5"].after) == {"a2", "a3"}          # the knife handed over, the tomato and board cut before
    assert by_id["a6"].pids == ("P1", "P2") and by_id["a6"].partner == Act("stir", "spoon", (), "pot")
    assert by_id["a6"].after == ("a4",)                    # the pot and the spoon were last used by a4
    assert by_id["a7"] == replace(by_id["a7"], verb="transfer", tool="spoon", ingredients=("tomato",),
                                  source="chopping_board", location="pot", after=("a5", "a6"))
    assert [a.pid for a in plan.agents] == ["P1", "P2"]


def test_a_holding_without_an_action_is_left_out() -> None:
    graph, obs = scenario()
    idle = node("a8", "P1", 180, 190, "(HP (HP (H LH_P1) (O pot)) (CP (C holding) (HP (H RH_P2) (O pot))))")
    plan = plan_from_graph(replace(graph, nodes=(*graph.nodes, idle)), obs)
    validate(plan)
    assert "a8" not in [a.id for a in plan.actions]


def test_layout_maps_the_video_onto_the_table_without_overlaps() -> None:
    graph, obs = scenario()
    plan = plan_from_graph(graph, obs)
    scene = plan.scene
    assert dict(scene.containing) == {"tomato": "chopping_board"}
    objects = {o.name: o for o in scene.objects}
    assert set(objects) == {"knife", "chopping_board", "tomato", "pot", "spoon", "bowl"}
    # left of the image (P1) -> -x; the image top -> +y
    assert objects["chopping_board"].x < 0 < objects["pot"].x
    assert objects["pot"].y > objects["knife"].y  # (the unused bowl may give way to what the arms must reach)
    # the contained ingredient sits inside its container
    board, tomato = objects["chopping_board"], objects["tomato"]
    bx, by = board.half_extents()
    assert abs(tomato.x - board.x) <= bx and abs(tomato.y - board.y) <= by
    # categories: tools long and thin, containers wide, ingredients small
    assert objects["knife"].size[0] >= 0.14 and objects["knife"].size[1] <= 0.04
    assert objects["pot"].shape == "cylinder" and objects["pot"].size[0] >= 0.1
    assert max(tomato.size) <= 0.08
    free = [o for o in scene.objects if o.name not in dict(scene.containing)]
    for i, a in enumerate(free):
        ax, ay = a.half_extents()
        assert scene.table.holds(a.x, a.y, ax, ay)
        for b in free[i + 1:]:
            bx, by = b.half_extents()
            overlap = abs(a.x - b.x) < ax + bx and abs(a.y - b.y) < ay + by
            assert not overlap, f"{a.name} overlaps {b.name}"


def test_crowded_video_is_pushed_apart_inside_the_table() -> None:
    names = [f"bowl_{k}" for k in range(8)]
    objects = tuple(track(k, n, (300 + k, 200, 340 + k, 240)) for k, n in enumerate(names))  # all on top
    obs = Observations(VideoInfo("v.mp4", 30.0, 100, W, H), objects, (), dict.fromkeys(names, Category.CONTAINER))
    plan = plan_from_graph(ActionGraph((), {}, ()), obs)
    validate(plan)
    placed = plan.scene.objects
    for i, a in enumerate(placed):
        for b in placed[i + 1:]:
            ax, ay = a.half_extents()
            bx, by = b.half_extents()
            assert abs(a.x - b.x) >= ax + bx or abs(a.y - b.y) >= ay + by


def test_generated_plan_round_trips(tmp_path: Path) -> None:
    graph, obs = scenario()
    plan = plan_from_graph(graph, obs)
    assert read_plan(write_plan(plan, tmp_path / "p.yaml")) == plan


@pytest.mark.parametrize(("seed", "persons"), [(0, 2), (1, 2), (2, 2), (3, 1)])
@pytest.mark.slow
def test_plans_of_synthetic_videos_are_valid_and_uncluttered(seed: int, persons: int) -> None:
    from wecook_core.model import ActionKind
    from wecook_core.synth.scenario import synthesize
    from wecook_core.trees.graph import build_graph

    scenario = synthesize(seed, persons)
    graph = build_graph(scenario.actions)
    plan = plan_from_graph(graph, scenario.observations)
    assert plan_problems(plan) == []
    assert [a.pid for a in plan.agents] == ["P1", "P2"][:persons]
    kept = [n for n in graph.nodes if n.action.kind is not ActionKind.GRASP]
    assert [a.id for a in plan.actions] == [n.id for n in sorted(kept, key=lambda n: (n.span.start, n.id))]
    inside = dict(plan.scene.containing)
    free = [o for o in plan.scene.objects if o.name not in inside]
    for i, a in enumerate(free):
        ax, ay = a.half_extents()
        for b in free[i + 1:]:
            bx, by = b.half_extents()
            assert abs(a.x - b.x) >= ax + bx + 0.005 or abs(a.y - b.y) >= ay + by + 0.005, (a.name, b.name)
    for ingredient, container in inside.items():
        o, c = plan.scene.object(ingredient), plan.scene.object(container)
        cx, cy = c.half_extents()
        assert abs(o.x - c.x) < cx and abs(o.y - c.y) < cy
    # an action waits for the latest earlier user of each of its objects, and for nothing unrelated
    for k, action in enumerate(plan.actions):
        mine = action_objects(action)
        for name in mine:
            users = [a.id for a in plan.actions[:k] if name in action_objects(a)]
            assert not users or users[-1] in action.after



def test_an_object_one_arm_uses_stays_on_its_half() -> None:
    objects = (track(1, "knife", (500, 300, 600, 320)),        # at the far right of the image (P2's side)
               track(2, "tomato", (100, 200, 140, 240)), track(3, "pot", (400, 100, 500, 200)))
    categories = {"knife": Category.TOOL, "tomato": Category.INGREDIENT, "pot": Category.CONTAINER}
    obs = Observations(VideoInfo("v.mp4", 30.0, 100, W, H), objects, (), categories)
    nodes = (node("a1", "P1", 0, 40, "(HP (HP (H RH_P1) (O knife)) (AP (A cut) (O tomato)))"),
             node("a2", "P2", 0, 40, "(HP (H LH_P2) (AP (A squeeze) (O pot)))"))
    plan = plan_from_graph(ActionGraph(nodes, {"P1": ("a1",), "P2": ("a2",)}, ()), obs)
    knife, pot = plan.scene.object("knife"), plan.scene.object("pot")
    assert knife.x <= 0.0 < pot.x  # the knife only P1 uses comes to P1's half; the pot stays right


def test_one_arm_objects_stay_on_its_half_when_the_table_is_crowded() -> None:
    """Ten things only P1 uses, all seen in the middle of the image: separating them never moves one across."""
    names = [f"lemon_{k}" for k in range(10)]
    objects = tuple(track(k, n, (300 + 2 * k, 200 + k, 330 + 2 * k, 230 + k)) for k, n in enumerate(names))
    categories = dict.fromkeys(names, Category.INGREDIENT)
    obs = Observations(VideoInfo("v.mp4", 30.0, 100, W, H), objects, (), categories)
    nodes = tuple(node(f"a{k}", "P1", 10 * k, 10 * k + 8, f"(HP (H RH_P1) (AP (A squeeze) (O {n})))")
                  for k, n in enumerate(names))
    plan = plan_from_graph(ActionGraph(nodes, {"P1": tuple(n.id for n in nodes)}, ()), obs)
    validate(plan)
    assert all(o.x <= 1e-9 for o in plan.scene.objects), [(o.name, o.x) for o in plan.scene.objects]
    for a, b in itertools.combinations(plan.scene.objects, 2):
        (ax, ay), (bx, by) = a.half_extents(), b.half_extents()
        assert abs(a.x - b.x) >= ax + bx or abs(a.y - b.y) >= ay + by, (a.name, b.name)


@pytest.mark.slow
def test_the_demo_layout_keeps_each_arm_s_things_on_its_half_and_room_for_the_hand() -> None:
    """The bundled demo's plan: what one person uses lies on that arm's half, and a gripper lying across a tool
    to take it has HAND_ROOM from anything tall (the spoon beside the pot, on P2's side, made P1's grasps and
    scoops fail)."""
    from wecook_core.plan.layout import GAP, HAND_ROOM, LOW
    from wecook_core.workflows import demo_plan

    plan = demo_plan()
    users: dict[str, set[str]] = {}
    for a in plan.actions:
        acts = [(a.pids[0], a.tool, a.ingredients, a.location, a.source)]
        if a.partner is not None:
            p = a.partner
            acts.append((a.pids[1], p.tool, p.ingredients, p.location, p.source))
        for pid, *names in acts:
            for name in [names[0], *names[1], names[2], names[3]]:
                if name is not None:
                    users.setdefault(name, set()).add(pid)
    inside = dict(plan.scene.containing)
    free = [o for o in plan.scene.objects if o.name not in inside]
    sides = {o.name: o.x for o in free if len(users.get(o.name, ())) == 1}
    assert len(sides) >= 5
    for name, x in sides.items():
        assert x <= 0.0 if users[name] == {"P1"} else x >= 0.0, (name, users[name], x)
    tools = [o for o in free if o.category is Category.TOOL]
    assert len(tools) == 4
    for tool in tools:
        tx, ty = tool.half_extents()
        assert ty > tx  # lying along y: the hand spans x
        for other in free:
            if other is tool or other.size[2] <= LOW:
                continue
            ox, oy = other.half_extents()
            assert abs(tool.x - other.x) - tx - ox >= HAND_ROOM - 1e-6 or \
                abs(tool.y - other.y) - ty - oy >= GAP - 1e-6, (tool.name, other.name)


@pytest.mark.parametrize(("name", "shape"), [
    ("pepper", "cylinder"), ("olive_oil", "cylinder"), ("soy_sauce", "cylinder"),
    ("bell_pepper", "sphere"), ("red_pepper", "box"), ("foil", "box"), ("tomatoes", "sphere"),
])
def test_bottles_are_matched_by_head_noun_not_substring(name: str, shape: str) -> None:
    from wecook_core.plan.layout import _shape_for

    assert _shape_for(name, Category.INGREDIENT, 0.05, 0.05)[0] == shape


def test_dependencies_come_from_objects_not_from_the_video_order() -> None:
    actions = (PlanAction("a1", ("P1",), "cut", "knife", ("tomato",), "chopping_board"),
               PlanAction("a2", ("P1",), "stir", "spoon", (), "pot"),
               PlanAction("a3", ("P1", "P2"), "handover", "knife"),
               PlanAction("a4", ("P2",), "peel", "peeler", ("potato",)),
               PlanAction("a5", ("P2", "P1"), "holding", "pot", partner=Act("stir", "spoon", (), "pot")),
               PlanAction("a6", ("P2",), "transfer", "knife", ("tomato",), "bowl", "chopping_board"))
    deps = object_dependencies(actions)
    assert deps == {"a1": (), "a2": (), "a3": ("a1",), "a4": (), "a5": ("a2",), "a6": ("a1", "a3")}
    assert action_objects(actions[4]) == {"pot", "spoon"}


def test_objects_lie_within_the_reach_of_the_arms_that_use_them() -> None:
    from wecook_core.plan.reach import reach_problems

    graph, obs = scenario()
    plan = plan_from_graph(graph, obs)
    assert reach_problems(plan) == []
    # on a table so long that no spot is within both arms' reach, the check says which action cannot be reached
    long = plan_from_graph(graph, obs, table=Table(size=(1.6, 0.8)))
    problems = reach_problems(long)
    assert problems and all(u.distance > u.high for u in problems)
    assert {u.action_id for u in problems} <= {a.id for a in long.actions}


def test_food_held_on_a_board_is_laid_out_as_a_held_board() -> None:
    """P1 holds the cucumber still while P2 cuts it on the board: the executor holds food lying on a board by
    the board, so the layout gives the board the holder's room and keeps the cucumber clear of P1's end."""
    from wecook_core.plan.contents import HOLD_ROOM
    from wecook_core.plan.room import room_problems

    objects = (track(1, "chopping_board", (280, 200, 360, 260)), track(2, "cucumber", (305, 215, 335, 245)),
               track(3, "knife", (560, 400, 630, 420)), track(4, "pot", (10, 10, 60, 60)))  # a small board
    categories = {"chopping_board": Category.CONTAINER, "cucumber": Category.INGREDIENT, "knife": Category.TOOL,
                  "pot": Category.CONTAINER}
    obs = Observations(VideoInfo("v.mp4", 30.0, 200, W, H), objects, (), categories)
    nodes = (node("a1", "P1", 0, 40, "(HP (HP (H LH_P1) (O cucumber)) (CP (C holding) "
                                     "(HP (HP (H LH_P2) (O knife)) (AP (A cut) (O chopping_board)))))"),)
    plan = plan_from_graph(ActionGraph(nodes, {"P1": ("a1",)}, ()), obs)
    board, cucumber = plan.scene.object("chopping_board"), plan.scene.object("cucumber")
    assert dict(plan.scene.containing) == {"cucumber": "chopping_board"}
    assert board.yaw == 0.0  # held along x, between the arms
    left = board.x - board.size[0] / 2  # the end P1 presses
    assert cucumber.x - cucumber.size[0] / 2 - left >= HOLD_ROOM - 1e-6
    assert room_problems(plan) == []


def _hands_at(x_p1: float, x_p2: float) -> tuple[HandTrack, ...]:
    frames = np.arange(0, 200, dtype=np.int64)
    return tuple(HandTrack(hand, frames, np.tile([x, 240.0], (200, 1)), np.tile([x - 20, 220, x + 20, 260.0], (200, 1)))
                 for hand, x in (("LH_P1", x_p1), ("RH_P1", x_p1), ("LH_P2", x_p2), ("RH_P2", x_p2)))


def test_when_p1_works_right_of_p2_the_video_is_laid_out_turned_half_round() -> None:
    """P1's arm stands at the table's -x end; a video with P1 on the right is turned so each person's things lie
    at their own arm's end (unturned, P1's pot would lie at P2's end and P2's knife at P1's)."""
    from wecook_core.plan.layout import p1_on_the_right

    objects = (track(1, "pot", (480, 150, 560, 230)), track(2, "knife", (80, 300, 190, 320)),
               track(3, "tomato", (300, 100, 340, 140)))
    categories = {"pot": Category.CONTAINER, "knife": Category.TOOL, "tomato": Category.INGREDIENT}
    nodes = (node("a1", "P1", 0, 40, "(HP (HP (H RH_P1) (O tomato)) (AP (A sprinkle) (O pot)))"),
             node("a2", "P2", 50, 90, "(HP (HP (H RH_P2) (O knife)) (AP (A cut) (O tomato)))"))
    graph = ActionGraph(nodes, {"P1": ("a1",), "P2": ("a2",)}, ())
    for hands, turned in ((_hands_at(520.0, 130.0), True), (_hands_at(130.0, 520.0), False)):
        obs = Observations(VideoInfo("v.mp4", 30.0, 200, W, H), objects, hands, categories)
        assert p1_on_the_right(obs) is turned
        plan = plan_from_graph(graph, obs)
        pot, knife, tomato = (plan.scene.object(n) for n in ("pot", "knife", "tomato"))
        if turned:
            assert pot.x < -0.03 and knife.x > 0.03  # P1's pot on P1's half, P2's knife on P2's
            assert tomato.y < 0.0  # the image's top is the far side, turned with the rest: -y
        else:  # each on the wrong side of the image: kept on its arm's half, at the middle line
            assert pot.x > -0.01 and knife.x < 0.01
            assert tomato.y > 0.0
    assert not p1_on_the_right(Observations(VideoInfo("v.mp4", 30.0, 200, W, H), objects, (), categories))


def test_a_container_too_near_an_arms_base_to_pour_over_is_named() -> None:
    """An arm takes an ingredient 0.3 m from its base, but cannot tip a spoon over a plate there."""
    from wecook_core.plan.reach import MIN_OVER_REACH, MIN_REACH, reach_problems

    def plan_with(dist: float) -> Plan:
        objects = (SceneObject("spoon", Category.TOOL, "box", (0.14, 0.03, 0.025), -0.1, 0.2, math.pi / 2),
                   SceneObject("plate", Category.CONTAINER, "cylinder", (0.1, 0.1, 0.03), -0.5 + dist, 0.0),
                   SceneObject("pea", Category.INGREDIENT, "sphere", (0.04, 0.04, 0.04), -0.5 + dist, -0.1))
        return Plan(agents=(Agent("P1", "franka_panda/panda.urdf", (-0.5, 0.0, 0.0), 0.0),),
                    scene=Scene(objects=objects),
                    actions=(PlanAction("a1", ("P1",), "transfer", "spoon", ("pea",), "plate", None),))

    assert MIN_REACH < 0.31 < MIN_OVER_REACH
    near = reach_problems(plan_with(0.31))
    assert [(u.name, u.low) for u in near] == [("plate", MIN_OVER_REACH)]
    assert "too close to its base" in str(near[0])
    assert reach_problems(plan_with(MIN_OVER_REACH + 0.01)) == []
