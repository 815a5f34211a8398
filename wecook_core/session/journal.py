"""The journal of corrections: an append-only file of JSON lines, folded into :class:`Corrections`.

Each line is ``{"seq": n, "time": "...Z", "op": OP, ...fields}``; ``seq`` counts up from 1 and is the entry's
stable id. The corrections are the typed operations of :mod:`wecook_core.session.corrections`, stored with
:func:`~wecook_core.session.corrections.to_record`; their fields:

===================== ====================================================================
``set_hand_object``   ``segment`` (start frame), ``hand``, ``object`` (a name, or null: holds nothing), ``end``
``set_object_object`` ``segment``, ``object``, ``targets`` (list of names), ``end``
``set_verb``          ``segment``, ``hand``, ``verb`` (from VERBS), ``end``
``set_status``        ``segment``, ``status`` (unreviewed, accepted, corrected, rejected), ``end``
``split``             ``frame`` (a new breakpoint)
``merge``             ``frame`` (a breakpoint removed; a merge of a split frame cancels the split)
``box_keyframe``      ``track`` (a drawn box's id), ``frame``, ``box`` ([x1, y1, x2, y2] pixels), ``label``
``box_label``         ``track``, ``label``
``box_drop``          ``track``, ``frame`` (the keyframe removed; the box with its only one)
``box_tracked``       ``track``, ``frames``, ``boxes`` (the tracker's, after the last keyframe), ``lost_at``
``set_category``      ``label``, ``category`` (tool, container, ingredient)
``undo``              ``target``: the seq of the correction undone
``redo``              ``target``: the seq of the correction redone
===================== ====================================================================

``end`` is optional (absent in journals written before it existed): the end of the action's span
``[segment, end)`` the correction was made on, so it applies to each segment of that span.

A line is written, flushed and fsynced before :meth:`Journal.record` (and :meth:`Journal.undo`,
:meth:`Journal.redo`) returns. Replaying applies corrections
in order; ``undo`` takes back the latest applied one, ``redo`` re-applies the latest undone one, and a new
correction forgets what could be redone. So undo and redo are unlimited and survive closing the file. A torn
last line (a crash mid-write) is reported as a warning and skipped, as is any other unreadable line; the next
append sets the torn bytes aside in ``journal.jsonl.torn`` first. One process writes a session's journal: the
first append (or an open with ``lock=True``, as the workbench's) takes an OS lock held until the journal is
closed, and another process's append is refused, naming the holder. Within one process, an append that finds
the file grown since it was read raises :class:`JournalChangedError`. The state is that of the bytes read, and
an append takes constant time (the corrections are folded again only when asked for).
"""

from __future__ import annotations

import contextlib
import datetime as dt
import fcntl
import functools
import json
import os
import weakref
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wecook_core.files import read_bytes
from wecook_core.model import Corrections, Segment
from wecook_core.session.corrections import TYPES, Correction, parse, to_record
from wecook_core.session.corrections import fold as fold_corrections
from wecook_core.session.lock import WriterLock

TORN_SUFFIX = ".torn"
"""Torn bytes cut off the journal go to a file named like it with this suffix added."""

OPS = TYPES
"""Correction operations and their types, from :mod:`wecook_core.session.corrections`."""

MAX_JOURNAL_BYTES = 256 << 20
"""The largest journal read (256 MiB, some million corrections); a larger one is an InputError."""


@dataclass(frozen=True)
class JournalEntry:
    """One line of the journal."""

    seq: int
    """Stable id, from 1, in the order written."""
    time: str
    """UTC, ISO 8601."""
    op: str
    """One of :data:`OPS`, ``undo`` or ``redo``."""
    fields: Mapping[str, Any] = field(default_factory=dict)
    """The operation's fields (``target`` for undo and redo)."""

    @functools.cached_property
    def correction(self) -> Correction:
        """The typed correction of a correction entry (ValueError for ``undo`` and ``redo``); parsed once (a
        tracked box's run holds a box per frame, and every append replays the whole journal)."""
        return parse({"op": self.op, **self.fields})

    def to_json(self) -> str:
        return json.dumps({"seq": self.seq, "time": self.time, "op": self.op, **self.fields},
                          ensure_ascii=False, separators=(",", ":"))


def check_correction(correction: Mapping[str, Any] | Correction) -> tuple[str, dict[str, Any]]:
    """(op, fields as stored) of a correction, or ValueError saying what is wrong."""
    _, op, record = _checked(correction)
    return op, record


def _checked(correction: Mapping[str, Any] | Correction) -> tuple[Correction, str, dict[str, Any]]:
    typed = correction if isinstance(correction, tuple(TYPES.values())) else parse(correction)  # type: ignore[arg-type]
    record = to_record(typed)  # type: ignore[arg-type]
    op = record.pop("op")
    return typed, op, record  # type: ignore[return-value]


def _entry(seq: int, time: str, op: str, fields: dict[str, Any], typed: Correction) -> JournalEntry:
    """A correction entry whose typed correction is already known (not parsed again)."""
    entry = JournalEntry(seq, time, op, fields)
    entry.__dict__["correction"] = typed  # the cached_property's slot
    return entry


