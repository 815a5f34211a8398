"""Segmentation: Greedy Gaussian Segmentation of each hand's trajectory, and the union over hands.

- :mod:`.ggs`: the algorithm (``ggs``), exact to the reference code's answers; :mod:`.scorer` scores splits.
- :mod:`.choose`: how many breakpoints to keep (``choose_k``, BIC).
- :mod:`.hands`: ``segment_hands(obs, params) -> Segmentation``, the pipeline stage.
- :mod:`.series`: ``load_series`` for numeric text files (the ``wecook segment`` command).
- :mod:`.synthetic`: hand trajectories with known breakpoints.
"""

from wecook_core.perception.segmentation.choose import breakpoint_penalty, choose_k
from wecook_core.perception.segmentation.ggs import ggs, refine_breakpoints, segment_objective
from wecook_core.perception.segmentation.hands import SAMPLE_HZ, hand_series, segment_hands
from wecook_core.perception.segmentation.series import load_series

__all__ = [
    "SAMPLE_HZ",
    "breakpoint_penalty",
    "choose_k",
    "ggs",
    "hand_series",
    "load_series",
    "refine_breakpoints",
    "segment_hands",
    "segment_objective",
]
