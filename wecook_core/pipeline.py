"""The whole perception pipeline as one pure function: observations + corrections -> trees and graph.

Each stage lives in its own module; this one only chains them and applies the user's corrections.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from wecook_core.model import (
    Action,
    ActionGraph,
    Associations,
    Corrections,
    Segmentation,
    TreeSpan,
)


@dataclass(frozen=True)
class Params:
    """Every tunable of the pipeline, recorded in a session's `session.yaml`."""

    lamb: float = 1e-3
    """GGS covariance regularisation (on hand positions scaled to the unit square)."""
    k_max: int = 40
    """Most breakpoints GGS considers per hand."""
    k: dict[str, int] = field(default_factory=dict)
    """Hand -> number of breakpoints forced by the user (otherwise chosen automatically)."""
    min_frames: int = 8
    """An association is kept only when it holds for at least this many consecutive frames."""
    seed: int = 0
    """Seed for anything random in the pipeline."""


@dataclass(frozen=True)
class Analysis:
    """The result of every stage for one video, after corrections."""

    segmentation: Segmentation
    associations: tuple[Associations, ...]
    """One per segment, in order."""
    actions: tuple[Action | None, ...]
    """Per segment: the action recognised for each hand that does something, flattened in
    (segment, hand) order; see `actions_by_segment` for the grouped view."""
    trees: tuple[TreeSpan, ...]
    """Merged trees (consecutive identical trees joined), in order of start frame."""
    graph: ActionGraph
    corrections: Corrections = field(default_factory=Corrections)
