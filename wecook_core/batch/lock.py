"""One batch at a time on a sessions folder: an OS lock on ``ROOT/batch.lock``, beside ``batch.json``.

Two batches on the same sessions (the same manifest run twice, or two manifests naming the same videos) would
make a session twice, run a video twice and overwrite each other's ``batch.json``. ``fcntl.flock`` on the lock
file keeps the second out: it refuses at once, naming who holds the lock (process, host, manifest, since when),
or with ``wait`` blocks until the first one ends. The kernel drops the lock when its holder exits, even on
``kill -9``, so a crashed batch never leaves a stale lock; the file itself stays (removing it would race).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import socket
import time
from collections.abc import Iterator
from pathlib import Path

from wecook_core.errors import InputError

LOCK_FILE = "batch.lock"


@contextlib.contextmanager
def batch_lock(root: str | Path, manifest: str | Path | None = None, *, wait: bool = False) -> Iterator[Path]:
    """Hold the batch lock of the sessions folder ``root`` for the ``with`` block; an :class:`InputError`
    naming the holder when another batch has it (unless ``wait``: then block until it is free)."""
    path = Path(root) / LOCK_FILE
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        raise InputError(path, f"cannot open the batch lock: {error.strerror or error}") from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX if wait else fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise InputError(path, f"another batch is running on these sessions ({_holder(fd)}); wait for it "
                                   f"to end (or pass --wait), or stop it") from None
        me = {"pid": os.getpid(), "host": socket.gethostname(), "manifest": str(manifest) if manifest else None,
              "since": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        os.ftruncate(fd, 0)
        os.pwrite(fd, (json.dumps(me) + "\n").encode(), 0)
        os.fsync(fd)
        yield path
    finally:
        os.close(fd)  # releases the lock


def _holder(fd: int) -> str:
    """Who holds the lock, as its holder wrote it."""
    try:
        data = json.loads(os.pread(fd, 4096, 0).decode("utf-8", "replace") or "{}")
    except ValueError:
        data = {}
    if not isinstance(data, dict) or "pid" not in data:
        return "its holder has not said who it is yet"
    manifest = f", manifest {data['manifest']}" if data.get("manifest") else ""
    return f"process {data['pid']} on {data.get('host', '?')}{manifest}, since {data.get('since', '?')}"
