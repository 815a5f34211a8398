"""`wecook execute`: run a plan (`wecook export` is in :mod:`.export`, `wecook runs` in :mod:`.runs`).

- ``wecook execute PLAN [--record FILE.mcap | --no-record] [--seed N] [--realtime] [--jsonl] [--timeout S]
  [--stop-at-first-failure]``: validate the plan (errors before anything runs, exit 2), say which actions
  ``wecook plan check`` finds out of reach, run it headless with progress per action and an ETA, within a
  wall-clock limit (default from the plan's size), record it (default
  ``runs/<plan>-<time>.mcap``: the session's ``runs/`` when the plan is in a session's ``plans/``, else beside
  the plan; ``--force`` replaces an existing ``--record`` file, but only when the run ends: it records to a
  hidden file beside it until then), stop after 4 actions failed in a row (the rest skipped), print a table of
  every action; exit 0 only if every action succeeded, else 1. ``--jsonl`` prints
  one JSON object per line instead (``run_start``, every plan event, then ``summary``) for programs such as the
  workbench. SIGTERM or Ctrl-C stop the run with the recording closed properly (exit 130).
- ``--live [--port N]`` serves the run over Foxglove's WebSocket protocol on ``ws://127.0.0.1:N`` while it runs
  (default 8765; 0: any free port; the address is printed first, and with ``--jsonl`` is the ``live`` field of
  the ``run_start`` event); ``--camera-hz HZ`` records a camera view at HZ
  images per simulated second (default 2; 0: one image at each action's start and end instead).
"""

from __future__ import annotations

import argparse
import datetime as dt
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:
    from rich.console import Console

    from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, Vec3
    from wecook_core.plan import Plan


def register(sub: Any) -> None:
    execute = sub.add_parser("execute", help="run a plan with two simulated arms, recorded as MCAP",
                             description="Validate a plan, run it headless in PyBullet and record the run.")
    execute.add_argument("plan", type=Path, help="plan file (YAML)")
    record = execute.add_mutually_exclusive_group()
    record.add_argument("--record", type=Path, metavar="FILE.mcap",
                        help="recording (default: runs/<plan>-<time>.mcap beside the plan or in its session)")
    record.add_argument("--no-record", action="store_true", help="do not record the run")
    execute.add_argument("--force", action="store_true", help="replace the --record file if it exists")
    execute.add_argument("--seed", type=int, default=0, help="seed of the run (same seed, same run)")
    execute.add_argument("--realtime", action="store_true", help="pace the simulation at real time")
    execute.add_argument("--jsonl", action="store_true",
                         help="print one JSON object per line instead: every plan event, then the summary")
    execute.add_argument("--live", action="store_true",
                         help="serve the run to Foxglove over WebSocket on 127.0.0.1 while it runs")
    execute.add_argument("--port", type=int, default=8765, help="port of --live (default: %(default)s; 0: any)")
    execute.add_argument("--camera-hz", type=_rate, default=2.0, metavar="HZ",
                         help="camera images per simulated second (default: %(default)s; 0: at action boundaries)")
    execute.add_argument("--timeout", type=float, metavar="SECONDS",
                         help="wall-clock limit of the run (default: 60 s + 30 s per action of the plan; the run "
                              "also stops after 4 actions failed in a row)")
    execute.add_argument("--stop-at-first-failure", action="store_true",
                         help="skip every action not yet started once one has failed (default: only the actions "
                              "that depend on the failure through their objects are skipped)")
    execute.add_argument("--dynamics", action="store_true",
                         help="physics mode: joints driven by position control within the URDF's effort and "
                              "velocity limits, objects held by friction (default: kinematic arms, held objects "
                              "fixed to the hand)")
    execute.set_defaults(func=run_execute)


# --------------------------------------------------------------------------------------------- execute


def default_record_path(plan_path: Path, now: dt.datetime | None = None) -> Path:
    """``runs/<plan-stem>-<time>.mcap``: in the session's ``runs/`` when the plan is in a session's ``plans/``,
    else in ``runs/`` beside the plan."""
    stamp = (now or dt.datetime.now()).strftime("%Y%m%d-%H%M%S")
    folder = plan_path.resolve().parent
    if folder.name == "plans" and (folder.parent / "session.yaml").is_file():
        folder = folder.parent
    return folder / "runs" / f"{plan_path.stem}-{stamp}.mcap"


