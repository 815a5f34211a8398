"""R0: a detector's frame-to-frame jitter is taken out of the boxes before motion is read."""

from __future__ import annotations

import numpy as np
from handmade_scenes import observations, still

from wecook_core.model import Category
from wecook_core.perception.params import Params
from wecook_core.perception.pipeline import repaired
from wecook_core.perception.repairs.smoothing import _median_runs, smoothed


def _glitching_onion(frames: int = 90):
    """An onion lying still on the board; on every third frame (from the second) its box is drawn 12 px off (a
    detector's glitch), and no hand is anywhere near."""
    onion = []
    for f in range(frames):
        box = (300.0, 200.0, 330.0, 230.0) if f % 3 != 1 else (312.0, 200.0, 342.0, 230.0)
        onion.append((f, f + 1, box, box))
    return observations(frames, {"onion": (Category.INGREDIENT, onion),
                                 "chopping_board": (Category.CONTAINER, [still(0, frames, (200, 150, 500, 400))])},
                        {"RH_P1": [still(0, frames, (20, 20, 50, 50))]})


def test_a_still_onion_whose_box_glitches_is_not_moved_by_an_unseen_hand():
    obs = _glitching_onion()
    assert repaired(obs, Params()).unseen == ()
    # what the glitches alone made of it: the onion moving by itself, held by a hand nobody sees
    assert repaired(obs, Params(smooth_s=0)).unseen != ()


def test_the_running_median_is_numpys_within_each_run_of_frames_and_never_across_a_gap():
    rng = np.random.default_rng(3)
    frames = np.concatenate([np.arange(0, 40), np.arange(50, 53), np.arange(60, 100)])
    values = rng.normal(size=(len(frames), 4))
    for half in (1, 2, 3):
        out = _median_runs(frames, values, half)
        for lo, hi in ((0, 40), (40, 43), (43, 83)):
            run = values[lo:hi]
            padded = np.pad(run, ((half, half), (0, 0)), mode="edge")
            expected = np.median(np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1, axis=0), axis=-1)
            assert np.array_equal(out[lo:hi], expected)


def test_smoothing_keeps_a_step_and_a_steady_motion():
    obs = observations(40, {"cup": (Category.CONTAINER, [still(0, 20, (100, 100, 140, 140)),
                                                         (20, 40, (200, 100, 240, 140), (280, 100, 320, 140))])},
                       {"LH_P1": [(0, 40, (0, 0, 20, 20), (390, 0, 410, 20))]})
    out = smoothed(obs, 2)
    cup, hand = out.objects[0], out.hands[0]
    assert np.array_equal(cup.boxes[:20], obs.objects[0].boxes[:20])  # still, then a jump: kept where it is
    assert np.allclose(cup.boxes[22:38], obs.objects[0].boxes[22:38])  # a steady motion is its own median
    assert np.allclose(hand.xy[2:38], obs.hands[0].xy[2:38])
    assert smoothed(obs, 0) is obs
