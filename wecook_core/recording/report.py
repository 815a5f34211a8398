"""What a run's recording says, from the file alone: its summary (``wecook runs show``) and CSV tables of its
joint states and events (``wecook runs export --csv``), for people who analyse runs in pandas.

Times are seconds since the run started (log time minus the recording's ``time_origin_ns``). A finished file is
read through its index; a file whose run was killed is read in order up to where it stops.
"""

from __future__ import annotations

import csv
import json
import struct
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wecook_core.errors import InputError

LONGEST_WAITS = 3
"""Waits listed in the summary's head, longest first."""


@dataclass(frozen=True)
class ActionLine:
    """One plan action and what became of it in the run."""

    id: str
    agents: str
    verb: str
    status: str = "not run"
    """``done``, ``failed``, ``skipped`` (failed without starting), ``unfinished`` or ``not run``."""
    reason: str = ""
    start: float | None = None
    end: float | None = None
    waited: float = 0.0
    """Simulated seconds its arms waited in it (waits told as ``wait`` events: half a second or more)."""


@dataclass(frozen=True)
class RunSummary:
    path: str
    actions: tuple[ActionLine, ...]
    duration_s: float
    """Simulated seconds from the start to the last message."""
    topics: dict[str, tuple[str, int]]
    """Topic -> (schema name, messages)."""
    metadata: dict[str, str] = field(default_factory=dict)
    """The ``wecook`` metadata record: versions, seed, planner, time origin."""
    agents: tuple[str, ...] = ()
    """``P1 franka_panda/panda.urdf`` per arm, from the plan."""
    objects: int = 0
    finished: bool = True
    """The run ended (a ``run_end`` event is there)."""
    end_detail: str = ""
    waited: dict[str, float] = field(default_factory=dict)
    """Arm -> simulated seconds it waited in the run (every wait; from the ``run_end`` event, else the sum of its
    ``wait`` events)."""
    longest_waits: tuple[str, ...] = ()
    """The longest waits, one line each: ``P2 52.0 s at 3.1 s for ...``."""

    @property
    def done(self) -> int:
        return sum(a.status == "done" for a in self.actions)


def read_messages(path: Path) -> Iterator[tuple[str, str, int, bytes]]:
    """(topic, schema name, log time, data) of every message, in log-time order when the file is finished."""
    from mcap.exceptions import McapError
    from mcap.reader import NonSeekingReader, make_reader

    if not path.is_file():
        raise InputError(path, "no such recording")
    try:
        with open(path, "rb") as f:
            reader = make_reader(f)
            for schema, channel, message in reader.iter_messages(log_time_order=True):
                yield channel.topic, schema.name if schema else "", message.log_time, message.data
        return
    except (McapError, EOFError, ValueError, OSError, KeyError, struct.error):  # struct.error: shorter than a header
        pass
    got = False
    try:
        with open(path, "rb") as f:
            for schema, channel, message in NonSeekingReader(f).iter_messages(log_time_order=False):
                got = True
                yield channel.topic, schema.name if schema else "", message.log_time, message.data
    except Exception as error:  # a truncated file: keep what was read
        if not got:
            raise InputError(path, f"not a readable MCAP recording ({type(error).__name__})") from None


def read_extras(path: Path) -> tuple[str | None, dict[str, str]]:
    """The plan attachment's text and the ``wecook`` metadata, when the file has them."""
    from mcap.records import Attachment, Metadata
    from mcap.stream_reader import StreamReader

    plan, meta = None, {}
    try:
        with open(path, "rb") as f:
            for record in StreamReader(f, skip_magic=False).records:
                if isinstance(record, Attachment) and record.name == "plan.yaml":
                    plan = record.data.decode("utf-8", "replace")
                elif isinstance(record, Metadata) and record.name == "wecook":
                    meta = dict(record.metadata)
    except Exception:  # a truncated file ends the pass; what was read counts
        pass
    return plan, meta


def _origin(meta: dict[str, str], first: int | None) -> int:
    try:
        return int(meta["time_origin_ns"])
    except (KeyError, ValueError):
        return first or 0