def recording_path(record: Path | None, plan_path: Path, *, force: bool = False) -> Path:
    """Where the run is recorded: ``record`` (created exclusively; an existing file only with ``force``), else
    :func:`default_record_path` numbered ``-2``, ``-3``... when taken, so two runs never share a file."""
    from wecook_core.files import check_output, create_new

    if record is None:
        return create_new(default_record_path(plan_path), number=True, what="recording")
    if force:
        return check_output(record, replace=True, what="recording")
    return create_new(record, what="recording")


@dataclass
class ActionRow:
    id: str
    agents: str
    verb: str
    status: str = "not run"
    """``done``, ``failed``, ``skipped`` (a predecessor failed), ``running`` or ``not run``."""
    reason: str = ""


class Progress:
    """A RunObserver showing the run on the terminal: a rich progress bar with each arm's current step on a
    terminal, one plain line per action event otherwise. Keeps the per-action table."""

    def __init__(self, plan: Plan, console: Console, *, live: bool, jsonl: bool = False) -> None:
        self.rows = {a.id: ActionRow(a.id, ",".join(a.pids), a.verb) for a in plan.actions}
        self.console = console
        self.live = live and not jsonl
        self.jsonl = jsonl
        live = self.live
        self.sim_time = 0.0
        self.live_url: str | None = None
        """``--live``: the address the run is served on (said in ``--jsonl``'s ``run_start`` event)."""
        self.began = time.perf_counter()
        self._bar: Any = None
        self._overall: Any = None
        self._agents: dict[str, Any] = {}
        if live:
            from rich.progress import BarColumn, MofNCompleteColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn
            from rich.progress import Progress as RichProgress

            self._bar = RichProgress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                     TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
                                     console=console, transient=False)
            self._overall = self._bar.add_task("actions", total=len(self.rows))
            for pid in sorted({p for a in plan.actions for p in a.pids}):  # each arm: its actions, its step now
                mine = sum(pid in a.pids for a in plan.actions)
                self._agents[pid] = self._bar.add_task(f"{pid}: waiting", total=mine)

    def _say(self, text: str) -> None:
        if self.jsonl:
            return
        if self.live:
            self.console.print(text)
        else:
            print(text, flush=True)

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None:
        if self._bar is not None:
            self._bar.start()
        elif self.jsonl:
            _json_line({"t": 0.0, "kind": "run_start", "actions": len(self.rows), "seed": seed,
                        **({"live": self.live_url} if self.live_url else {})})
        else:
            self._say(f"run started: {len(self.rows)} actions, seed {seed}")

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        if self._bar is not None and int(t) != int(self.sim_time):
            self._bar.update(self._overall, description=f"actions ({int(t)} s simulated)")
        self.sim_time = t

    def on_event(self, t: float, event: RunEvent) -> None:
        self.sim_time = max(self.sim_time, t)
        if self.jsonl:
            _json_line({"t": round(t, 4), "kind": event.kind, "action_id": event.action_id,
                        "primitive": event.primitive, "agent": event.agent, "detail": event.detail})
        row = self.rows.get(event.action_id or "")
        agent = event.agent or (row.agents.split(",")[0] if row else None)
        if event.kind == "action_start" and row is not None:
            row.status = "running"
            self._agent(agent, f"{row.id} {row.verb}")
            if not self.live:
                self._say(f"[{t:7.2f}s] {row.id} {row.agents} {row.verb}: started")
        elif event.kind in ("action_end", "action_failed") and row is not None:
            started = row.status == "running"
            row.status = "done" if event.kind == "action_end" else "failed" if started else "skipped"
            row.reason = event.detail if event.kind == "action_failed" else ""
            for prefix in ("skipped: ", "failed: "):  # the status column already says it
                row.reason = row.reason.removeprefix(prefix)
            mark = {"done": "done", "failed": "FAILED", "skipped": "skipped"}[row.status]
            if row.status != "done":
                mark += f": {row.reason or 'no reason given'}"
            self._say(f"[{t:7.2f}s] {row.id} {row.agents} {row.verb}: {mark} ({self.eta()})")
            if self._bar is not None:
                self._bar.advance(self._overall)
                for pid in row.agents.split(","):
                    if pid in self._agents:
                        self._bar.advance(self._agents[pid])
                    self._agent(pid, "idle")
        elif event.kind in ("primitive_start", "retry", "wait") and row is not None:
            what = event.primitive or event.kind
            if event.kind == "retry":
                what = f"{event.primitive or ''} retry {event.detail}".strip()
            elif event.kind == "wait":
                what = f"waiting: {event.detail}"
            self._agent(agent, f"{row.id} {row.verb}: {what}")

    def eta(self) -> str:
        """``k/n actions, ETA s``: the wall time left at the pace of the actions finished so far."""
        finished = sum(r.status in ("done", "failed", "skipped") for r in self.rows.values())
        total = len(self.rows)
        wall = time.perf_counter() - self.began
        left = wall / finished * (total - finished) if finished else float("nan")
        return f"{finished}/{total} actions, ETA {left:.0f} s" if finished < total else f"{finished}/{total} actions"

    def _agent(self, agent: str | None, text: str) -> None:
        if self._bar is not None and agent in self._agents:
            self._bar.update(self._agents[agent], description=f"{agent}: {text}")

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None:
        if level in ("warning", "error"):
            self._say(f"[{t:7.2f}s] {level}: {message}")

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        pass

    def on_end(self, t: float) -> None:
        self.sim_time = max(self.sim_time, t)
        self.stop(finished=True)

    def stop(self, finished: bool = False) -> None:
        if self._bar is not None:
            self._bar.update(self._overall, description=f"actions ({self.sim_time:.1f} s simulated)")
            for pid in self._agents:
                self._agent(pid, "finished" if finished else "stopped")
            self._bar.stop()
            self._bar = None


