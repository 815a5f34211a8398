"""Where the box mode's corrections go (:class:`BoxEdits`) and the tracks they give: the workbench's journal
(:class:`SessionEdits`) or, for `wecook boxes` without a session, memory (:class:`MemoryEdits`)."""

from __future__ import annotations

from typing import Any, Protocol

from wecook_core.observations.tracking import BoxTrack
from wecook_core.session.boxes import BoxCorrection, fold_boxes


class BoxEdits(Protocol):
    """Where the box mode's corrections go, and the tracks they give."""

    def tracks(self) -> tuple[BoxTrack, ...]: ...

    def apply(self, correction: BoxCorrection) -> bool:
        """Record one correction; False when it was not recorded."""

    def undo(self) -> None: ...

    def redo(self) -> None: ...

    def message(self) -> str:
        """The answer to the latest edit, undo or redo (empty when there is none to show)."""


class MemoryEdits:
    """`wecook boxes` (no session): the corrections in memory, with undo and redo."""

    def __init__(self) -> None:
        self.applied: list[BoxCorrection] = []
        self.undone: list[BoxCorrection] = []

    def tracks(self) -> tuple[BoxTrack, ...]:
        return fold_boxes(self.applied)

    def apply(self, correction: BoxCorrection) -> bool:
        self.applied.append(correction)
        self.undone.clear()
        return True

    def undo(self) -> None:
        if self.applied:
            self.undone.append(self.applied.pop())

    def redo(self) -> None:
        if self.undone:
            self.applied.append(self.undone.pop())

    def message(self) -> str:
        return ""


class SessionEdits:
    """The workbench: every box correction journaled (``Workbench.correct``), undone and redone with the rest."""

    def __init__(self, app: Any) -> None:
        from wecook_tui.workbench_state import workbench

        self.wb = workbench(app)

    def tracks(self) -> tuple[BoxTrack, ...]:
        session = self.wb.opened.session if self.wb.opened is not None else None
        return fold_boxes(session.applied_corrections) if session is not None else ()

    def apply(self, correction: BoxCorrection) -> bool:
        return self.wb.correct(correction)

    def undo(self) -> None:
        self.wb.undo()

    def redo(self) -> None:
        self.wb.redo()

    def message(self) -> str:
        return self.wb.last_message