def summarize_recording(path: str | Path) -> RunSummary:
    """The plan, each action's result, the duration and the topics, from the recording alone."""
    import yaml

    path = Path(path)
    topics: Counter[str] = Counter()
    schemas: dict[str, str] = {}
    events: list[tuple[int, dict[str, Any]]] = []
    first = last = None
    for topic, schema, ns, data in read_messages(path):
        topics[topic] += 1
        schemas.setdefault(topic, schema)
        first = ns if first is None else min(first, ns)
        last = ns if last is None else max(last, ns)
        if topic == "/plan/events":
            try:
                events.append((ns, json.loads(data)))
            except ValueError:
                continue
    plan_text, meta = read_extras(path)
    origin = _origin(meta, first)
    lines: dict[str, dict[str, Any]] = {}
    agents: tuple[str, ...] = ()
    objects = 0
    try:
        plan = yaml.safe_load(plan_text) if plan_text else None
    except yaml.YAMLError:
        plan = None
    if isinstance(plan, dict):
        for action in plan.get("actions") or ():
            if isinstance(action, dict) and "id" in action:
                pids = action.get("pids") or action.get("pid") or ""
                pids = ",".join(pids) if isinstance(pids, list) else str(pids)
                lines[str(action["id"])] = {"id": str(action["id"]), "agents": pids,
                                            "verb": str(action.get("verb", ""))}
        agents = tuple(f"{a.get('pid')} {a.get('robot')}" for a in plan.get("agents") or () if isinstance(a, dict))
        scene = plan.get("scene")
        objects = len(scene.get("objects") or ()) if isinstance(scene, dict) else 0
    finished, end_detail = False, ""
    waited: dict[str, float] = {}
    told: dict[str, float] = {}
    longest: list[tuple[float, str]] = []
    for ns, event in events:
        t = (ns - origin) / 1e9
        kind, aid = event.get("kind"), event.get("action_id")
        payload: dict[str, Any] = event["data"] if isinstance(event.get("data"), dict) else {}
        if kind == "run_end":
            finished, end_detail = True, str(event.get("detail") or "")
            if isinstance(payload.get("waited_s"), dict):
                waited = {str(k): float(v) for k, v in payload["waited_s"].items()}
            continue
        if kind == "wait" and "seconds" in payload:
            seconds, agent = float(payload["seconds"]), str(event.get("agent") or "?")
            told[agent] = told.get(agent, 0.0) + seconds
            longest.append((seconds, f"{agent} {seconds:.1f} s from {float(payload.get('since', t)):.1f} s for "
                                     f"{payload.get('for', '?')}"))
            if aid is not None and str(aid) in lines:
                lines[str(aid)]["waited"] = lines[str(aid)].get("waited", 0.0) + seconds
            continue
        if aid is None:
            continue
        line = lines.setdefault(str(aid), {"id": str(aid), "agents": event.get("agent") or "", "verb": ""})
        if kind == "action_start":
            line.update(status="unfinished", start=t)
        elif kind == "action_end":
            line.update(status="done", end=t, reason="")
        elif kind == "action_failed":
            detail = str(event.get("detail") or "")
            started = line.get("start") is not None
            status = "failed" if started else "skipped"
            for prefix in ("skipped: ", "failed: "):
                detail = detail.removeprefix(prefix)
            line.update(status=status, reason=detail, end=t if started else None)
    actions = tuple(ActionLine(**line) for line in lines.values())
    duration = (last - origin) / 1e9 if last is not None else 0.0
    longest.sort(key=lambda w: -w[0])
    return RunSummary(str(path), actions, max(duration, 0.0), {t: (schemas[t], n) for t, n in sorted(topics.items())},
                      meta, agents, objects, finished, end_detail, waited or told,
                      tuple(line for _, line in longest[:LONGEST_WAITS]))


