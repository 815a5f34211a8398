"""The segmentation stage (DESIGN.md: ``segment.py``). The code lives in :mod:`wecook_core.segmentation`."""

from wecook_core.segmentation import (
    SAMPLE_HZ,
    breakpoint_penalty,
    choose_k,
    ggs,
    hand_series,
    load_series,
    refine_breakpoints,
    segment_hands,
    segment_objective,
)

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
