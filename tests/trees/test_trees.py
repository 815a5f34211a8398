from __future__ import annotations

import pytest

from wecook_core.model import Action, ActionKind
from wecook_core.trees.notation import TreeSyntaxError, action_of, format_tree, has_action, parse_tree, tree_of

DESIGN_TABLE = [
    "(HP (H RH_P1) (O knife))",
    "(HP (HP (H RH_P1) (O knife)) (AP (A cut) (O tomato)))",
    "(HP (HP (H RH_P1) (O knife)) (AP (A cut) (OP (O tomato) (O chopping_board))))",
    "(HP (H LH_P1) (AP (A squeeze) (O lemon)))",
    "(HP (HP (H RH_P1) (O spoon)) (AP (A transfer) (OP (O meat) (OP (O chopping_board) (O pot)))))",
    "(HP (HP (H LH_P1) (O chopping_board)) (CP (C holding) (HP (HP (H RH_P2) (O knife)) (AP (A cut) (O meat)))))",
    "(HP (HP (H RH_P1) (O lemon)) (CP (C handover) (HP (H LH_P2) (O lemon))))",
    "(HP (HP (H RH_P1) (O oil)) (AP (A pour) (O pot)))",
    "(HP (HP (H RH_P1) (O bowl)) (AP (A transfer) (OP (O cheese) (OP (O bowl) (O pot)))))",
]


@pytest.mark.parametrize("text", DESIGN_TABLE)
def test_design_table_round_trips(text: str) -> None:
    tree = parse_tree(text)
    assert format_tree(tree) == text
    assert parse_tree(format_tree(tree)) == tree


@pytest.mark.parametrize("text", DESIGN_TABLE)
def test_action_of_inverts_tree_of(text: str) -> None:
    assert format_tree(tree_of(action_of(parse_tree(text)))) == text


def test_tree_of_builds_the_holding_case() -> None:
    cut = Action(ActionKind.TOOL, "RH_P2", 0, 10, verb="cut", held="knife", targets=("meat",))
    holding = Action(ActionKind.HOLDING, "LH_P1", 0, 10, held="chopping_board", partner=cut)
    assert format_tree(tree_of(holding)) == DESIGN_TABLE[5]


def test_objects_named_like_verbs_still_parse() -> None:
    text = "(HP (HP (H RH_P1) (O cutting_board)) (AP (A cut) (O cut)))"
    assert format_tree(parse_tree(text)) == text


@pytest.mark.parametrize(
    "bad",
    [
        "(HP (H XX_P1) (O knife))",  # unknown hand
        "(HP (H RH_P1) (A cut))",  # HP -> H A is not a rule
        "(HP (HP (H RH_P1) (O knife)) (AP (A chop) (O tomato)))",  # not in the vocabulary
        "(HP (H RH_P1) (O knife)",  # unbalanced
        "",
    ],
)
def test_bad_trees_raise(bad: str) -> None:
    with pytest.raises(TreeSyntaxError):
        parse_tree(bad)


def test_has_action() -> None:
    assert not has_action(parse_tree(DESIGN_TABLE[0]))
    assert all(has_action(parse_tree(t)) for t in DESIGN_TABLE[1:])
