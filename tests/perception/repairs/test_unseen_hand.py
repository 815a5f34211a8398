"""Which hand an unseen hold is given when no hand is seen near the object before or after it: the cook's
working hand, the one that travels farthest while seen, not the one seen most (kfc-b: the hand steadying the
bowl keeps still and is detected on more frames than the one that fetches and stirs)."""

from __future__ import annotations

import pytest
from handmade_scenes import at, observations, still

from wecook_core.model import Category
from wecook_core.perception.params import Params
from wecook_core.perception.repairs.unseen import unseen_holds

STEADY = (40, 300, 90, 390)
"""A hand on a bowl's rim, still and seen throughout."""
WORKING = (400, 300, 450, 350)


def scene(working: str, steady: str):
    """The steady hand seen on all 300 frames; the working hand seen on 100, fetching across the table and
    back; then, from 200 on, a jar swings over the far corner with no hand seen within reach of it."""
    far = at(WORKING, -250, -200)
    jar = (560, 40, 600, 80)
    hands = {steady: [still(0, 300, STEADY)],
             working: [(0, 50, WORKING, far), (50, 100, far, WORKING)]}
    objects = {"jar": (Category.INGREDIENT, [still(0, 200, jar), (200, 230, jar, at(jar, -60, 40)),
                                              (230, 260, at(jar, -60, 40), jar), still(260, 300, jar)])}
    return observations(300, objects, hands)


@pytest.mark.parametrize(("working", "steady"), [("RH_P1", "LH_P1"), ("LH_P1", "RH_P1")])
def test_an_unseen_hold_far_from_every_hand_goes_to_the_hand_that_travels_farthest(working: str,
                                                                                   steady: str) -> None:
    holds = unseen_holds(scene(working, steady), Params())
    assert holds and {h.obj for h in holds} == {"jar"}
    assert {h.hand for h in holds} == {working}, holds


def elsewhere_scene(passer: str, mover: str):
    """A jar swings over frames 100-160 with no hand seen at it. Just before, ``passer`` came by the jar (it is
    the hand seen nearest it then), and during the swing it is seen at the far end of the table, still; the
    ``mover`` is seen only before and after, near its own side, far from everything (it travels farthest)."""
    jar = (300, 200, 340, 240)
    passing = (340, 240, 390, 290)  # touching the jar's corner at frames 80-100
    far_end = (40, 400, 90, 450)
    home = (560, 40, 610, 90)
    hands = {passer: [(60, 80, far_end, passing), still(80, 100, passing), (100, 110, passing, far_end),
                      still(110, 200, far_end)],
             mover: [(0, 30, home, at(home, 0, 300)), (30, 60, at(home, 0, 300), home),
                     (170, 200, home, at(home, 0, 300))]}
    objects = {"jar": (Category.INGREDIENT, [still(0, 100, jar), (100, 130, jar, at(jar, 80, 60)),
                                              (130, 160, at(jar, 80, 60), jar), still(160, 200, jar)])}
    return observations(200, objects, hands)


@pytest.mark.parametrize(("passer", "mover"), [("RH_P1", "LH_P1"), ("LH_P1", "RH_P2")])
def test_a_hand_seen_elsewhere_while_the_object_moves_is_not_the_unseen_hand_moving_it(passer: str,
                                                                                     mover: str) -> None:
    """R7b: the hand seen nearest the jar just before its swing is seen at the far end of the table while the
    jar swings; it is not the one swinging it (with ``elsewhere_s`` too long to count those frames, R7 gives
    it the hold)."""
    obs = elsewhere_scene(passer, mover)
    holds = unseen_holds(obs, Params())
    assert holds and {h.obj for h in holds} == {"jar"}, holds
    assert {h.hand for h in holds} == {mover}, holds
    blind = unseen_holds(obs, Params(elsewhere_s=100.0))
    assert {h.hand for h in blind} == {passer}, blind
