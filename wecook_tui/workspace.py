"""What the workbench's workers call: open a session's inputs and analyse them (core functions only).

Opening never fails on a bad video: the boxes and hands are read without it (the video's facts recorded in
``session.yaml`` stand in), and the notice says what is wrong. Only a folder that is not a session fails.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from wecook_tui.frames import FrameSource

if TYPE_CHECKING:
    from wecook_core.perception.pipeline import Analysis
    from wecook_core.session.corrections import Correction


@dataclass
class Opened:
    """What opening a session yields (the ``open`` worker's result)."""

    session: Any
    """A ``wecook_core.session.store.Session``."""
    observations: Any
    """``Observations``; None when even the boxes and hands cannot be read."""
    knowledge: Any
    """The commonsense tables (``recognize.load_knowledge()``); None if unreadable."""
    frames: FrameSource | None
    warnings: list[str] = field(default_factory=list)
    segmentation: Any = None
    """GGS's own segmentation, computed by the first analysis and reused by the next ones."""
    review: Any = None
    """The ``wecook_core.workflows.Review`` the session was opened as: what analyses it (None in test fakes)."""


def open_video(path: Path) -> FrameSource | None:
    """The session's video, from ``session.yaml`` alone: what the first picture needs, shown while the boxes,
    hands and commonsense tables load (:func:`open_workspace`). None when the session does not open or its
    video does not decode: the full open says why."""
    from wecook_core.errors import InputError
    from wecook_core.session.store import open_session

    try:
        video = open_session(path).inputs.get("video")
    except (InputError, OSError, ValueError, KeyError):
        return None
    frames = FrameSource(video.path) if video is not None else None
    return frames if frames is not None and frames.ok else None


def open_workspace(path: Path, frames: FrameSource | None = None) -> Opened:
    """Open the session for review (:func:`wecook_core.workflows.open_review`) and its video (``frames``, when
    :func:`open_video` opened it already and it is the observations' video)."""
    from wecook_core.workflows import open_review

    review = open_review(path)
    obs, warnings = review.observations, review.warnings
    if frames is not None and (obs is None or frames.path != Path(obs.video.path)):
        frames.close()
        frames = None
    if obs is not None and frames is None:
        frames = FrameSource(obs.video.path)
    if obs is not None and frames is not None and frames.facts.error and not any(str(obs.video.path) in w
                                                                                  for w in warnings):
        warnings.append(f"{frames.facts.error}: boxes and hands are drawn on a blank frame")
    return Opened(review.session, obs, review.knowledge, frames, warnings, review=review)


def analyze_workspace(opened: Opened, corrections: Sequence[Correction]) -> Analysis:
    """The analysis with the typed corrections: the session's :meth:`wecook_core.workflows.Review.analyse`, the
    path `wecook analyze` and `wecook export` take (the video's shot cuts, the session's category table); GGS
    runs once per session (corrections never change it)."""
    from wecook_core.workflows import analyse, segment

    review = opened.review
    if review is not None:
        analysis = review.analyse(corrections)
        opened.segmentation = review.segmentation
        return analysis
    if opened.segmentation is None:  # a test's stand-in session, with no Review behind it
        opened.segmentation = segment(opened.observations, opened.session.params)
    return analyse(opened.observations, opened.knowledge, opened.session.params, corrections,
                   segmentation=opened.segmentation)
