"""Run screen: `wecook execute --jsonl` in a subprocess (a worker reads its events), live per-action progress
and log, the summary and the MCAP path; past runs of the session listed with their table and log.

`wecook execute --jsonl` prints one JSON object per line (``run_start``, every plan event, ``summary``) on
stdout, its messages on stderr; the screen folds the events into each action's state (:func:`apply_event`) and
never reads the human text. A run served live (``live_port``: ``--live --port N``) says its address, from the
``live`` field of its ``run_start`` event, for Foxglove to connect to. Stopping sends SIGTERM: the run closes
its recording and reports the action under way as interrupted, which shows as stopped.
"""

from __future__ import annotations

import contextlib
import json
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, ClassVar

from rich.text import Text
from textual import work
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.screen import Screen
from textual.widgets import DataTable, Footer, OptionList, ProgressBar, RichLog, Static
from textual.widgets.option_list import Option

from wecook_core.errors import InputError
from wecook_tui.messages import RunEvent, RunFinished, RunOutput
from wecook_tui.screens.plan_review import plan_file

RUN_BINDINGS: list[Binding] = [
    Binding("escape,q", "back", "Back", id="run-back"),
    Binding("ctrl+k", "stop", "Stop run", id="run-stop"),
]

Command = Callable[[Path, Path], list[str]]
"""(plan path, mcap path) -> the argv that executes the plan, printing JSON lines (``--jsonl``)."""

FINAL = ("done", "failed", "skipped", "stopped")
COLOURS = {"done": "green", "failed": "red", "skipped": "magenta", "running": "yellow", "stopped": "cyan"}
STOPPED_CODES = (130, -15, 143)
"""Exit codes of a run stopped by SIGTERM (handled: 130) or killed by it."""


def apply_event(states: dict[str, str], event: Mapping[str, Any]) -> str | None:
    """Fold one event of `wecook execute --jsonl` into ``states`` (action id -> state); the action changed."""
    kind, action = event.get("kind"), event.get("action_id")
    if kind == "summary":
        for row in event.get("actions", ()):
            if row.get("id") in states and row.get("status") in (*FINAL, "running"):
                states[row["id"]] = row["status"]
        return None
    if action not in states:
        return None
    if kind == "action_start":
        states[action] = "running"
    elif kind == "action_end":
        states[action] = "done"
    elif kind == "action_failed":
        if event.get("detail") == "interrupted":
            states[action] = "stopped"
        else:
            states[action] = "failed" if states[action] == "running" else "skipped"
    else:
        return None
    return str(action)