def _json_line(data: Mapping[str, Any]) -> None:
    import json

    print(json.dumps(data), flush=True)


def merge_result(rows: dict[str, ActionRow], result: Any) -> None:
    """Take statuses and reasons from the executor's result where it gives them (it knows why an action was
    never run, e.g. a failed predecessor). Accepts ``result.actions`` as a mapping id -> item or a sequence of
    items with ``id``/``action_id``, each with ``status`` (or ``ok``/``done``) and ``reason``."""
    items = getattr(result, "actions", None)
    if items is None:
        return
    pairs = items.items() if isinstance(items, Mapping) else ((getattr(i, "id", None) or getattr(i, "action_id", None),
                                                                i) for i in items)
    for aid, item in pairs:
        row = rows.get(str(aid))
        if row is None:
            continue
        status = getattr(item, "status", None)
        if status is None:
            ok = getattr(item, "ok", getattr(item, "done", None))
            status = None if ok is None else ("done" if ok else "failed")
        if status is not None:
            row.status = str(getattr(status, "value", status))
        reason = getattr(item, "reason", None) or getattr(item, "detail", None)
        if reason:
            row.reason = str(reason)


def summary_table(rows: Sequence[ActionRow]) -> Any:
    from rich.table import Table

    table = Table(title="run summary")
    for column in ("action", "agent", "verb", "status", "reason"):
        table.add_column(column)
    style = {"done": "green", "failed": "red", "skipped": "magenta"}
    for row in rows:
        table.add_row(row.id, row.agents, row.verb, f"[{style.get(row.status, 'yellow')}]{row.status}[/]",
                      row.reason)
    return table