def format_summary(summary: RunSummary) -> str:
    """The summary as text: a header, the plan, the result table, the topics."""
    meta = summary.metadata
    head = [f"{summary.path}: {summary.duration_s:.1f} s simulated; {summary.done}/{len(summary.actions)} actions "
            f"done" + ("" if summary.finished else "; the run did not finish (killed?)")]
    if meta:
        head.append(f"seed {meta.get('seed', '?')}, planner {meta.get('planner', '?')}, wecook "
                    f"{meta.get('wecook', '?')}, pybullet {meta.get('pybullet', '?')}")
    if summary.end_detail:
        head.append(f"run end: {summary.end_detail}")
    head.append(f"plan: {len(summary.actions)} actions, {len(summary.agents)} arms"
                + (f" ({'; '.join(summary.agents)})" if summary.agents else "") + f", {summary.objects} objects")
    if summary.waited:
        head.append("waited: " + ", ".join(f"{pid} {s:.1f} s" for pid, s in sorted(summary.waited.items())))
        head += [f"  longest: {line}" for line in summary.longest_waits]
    rows = [("action", "agents", "verb", "status", "start", "end", "waited", "reason")]
    for a in summary.actions:
        rows.append((a.id, a.agents, a.verb, a.status, "" if a.start is None else f"{a.start:.2f}",
                     "" if a.end is None else f"{a.end:.2f}", f"{a.waited:.1f}" if a.waited else "", a.reason))
    widths = [max(len(r[k]) for r in rows) for k in range(7)]
    table = ["  ".join(r[k].ljust(widths[k]) for k in range(7)) + ("  " + r[7] if r[7] else "") for r in rows]
    topic_rows = [f"  {topic:<16} {schema:<28} {n} messages" for topic, (schema, n) in summary.topics.items()]
    return "\n".join([*head, "", *table, "", "topics:", *topic_rows])


def export_csv(path: str | Path, out_dir: str | Path) -> list[Path]:
    """Write ``joint_states.csv`` (``t_s``, then ``<joint>.position`` and ``<joint>.velocity`` for every joint)
    and ``events.csv`` (``t_s, kind, action_id, primitive, agent, detail, data`` (JSON)) into ``out_dir``.
    Existing files are never overwritten (InputError)."""
    path, out_dir = Path(path), Path(out_dir)
    targets = [out_dir / "joint_states.csv", out_dir / "events.csv"]
    for target in targets:
        if target.exists():
            raise InputError(target, "exists; not overwritten (choose another --csv folder)")
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(out_dir, "is not a folder")
    _, meta = read_extras(path)
    messages = list(read_messages(path))
    first = min((ns for _, _, ns, _ in messages), default=None)
    origin = _origin(meta, first)
    joints: list[tuple[float, dict[str, tuple[Any, Any]]]] = []
    events: list[list[Any]] = []
    names: dict[str, None] = {}
    for topic, _, ns, data in messages:
        t = round((ns - origin) / 1e9, 6)
        try:
            message = json.loads(data)
        except ValueError:
            continue
        if topic == "/joint_states":
            prefix = f"{message['agent']}/" if "agent" in message else ""  # wecook.JointState (older files)
            positions, velocities = message.get("position") or [], message.get("velocity") or []
            row: dict[str, tuple[Any, Any]] = {}
            for k, name in enumerate(message.get("name") or []):
                full = prefix + str(name)
                names.setdefault(full)
                row[full] = (positions[k] if k < len(positions) else "",
                             velocities[k] if k < len(velocities) else "")
            if joints and joints[-1][0] == t:
                joints[-1][1].update(row)
            else:
                joints.append((t, row))
        elif topic == "/plan/events":
            events.append([t, message.get("kind"), message.get("action_id") or "", message.get("primitive") or "",
                           message.get("agent") or "", message.get("detail") or "",
                           json.dumps(message.get("data") or {}, sort_keys=True)])
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(targets[0], "x", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["t_s", *(f"{n}.position" for n in names), *(f"{n}.velocity" for n in names)])
        for t, row in joints:
            writer.writerow([t, *(row.get(n, ("", ""))[0] for n in names), *(row.get(n, ("", ""))[1] for n in names)])
    with open(targets[1], "x", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["t_s", "kind", "action_id", "primitive", "agent", "detail", "data"])
        writer.writerows(events)
    return targets
