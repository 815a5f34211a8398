from __future__ import annotations

import pytest

from wecook_core.errors import InputError
from wecook_core.model import Action, ActionKind, Category
from wecook_core.trees.graph import (
    PARTNER,
    build_graph,
    case_of,
    compatible,
    dump_graph,
    merge_lane,
    read_graph_file,
    tree_spans,
    write_graph_file,
)
from wecook_core.trees.notation import format_tree, parse_tree

CATEGORIES = {"knife": Category.TOOL, "spoon": Category.TOOL, "tomato": Category.INGREDIENT,
              "onion": Category.INGREDIENT, "lemon": Category.INGREDIENT, "chopping_board": Category.CONTAINER,
              "pot": Category.CONTAINER}


def cut(start, end, *targets, hand="RH_P1"):
    return Action(ActionKind.TOOL, hand, start, end, verb="cut", held="knife", targets=targets)


def grasp(start, end, held="knife", hand="RH_P1"):
    return Action(ActionKind.GRASP, hand, start, end, held=held)


def test_actions_identical_up_to_their_ingredients_are_compatible():
    # one grasp of a tool on one container is one action, whichever ingredient it was nearest to
    assert compatible(cut(0, 1, "tomato", "chopping_board"), cut(1, 2, "chopping_board"), CATEGORIES)
    assert compatible(cut(0, 1, "tomato", "chopping_board"), cut(1, 2, "onion", "chopping_board"), CATEGORIES)
    transfer = Action(ActionKind.TRANSFER, "RH_P1", 0, 1, verb="transfer", held="spoon",
                      targets=("tomato", "chopping_board", "pot"))
    other = Action(ActionKind.TRANSFER, "RH_P1", 1, 2, verb="transfer", held="spoon",
                   targets=("onion", "chopping_board", "pot"))
    assert not compatible(transfer, other, CATEGORIES)
    assert not compatible(cut(0, 1, "chopping_board"), cut(1, 2, "pot"), CATEGORIES)
    assert not compatible(cut(0, 1, "tomato"), cut(1, 2, "tomato", hand="LH_P1"), CATEGORIES)


def test_a_lane_merges_consecutive_compatible_segments_from_grasp_to_release():
    items = [(0, 10, None), (10, 20, grasp(10, 20)), (20, 30, cut(20, 30, "chopping_board")),
             (30, 50, cut(30, 50, "tomato", "chopping_board")), (50, 60, grasp(50, 60)), (60, 70, None)]
    (merged,) = merge_lane(items, CATEGORIES)
    assert (merged.start, merged.end) == (10, 60)
    assert merged.targets == ("tomato", "chopping_board")


def test_a_lane_splits_at_a_different_action_and_at_an_empty_segment():
    items = [(0, 10, cut(0, 10, "tomato")), (10, 30, cut(10, 30, "onion")), (30, 40, cut(30, 40, "pot")),
             (40, 50, None), (50, 60, cut(50, 60, "onion"))]
    merged = merge_lane(items, CATEGORIES)
    # the ingredient seen over most frames names the first action; another container is another action
    assert [(a.start, a.end, a.targets) for a in merged] == [(0, 30, ("onion",)), (30, 40, ("pot",)),
                                                           (50, 60, ("onion",))]


def test_grasps_alone_merge_into_one_grasp_and_partner_segments_do_not_break_a_lane():
    items = [(0, 10, grasp(0, 10)), (10, 20, grasp(10, 20)), (20, 30, PARTNER), (30, 40, grasp(30, 40, "spoon"))]
    merged = merge_lane(items, CATEGORIES)
    assert [(a.kind, a.held, a.start, a.end) for a in merged] == [
        (ActionKind.GRASP, "knife", 0, 30), (ActionKind.GRASP, "spoon", 30, 40)]


def holding_action(start, end):
    partner = cut(start, end, "tomato", hand="RH_P2")
    return Action(ActionKind.HOLDING, "LH_P1", start, end, held="chopping_board", partner=partner)


def test_graph_numbers_nodes_by_start_and_links_sequences_and_collaborations():
    actions = [
        cut(50, 90, "tomato", hand="RH_P2"),
        grasp(0, 40, "spoon", hand="RH_P2"),
        cut(0, 30, "tomato", "chopping_board"),
        holding_action(100, 160),
        Action(ActionKind.HAND, "LH_P2", 170, 200, verb="squeeze", targets=("lemon",)),
    ]
    graph = build_graph(actions)
    assert [(n.id, n.person, n.span.start) for n in graph.nodes] == [
        ("a1", "P1", 0), ("a2", "P2", 0), ("a3", "P2", 50), ("a4", "P1", 100), ("a5", "P2", 170)]
    assert graph.sequences == {"P1": ("a1", "a4"), "P2": ("a2", "a3", "a5")}
    edges = {(e.source, e.target, e.kind) for e in graph.edges}
    assert edges == {("a1", "a4", "sequence"), ("a2", "a3", "sequence"), ("a3", "a5", "sequence"),
                     ("a3", "a4", "holding"), ("a4", "a5", "holding")}
    holding_node = graph.nodes[3]
    assert format_tree(holding_node.span.tree) == (
        "(HP (HP (H LH_P1) (O chopping_board)) (CP (C holding) (HP (HP (H RH_P2) (O knife)) "
        "(AP (A cut) (O tomato)))))")


