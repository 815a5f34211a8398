"""Reading every intact record of a damaged or unfinished MCAP file, and saying exactly what could not be read.

The file is walked record by record (opcode, length, body). A chunk is kept when it decompresses and its CRC
matches; an attachment when its CRC matches. A record that does not read (a flipped byte, a torn tail) is set
aside as :class:`Damage` and the walk resumes at the next chunk or attachment whose CRC matches, so one bad byte
costs one chunk, not the rest of the file. The message index records that follow a lost chunk say how many
messages of which channel it held; the summary's statistics, when they read, say how many the whole file held.
"""

from __future__ import annotations

import io
import mmap
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import (
    Attachment,
    Channel,
    Chunk,
    DataEnd,
    Footer,
    Header,
    Message,
    MessageIndex,
    Metadata,
    Schema,
    Statistics,
)
from mcap.stream_reader import breakup_chunk

MAGIC = b"\x89MCAP0\r\n"
MAX_CHUNK_BYTES = 1 << 30
"""The largest uncompressed chunk read (1 GiB; the recorder's are about 1 MiB): a larger size is damage."""

_READERS: dict[int, Any] = {Opcode.HEADER: Header, Opcode.FOOTER: Footer, Opcode.SCHEMA: Schema,
                            Opcode.CHANNEL: Channel, Opcode.ATTACHMENT: Attachment, Opcode.METADATA: Metadata,
                            Opcode.CHUNK: Chunk, Opcode.MESSAGE_INDEX: MessageIndex, Opcode.DATA_END: DataEnd,
                            Opcode.STATISTICS: Statistics}
_SKIPPED = frozenset(int(o) for o in Opcode) - frozenset(_READERS) - {Opcode.MESSAGE}
"""Index records of the summary: known, not needed to rewrite the file."""


@dataclass(frozen=True)
class Damage:
    """Bytes ``[start, end)`` of the file that could not be read."""

    start: int
    end: int
    what: str
    """What was there and why it did not read, e.g. ``chunk (CRC mismatch)``."""
    messages: dict[int, int] | None = None
    """Channel id -> messages the lost chunk held, from its message index (None: not known)."""


@dataclass(frozen=True)
class Salvage:
    records: tuple[Any, ...]
    """Every record that reads, in file order, chunks opened (schemas, channels, messages, attachments...)."""
    damage: tuple[Damage, ...]
    footer: bool
    """The file ends in a footer that reads: it was finished."""
    statistics: Statistics | None
    """The summary's statistics, when they read."""
    size: int


def _u64(data: Any, at: int) -> int:
    return int(struct.unpack_from("<Q", data, at)[0])


def _read(opcode: int, body: bytes) -> Any:
    """The record of ``opcode`` in ``body``, checked (chunks opened and CRC-checked); raises when it does not read."""
    if opcode == Opcode.MESSAGE:
        return Message.read(ReadDataStream(io.BytesIO(body)), len(body))
    record = _READERS[opcode].read(ReadDataStream(io.BytesIO(body)))
    if isinstance(record, Attachment):
        crc = struct.unpack_from("<I", body, len(body) - 4)[0]
        if crc and zlib.crc32(body[:-4]) != crc:
            raise ValueError("CRC mismatch")
    if isinstance(record, Chunk):
        if record.uncompressed_size > MAX_CHUNK_BYTES:
            raise ValueError(f"uncompressed size {record.uncompressed_size} is implausible")
        return record, breakup_chunk(record, validate_crc=True)
    return record


def _why(error: BaseException) -> str:
    text = str(error)
    if "crc" in type(error).__name__.lower() or "crc" in text.lower():
        return "CRC mismatch"
    return f"{type(error).__name__}: {text[:80]}" if text else type(error).__name__


def _record_at(data: Any, at: int, size: int) -> tuple[int, int] | None:
    """(opcode, end) of a plausible record starting at ``at``, else None."""
    if at + 9 > size:
        return None
    opcode, end = data[at], at + 9 + _u64(data, at + 1)
    if end > size or (opcode not in _READERS and opcode not in _SKIPPED and opcode != Opcode.MESSAGE):
        return None
    return opcode, end


