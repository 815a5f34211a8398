"""Resume where the user left off: the workbench's cursor, kept in the session's ``workbench.json``."""

from __future__ import annotations

import contextlib
import json
import os
import time
from collections.abc import Callable
from pathlib import Path

from wecook_core.session.paths import session_paths


def load_position(session: Path) -> int | None:
    """The frame the workbench showed last in ``session``; None when unknown or unreadable."""
    try:
        frame = json.loads(session_paths(session).view.read_text()).get("frame")
    except (OSError, ValueError, AttributeError):
        return None
    return frame if isinstance(frame, int) and not isinstance(frame, bool) and frame >= 0 else None


def save_position(session: Path, frame: int) -> None:
    """Remember ``frame`` (written to a temporary file and renamed; failing silently: it is a convenience)."""
    path = session_paths(session).view
    tmp = path.with_name(path.name + ".tmp")
    with contextlib.suppress(OSError):
        tmp.write_text(json.dumps({"frame": int(frame)}))
        os.replace(tmp, path)


class PositionKeeper:
    """Remembers the cursor without writing a file at every segment change of a playback: the first change
    is written at once, later ones at most every ``interval`` seconds (the caller asks :meth:`due` when to
    :meth:`flush` the last one), and :meth:`flush` on quitting writes whatever is left."""

    INTERVAL = 1.0
    """Seconds between two writes."""

    def __init__(self, session: Path, interval: float | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.session = session
        self.interval = self.INTERVAL if interval is None else interval
        self._clock = clock
        self._written_at: float | None = None
        self._pending: int | None = None
        """The frame noted but not written yet."""
        self.writes = 0

    @property
    def pending(self) -> bool:
        return self._pending is not None

    def note(self, frame: int) -> bool:
        """Remember ``frame``; written now if the last write is ``interval`` old, else kept pending. True: written."""
        self._pending = frame
        if self._written_at is None or self._clock() - self._written_at >= self.interval:
            self.flush()
            return True
        return False

    def due(self) -> float:
        """Seconds until a pending frame may be written."""
        if self._written_at is None:
            return 0.0
        return max(0.0, self.interval - (self._clock() - self._written_at))

    def flush(self) -> None:
        """Write the pending frame, if any."""
        if self._pending is None:
            return
        save_position(self.session, self._pending)
        self._pending = None
        self._written_at = self._clock()
        self.writes += 1
