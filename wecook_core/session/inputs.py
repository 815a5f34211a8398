"""A session's input files as they were when it was made (path, content hash, size, mtime), and whether they
still are: what lets opening a session warn that an input changed or went missing."""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class InputFile:
    """One input of a session, as it was when the session was made."""

    role: str
    """``video``, ``objects``, ``hands`` or ``labels``."""
    path: str
    """Absolute path."""
    sha256: str
    """Hex digest of the content; of a folder: of its sorted relative file names and their contents."""
    size: int
    """Bytes (of all files, for a folder)."""
    mtime_ns: int
    """Latest modification time (ns); with ``size``, lets opening skip re-hashing an unchanged input."""
    format: str | None = None
    select: str | None = None
    """Which video of a COCO-VID file holding several (name or id); None: the only one, or the one named
    like the video file."""
    fps: float | None = None
    """The frame rate a Label Studio annotation was made at (``wecook new --annotation-fps``); None: read from
    the file."""


def content_hash(path: str | Path) -> str:
    """sha256 of a file's bytes, or of a folder's sorted ``relative/name\\0`` + file digest pairs."""
    path = Path(path)
    if path.is_dir():
        digest = hashlib.sha256()
        for file in _files(path):
            digest.update(file.relative_to(path).as_posix().encode() + b"\0")
            digest.update(bytes.fromhex(content_hash(file)))
        return digest.hexdigest()
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def folder_files(folder: Path) -> list[tuple[tuple[str, ...], os.stat_result]]:
    """Every file under ``folder`` as (its path's parts relative to ``folder``, its stat), in no order: what
    ``folder.rglob("*")`` with ``is_file()`` and ``stat()`` finds (links to folders not followed), with one
    ``scandir`` per folder instead of a ``stat`` per call (a folder of OpenPose files holds thousands)."""
    found: list[tuple[tuple[str, ...], os.stat_result]] = []

    def walk(path: str, parts: tuple[str, ...]) -> None:
        try:
            with os.scandir(path) as scan:
                entries = list(scan)
        except PermissionError:
            return
        for entry in entries:
            if entry.is_dir(follow_symlinks=False):
                walk(entry.path, (*parts, entry.name))
            elif entry.is_file():
                found.append(((*parts, entry.name), entry.stat()))

    walk(str(folder), ())
    return found


def _files(folder: Path) -> list[Path]:
    return [folder.joinpath(*parts) for parts, _ in sorted(folder_files(folder), key=lambda f: "/".join(f[0]))]


def _stat(path: Path) -> tuple[int, int]:
    """(size, latest mtime_ns) of a file or a folder's files."""
    if path.is_dir():
        stats = [stat for _, stat in folder_files(path)]
        return sum(s.st_size for s in stats), max((s.st_mtime_ns for s in stats), default=path.stat().st_mtime_ns)
    stat = path.stat()
    return stat.st_size, stat.st_mtime_ns


def record_input(role: str, path: str | Path, format: str | None = None, select: str | None = None,
                 fps: float | None = None) -> InputFile:
    """The :class:`InputFile` of ``path`` as it is now (absolute path, content hash, size, mtime)."""
    path = Path(path).resolve()
    size, mtime = _stat(path)
    return InputFile(role, str(path), content_hash(path), size, mtime, format, select, fps)


def input_problem(item: InputFile) -> str | None:
    """A warning when the input is missing or its content changed, else None."""
    path = Path(item.path)
    if not path.exists():
        return f"{item.role} input is missing: {item.path}"
    try:
        if _stat(path) == (item.size, item.mtime_ns):
            return None
        if content_hash(path) == item.sha256:
            return None
    except OSError as error:
        return f"{item.role} input cannot be read: {item.path} ({error.strerror})"
    return f"{item.role} input changed since the session was made (sha256 differs): {item.path}"