def test_graph_file_round_trips(tmp_path):
    graph = build_graph([cut(0, 30, "tomato", "chopping_board"), holding_action(40, 80)])
    path = tmp_path / "graph.yaml"
    write_graph_file(path, graph)
    again = read_graph_file(path)
    assert [(n.id, n.person, n.span) for n in again.nodes] == [(n.id, n.person, n.span) for n in graph.nodes]
    assert again.sequences == graph.sequences and again.edges == graph.edges
    assert dump_graph(again) == path.read_text()


def test_bad_graph_files_name_the_entry(tmp_path):
    path = tmp_path / "graph.yaml"
    path.write_text('wecook_graph: 1\nnodes:\n- {id: a1, person: P1, start: 5, end: 2, tree: "(HP (H RH_P1) (O x))"}\n')
    with pytest.raises(InputError, match=r"nodes\[1\]"):
        read_graph_file(path)
    path.write_text('wecook_graph: 1\nnodes:\n- {id: a1, person: P1, start: 0, end: 2, tree: "(HP (H XX) (O x))"}\n')
    with pytest.raises(InputError, match="tree"):
        read_graph_file(path)
    path.write_text("nodes: []\n")
    with pytest.raises(InputError, match="not a graph file"):
        read_graph_file(path)


def test_tree_spans_and_cases():
    actions = [cut(0, 10, "tomato"), cut(0, 10, "tomato", "chopping_board"), grasp(0, 5),
               Action(ActionKind.TOOL, "RH_P1", 0, 9, verb="pour", held="lemon", targets=("pot",)),
               holding_action(0, 10)]
    assert [case_of(a, CATEGORIES) for a in actions] == ["tool", "container", "grasp", "held", "holding"]
    spans = tree_spans(actions)
    assert [(s.start, s.end) for s in spans] == [(0, 10), (0, 10), (0, 5), (0, 9), (0, 10)]
    assert all(parse_tree(format_tree(s.tree)) == s.tree for s in spans)


def stir(start, end, *targets, hand="RH_P1"):
    return Action(ActionKind.TOOL, hand, start, end, verb="stir", held="spoon", targets=targets)


def test_one_grasp_on_the_same_targets_is_one_action_with_the_verb_of_most_frames():
    # the first strokes of a stir do not show its circles yet: GGS's first segment is recognised as a pour
    pour = Action(ActionKind.TOOL, "RH_P1", 0, 20, verb="pour", held="spoon", targets=("pot",))
    items = [(0, 20, pour), (20, 60, stir(20, 60, "pot")), (60, 70, grasp(60, 70, "spoon"))]
    (merged,) = merge_lane(items, CATEGORIES)
    assert (merged.verb, merged.start, merged.end) == ("stir", 0, 70)
    transfer = Action(ActionKind.TRANSFER, "RH_P1", 20, 60, verb="transfer", held="spoon",
                      targets=("onion", "pot", "chopping_board"))
    assert len(merge_lane([(0, 20, pour), (20, 60, transfer)], CATEGORIES)) == 2


def test_short_bare_holds_and_a_partners_own_hold_are_not_actions():
    from wecook_core.model import Segment, SegmentActions
    from wecook_core.trees.graph import merge_actions

    held = holding_action(40, 100)
    per_segment = [
        SegmentActions(Segment(0, 20), (grasp(0, 20, "pot"),)),  # a touch on the way: 20 frames
        SegmentActions(Segment(20, 40), (cut(20, 40, "tomato"), grasp(20, 40, "knife", hand="RH_P2"))),
        SegmentActions(Segment(40, 100), (cut(40, 100, "tomato"), held), partners=("RH_P2",)),
        SegmentActions(Segment(100, 140), (grasp(100, 140, "knife", hand="RH_P2"),)),
    ]
    kept = merge_actions(per_segment, CATEGORIES, min_hold=30)
    assert [(a.kind, a.hand) for a in kept] == [(ActionKind.TOOL, "RH_P1"), (ActionKind.HOLDING, "LH_P1")]
    everything = merge_actions(per_segment, CATEGORIES)
    assert (ActionKind.GRASP, "RH_P1") in [(a.kind, a.hand) for a in everything]
