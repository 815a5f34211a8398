"""One writer per session: an OS lock (``fcntl.flock``) on ``journal.jsonl.lock`` beside the journal.

The process holding it writes its pid and command line into the file, so another one that is refused can say
who holds it. The operating system lets go of the lock when the holder exits, however it exits (``kill -9``
too), so a lock is never stale. Within one process the lock is shared: every :class:`WriterLock` of a session
counts, and the last one released lets it go.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import sys
import threading
import time
from pathlib import Path

from wecook_core.errors import InputError

LOCK_SUFFIX = ".lock"
"""The lock file is named like the journal with this suffix added."""

_HELD: dict[Path, tuple[int, int]] = {}
"""Lock file -> (its open descriptor, how many WriterLocks of this process hold it)."""
_GUARD = threading.Lock()


def lock_path(journal: Path) -> Path:
    return journal.with_name(journal.name + LOCK_SUFFIX)


def holder(path: Path, wait: float = 0.5) -> str:
    """Who holds the lock file ``path``, as its holder wrote it (``pid N: command``), or ``another process``;
    waiting up to ``wait`` seconds for a holder that has just taken the lock to say so."""
    deadline = time.monotonic() + wait
    while True:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            return f"pid {int(data['pid'])}: {str(data['command'])[:200]}"
        except (OSError, ValueError, KeyError, TypeError):
            if time.monotonic() > deadline:
                return "another process"
            time.sleep(0.01)


class WriterLock:
    """A hold on a session's writer lock; :meth:`release` it (once; again is a no-op)."""

    def __init__(self, path: Path | None) -> None:
        self.path = path
        """The lock file, or None when it could not be made (a read-only session: nothing can be written)."""

    @classmethod
    def take(cls, journal: Path) -> WriterLock:
        """Hold the writer lock of the session whose journal is ``journal``: an :class:`InputError` naming the
        session folder and the holder when another process holds it."""
        path = lock_path(journal).absolute()
        with _GUARD:
            if path in _HELD:
                fd, count = _HELD[path]
                _HELD[path] = (fd, count + 1)
                return cls(path)
            try:
                fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError:  # a read-only session: no writer can write it, so no lock is needed
                return cls(None)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                raise InputError(journal.parent, f"the session is open for writing in another wecook "
                                 f"({holder(path)}); close that one first") from None
            except BaseException:
                os.close(fd)
                raise
            with contextlib.suppress(OSError):  # say who holds it (a convenience: the lock is what counts)
                os.ftruncate(fd, 0)
                os.pwrite(fd, json.dumps({"pid": os.getpid(), "command": " ".join(sys.argv)}).encode(), 0)
            _HELD[path] = (fd, 1)
            return cls(path)

    def release(self) -> None:
        path, self.path = self.path, None
        if path is None:
            return
        with _GUARD:
            fd, count = _HELD.pop(path)
            if count > 1:
                _HELD[path] = (fd, count - 1)
                return
            os.close(fd)  # lets go of the flock