def run_execute(args: argparse.Namespace) -> int:
    from rich.console import Console

    from wecook_core.errors import InputError
    from wecook_core.plan import read_plan

    plan = read_plan(args.plan)  # validates: a bad plan is an InputError before anything runs
    from wecook_tui.commands.plan import plan_findings

    for line in plan_findings(plan):  # what will fail, said before the run
        print(f"wecook: warning: {args.plan}: {line}", file=sys.stderr)
    try:
        import wecook_core.execution.run  # noqa: F401 (the simulator loads)
        from wecook_core.recording.run import recorded_run
    except ImportError as error:
        raise InputError(None, f"the executor is not available ({error})") from None
    console = Console(stderr=args.jsonl)  # --jsonl: stdout carries only JSON lines
    live = console.is_terminal
    progress = Progress(plan, console, live=live, jsonl=args.jsonl)
    observers: list[Any] = [progress]
    record_path: Path | None = None
    replacing = False
    """``--force`` replaces an existing recording: the run is written beside it until it ends."""
    if not args.no_record:
        force = getattr(args, "force", False)
        replacing = force and args.record is not None and (args.record.exists() or args.record.is_symlink())
        if replacing:  # the run is written beside the old recording: its folder must take a file
            from wecook_core.files import check_writable

            check_writable(args.record.parent, "recording")
        record_path = recording_path(args.record, args.plan, force=force)
    server = _live_server(args, console)
    if server is not None:
        observers.append(server)
        progress.live_url = server.url

    def over() -> None:
        progress.stop()
        if server is not None:
            server.close()

    clock = time.perf_counter()
    _interrupt_on_signals()
    result = recorded_run(plan, record_path, observers, replace=replacing, camera_hz=args.camera_hz, over=over,
                          say=console.print, seed=args.seed, realtime=args.realtime, images=not args.camera_hz,
                          timeout=args.timeout, stop_at_first_failure=args.stop_at_first_failure,
                          dynamics=args.dynamics).result
    wall = time.perf_counter() - clock
    rows = list(progress.rows.values())
    merge_result(progress.rows, result)
    contacts = int(getattr(result, "arm_contacts", 0) or 0)
    done = sum(r.status == "done" for r in rows)
    code = 0 if done == len(rows) and not contacts else 1
    if args.jsonl:
        _json_line({"kind": "summary", "actions": [vars(r) for r in rows], "done": done, "total": len(rows),
                    "sim_time": round(progress.sim_time, 4), "wall_time": round(wall, 3), "arm_contacts": contacts,
                    "recording": str(record_path) if record_path else None, "exit_code": code})
        return code
    if progress.live:
        console.print(summary_table(rows))
    else:
        for row in rows:
            print(f"{row.id}\t{row.agents}\t{row.verb}\t{row.status}\t{row.reason}")
    speed = f", {progress.sim_time / wall:.1f}x real time" if wall > 0 and progress.sim_time > 0 else ""
    print(f"{done}/{len(rows)} actions done in {progress.sim_time:.1f} s simulated, {wall:.1f} s wall{speed}")
    if contacts:
        print(f"the arms touched each other {contacts} times")
    return code


def _live_server(args: argparse.Namespace, console: Console) -> Any:
    """``--live``: the server (started, its address said), else None."""
    if not args.live:
        return None
    from wecook_core.recording.live import LiveServer

    server = LiveServer(args.port)
    console.print(f"live view: {server.url} (Foxglove: Open connection > Foxglove WebSocket)")
    return server


def _rate(text: str) -> float:
    try:
        hz = float(text)
    except ValueError:
        hz = -1.0
    if not 0 <= hz < float("inf"):
        raise argparse.ArgumentTypeError(f"not a rate in Hz (0 or more): {text!r}")
    return hz


class RunStopped(KeyboardInterrupt):
    """A SIGTERM or Ctrl-C stopped the run. Handled wherever Ctrl-C is; a subclass, not KeyboardInterrupt
    itself, because CPython kills a process with SIGINT at exit when a bare KeyboardInterrupt once escaped code
    that an extension ran (the planner's callbacks), whatever exit code `main` returned afterwards (Ctrl-C
    left to Python's own handler exited -2 instead of 130 on two runs in three)."""


def _interrupt_on_signals() -> None:
    """SIGTERM (a workbench stopping the run) and Ctrl-C end the run with :class:`RunStopped`: the recording is
    closed properly and `main` returns 130."""
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        def interrupt(signum: int, frame: object) -> None:
            signal.signal(signum, signal.SIG_IGN)  # one stop is enough
            raise RunStopped

        signal.signal(signal.SIGTERM, interrupt)
        signal.signal(signal.SIGINT, interrupt)
