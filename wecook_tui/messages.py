"""App-wide messages: what workers report back to the UI thread. Widget-local messages live in their widget.

Each worker calls one core function and posts one of these; handlers only update view state.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from textual.message import Message


@dataclass
class SessionOpened(Message):
    """The session, its observations, the commonsense tables and the video are open (``open`` worker)."""

    opened: Any
    """A ``wecook_tui.workspace.Opened``: session, observations (None if unreadable), knowledge, frame source."""
    warnings: tuple[str, ...] = ()
    """Problems to show in a notice: changed input, torn journal line, missing video, ..."""


@dataclass
class VideoOpened(Message):
    """The session's video opened (``open`` worker, before the observations load): the first picture can show."""

    frames: Any
    """A ``wecook_tui.frames.FrameSource`` that decodes."""


@dataclass
class SessionFailed(Message):
    """The session could not be opened at all; ``error`` is the one line to show."""

    error: str


@dataclass
class AnalysisReady(Message):
    """The analysis (``workflows.analyse``) finished for the corrections of journal generation ``generation``."""

    analysis: Any
    generation: int
    seconds: float


@dataclass
class AnalysisFailed(Message):
    error: str
    generation: int


@dataclass
class FrameDecoded(Message):
    """A frame reached the cache (decode worker); the view repaints if it still wants it."""

    index: int
    ok: bool


@dataclass
class FirstFramePainted(Message):
    """The frame view painted its first video frame (the app starts the analysis only then: it would hold
    the interpreter while the first picture is drawn)."""


@dataclass
class PlanBuilt(Message):
    """``plan_from_graph`` finished (plan review screen)."""

    plan: Any
    error: str | None = None


@dataclass
class PlanExported(Message):
    """``write_plan`` wrote the plan YAML to ``path``."""

    path: Path
    error: str | None = None


@dataclass
class RunOutput(Message):
    """One line of the ``wecook execute`` subprocess' messages (stderr), for the log."""

    line: str


@dataclass
class RunEvent(Message):
    """One event of ``wecook execute --jsonl`` (a JSON object with ``kind``)."""

    event: dict[str, Any]


@dataclass
class RunFinished(Message):
    """The ``wecook execute`` subprocess ended."""

    returncode: int
    mcap: Path
    log: Path
    seconds: float
