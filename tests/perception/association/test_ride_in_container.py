"""The paper's hand-object rule: a hand on an ingredient that lies in a container it carries holds the container
(the egg rides in the small bowl the hand tips into a bigger one), while an ingredient held over a still
container (the oil bottle over the pot) stays the held object."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from handmade_scenes import Piece, at, observations, still

from wecook_core.knowledge.recognize import load_knowledge
from wecook_core.model import HANDS, Category, Observations
from wecook_core.perception.association.frame_links import frame_links
from wecook_core.perception.params import Params
from wecook_core.perception.pipeline import analyze
from wecook_core.trees.notation import format_tree

BIG: tuple[float, float, float, float] = (300, 180, 520, 400)
SMALL: tuple[float, float, float, float] = (60, 220, 180, 340)
"""Bigger than the hand that tips it (a partly seen hand on its rim)."""
EGG: tuple[float, float, float, float] = (100, 260, 140, 300)
HAND: tuple[float, float, float, float] = (120, 240, 190, 310)


def _tipping(frames: int = 150) -> Observations:
    """At 5 fps, as real frame dumps are (where a few frames of evidence flip what a hand holds)."""
    carry = 260.0  # the small bowl moves over the big one, is tipped there, and is brought back
    obs = observations(frames, {
        "big_bowl": (Category.CONTAINER, [still(0, frames, BIG)]),
        "small_bowl": (Category.CONTAINER, [still(0, 30, SMALL), (30, 70, SMALL, at(SMALL, carry)),
                                            still(70, 110, at(SMALL, carry)), (110, frames, at(SMALL, carry), SMALL)]),
        "egg": (Category.INGREDIENT, [still(0, 30, EGG), (30, 70, EGG, at(EGG, carry)), still(70, 85, at(EGG, carry)),
                                     (85, 95, at(EGG, carry), at(EGG, carry + 60, -10)),
                                     still(95, frames, at(EGG, carry + 60, -10))]),
    }, {
        # the hand on the rim, lost by the detector while it carries the bowl over (as on real footage), seen
        # again, still, while it tips it and the egg slides out
        "RH_P1": [still(0, 30, HAND), still(70, 110, at(HAND, carry)), (110, frames, at(HAND, carry), HAND)],
    })
    return replace(obs, video=replace(obs.video, fps=5.0))


def test_the_hand_holds_the_container_the_ingredient_rides_in() -> None:
    obs = _tipping()
    links = frame_links(obs, 0, obs.video.frame_count, Params())
    names = links.boxes.names
    held = [names[i] if i >= 0 else None for i in links.held[70:110, HANDS.index("RH_P1")]]
    assert "egg" not in held, held
    assert held.count("small_bowl") > len(held) // 2, held


def test_the_tipped_bowl_transfers_the_egg_from_it_into_the_big_bowl() -> None:
    trees = [format_tree(t.tree) for t in analyze(_tipping(), load_knowledge(), Params()).trees]
    tipped = "(O small_bowl)) (AP (A transfer) (OP (O egg) (OP (O small_bowl) (O big_bowl))))"
    assert any(tipped in t for t in trees), trees


def test_an_ingredient_held_over_a_still_container_stays_held() -> None:
    pot: tuple[float, float, float, float] = (200, 150, 450, 400)
    bottle: tuple[float, float, float, float] = (60, 200, 100, 300)
    hand: tuple[float, float, float, float] = (50, 230, 110, 290)
    obs = observations(120, {
        "pot": (Category.CONTAINER, [still(0, 120, pot)]),
        "oil": (Category.INGREDIENT, [(0, 40, bottle, at(bottle, 240)), still(40, 80, at(bottle, 240)),
                                      (80, 120, at(bottle, 240), bottle)]),
    }, {"RH_P1": [(0, 40, hand, at(hand, 240)), still(40, 80, at(hand, 240)), (80, 120, at(hand, 240), hand)]})
    links = frame_links(obs, 0, 120, Params())
    names = links.boxes.names
    held = np.asarray([names[i] if i >= 0 else "" for i in links.held[10:110, HANDS.index("RH_P1")]])
    assert (held == "oil").mean() > 0.8, held


def test_a_hand_that_pivots_on_the_rim_holds_the_bowl_it_tips_not_the_egg_in_it() -> None:
    """The hand's box stays put while its wrist turns; the bowl, bigger than the hand, and the egg in it move:
    the motion of the egg alone would name the egg (it is small enough to be carried by the hand), but it rides
    in the bowl that moves with it."""
    bowl: tuple[float, float, float, float] = (60, 220, 180, 340)
    egg: tuple[float, float, float, float] = (130, 260, 170, 300)
    hand: tuple[float, float, float, float] = (150, 240, 210, 300)
    def swing(box: tuple[float, float, float, float]) -> list[Piece]:
        """Rocked back and forth while tipped, 0.4 s each way."""
        there = at(box, 40, -20)
        return [(15 + 2 * i, 17 + 2 * i, *((box, there) if i % 2 == 0 else (there, box))) for i in range(15)]

    obs = observations(60, {
        "big_bowl": (Category.CONTAINER, [still(0, 60, (250, 150, 500, 400))]),
        "small_bowl": (Category.CONTAINER, [still(0, 15, bowl), *swing(bowl), still(45, 60, bowl)]),
        "egg": (Category.INGREDIENT, [still(0, 15, egg), *swing(egg), still(45, 60, egg)]),
    }, {"RH_P1": [still(0, 60, hand)]})
    obs = replace(obs, video=replace(obs.video, fps=5.0))
    links = frame_links(obs, 0, 60, Params())
    names = links.boxes.names
    held = [names[i] if i >= 0 else None for i in links.held[15:45, HANDS.index("RH_P1")]]
    assert "egg" not in held, held
    assert "small_bowl" in held, held
