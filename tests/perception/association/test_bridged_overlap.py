"""R1a: boxes that part for a frame or two and touch again keep the grasp (box noise, like a missed detection)."""

from __future__ import annotations

import numpy as np
from handmade_scenes import observations

from wecook_core.model import Category
from wecook_core.perception.association.frame_links import NONE, bridged, frame_links
from wecook_core.perception.params import Params


def _carry(apart: range, frames: int = 60):
    """RH_P1 carries an onion 4 px a frame; on the frames of ``apart`` the onion's box is drawn 6 px below the
    hand's (the boxes do not touch)."""
    hand, onion = [], []
    for f in range(frames):
        x = 100 + 4 * f
        hand.append((f, f + 1, (x, 200, x + 30, 230), (x, 200, x + 30, 230)))
        drop = 36 if f in apart else 0  # the onion's top 6 px under the hand's bottom edge
        onion.append((f, f + 1, (x + 2, 225 + drop - 25, x + 28, 250 + drop - 25),
                      (x + 2, 225 + drop - 25, x + 28, 250 + drop - 25)))
    return observations(frames, {"onion": (Category.INGREDIENT, onion)}, {"RH_P1": hand})


def test_a_carried_onion_whose_box_parts_from_the_hand_for_three_frames_stays_held():
    obs = _carry(range(20, 23))
    links = frame_links(obs, 0, 60, Params())
    onion = links.boxes.names.index("onion")
    assert (links.held[:, 1] == onion).all()


def test_boxes_apart_for_longer_than_a_detector_gap_are_apart():
    obs = _carry(range(20, 40))  # 20 frames, two thirds of a second: the onion is not in that hand there
    links = frame_links(obs, 0, 60, Params())
    assert (links.held[22:38, 1] == NONE).all()


def test_only_short_gaps_between_touching_frames_in_one_shot_with_both_boxes_seen_are_bridged():
    touch = np.array([1, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 1, 1], dtype=bool)[:, None]
    seen = np.ones_like(touch)
    one_shot = np.zeros(len(touch), dtype=np.int64)
    result = bridged(touch, seen, 2, one_shot)[:, 0]
    assert result.tolist() == [True] * 5 + [False] * 5 + [True] * 4  # gaps of 2 and 1 bridged, 5 not
    cut = one_shot.copy()
    cut[3:] = 1  # a shot cut inside the first gap
    assert not bridged(touch, seen, 2, cut)[2:4, 0].any()
    unseen = seen.copy()
    unseen[11] = False  # the hand not seen there: R1's business, not box noise
    assert not bridged(touch, unseen, 2, one_shot)[11, 0]
