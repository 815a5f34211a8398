"""A1u: an ingredient tipped out of a container by a hand the detector lost moves more than the container
tilting it out; the hold written for that unseen hand is the container's when the same hand holds it just before
or after (the paper: a hand whose closest object is an ingredient in a container holds the container)."""

from __future__ import annotations

from dataclasses import replace

from wecook_core.knowledge.recognize import load_knowledge
from wecook_core.perception.params import Params
from wecook_core.perception.pipeline import analyze
from wecook_core.synth import synthesize
from wecook_core.trees.notation import format_tree


def test_a_bowl_tipped_by_a_hand_lost_meanwhile_is_what_the_hand_holds() -> None:
    """The project's synthetic seed 5: RH_P1 tips the carrots from a bowl into the pot (708-817). With the hand
    lost on 745-790, the carrots falling out moved by themselves, the unseen hold was theirs, and the transfer
    came out with no bowl in the hand (the old code: '(HP (H RH_P1) (AP (A transfer) ...')."""
    scenario = synthesize(5, 2)

    def lost(track):
        keep = ~((track.frames >= 745) & (track.frames < 790))
        return replace(track, frames=track.frames[keep], xy=track.xy[keep], boxes=track.boxes[keep])

    obs = replace(scenario.observations,
                  hands=tuple(lost(t) if t.hand == "RH_P1" else t for t in scenario.observations.hands))
    trees = [format_tree(s.tree) for s in analyze(obs, load_knowledge(), Params()).trees
             if s.start < 817 and s.end > 708 and "transfer" in format_tree(s.tree)]
    assert trees == ["(HP (HP (H RH_P1) (O bowl)) (AP (A transfer) (OP (O carrot) (OP (O bowl) (O pot)))))"], trees
