"""Resume where the user left off: the workbench's cursor, kept in the session's ``workbench.json``."""

from __future__ import annotations

import contextlib
import json
import os
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
