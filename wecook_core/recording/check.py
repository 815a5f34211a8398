"""Checking a run's MCAP recording, and recovering the recording of a run that was killed.

A recording is checked by one sequential pass (chunk and data-section CRCs verified, every message decoded as
JSON, the first :data:`SCHEMA_CHECKED` of each topic checked against their channel's JSON Schema) plus the
seeking reader's summary: expected topics with their schema names, the plan attachment and the
metadata, per-topic log times that never go back, an event sequence where every started action ends or
fails and the run ends, and every recorded joint step within the arm's position, velocity and acceleration limits
(:mod:`.limits`).
"""

from __future__ import annotations

import contextlib
import json
import struct
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mcap.exceptions import McapError
from mcap.reader import SeekingReader
from mcap.records import Attachment, Channel, Footer, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from wecook_core.errors import InputError
from wecook_core.execution.schedule.observer import RunEvent
from wecook_core.recording import foxglove
from wecook_core.recording.json_schema import schema_json, schema_problems
from wecook_core.recording.limits import JointTrack, limit_violations


@dataclass(frozen=True)
class CheckReport:
    path: str
    problems: tuple[str, ...]
    """Everything wrong, one line each; empty when the recording is sound."""
    messages: dict[str, int]
    """Topic -> number of messages."""
    duration_s: float
    """Seconds between the first and the last message's log time."""
    actions: dict[str, str] = field(default_factory=dict)
    """Action id -> ``done``, ``failed: reason`` or ``unfinished``, from ``/plan/events``."""
    attachments: tuple[str, ...] = ()
    metadata: dict[str, dict[str, str]] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not self.problems


@dataclass(frozen=True)
class RecoverReport:
    source: str
    out: str
    messages: dict[str, int]
    """Topic -> messages written to ``out``."""
    attachments: int
    metadata: int
    complete: bool
    """The source had its footer and no damage: nothing was lost."""
    stopped: str
    """``end of file``, or what the first damage was."""
    bytes_read: int
    """Bytes of the source before the first damage."""
    bytes_total: int
    closed_actions: tuple[str, ...] = ()
    """Actions that had started but not ended when the run was killed: ``action_failed`` events were added."""
    finished: bool = False
    """The run's own ``run_end`` event is among what was kept: the run had finished."""
    lost: tuple[str, ...] = ()
    """What could not be kept, one line each (empty: nothing was lost)."""

    @property
    def total(self) -> int:
        return sum(self.messages.values())


_READ_ERRORS = (McapError, EOFError, struct.error, ValueError, UnicodeDecodeError, KeyError, MemoryError)
"""What reading a damaged or truncated file raises (mcap's EndOfFile is an McapError; CRC errors ValueErrors;
a truncated zstd frame raises zstandard.ZstdError, a subclass of Exception handled separately)."""


def _records(stream_reader: StreamReader) -> Iterator[Any]:
    yield from stream_reader.records


END_OF_FILE = "end of file"
"""What :attr:`RecoverReport.stopped` says of a file read to its end."""


@dataclass(frozen=True)
class _Read:
    """What one sequential pass over a recording read."""

    records: list[Any]
    """Every record that could be read in order (chunks opened, CRCs checked)."""
    damage: str | None
    """Why reading stopped before the end of the file (the error), or None when it read to the end."""
    good: int
    """The offset after the last good record."""
    footer: bool
    """The footer was reached: the file was finished."""


def _read_error(error: Exception) -> str | None:
    """The one-line name of a damaged or truncated file's read error, None for any other exception."""
    if not (isinstance(error, _READ_ERRORS) or type(error).__module__.startswith(("zstandard", "lz4"))):
        return None
    name = type(error).__qualname__
    if name == "error":
        name = f"{type(error).__module__}.error"
    return f"{name}: {error}" if str(error) else name


def _sequential(path: Path) -> _Read:
    records: list[Any] = []
    good = 0
    damage = None
    footer = False
    with open(path, "rb") as f:
        reader = StreamReader(f, validate_crcs=True)
        iterator = _records(reader)
        while True:
            try:
                record = next(iterator)
            except StopIteration:
                break
            except Exception as error:
                damage = _read_error(error)
                if damage is None:
                    raise
                break
            records.append(record)
            good = f.tell()
            if isinstance(record, Footer):
                footer = True
    return _Read(records, damage, good, footer)


SCHEMA_CHECKED = 200
"""Messages per topic checked against their channel's JSON Schema (the first ones)."""

