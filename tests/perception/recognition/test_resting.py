"""Where a held object lies at the ends of its hold (resting.py): a hand the detector loses has not let go, so
the hold goes on across a gap on which the hand is never detected, and the object is not "at rest" there."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from wecook_core.model import Segment
from wecook_core.perception.recognition.resting import hold_of


class _Timeline:
    """The two things hold_of reads of a timeline: the held labels and the object columns."""

    def __init__(self, held: np.ndarray) -> None:
        self.held = held
        self.names = ("salt", "pot")

    def column(self, name: str) -> int:
        return self.names.index(name)


def _held() -> np.ndarray:
    held = np.full((200, 4), -1, dtype=np.int32)
    held[60:90, 1] = 0  # RH_P1 (column 1) holds the salt, then nothing is decoded 90-111, then the salt again
    held[111:200, 1] = 0
    return held


def test_a_hold_goes_on_across_frames_where_its_hand_is_never_detected() -> None:
    timeline = _Timeline(_held())
    lost = np.r_[np.arange(30, 60), np.arange(111, 200)]  # the hand's detections: none in 60-111
    assert hold_of(timeline, "RH_P1", "salt", Segment(75, 98), 8, {}, lost) == (60, 200)  # type: ignore[arg-type]


def test_a_hold_ends_where_the_hand_is_seen_holding_nothing() -> None:
    timeline = _Timeline(_held())
    seen = np.arange(30, 200)  # seen throughout: 90-111 it is seen and holds nothing, a release
    assert hold_of(timeline, "RH_P1", "salt", Segment(75, 98), 8, {}, seen) == (60, 90)  # type: ignore[arg-type]
    assert hold_of(timeline, "RH_P1", "salt", Segment(75, 98), 8, {}) == (60, 90)  # type: ignore[arg-type]


def test_a_salt_shaken_over_a_pot_while_its_hand_is_lost_is_still_sprinkled() -> None:
    """The project's synthetic seed 1: RH_P1 shakes salt over the pot (45-211); with the hand lost on 61-111 the
    first hold (an unseen hand's, from the salt's motion) ended where the hand was lost, the salt lay "at
    rest" at that end beside the pot, the link to the pot was dropped, and the rest read as squeezing the salt
    (the old code)."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.perception.params import Params
    from wecook_core.perception.pipeline import analyze
    from wecook_core.synth import synthesize
    from wecook_core.trees.notation import format_tree

    scenario = synthesize(1, 2)
    obs = scenario.observations

    def lost(track):
        keep = ~((track.frames >= 61) & (track.frames < 111))
        return replace(track, frames=track.frames[keep], xy=track.xy[keep], boxes=track.boxes[keep])

    obs = replace(obs, hands=tuple(lost(t) if t.hand == "RH_P1" else t for t in obs.hands))
    trees = [format_tree(s.tree) for s in analyze(obs, load_knowledge(), Params()).trees
             if s.start < 211 and s.end > 45 and "RH_P1" in format_tree(s.tree)]
    assert trees == ["(HP (HP (H RH_P1) (O salt)) (AP (A sprinkle) (O pot)))"], trees