def execute_command(plan: Path, mcap: Path) -> list[str]:
    return [sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--record", str(mcap), "--jsonl"]


def runs_dir(session_path: Path) -> Path:
    from wecook_core.session.paths import session_paths

    return session_paths(session_path).runs


def past_runs(session_path: Path) -> list[dict[str, Any]]:
    """Each finished run's record (``runs/*.json``), newest first; MCAP files without a record are listed too."""
    folder = runs_dir(session_path)
    records: dict[str, dict[str, Any]] = {}
    for mcap in sorted(folder.glob("*.mcap")):
        records[mcap.stem] = {"name": mcap.stem, "mcap": str(mcap), "returncode": None}
    for path in sorted(folder.glob("*.json")):
        if path.name.endswith(".layout.json"):  # the Foxglove layout written beside each recording
            continue
        try:
            record = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        records[path.stem] = {**records.get(path.stem, {}), **record, "name": path.stem}
    return sorted(records.values(), key=lambda r: r["name"], reverse=True)


class RunScreen(Screen[None]):
    BINDINGS: ClassVar[list[BindingType]] = [*RUN_BINDINGS]

    def __init__(self, session_path: Path, analysis: Any, obs: Any, command: Command = execute_command,
                 live_port: int | None = None) -> None:
        super().__init__()
        self.live_port = live_port
        """Serve the run over Foxglove's WebSocket on this port (0: any free one); None: not served."""
        self.live_url: str | None = None
        """The address the run is served on, as its ``run_start`` event says."""
        self.session_path = session_path
        self.analysis = analysis
        """Run the current analysis' plan; None only lists the past runs."""
        self.obs = obs
        self.command = command
        self.process: subprocess.Popen[str] | None = None
        self.states: dict[str, str] = {}
        self.result: RunFinished | None = None
        self.stopping = False
        self.shown_run: str | None = None
        """The past run whose table and log are shown."""

    def compose(self) -> ComposeResult:
        with Horizontal(id="run-body"):
            with Vertical(id="run-past"):
                yield Static("Past runs (enter opens)", classes="title")
                yield OptionList(id="run-list")
            with Vertical(id="run-main"):
                yield Static(id="run-summary")
                yield ProgressBar(id="run-progress", show_eta=False)
                yield DataTable(id="run-actions", cursor_type="none")
                yield RichLog(id="run-log", wrap=True, markup=False, max_lines=5000)
        yield Footer()

    def on_mount(self) -> None:
        table = self.query_one("#run-actions", DataTable)
        for column in ("action", "persons", "verb", "state"):
            table.add_column(column, key=column)
        self._list_runs()
        if self.analysis is None:
            self.query_one("#run-progress", ProgressBar).display = False
            runs = past_runs(self.session_path)
            self.query_one("#run-summary", Static).update(
                f"{len(runs)} past run(s) of this session: enter shows one (r on the main screen runs the plan)."
                if runs else "No runs of this session yet (r on the main screen runs the plan).")
            if runs:
                self.show_run(runs[0]["name"])
                options = self.query_one("#run-list", OptionList)
                options.highlighted = 0
                options.focus()
            return
        stamp = time.strftime("%Y%m%d-%H%M%S")
        self.mcap = runs_dir(self.session_path) / f"run-{stamp}.mcap"
        self.query_one("#run-summary", Static).update(self._running_summary())
        self._execute(self.mcap)

    def _running_summary(self) -> Text:
        """The summary while the run goes: where it records and, served live, where Foxglove connects."""
        text = Text(f"Running… recording to {self.mcap}", style="yellow")
        if self.live_url:
            text.append_text(Text.assemble("\nlive: ", (self.live_url, "bold cyan"),
                                           " (Foxglove: Open connection > Foxglove WebSocket)"))
        elif self.live_port is not None:
            text.append("\nlive: starting the server…", style="dim")
        return text

    def _list_runs(self) -> None:
        options = self.query_one("#run-list", OptionList)
        options.clear_options()
        for record in past_runs(self.session_path):
            code = record.get("returncode")
            mark = "✓" if code == 0 else ("?" if code is None else "■" if code in STOPPED_CODES else "✗")
            options.add_option(Option(f"{mark} {record['name']}", id=record["name"]))

    def _run_in_progress(self) -> bool:
        return self.analysis is not None and self.result is None

    def on_option_list_option_selected(self, event: OptionList.OptionSelected) -> None:
        if event.option.id is not None and not self._run_in_progress():
            self.show_run(event.option.id)

    def show_run(self, name: str) -> None:
        """Show a past run: its per-action table, its verdict and its log."""
        record = next((r for r in past_runs(self.session_path) if r["name"] == name), None)
        if record is None:
            return
        self.shown_run = name
        table = self.query_one("#run-actions", DataTable)
        table.clear()
        actions = record.get("actions") or {}
        verbs = record.get("verbs") or {}
        for action_id, state in actions.items():
            persons, verb = verbs.get(action_id, ["", ""])
            table.add_row(action_id, persons, verb, Text(state, style=COLOURS.get(state, "")), key=action_id)
        code = record.get("returncode")
        verdict = ("every action done" if code == 0 else "unknown (no record)" if code is None
                   else "stopped" if code in STOPPED_CODES else f"exit {code}")
        done = sum(1 for s in actions.values() if s == "done")
        self.query_one("#run-summary", Static).update(Text.assemble(
            (f"{name}: {verdict}", "bold"), f", {done}/{len(actions)} actions done" if actions else "",
            f"\nMCAP: {record.get('mcap')}",
            f"\nserved live on {record['live']}" if isinstance(record.get("live"), str) else ""))
        log = self.query_one("#run-log", RichLog)
        log.clear()
        path = Path(record.get("log") or Path(record.get("mcap", "")).with_suffix(".log"))
        try:
            lines = path.read_text().splitlines()[-2000:]
        except OSError:
            lines = list(record.get("tail", []))
        for line in lines:
            log.write(Text.from_ansi(line))

    # ----------------------------------------------------------------------------------- worker

    @work(thread=True, exclusive=True, group="run", exit_on_error=False)
    def _execute(self, mcap: Path) -> None:
        from wecook_core.workflows import plan_of, write_checked_plan

        started = time.perf_counter()
        runs_dir(self.session_path).mkdir(parents=True, exist_ok=True)
        log_path = mcap.with_suffix(".log")
        try:
            plan = plan_of(self.analysis, self.obs)
            plan_path = write_checked_plan(plan, plan_file(self.session_path))
            self.app.call_from_thread(self._show_plan, plan)
            env = {**os.environ, "PYTHONUNBUFFERED": "1", "COLUMNS": "120", "NO_COLOR": "1"}
            argv = self.command(Path(plan_path), mcap)
            if self.live_port is not None:
                argv += ["--live", "--port", str(self.live_port)]
            self.process = subprocess.Popen(argv, stdout=subprocess.PIPE,
                                            stderr=subprocess.PIPE, text=True, bufsize=1, env=env)
        except Exception as error:
            self.post_message(RunOutput(f"cannot start the run: {type(error).__name__}: {error}"))
            self.post_message(RunFinished(-1, mcap, log_path, time.perf_counter() - started))
            return
        states = {action.id: "waiting" for action in plan.actions}
        verbs = {action.id: [",".join(action.pids), action.verb] for action in plan.actions}
        tail: list[str] = []
        live: str | None = None
        process = self.process
        assert process.stdout is not None and process.stderr is not None
        with log_path.open("w") as log:
            lock = threading.Lock()

            def messages() -> None:  # stderr: the run's own messages, for the log
                assert process.stderr is not None
                for line in process.stderr:
                    with lock:
                        log.write(line)
                    if not self.stopping:
                        self.post_message(RunOutput(line.rstrip("\n")))

            reader = threading.Thread(target=messages, daemon=True)
            reader.start()
            for line in process.stdout:
                try:
                    event = json.loads(line)
                except ValueError:
                    event = None
                if not isinstance(event, dict) or "kind" not in event:
                    with lock:
                        log.write(line)
                    continue
                with lock:
                    log.write(_describe(event, verbs) + "\n")
                tail = [*tail[-199:], _describe(event, verbs)]
                if event.get("kind") == "run_start" and isinstance(event.get("live"), str):
                    live = event["live"]
                apply_event(states, event)
                self.post_message(RunEvent(event))
            code = process.wait()
            reader.join(timeout=5)
        if code in STOPPED_CODES:
            for action_id, state in states.items():
                if state == "running":
                    states[action_id] = "stopped"
        seconds = time.perf_counter() - started
        record = {"returncode": code, "mcap": str(mcap), "log": str(log_path), "seconds": round(seconds, 2),
                  "actions": states, "verbs": verbs, "tail": tail[-40:], **({"live": live} if live else {})}
        from wecook_core.files import write_atomic

        with contextlib.suppress(OSError, InputError):  # the run's summary beside it: a convenience
            write_atomic(mcap.with_suffix(".json"), json.dumps(record, indent=1), replace=True, what="run summary")
        self.post_message(RunFinished(code, mcap, log_path, seconds))

    def _show_plan(self, plan: Any) -> None:
        table = self.query_one("#run-actions", DataTable)
        for action in plan.actions:
            self.states[action.id] = "waiting"
            table.add_row(action.id, ",".join(action.pids), action.verb, "waiting", key=action.id)
        self.query_one("#run-progress", ProgressBar).update(total=max(1, len(plan.actions)), progress=0)

    def on_run_output(self, message: RunOutput) -> None:
        self.query_one("#run-log", RichLog).write(Text.from_ansi(message.line))

    def on_run_event(self, message: RunEvent) -> None:
        event = message.event
        if event.get("kind") in ("action_start", "action_end", "action_failed", "run_start", "retry"):
            self.query_one("#run-log", RichLog).write(Text(_describe(event, {})))
        if event.get("kind") == "run_start" and isinstance(event.get("live"), str):
            self.live_url = event["live"]
            self.query_one("#run-summary", Static).update(self._running_summary())
        changed = apply_event(self.states, event)
        for action_id in ([changed] if changed else list(self.states) if event.get("kind") == "summary" else []):
            self._show_state(action_id)

    def _show_state(self, action_id: str) -> None:
        state = self.states[action_id]
        table = self.query_one("#run-actions", DataTable)
        table.update_cell(action_id, "state", Text(state, style=COLOURS.get(state, "")))
        finished = sum(1 for s in self.states.values() if s in FINAL)
        self.query_one("#run-progress", ProgressBar).update(progress=finished)

    def on_run_finished(self, message: RunFinished) -> None:
        self.result = message
        self.process = None
        stopped = message.returncode in STOPPED_CODES
        if stopped:
            for action_id, state in self.states.items():
                if state == "running":
                    self.states[action_id] = "stopped"
                    self._show_state(action_id)
        done = sum(1 for s in self.states.values() if s == "done")
        failed = [a for a, s in self.states.items() if s == "failed"]
        skipped = [a for a, s in self.states.items() if s == "skipped"]
        style = "bold green" if message.returncode == 0 else "bold cyan" if stopped else "bold red"
        head = ("Run finished: " if message.returncode == 0 else "Run stopped: " if stopped
                else f"Run ended with exit code {message.returncode}: ")
        summary = Text.assemble(
            (head, style),
            f"{done}/{len(self.states)} actions done",
            f", failed: {', '.join(failed)}" if failed else "",
            f", skipped: {', '.join(skipped)}" if skipped else "",
            f" in {message.seconds:.1f} s\nMCAP: {message.mcap}\nlog: {message.log}",
            f"\nlive view was {self.live_url} (closed with the run)" if self.live_url else "",
        )
        self.query_one("#run-summary", Static).update(summary)
        if stopped:
            self.query_one("#run-log", RichLog).write(Text("Run stopped.", style="bold cyan"))
        self._list_runs()

    def action_stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.stopping = True
            self.process.terminate()
            self.notify("Stopping the run…")

    def on_unmount(self) -> None:
        self.action_stop()

    def action_back(self) -> None:
        self.dismiss(None)


def _describe(event: Mapping[str, Any], verbs: Mapping[str, list[str]]) -> str:
    """One log line for an event: ``[  1.20s] a3 action_end``."""
    t = event.get("t")
    stamp = f"[{t:7.2f}s] " if isinstance(t, int | float) else ""
    kind = event.get("kind")
    if kind == "run_start":
        return f"{stamp}run started: {event.get('actions')} actions, seed {event.get('seed')}"
    if kind == "summary":
        return f"summary: {event.get('done')}/{event.get('total')} actions done, exit {event.get('exit_code')}"
    action = event.get("action_id") or ""
    persons, verb = verbs.get(action, ["", ""])
    what = {"action_start": "started", "action_end": "done", "action_failed": "failed"}.get(str(kind), str(kind))
    detail = f": {event['detail']}" if event.get("detail") else ""
    return f"{stamp}{action} {persons} {verb} {what}{detail}".replace("  ", " ")