def _event_problems(events: list[dict[str, Any]]) -> tuple[list[str], dict[str, str]]:
    problems: list[str] = []
    state: dict[str, str] = {}
    for k, event in enumerate(events):
        kind, aid = event.get("kind"), str(event.get("action_id"))
        if kind == "action_start":
            if state.get(aid) == "running":
                problems.append(f"/plan/events[{k}]: action {aid} started twice")
            state[aid] = "running"
        elif kind in ("action_end", "action_failed"):
            if kind == "action_end" and state.get(aid) != "running":
                problems.append(f"/plan/events[{k}]: action {aid} ends without having started")
            elif kind == "action_failed" and aid in state and state[aid] != "running":
                problems.append(f"/plan/events[{k}]: action {aid} fails after it had ended")
            # an action that fails without starting was skipped (a predecessor failed)
            state[aid] = "done" if kind == "action_end" else f"failed: {event.get('detail') or 'no reason given'}"
        elif kind == "run_end" and k != len(events) - 1:
            problems.append(f"/plan/events[{k}]: run_end is not the last event")
    unfinished = [aid for aid, s in state.items() if s == "running"]
    for aid in unfinished:
        problems.append(f"/plan/events: action {aid} started but never ended or failed")
        state[aid] = "unfinished"
    if events and not any(e.get("kind") == "run_end" for e in events):
        problems.append("/plan/events: no run_end event (the run did not finish)")
    return problems, state


@dataclass
class _Scan:
    """What the records of a recording hold, gathered in one pass (:func:`_scan`)."""

    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    counts: Counter[str] = field(default_factory=Counter)
    """Topic -> messages."""
    events: list[dict[str, Any]] = field(default_factory=list)
    """The decoded ``/plan/events`` messages, in order."""
    attachments: list[str] = field(default_factory=list)
    metadata: dict[str, dict[str, str]] = field(default_factory=dict)
    first_ns: int | None = None
    last_ns: int | None = None
    last_time: dict[str, int] = field(default_factory=dict)
    """Topic -> log time of its last message."""
    problems: list[str] = field(default_factory=list)
    joints: JointTrack = field(default_factory=JointTrack)
    """``/joint_states`` positions, for the limit check."""

    @property
    def duration_s(self) -> float:
        return (self.last_ns - self.first_ns) / 1e9 if self.first_ns is not None and self.last_ns is not None \
            else 0.0


def _scan(records: list[Any]) -> _Scan:
    scan = _Scan()
    for record in records:
        if isinstance(record, Schema):
            scan.schemas[record.id] = record
        elif isinstance(record, Channel):
            scan.channels[record.id] = record
        elif isinstance(record, Attachment):
            scan.attachments.append(record.name)
        elif isinstance(record, Metadata):
            scan.metadata[record.name] = dict(record.metadata)
        elif isinstance(record, Message):
            _scan_message(scan, record)
    return scan


def _scan_message(scan: _Scan, record: Message) -> None:
    """One message counted, its log time checked, decoded, kept when an event, checked against its schema."""
    channel = scan.channels.get(record.channel_id)
    if channel is None:
        scan.problems.append(f"message on unknown channel {record.channel_id}")
        return
    topic = channel.topic
    scan.counts[topic] += 1
    n = scan.counts[topic]
    if topic in scan.last_time and record.log_time < scan.last_time[topic]:
        scan.problems.append(f"{topic}: log time goes back at message {n}")
    scan.last_time[topic] = record.log_time
    scan.first_ns = record.log_time if scan.first_ns is None else min(scan.first_ns, record.log_time)
    scan.last_ns = record.log_time if scan.last_ns is None else max(scan.last_ns, record.log_time)
    try:
        decoded = json.loads(record.data)
    except ValueError:
        scan.problems.append(f"{topic}: message {n} is not JSON")
        return
    if topic == "/plan/events":
        scan.events.append(decoded)
    elif topic == "/joint_states" and isinstance(decoded, dict):
        scan.joints.add(record.log_time / 1e9, decoded.get("name") or [], decoded.get("position") or [])
    schema = scan.schemas.get(channel.schema_id)
    if n <= SCHEMA_CHECKED and schema is not None:
        wrong = schema_problems(decoded, schema_json(schema), f"{topic}[{n - 1}]")
        if wrong:
            scan.problems.append(f"{wrong[0]} (schema {schema.name})")


def _file_problems(path: Path, read: _Read) -> tuple[list[str], Any]:
    """What is wrong with the file as a file (damage, no footer, no summary), and its summary (None: none)."""
    problems = []
    if read.damage is not None:
        problems.append(f"unreadable after byte {read.good} of {path.stat().st_size}: {read.damage}")
    if not read.footer:
        problems.append("no footer: the file was not finished (run `wecook runs recover`)")
        return problems, None
    try:
        with open(path, "rb") as f:
            summary = SeekingReader(f, validate_crcs=True).get_summary()
    except Exception as error:
        return [*problems, f"summary unreadable: {error}"], None
    if summary is None:
        problems.append("no summary section")
    return problems, summary


