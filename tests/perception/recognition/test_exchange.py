"""C-h: a handover is told by the segment where the giver's hold ends, even when the segmentation cut that hold
a few frames before the exchange (``handover_gap_s``), so the segment with the exchange has the giver's hold
on too few frames to count."""

from __future__ import annotations

from bench.quality import hands_dropped
from wecook_core.knowledge.recognize import load_knowledge
from wecook_core.perception.params import Params
from wecook_core.perception.pipeline import analyze
from wecook_core.synth import synthesize
from wecook_core.trees.notation import format_tree


def test_a_handover_whose_giver_s_hold_ends_just_after_a_segment_cut_is_found() -> None:
    """The project's synthetic seed 1 with hands lost a second at a time (bench.quality's stand-in, 60%, draw 1):
    RH_P1 passes the salt to RH_P2 (580-648), whom the detector misses; RH_P1's hold ends at 609, two frames
    after a segment cut (607), and the old code found only RH_P1's bare hold 577-607."""
    scenario = synthesize(1, 2)
    obs = hands_dropped(scenario.observations, 0.6, 1)
    trees = [(s.start, s.end, format_tree(s.tree)) for s in analyze(obs, load_knowledge(), Params()).trees
             if s.start < 648 and s.end > 580]
    assert [t for _, _, t in trees] == ["(HP (HP (H RH_P1) (O salt)) (CP (C handover) (HP (H RH_P2) (O salt))))"], \
        trees
