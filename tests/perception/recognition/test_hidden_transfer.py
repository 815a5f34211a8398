"""A transfer whose ingredient is hidden on the way (issue 16): at 5 fps the garlic in a small dish is not boxed
while the hand brings the dish over the pan and tips it; it shows up again in the pan."""

from __future__ import annotations

from dataclasses import replace

from handmade_scenes import at, observations, still

from wecook_core.model import Category, Segment
from wecook_core.perception.association.associate import associate_segments
from wecook_core.perception.params import Params
from wecook_core.perception.recognition.transfers import transfer_events

PAN = (0, 80, 420, 480)
DISH = (460, 240, 540, 320)
GARLIC = (470, 250, 530, 310)
"""In the dish."""
MARGIN = 20


def garlic_brought_over(frames: int = 24):
    """The dish waits on the counter (0-5), is carried 25 px a frame over the pan (5-13), then away (13-24);
    the garlic is boxed in it until frame 6 and in the pan from frame 14 (300 px to the left of where it
    was), never in between; the hand around the dish is seen from frame 3 on."""
    over = at(DISH, -25 * 8)
    dish = [still(0, 5, DISH), (5, 13, DISH, over), (13, frames, over, at(over, 10 * (frames - 13)))]
    grip = (-MARGIN, -MARGIN, MARGIN, MARGIN)
    hand = [(first, end, tuple(a + g for a, g in zip(b0, grip, strict=True)),
             tuple(a + g for a, g in zip(b1, grip, strict=True))) for first, end, b0, b1 in dish]
    hand[0] = (3, 5, hand[0][2], hand[0][3])
    obs = observations(frames, {"pan": (Category.CONTAINER, [still(0, frames, PAN)]),
                                "small_bowl": (Category.CONTAINER, dish),
                                "garlic": (Category.INGREDIENT, [still(0, 6, GARLIC),
                                                                 still(14, frames, at(GARLIC, -300))])},
                       {"RH_P1": hand})
    return replace(obs, video=replace(obs.video, fps=5.0))


def test_the_hand_holding_the_dish_the_hidden_garlic_left_transfers_it():
    obs = garlic_brought_over()
    _, timeline = associate_segments(obs, (Segment(0, obs.video.frame_count),), Params())
    assert (timeline.held[6:13, 1] == timeline.names.index("small_bowl")).all()
    (event,) = transfer_events(obs, timeline, Params())
    assert (event.ingredient, event.source, event.destination, event.hand, event.carrier) == \
        ("garlic", "small_bowl", "pan", "RH_P1", "small_bowl")
    assert event.start <= 6 and event.end >= 14


def test_without_a_hand_on_the_dish_nothing_transfers_it():
    obs = garlic_brought_over()
    obs = replace(obs, hands=())
    _, timeline = associate_segments(obs, (Segment(0, obs.video.frame_count),), Params())
    assert transfer_events(obs, timeline, Params()) == ()


def test_a_hand_steadying_the_pan_the_garlic_lands_in_did_not_carry_it_there():
    """What receives an ingredient did not carry it: the hand on the pan's rim holds the destination, and the
    garlic the (undetected) other hand tips from the dish into the pan is no transfer of the steadying hand's,
    with the pan as its carrier (kfc-b 739-781: the cauliflower from the strainer "carried by the bowl" the
    other hand steadied)."""
    frames = 24
    over = at(DISH, -25 * 8)
    dish = [still(0, 5, DISH), (5, 13, DISH, over), (13, frames, over, at(over, 10 * (frames - 13)))]
    garlic = [still(0, 5, GARLIC), (5, 13, GARLIC, at(GARLIC, -25 * 8)),
              (13, 16, at(GARLIC, -25 * 8), at(GARLIC, -300)), still(16, frames, at(GARLIC, -300))]
    rim = (10, 300, 70, 360)  # on the pan's left rim, still throughout
    obs = observations(frames, {"pan": (Category.CONTAINER, [still(0, frames, PAN)]),
                                "small_bowl": (Category.CONTAINER, dish),
                                "garlic": (Category.INGREDIENT, garlic)},
                       {"LH_P1": [still(0, frames, rim)]})
    obs = replace(obs, video=replace(obs.video, fps=5.0))
    _, timeline = associate_segments(obs, (Segment(0, frames),), Params())
    assert (timeline.held[:, 0] == timeline.names.index("pan")).mean() > 0.9  # the hand holds the pan
    assert [e for e in transfer_events(obs, timeline, Params()) if e.carrier == "pan"] == []