def _topic_problems(scan: _Scan) -> list[str]:
    """Required topics with messages, every known topic on its schema and encodings."""
    problems = []
    by_topic = {c.topic: c for c in scan.channels.values()}
    for topic in foxglove.REQUIRED_TOPICS:
        if topic in by_topic and scan.counts[topic] == 0:
            problems.append(f"{topic}: no messages")
    for topic, schema_name in foxglove.TOPIC_SCHEMAS.items():
        channel = by_topic.get(topic)
        if channel is None:
            if topic in foxglove.REQUIRED_TOPICS:
                problems.append(f"{topic}: no channel")
            continue
        schema = scan.schemas.get(channel.schema_id)
        if schema is None or schema.name != schema_name:
            problems.append(f"{topic}: schema {schema.name if schema else None!r}, expected {schema_name!r}")
        elif schema.encoding != "jsonschema" or channel.message_encoding != "json":
            problems.append(f"{topic}: encoding {schema.encoding}/{channel.message_encoding}, expected "
                            "jsonschema/json")
    return problems


def _content_problems(scan: _Scan, summary: Any) -> list[str]:
    """The summary's count against the file's, the plan attachment, wecook's metadata."""
    problems = []
    total = sum(scan.counts.values())
    if summary is not None and summary.statistics is not None and summary.statistics.message_count != total:
        problems.append(f"summary counts {summary.statistics.message_count} messages, the file holds {total}")
    if "plan.yaml" not in scan.attachments:
        problems.append("no plan.yaml attachment")
    if "wecook" not in scan.metadata:
        problems.append("no wecook metadata (versions, seed)")
    return problems


