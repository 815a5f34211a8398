"""What the workbench's workers call: open a session's inputs and analyse them (core functions only).

Opening never fails on a bad video: the boxes and hands are read without it (the video's facts recorded in
``session.yaml`` stand in), and the notice says what is wrong. Only a folder that is not a session fails.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError
from wecook_tui.frames import FrameSource


@dataclass
class Opened:
    """What opening a session yields (the ``open`` worker's result)."""

    session: Any
    """A ``wecook_core.session.Session``."""
    observations: Any
    """``Observations``; None when even the boxes and hands cannot be read."""
    knowledge: Any
    """The commonsense tables (``recognize.load_knowledge()``); None if unreadable."""
    frames: FrameSource | None
    warnings: list[str] = field(default_factory=list)
    segmentation: Any = None
    """GGS's own segmentation, computed by the first analysis and reused by the next ones."""


def open_workspace(path: Path) -> Opened:
    """Open the session, read its observations and the commonsense tables, open the video."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.session.store import open_session

    session = open_session(path)
    warnings = [str(w) for w in getattr(session, "warnings", ())]
    obs = None
    try:
        imported = session.import_observations(video_optional=True)
        obs = imported.observations
        if imported.video_problem:
            warnings.append(f"{imported.video_problem}: boxes and hands shown against the video facts recorded "
                            "in the session")
    except (InputError, OSError) as error:
        warnings.append(f"inputs cannot be read: {error}")
    knowledge = None
    try:
        knowledge = load_knowledge()
    except InputError as error:
        warnings.append(f"commonsense tables cannot be read ({error}); action picker unranked")
    frames = FrameSource(obs.video.path) if obs is not None else None
    if frames is not None and frames.facts.error and not any(str(obs.video.path) in w for w in warnings):
        warnings.append(f"{frames.facts.error}: boxes and hands are drawn on a blank frame")
    return Opened(session, obs, knowledge, frames, warnings)


def analyze_workspace(opened: Opened, corrections: Any) -> Any:
    """``pipeline.analyze`` with the corrections; GGS runs once per session (corrections never change it)."""
    from wecook_core.perception.pipeline import analyze
    from wecook_core.perception.segmentation import segment_hands

    if opened.segmentation is None:
        opened.segmentation = segment_hands(opened.observations, opened.session.params)
    return analyze(opened.observations, opened.knowledge, opened.session.params, corrections,
                   segmentation=opened.segmentation)
