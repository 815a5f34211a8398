"""One stir broken by the detector is one stir: a person's same work with a tool, broken for a moment or named by
the other hand for a while, is joined (:func:`wecook_core.trees.graph.rejoined`); a shot cut, another person or a
transfer (each trip its own) keeps them apart."""

from __future__ import annotations

from wecook_core.model import Action, ActionKind, Category, Segment, SegmentActions
from wecook_core.trees.graph import merge_actions

CATEGORIES = {"spoon": Category.TOOL, "pot": Category.CONTAINER, "onion": Category.INGREDIENT,
              "bowl": Category.CONTAINER}


def _stir(hand: str, start: int, end: int) -> SegmentActions:
    action = Action(ActionKind.TOOL, hand, start, end, verb="stir", held="spoon", targets=("pot",))
    return SegmentActions(Segment(start, end), (action,))


def _grasp(hand: str, start: int, end: int) -> SegmentActions:
    return SegmentActions(Segment(start, end), (Action(ActionKind.GRASP, hand, start, end, held="spoon"),))


def test_a_stir_named_by_the_other_hand_for_a_while_is_one_stir() -> None:
    segments = [_stir("RH_P1", 0, 90), _grasp("LH_P1", 90, 100), _stir("LH_P1", 100, 140), _stir("RH_P1", 140, 200)]
    merged = merge_actions(segments, CATEGORIES, rejoin=30)
    assert [(a.kind, a.hand, a.start, a.end) for a in merged] == [(ActionKind.TOOL, "RH_P1", 0, 200)]
    assert len(merge_actions(segments, CATEGORIES)) > 1  # without rejoining: the detector's breaks stay


def test_a_shot_cut_or_a_long_break_keeps_two_stirs() -> None:
    segments = [_stir("RH_P1", 0, 90), SegmentActions(Segment(90, 140), ()), _stir("RH_P1", 140, 200)]
    assert len(merge_actions(segments, CATEGORIES, rejoin=30)) == 2  # 50 frames apart
    assert len(merge_actions(segments, CATEGORIES, rejoin=60)) == 1
    close = [_stir("RH_P1", 0, 90), _stir("LH_P1", 95, 200)]
    assert len(merge_actions(close, CATEGORIES, rejoin=30, shots=(92,))) == 2
    assert len(merge_actions(close, CATEGORIES, rejoin=30)) == 1


def test_another_person_or_a_second_trip_is_not_joined() -> None:
    other = [_stir("RH_P1", 0, 90), _stir("LH_P2", 95, 200)]
    assert len(merge_actions(other, CATEGORIES, rejoin=30)) == 2

    def trip(start: int, end: int) -> SegmentActions:
        action = Action(ActionKind.TRANSFER, "RH_P1", start, end, verb="transfer", held="spoon",
                        targets=("onion", "bowl", "pot"))
        return SegmentActions(Segment(start, end), (action,))

    assert len(merge_actions([trip(0, 60), SegmentActions(Segment(60, 70), ()), trip(70, 130)], CATEGORIES,
                             rejoin=30)) == 2