def check_recording(path: str | Path) -> CheckReport:
    """Check a recording; problems are listed in the report, never raised (a missing file raises InputError)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "no such recording")
    read = _sequential(path)
    if not read.records:
        return CheckReport(str(path), (f"not an MCAP file ({read.damage or END_OF_FILE})",), {}, 0.0)
    problems, summary = _file_problems(path, read)
    scan = _scan(read.records)
    event_problems, actions = _event_problems(scan.events)
    problems += scan.problems + _topic_problems(scan) + _content_problems(scan, summary) + event_problems
    problems += limit_violations(scan.joints)
    return CheckReport(str(path), tuple(problems), dict(scan.counts), scan.duration_s, actions,
                       tuple(scan.attachments), scan.metadata)


def recover_recording(path: str | Path, out: str | Path, *, replace: bool = False) -> RecoverReport:
    """Rewrite a recording, finished or not, damaged or not, as a complete file with a summary.

    Every record that reads is kept (messages, schemas, channels, the attachment, metadata), also past damage:
    a chunk that fails its CRC or does not decompress is lost alone, and :attr:`RecoverReport.lost` says which
    bytes, which messages per topic and why (see :mod:`wecook_core.recording.recover`). Actions that had started
    and not ended get an ``action_failed`` event ("run interrupted"), and a ``run_end`` event is added when the
    run's own is missing, both flagged ``recovered: true``, so the rewritten file passes ``runs check``. ``out``
    is written atomically; an existing one is an InputError unless ``replace``.
    """
    from wecook_core.files import check_output, regular_file, write_atomic
    from wecook_core.recording.recover import salvage

    path, out = regular_file(path, "recording"), Path(out)
    if out.exists() and path.resolve() == out.resolve():
        raise InputError(out, "the recovered file must not overwrite the source")
    check_output(out, replace=replace, what="recovered recording")
    found = salvage(path)
    schemas = {r.id: r for r in found.records if isinstance(r, Schema)}
    channels = {r.id: r for r in found.records if isinstance(r, Channel)}
    if not any(isinstance(r, Message | Attachment | Metadata) for r in found.records):
        why = "; ".join(d.what for d in found.damage[:2]) or "no messages"
        raise InputError(path, f"not an MCAP file or nothing readable ({why})")
    counts: Counter[str] = Counter()
    holder: dict[str, Any] = {}

    def write(stream: Any) -> None:
        writer = Writer(stream, compression=CompressionType.ZSTD, enable_data_crcs=True)
        writer.start(profile="", library="wecook (recovered)")
        schema_ids: dict[int, int] = {}
        channel_ids: dict[int, int] = {}

        def channel_id(source_id: int) -> int:
            if source_id not in channel_ids:
                channel = channels[source_id]
                sid = 0
                if channel.schema_id and channel.schema_id in schemas:
                    if channel.schema_id not in schema_ids:
                        s = schemas[channel.schema_id]
                        schema_ids[channel.schema_id] = writer.register_schema(s.name, s.encoding, s.data)
                    sid = schema_ids[channel.schema_id]
                channel_ids[source_id] = writer.register_channel(channel.topic, channel.message_encoding, sid,
                                                                 dict(channel.metadata))
            return channel_ids[source_id]

        events: list[dict[str, Any]] = []
        n_attachments = n_metadata = last_ns = 0
        for source_id in sorted(channels):  # every channel, even one without messages
            channel_id(source_id)
        for record in found.records:
            if isinstance(record, Attachment):
                writer.add_attachment(record.create_time, record.log_time, record.name, record.media_type,
                                      record.data)
                n_attachments += 1
            elif isinstance(record, Metadata):
                writer.add_metadata(record.name, dict(record.metadata))
                n_metadata += 1
            elif isinstance(record, Message) and record.channel_id in channels:
                topic = channels[record.channel_id].topic
                writer.add_message(channel_id(record.channel_id), record.log_time, record.data,
                                   record.publish_time, record.sequence)
                counts[topic] += 1
                last_ns = max(last_ns, record.log_time)
                if topic == "/plan/events":
                    with contextlib.suppress(ValueError):
                        events.append(json.loads(record.data))
        holder["finished"] = any(e.get("kind") == "run_end" for e in events if isinstance(e, dict))
        before = counts["/plan/events"]
        holder["closed"] = _close_events(writer, channels, channel_id, events, last_ns, counts)
        holder["added"] = counts["/plan/events"] - before
        holder["attachments"], holder["metadata"] = n_attachments, n_metadata
        writer.finish()

    write_atomic(out, write, replace=replace, what="recovered recording")
    orphans = sum(isinstance(r, Message) and r.channel_id not in channels for r in found.records)
    lost = _lost_lines(found, channels, counts, holder["added"], orphans)
    damage = [d for d in found.damage if d.end > d.start]
    good = damage[0].start if damage else found.size
    return RecoverReport(str(path), str(out), dict(counts), holder["attachments"], holder["metadata"],
                         found.footer and not damage, damage[0].what if damage else END_OF_FILE, good, found.size,
                         holder["closed"], finished=holder["finished"], lost=tuple(lost))


def _lost_lines(found: Any, channels: dict[int, Channel], kept: Counter[str], added: int, orphans: int
                ) -> list[str]:
    """What recovery could not keep, one line each: damaged byte ranges with what they held, per-topic counts
    of lost messages from the file's own statistics, messages whose channel was lost."""
    lines = []
    for d in found.damage:
        held = ""
        if d.messages:
            held = "; held " + ", ".join(f"{n} {channels[c].topic if c in channels else f'channel {c}'}"
                                          for c, n in sorted(d.messages.items()))
        span = f"bytes {d.start}-{d.end}: " if d.end > d.start else ""
        lines.append(f"{span}{d.what}{held}")
    stats = found.statistics
    if stats is not None:
        missing = []
        for cid, expected in sorted(stats.channel_message_counts.items()):
            topic = channels[cid].topic if cid in channels else f"channel {cid}"
            have = kept.get(topic, 0) - (added if topic == "/plan/events" else 0)
            if expected > have:
                missing.append(f"{expected - have} {topic}")
        if missing:
            lines.append(f"lost {sum(int(m.split()[0]) for m in missing)} of {stats.message_count} messages "
                         f"(the file's statistics): " + ", ".join(missing))
    if orphans:
        lines.append(f"{orphans} messages on channels whose definition was lost")
    return lines


def _close_events(writer: Writer, channels: dict[int, Channel], channel_id: Any, events: list[dict[str, Any]],
                  ns: int, counts: Counter[str]) -> tuple[str, ...]:
    """Add action_failed for running actions and a run_end, when the recording lacks them."""
    if any(e.get("kind") == "run_end" for e in events):
        return ()
    source = next((cid for cid, c in channels.items() if c.topic == "/plan/events"), None)
    if source is None:
        return ()
    running: dict[str, str | None] = {}
    for e in events:
        if e.get("kind") == "action_start":
            running[e.get("action_id") or ""] = e.get("agent")
        elif e.get("kind") in ("action_end", "action_failed"):
            running.pop(e.get("action_id") or "", None)
    cid = channel_id(source)
    for aid, agent in running.items():
        event = RunEvent("action_failed", action_id=aid, agent=agent, detail="run interrupted (recovered file)",
                         data={"recovered": True})
        writer.add_message(cid, ns, json.dumps(foxglove.run_event(ns, event)).encode(), ns)
        counts["/plan/events"] += 1
    end = RunEvent("run_end", detail="run interrupted; file recovered", data={"recovered": True})
    writer.add_message(cid, ns, json.dumps(foxglove.run_event(ns, end)).encode(), ns)
    counts["/plan/events"] += 1
    return tuple(running)
