"""Reading the user's files safely and writing wecook's own without losing anything.

Reading: :func:`regular_file` refuses what is not a plain file (a folder, a FIFO that would block forever, a
device, a dangling link) before anything opens it; :func:`read_text` also bounds the size and decodes UTF-8
(a byte-order mark is dropped), each problem an :class:`InputError` naming the file.

Writing: :func:`write_atomic` writes a whole file under a temporary name in the target's folder, fsyncs it and
moves it into place in one step, so a reader sees the old file or the new one, never a torn one; an existing
target is only replaced when asked (``replace=True``), else the move itself refuses it (``link`` fails when the
name exists, so two writers cannot both win). :func:`create_new` claims a name for a file that is written
as it goes (a recording): created exclusively, never truncating anything, with a numbered name when wanted.
"""

from __future__ import annotations

import contextlib
import io
import os
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO

from wecook_core.errors import InputError

MAX_INPUT_BYTES = 1 << 30
"""The largest text file wecook reads whole (1 GiB): plans, session files, JSON and CSV inputs."""


def _a(what: str) -> str:
    """``what`` with its article (``a plan``, ``an object box file``) unless it has one."""
    if what.startswith(("a ", "an ")):
        return what
    return ("an " if what[:1].lower() in "aeiou" else "a ") + what


def regular_file(path: str | Path, what: str = "file") -> Path:
    """``path`` when it is a regular file (after links), else an :class:`InputError` saying what it is."""
    path = Path(path)
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        if path.is_symlink():
            raise InputError(path, f"dangling symbolic link, expected {_a(what)}") from None
        raise InputError(path, f"{what} not found") from None
    except OSError as error:
        raise InputError(path, f"cannot read: {error.strerror or error}") from None
    if stat.S_ISDIR(mode):
        raise InputError(path, f"is a directory, expected {_a(what)}")
    if not stat.S_ISREG(mode):
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode) else "a device"
        raise InputError(path, f"is {kind}, not a regular file: expected {_a(what)}")
    return path


def read_bytes(path: str | Path, what: str = "file", max_bytes: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of the regular file ``path``, at most ``max_bytes`` of them (else an :class:`InputError`)."""
    path = regular_file(path, what)
    try:
        with path.open("rb") as handle:
            data = handle.read(max_bytes + 1)
    except OSError as error:
        raise InputError(path, f"cannot read: {error.strerror or error}") from None
    if len(data) > max_bytes:
        raise InputError(path, f"larger than {max_bytes} bytes, the most wecook reads for {_a(what)}")
    return data


def read_text(path: str | Path, what: str = "file", max_bytes: int = MAX_INPUT_BYTES) -> str:
    """The UTF-8 text of the regular file ``path`` (a leading byte-order mark dropped), bounded like
    :func:`read_bytes`; text that is not UTF-8 is an :class:`InputError` naming the byte."""
    data = read_bytes(path, what, max_bytes)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        raise InputError(path, f"not a text file (byte {error.start} is {data[error.start]:#04x}, not UTF-8)",
                         place=f"line {line}") from None


def check_output(path: str | Path, *, replace: bool = False, what: str = "file") -> Path:
    """``path`` when a file may be written there: not a folder, its folder not a file, and not existing
    unless ``replace`` (the ``--force`` of the command line)."""
    path = Path(path)
    if path.is_dir():
        raise InputError(path, f"is a folder; give the name of the {what} to write")
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(parent, f"is not a folder, so the {what} {path.name} cannot go in it")
            break
    if (path.exists() or path.is_symlink()) and not replace:
        raise InputError(path, f"exists; not overwritten (pass --force to replace the {what})")
    return path


def fsync_dir(path: str | Path) -> None:
    """Make a rename or a new name in the folder ``path`` durable."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_atomic(path: str | Path, write: Callable[[IO[bytes]], None] | bytes | str, *, replace: bool = False,
                 what: str = "file") -> Path:
    """Write a whole file at ``path``: ``write`` (bytes, text, or a function given the open binary file) goes to
    a temporary file beside it, which is fsynced and then moved into place. An existing ``path`` is an
    :class:`InputError` unless ``replace``; either way the old file stays whole until the new one is complete."""
    path = check_output(path, replace=replace, what=what)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as error:  # a read-only or full folder: name the file asked for, not the temporary one
        error.filename = str(path)
        raise
    try:
        with os.fdopen(fd, "wb") as handle:
            if callable(write):
                write(handle)
            else:
                handle.write(write.encode("utf-8") if isinstance(write, str) else write)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes its file private; a file written as usual is not
        if replace:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)  # fails when the name exists: nothing is ever overwritten
            except FileExistsError:
                raise InputError(path, f"exists; not overwritten (pass --force to replace the {what})") from None
            os.unlink(tmp)
    except BaseException as error:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        if isinstance(error, OSError) and error.errno is not None and error.filename in (None, tmp):  # name it
            error.filename = str(path)
        raise
    fsync_dir(path.parent)
    return path