@dataclass(frozen=True)
class Replay:
    """The journal folded: what is in effect and what can be undone or redone."""

    applied: tuple[int, ...]
    """Seqs of the corrections in effect, oldest first (the last one is what undo takes back)."""
    undone: tuple[int, ...]
    """Seqs that redo can bring back, the next one last."""
    corrections: Corrections
    warnings: tuple[str, ...] = ()


def replay(entries: Sequence[JournalEntry]) -> Replay:
    """Fold journal entries into corrections plus the undo and redo stacks (pure)."""
    by_seq = {e.seq: e for e in entries}
    applied: list[int] = []
    undone: list[int] = []
    warnings = []
    for entry in entries:
        if entry.op in ("undo", "redo"):
            stack, other = (applied, undone) if entry.op == "undo" else (undone, applied)
            target = entry.fields.get("target")
            if not stack or stack[-1] != target:
                warnings.append(f"journal entry {entry.seq}: {entry.op} of {target} does not match the history; "
                                "skipped")
                continue
            other.append(stack.pop())
        else:
            applied.append(entry.seq)
            undone.clear()
    return Replay(tuple(applied), tuple(undone), fold([by_seq[s] for s in applied]), tuple(warnings))


def fold(entries: Sequence[JournalEntry], segments: Sequence[Segment] | None = None) -> Corrections:
    """Corrections of the given (applied) entries, later ones winning (:func:`corrections.fold`)."""
    return fold_corrections((e.correction for e in entries), segments)


def read_journal(path: Path) -> tuple[list[JournalEntry], list[str], bool]:
    """(entries, warnings, torn tail): unreadable lines are warnings, never errors."""
    entries, warnings, torn, _ = _read(path)
    return entries, warnings, torn


def _read(path: Path) -> tuple[list[JournalEntry], list[str], bool, int]:
    """:func:`read_journal` and the number of bytes it read (the journal's state is that of these bytes)."""
    if not path.exists() and not path.is_symlink():
        return [], [], False, 0
    data = read_bytes(path, "journal", MAX_JOURNAL_BYTES)  # a folder, a FIFO, too large: InputError
    entries, warnings, torn = _parse(path, data)
    return entries, warnings, torn, len(data)


def _parse(path: Path, data: bytes) -> tuple[list[JournalEntry], list[str], bool]:
    entries: list[JournalEntry] = []
    warnings: list[str] = []
    lines = data.split(b"\n")
    last = len(lines) - 1  # the piece after the final newline: empty unless the last line is torn
    torn = bool(lines[last])
    seqs: set[int] = set()
    for number, raw in enumerate(lines, 1):
        if not raw.strip():
            continue
        entry, problem = _parse_line(raw)
        if entry is not None and entry.seq in seqs:
            problem = f"seq {entry.seq} again"
            entry = None
        if entry is None:
            if number - 1 == last:
                warnings.append(f"{path}: the last line is torn (a crash while writing?); skipped: "
                                f"{raw[:60].decode('utf-8', 'replace')!r}")
            else:
                warnings.append(f"{path}:line {number}: unreadable journal entry ({problem}); skipped")
            continue
        seqs.add(entry.seq)
        entries.append(entry)
    return entries, warnings, torn


def _parse_line(raw: bytes) -> tuple[JournalEntry | None, str]:
    try:
        value = json.loads(raw)
    except (ValueError, RecursionError) as error:  # JSONDecodeError, not UTF-8, too deep, an int too long
        return None, f"not JSON: {str(error)[:80] or type(error).__name__}"
    if not isinstance(value, dict):
        return None, "not a JSON object"
    seq, time, op = value.pop("seq", None), value.pop("time", ""), value.pop("op", None)
    if isinstance(seq, bool) or not isinstance(seq, int) or not 1 <= seq < 2**63:
        return None, f"bad seq {seq!r:.40}"
    if op in ("undo", "redo"):
        target = value.get("target")
        if isinstance(target, bool) or not isinstance(target, int) or set(value) != {"target"} \
                or not 1 <= target < 2**63:
            return None, f"{op} needs only an int target"
        return JournalEntry(seq, str(time), op, {"target": target}), ""
    try:
        typed, op, fields = _checked({"op": op, **value})
    except ValueError as error:
        return None, str(error)
    return _entry(seq, str(time), op, fields, typed), ""


def _now() -> str:
    return dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%S.%fZ")


class JournalChangedError(RuntimeError):
    """Another process wrote the journal since it was read: read it again."""


