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