def check_writable(folder: str | Path, what: str = "folder") -> Path:
    """``folder`` when a file can be made in it (or, when it does not exist yet, in its nearest existing parent):
    a probe file is created and removed there, so a read-only or full file system, a missing permission or a
    path through a file is said at once, before long work, as the :class:`InputError` of :func:`os_problem`."""
    folder = Path(folder)
    here = next((p for p in (folder, *folder.parents) if p.exists() or p.is_symlink()), Path("."))
    if not here.is_dir():
        raise InputError(here, f"is not a folder, so the {what} {folder} cannot be made in it")
    try:
        fd, probe = tempfile.mkstemp(prefix=".wecook-probe-", dir=here)
    except OSError as error:
        raise InputError(here, f"cannot write here: {os_problem(error)}") from None
    os.close(fd)
    os.unlink(probe)
    return folder


OS_CAUSES = {
    "ENOSPC": "no space left on the device",
    "EDQUOT": "the disk quota is used up",
    "EFBIG": "file too large (past a file-size limit: `ulimit -f`?)",
    "EROFS": "the file system is read-only",
    "EACCES": "permission denied",
    "EPERM": "operation not permitted",
    "EISDIR": "is a folder, not a file",
    "ENOTDIR": "a part of the path is a file, not a folder",
    "ENOENT": "no such file or folder",
    "EEXIST": "exists already",
    "ENAMETOOLONG": "the name is too long",
    "ELOOP": "a loop of symbolic links",
    "EMFILE": "too many open files",
    "EIO": "input/output error (a failing disk?)",
}
"""What each operating-system error means, in the words of the one line wecook prints."""


def os_problem(error: OSError) -> str:
    """The cause of an operating-system error in a few words (:data:`OS_CAUSES`), or its own message."""
    import errno as errnos

    name = errnos.errorcode.get(error.errno or -1, "")
    return OS_CAUSES.get(name) or (error.strerror or str(error) or type(error).__name__).lower()


def os_error_line(error: OSError, fallback: str | Path | None = None) -> str:
    """One line naming the file of ``error`` (or ``fallback`` when the error names none) and its cause."""
    names = [str(n) for n in (error.filename, error.filename2) if n is not None]
    where = " -> ".join(names) if names else (str(fallback) if fallback is not None else "")
    return (f"{where}: " if where else "") + os_problem(error)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text_atomic(path: str | Path, write: Callable[[IO[str]], None], *, what: str = "file") -> Path:
    """:func:`write_atomic` (replacing) of the text ``write`` puts in the open text file it is given (a CSV
    writer's file, say): UTF-8, newlines as written."""
    def binary(handle: IO[bytes]) -> None:
        text = io.TextIOWrapper(handle, encoding="utf-8", newline="", write_through=True)
        write(text)
        text.flush()
        text.detach()  # the binary handle stays open for write_atomic's fsync

    return write_atomic(path, binary, replace=True, what=what)


def create_new(path: str | Path, *, number: bool = False, what: str = "file", limit: int = 1000) -> Path:
    """Create ``path`` empty and exclusively (``O_EXCL``) for a file written as it goes; an existing one is an
    :class:`InputError`, or with ``number`` the next free ``stem-2.suffix``, ``stem-3.suffix``... is taken, so
    two writers starting at once never share a file."""
    path = check_output(path, replace=number, what=what)
    path.parent.mkdir(parents=True, exist_ok=True)
    for k in range(1, limit + 1):
        candidate = path if k == 1 else path.with_name(f"{path.stem}-{k}{path.suffix}")
        try:
            fd = os.open(candidate, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            if not number:
                raise InputError(path, f"exists; not overwritten (pass --force to replace the {what})") from None
            continue
        os.close(fd)
        fsync_dir(candidate.parent)
        return candidate
    raise InputError(path, f"{limit} {what}s of that name exist already")