class Journal:
    """An open journal file: its entries, their replay, and durable appends.

    ``lock``: take the session's writer lock now (:mod:`wecook_core.session.lock`) and hold it until
    :meth:`close`; else it is taken at the first append. Another process holding it is an
    :class:`~wecook_core.errors.InputError` saying which (pid, command)."""

    def __init__(self, path: str | Path, *, lock: bool = False) -> None:
        self.path = Path(path)
        self._lock: WriterLock | None = None
        self._release: weakref.finalize | None = None
        if lock:
            self._hold()
        entries, warnings, self._torn, self._size = _read(self.path)  # the size of the very bytes parsed
        self._entries = entries
        self._by_seq = {e.seq: e for e in entries}
        self._last_seq = max(self._by_seq, default=0)
        folded = replay(entries)
        self._applied = list(folded.applied)
        self._undone = list(folded.undone)
        self._corrections: Corrections | None = folded.corrections
        self.warnings: list[str] = warnings + list(folded.warnings)
        """Unreadable lines (a torn last one) and undo / redo lines that did not fit the history."""

    def _hold(self) -> None:
        self._lock = WriterLock.take(self.path)
        self._release = weakref.finalize(self, self._lock.release)  # also when the journal is dropped unclosed

    def close(self) -> None:
        """Let go of the writer lock (another process may write the journal then)."""
        if self._release is not None:
            self._release()
        self._lock = self._release = None

    def __enter__(self) -> Journal:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def entries(self) -> tuple[JournalEntry, ...]:
        return tuple(self._entries)

    @property
    def version(self) -> int:
        """Changes with every line appended (a cheap key for what the corrections give)."""
        return len(self._entries)

    @property
    def corrections(self) -> Corrections:
        if self._corrections is None:  # folded again only when asked for after an append
            self._corrections = fold([self._by_seq[s] for s in self._applied])
        return self._corrections

    @property
    def applied(self) -> tuple[JournalEntry, ...]:
        """Corrections in effect, oldest first."""
        return tuple(self._by_seq[s] for s in self._applied)

    @property
    def can_undo(self) -> bool:
        return bool(self._applied)

    @property
    def can_redo(self) -> bool:
        return bool(self._undone)

    @property
    def applied_corrections(self) -> tuple[Correction, ...]:
        """The typed corrections in effect, oldest first (what :func:`corrections.fold` takes)."""
        return tuple(e.correction for e in self.applied)

    def record(self, correction: Correction | Mapping[str, Any]) -> JournalEntry:
        """Append a correction (typed, or a record ``{"op": ..., fields}``); durable (fsynced) on return.

        ValueError for a malformed correction; OSError when the disk refuses (nothing changes then).
        """
        typed, op, fields = _checked(correction)
        return self._append(op, fields, typed)

    def undo(self) -> JournalEntry | None:
        """Take back the latest correction in effect; None when there is none."""
        if not self._applied:
            return None
        return self._append("undo", {"target": self._applied[-1]})

    def redo(self) -> JournalEntry | None:
        """Re-apply the latest undone correction; None when there is none."""
        if not self._undone:
            return None
        return self._append("redo", {"target": self._undone[-1]})

    def _append(self, op: str, fields: dict[str, Any], typed: Correction | None = None) -> JournalEntry:
        if self._lock is None:
            self._hold()  # one writer per session: an InputError naming the other
        seq = self._last_seq + 1
        entry = JournalEntry(seq, _now(), op, fields) if typed is None else _entry(seq, _now(), op, fields, typed)
        line = (entry.to_json() + "\n").encode("utf-8")
        fd = os.open(self.path, os.O_RDWR | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            size = os.fstat(fd).st_size
            if size != self._size:
                raise JournalChangedError(f"{self.path} changed since it was read (another wecook?); "
                                          "reopen the session")
            if self._torn:
                size = self._set_torn_aside(fd)
            try:
                written = 0
                while written < len(line):
                    written += os.write(fd, line[written:])
                os.fsync(fd)
            except BaseException:
                # The caller is told it failed, so the line must not count: cut it off again, or failing that
                # treat whatever got on disk as torn (set aside before the next write, skipped when read).
                try:
                    os.ftruncate(fd, size)
                    os.fsync(fd)
                    self._size = size
                except OSError:
                    self._torn = True
                    with contextlib.suppress(OSError):
                        self._size = os.fstat(fd).st_size
                raise
        finally:
            os.close(fd)
        self._size = size + len(line)
        self._entries.append(entry)
        self._by_seq[seq] = entry
        self._last_seq = seq
        if op == "undo":
            self._undone.append(self._applied.pop())
        elif op == "redo":
            self._applied.append(self._undone.pop())
        else:
            self._applied.append(seq)
            self._undone.clear()
        self._corrections = None  # constant time: no replay, the fold waits until the corrections are asked for
        return entry

    def _set_torn_aside(self, fd: int) -> int:
        """Cut the bytes after the last newline off the journal (kept in ``journal.jsonl.torn``); the new size."""
        size = os.fstat(fd).st_size
        os.lseek(fd, 0, os.SEEK_SET)
        data = b""
        while chunk := os.read(fd, 1 << 20):
            data += chunk
        keep = data.rfind(b"\n") + 1
        tail = data[keep:]
        if tail:
            entry, _ = _parse_line(tail)
            if entry is not None and entry.seq in self._by_seq:
                os.write(fd, b"\n")  # a complete entry that only lacks its newline
                os.fsync(fd)
                self._torn = False
                return size + 1
            with self.path.with_name(self.path.name + TORN_SUFFIX).open("ab") as torn:
                torn.write(tail + b"\n")
                torn.flush()
                os.fsync(torn.fileno())
            os.ftruncate(fd, keep)
            os.fsync(fd)
        self._torn = False
        return keep
