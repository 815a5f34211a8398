"""Holds by unseen hands: what an ingredient rides in is what is carried (common fate), even when the container,
bigger, moves less than its own size's share."""

from __future__ import annotations

from dataclasses import replace

from handmade_scenes import Box, Piece, at, observations, still

from wecook_core.model import Category
from wecook_core.perception.params import Params
from wecook_core.perception.repairs.unseen import unseen_holds

CUP: tuple[float, float, float, float] = (100, 200, 260, 360)
"""A measuring cup, its diagonal 226 px: 40 px moves it less than a quarter of its size."""
YOGURT: tuple[float, float, float, float] = (160, 260, 200, 300)
BOWL: tuple[float, float, float, float] = (300, 150, 600, 450)


def _tipped(box: Box) -> list[Piece]:
    """Tipped and rocked over frames 10-30, 0.4 s each way at 5 fps."""
    there = at(box, 40, -10)
    return [(10 + 2 * i, 12 + 2 * i, *((box, there) if i % 2 == 0 else (there, box))) for i in range(10)]


def test_the_cup_tipped_by_a_hand_nobody_sees_is_held_not_the_yogurt_in_it() -> None:
    obs = observations(40, {
        "bowl": (Category.CONTAINER, [still(0, 40, BOWL)]),
        "measuring_cup": (Category.CONTAINER, [still(0, 10, CUP), *_tipped(CUP), still(30, 40, CUP)]),
        "yogurt": (Category.INGREDIENT, [still(0, 10, YOGURT), *_tipped(YOGURT), still(30, 40, YOGURT)]),
    }, {})
    obs = replace(obs, video=replace(obs.video, fps=5.0))
    held = {hold.obj for hold in unseen_holds(obs, Params())}
    assert held == {"measuring_cup"}, held


def test_the_hold_goes_to_the_hand_last_seen_at_the_object_not_the_videos_busiest_hand() -> None:
    """P1's right hand is seen all along at its board; P2's left hand reaches the cup, is lost by the detector
    while it tips it, and is seen again letting go: the hold is P2's."""
    p2_on_cup = (240, 180, 290, 230)
    obs = observations(40, {
        "bowl": (Category.CONTAINER, [still(0, 40, BOWL)]),
        "measuring_cup": (Category.CONTAINER, [still(0, 10, CUP), *_tipped(CUP), still(30, 40, CUP)]),
    }, {"RH_P1": [still(0, 40, (560, 20, 620, 80))],
        "LH_P2": [still(4, 10, p2_on_cup), still(31, 36, p2_on_cup)]})
    obs = replace(obs, video=replace(obs.video, fps=5.0))
    holds = unseen_holds(obs, Params())
    assert {(h.hand, h.obj) for h in holds} == {("LH_P2", "measuring_cup")}, holds
