"""`wecook plan check`'s room rules (:mod:`wecook_core.plan.room`) and the layout that keeps them."""

from __future__ import annotations

import math

import pytest

from wecook_core.model import Category
from wecook_core.plan import Act, Plan, PlanAction, Scene, SceneObject, agents_for
from wecook_core.plan.contents import END_ROOM, HOLD_ROOM, end_rooms, fit_board, spread
from wecook_core.plan.room import MIN_HAND_ROOM, room_problems

PIN = SceneObject("rolling_pin", Category.TOOL, "box", (0.14, 0.03, 0.025), 0.2, 0.25, math.pi / 2)
DOUGH = SceneObject("dough", Category.INGREDIENT, "box", (0.06, 0.04, 0.03), 0.1, 0.1)
BOARD = SceneObject("board", Category.CONTAINER, "box", (0.3, 0.14, 0.02), 0.0, -0.1)
KNIFE = SceneObject("knife", Category.TOOL, "box", (0.14, 0.03, 0.025), 0.2, -0.3, math.pi / 2)


def pot(x: float) -> SceneObject:
    return SceneObject("pot", Category.CONTAINER, "cylinder", (0.1, 0.1, 0.12), x, 0.1)


def roll_plan(*objects: SceneObject) -> Plan:
    return Plan(agents=agents_for(["P1", "P2"]), scene=Scene(objects=objects),
                actions=(PlanAction("a1", ("P2",), "roll", "rolling_pin", ("dough",)),))


def test_a_tall_object_beside_what_a_tool_works_on_is_named_with_the_room_there_is() -> None:
    near = room_problems(roll_plan(PIN, DOUGH, pot(0.1 - 0.03 - 0.04 - 0.05)))  # 4 cm between the footprints
    assert [(p.action_id, p.name, p.what, round(p.distance, 3)) for p in near] == [("a1", "pot", "dough", 0.04)]
    assert "a1 (roll by P2): the pot stands 0.04 m from the dough" in str(near[0])
    assert room_problems(roll_plan(PIN, DOUGH, pot(0.1 - 0.03 - MIN_HAND_ROOM - 0.06))) == []
    low = SceneObject("pot", Category.CONTAINER, "cylinder", (0.1, 0.1, 0.03), 0.0, 0.1)  # a plate: under the palm
    assert room_problems(roll_plan(PIN, DOUGH, low)) == []


def holding_plan(food_x: float, held: str = "board") -> Plan:
    """P1 holds the board (or the cucumber on it: ``held``) while P2 cuts the cucumber."""
    cucumber = SceneObject("cucumber", Category.INGREDIENT, "box", (0.06, 0.04, 0.03), food_x, -0.1)
    partner = Act("cut", "knife", ("cucumber",)) if held == "board" else Act("cut", "knife", (), "board")
    return Plan(agents=agents_for(["P1", "P2"]),
                scene=Scene(objects=(BOARD, KNIFE, cucumber), containing=(("cucumber", "board"),)),
                actions=(PlanAction("a1", ("P1", "P2"), "holding", held, partner=partner),))


@pytest.mark.parametrize("held", ["board", "cucumber"])
def test_food_at_the_end_of_a_board_the_holder_presses_is_named(held: str) -> None:
    # P1 holds, P2 (at +x) cuts: P1 presses the -x end, at x = -0.15 (food on a board is held by the board)
    crowded = room_problems(holding_plan(-0.15 + 0.03 + 0.03, held))  # 3 cm from the end
    assert [(p.holding, p.name, p.what, round(p.distance, 3)) for p in crowded] == [(True, "cucumber", "board", 0.03)]
    assert "the cucumber lies 0.03 m from the end of the board the holder presses" in str(crowded[0])
    assert room_problems(holding_plan(-0.15 + HOLD_ROOM + 0.03, held)) == []
    assert room_problems(holding_plan(0.15 - 0.03 - 0.005, held)) == []  # at the other end: the partner's side


def test_a_held_board_lies_along_x_and_keeps_its_food_clear_of_the_holders_end() -> None:
    turned = SceneObject("board", Category.CONTAINER, "box", (0.25, 0.14, 0.02), 0.0, 0.0, math.pi / 2)
    items = [SceneObject(n, Category.INGREDIENT, "box", (0.06, 0.04, 0.03), 0.0, 0.0) for n in ("a", "b")]
    assert end_rooms({"P1"}) == (HOLD_ROOM, END_ROOM) and end_rooms({"P2"}) == (END_ROOM, HOLD_ROOM)
    for holders in ({"P1"}, {"P2"}, {"P1", "P2"}):
        board = fit_board(turned, items, holders)
        assert board.yaw == 0.0
        placed = spread(board, items, holders)
        low, high = end_rooms(holders)
        left, right = -board.size[0] / 2, board.size[0] / 2
        assert min(o.x - 0.03 for o in placed) - left >= low - 1e-6
        assert right - max(o.x + 0.03 for o in placed) >= high - 1e-6
        assert all(abs(o.y) < 1e-9 for o in placed)
    assert fit_board(turned, items, set()).yaw == turned.yaw  # a board no one holds keeps its way
