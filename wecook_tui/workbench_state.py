"""What a screen may ask of the workbench app: a small protocol, so screens never import the app (no cycle).

The app (:class:`wecook_tui.app.WecookApp`) satisfies it; screens reach it as ``workbench(self.app)``.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, cast

if TYPE_CHECKING:
    from textual.app import App

    from wecook_core.model import Corrections, Observations
    from wecook_core.perception.pipeline import Analysis
    from wecook_core.session.corrections import Correction


class Workbench(Protocol):
    session_name: str
    session_path: Path
    analysis: Analysis | None
    pending: bool
    """An analysis is being recomputed for the latest corrections."""
    last_message: str
    """The answer to the latest edit, undo or redo (one line)."""

    @property
    def opened(self) -> Any: ...

    @property
    def obs(self) -> Observations | None: ...

    @property
    def corrections(self) -> Corrections | None:
        """The corrections in effect, folded against the current segmentation (keys: segment starts)."""

    @property
    def frame_count(self) -> int: ...

    @property
    def fps(self) -> float: ...

    def rank(self, objects: tuple[str, ...]) -> list[tuple[str, float]]: ...

    def correct(self, correction: Correction) -> bool:
        """Journal one correction (durable on return), say what changed, recompute."""

    def go_to(self, frame: int) -> None:
        """Move the review's cursor to ``frame`` (clamped to the video)."""

    def say(self, message: str) -> None:
        """The one-line answer on the status line."""

    def undo(self) -> None: ...

    def redo(self) -> None: ...

    def open_plan(self) -> None: ...

    def open_runs(self, start: bool, live_port: int | None = None) -> None:
        """The run screen: running the plan (``start``; served live on ``live_port`` when given) or past runs."""

    def open_help(self) -> None: ...


def workbench(app: App[Any]) -> Workbench:
    """The running app, seen through :class:`Workbench`."""
    return cast("Workbench", app)