def _resync(data: Any, start: int, size: int) -> int:
    """The offset of the next chunk or attachment after ``start`` that reads with a matching CRC (else ``size``)."""
    following = {opcode: data.find(bytes([opcode]), start, size) for opcode in (Opcode.CHUNK, Opcode.ATTACHMENT)}
    while True:
        found = {opcode: at for opcode, at in following.items() if at >= 0}
        if not found:
            return size
        opcode, at = min(found.items(), key=lambda item: item[1])
        plausible = _record_at(data, at, size)
        if plausible is not None:
            try:
                _read(plausible[0], bytes(data[at + 9:plausible[1]]))
                return at
            except Exception:  # any failure: not a record start
                pass
        following[opcode] = data.find(bytes([opcode]), at + 1, size)


def salvage(path: str | Path) -> Salvage:
    """Every intact record of the MCAP file ``path`` and the damage between them (see the module docstring)."""
    with open(path, "rb") as handle:
        size = Path(path).stat().st_size
        if size <= len(MAGIC):
            return Salvage((), (Damage(0, size, "not an MCAP file (too short)"),), False, None, size)
        magic = handle.read(len(MAGIC)) == MAGIC
        data: Any = mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ)
        try:
            found = _walk(data, size)
        finally:
            data.close()
    if magic:
        return found
    return Salvage(found.records, (Damage(0, len(MAGIC), "the MCAP magic bytes"), *found.damage), found.footer,
                   found.statistics, size)


def _walk(data: Any, size: int) -> Salvage:
    records: list[Any] = []
    damage: list[Damage] = []
    footer = False
    statistics = None
    lost_chunk: Damage | None = None
    summary = False  # past the data section's end: only indexes and statistics follow
    last: tuple[int, str] | None = None  # start and kind of the last record that read
    at = len(MAGIC)
    while at < size:
        if size - at == len(MAGIC) and data[at:size] == MAGIC:
            break
        plausible = _record_at(data, at, size)
        record = None
        why = "unreadable bytes"
        if plausible is None and at + 9 <= size and data[at] in _READERS and at + 9 + _u64(data, at + 1) > size:
            why = f"{Opcode(data[at]).name.lower()} cut short at the end of the file (the run was killed?)"
        if plausible is not None:
            opcode, end = plausible
            if opcode in _SKIPPED:
                lost_chunk = None
                at = end
                continue
            try:
                record = _read(opcode, bytes(data[at + 9:end]))
            except Exception as error:
                why = f"{Opcode(opcode).name.lower().replace('_', ' ')} ({_why(error)})"
        if record is None:
            # The last record's length may be what is damaged: look for the next sound record from its start.
            resume = _resync(data, last[0] + 1 if last is not None else at + 1, size)
            if last is not None and resume < at:
                damage.append(Damage(last[0], resume, f"{last[1]} (its length is damaged; its fields read)"))
                lost_chunk, last = None, None
                at = resume
                continue
            if plausible is not None and plausible[0] == Opcode.CHUNK and resume >= plausible[1]:
                resume = plausible[1]  # the chunk's length was sound: what follows may be its index
            if summary:
                why = f"summary section ({why}): indexes only, no messages lost"
            lost_chunk = Damage(at, resume, why, {} if why.startswith("chunk") else None)
            damage.append(lost_chunk)
            at = resume
            continue
        last = (at, Opcode(data[at]).name.lower().replace("_", " "))
        if isinstance(record, MessageIndex):
            if lost_chunk is not None and lost_chunk.messages is not None:
                lost_chunk.messages[record.channel_id] = len(record.records)
        else:
            lost_chunk = None
        if isinstance(record, tuple):
            records.extend(record[1])
        elif isinstance(record, Statistics):
            statistics = record
        elif isinstance(record, Footer):
            footer = True
        elif isinstance(record, DataEnd):
            summary = True
        elif not isinstance(record, MessageIndex | Header | DataEnd):
            records.append(record)
        at = end
    if not footer and not damage:
        damage.append(Damage(size, size, "no footer: the file ends early (the run was killed?)"))
    return Salvage(tuple(records), tuple(damage), footer, statistics, size)
