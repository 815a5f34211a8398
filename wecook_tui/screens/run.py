"""Run screen: `wecook execute` in a subprocess (a worker reads its output), live per-action progress and log,
the summary and the MCAP path; past runs of the session listed with their results."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rich.text import Text
from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.screen import Screen
from textual.widgets import DataTable, Footer, OptionList, ProgressBar, RichLog, Static
from textual.widgets.option_list import Option

from wecook_tui.messages import RunFinished, RunOutput
from wecook_tui.screens.plan_review import plan_file

RUN_BINDINGS: list[Binding] = [
    Binding("escape,q", "back", "Back", id="run-back"),
    Binding("ctrl+k", "stop", "Stop run", id="run-stop"),
]

Command = Callable[[Path, Path], list[str]]
"""(plan path, mcap path) -> the argv that executes the plan."""

WORD = re.compile(r"[A-Za-z0-9_]+")
STATES = (("skipped", re.compile(r"\bskipped\b", re.I)), ("failed", re.compile(r"fail|error", re.I)),
          ("done", re.compile(r"\bdone\b|succe|\bok\b|✓", re.I)),
          ("running", re.compile(r"start|running|begin", re.I)))
"""First match wins: a skipped action's line names the failure it waits on."""


def execute_command(plan: Path, mcap: Path) -> list[str]:
    return [sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--record", str(mcap)]


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
        try:
            record = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        records[path.stem] = {**records.get(path.stem, {}), **record, "name": path.stem}
    return sorted(records.values(), key=lambda r: r["name"], reverse=True)


def action_state(line: str, ids: set[str] | dict[str, str]) -> tuple[str, str] | None:
    """(action id, state) when an output line of `wecook execute` reports an action's progress
    (``[  1.20s] a3 P1 cut: started`` / ``: done`` / ``: FAILED: why``, or a summary row ``a3<TAB>P1<TAB>...``)."""
    found = next((word for word in WORD.findall(line) if word in ids), None)
    if found is None:
        return None
    for state, pattern in STATES:
        if pattern.search(line):
            return found, state
    return None


class RunScreen(Screen[None]):
    BINDINGS = RUN_BINDINGS

    def __init__(self, session_path: Path, analysis: Any, obs: Any, command: Command = execute_command) -> None:
        super().__init__()
        self.session_path = session_path
        self.analysis = analysis
        """Run the current analysis' plan; None only lists the past runs."""
        self.obs = obs
        self.command = command
        self.process: subprocess.Popen[str] | None = None
        self.states: dict[str, str] = {}
        self.result: RunFinished | None = None

    def compose(self) -> ComposeResult:
        with Horizontal(id="run-body"):
            with Vertical(id="run-past"):
                yield Static("Past runs", classes="title")
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
            self.query_one("#run-summary", Static).update("Past runs of this session (r on the main screen runs).")
            return
        stamp = time.strftime("%Y%m%d-%H%M%S")
        self.mcap = runs_dir(self.session_path) / f"run-{stamp}.mcap"
        self.query_one("#run-summary", Static).update(Text(f"Running… recording to {self.mcap}", style="yellow"))
        self._execute(self.mcap)

    def _list_runs(self) -> None:
        options = self.query_one("#run-list", OptionList)
        options.clear_options()
        for record in past_runs(self.session_path):
            code = record.get("returncode")
            mark = "✓" if code == 0 else ("?" if code is None else "✗")
            options.add_option(Option(f"{mark} {record['name']}", id=record["name"]))

    def on_option_list_option_highlighted(self, event: OptionList.OptionHighlighted) -> None:
        record = next((r for r in past_runs(self.session_path) if r["name"] == event.option.id), None)
        if record is None or (self.analysis is not None and self.result is None):
            return  # a run in progress owns the log
        log = self.query_one("#run-log", RichLog)
        log.clear()
        code = record.get("returncode")
        verdict = "every action done" if code == 0 else ("unknown (no record)" if code is None else f"exit {code}")
        log.write(Text(f"{record['name']}: {verdict}; MCAP {record.get('mcap')}", style="bold"))
        for line in record.get("tail", []):
            log.write(Text.from_ansi(line))

    # ----------------------------------------------------------------------------------- worker

    @work(thread=True, exclusive=True, group="run", exit_on_error=False)
    def _execute(self, mcap: Path) -> None:
        from wecook_core.plan import plan_from_graph, write_plan

        started = time.perf_counter()
        folder = runs_dir(self.session_path)
        folder.mkdir(parents=True, exist_ok=True)
        log_path = mcap.with_suffix(".log")
        try:
            plan = plan_from_graph(self.analysis.graph, self.obs)
            plan_path = write_plan(plan, plan_file(self.session_path))
            self.app.call_from_thread(self._show_plan, plan)
            env = {**os.environ, "PYTHONUNBUFFERED": "1", "COLUMNS": "120", "NO_COLOR": "1"}
            self.process = subprocess.Popen(self.command(Path(plan_path), mcap), stdout=subprocess.PIPE,
                                            stderr=subprocess.STDOUT, text=True, bufsize=1, env=env)
        except Exception as error:
            self.post_message(RunOutput(f"cannot start the run: {type(error).__name__}: {error}"))
            self.post_message(RunFinished(-1, mcap, log_path, time.perf_counter() - started))
            return
        tail: list[str] = []
        states = {action.id: "waiting" for action in plan.actions}
        assert self.process.stdout is not None
        with log_path.open("w") as log:
            for line in self.process.stdout:
                line = line.rstrip("\n")
                log.write(line + "\n")
                tail = [*tail[-199:], line]
                found = action_state(line, states)
                if found is not None:
                    states[found[0]] = found[1]
                self.post_message(RunOutput(line))
        code = self.process.wait()
        seconds = time.perf_counter() - started
        record = {"returncode": code, "mcap": str(mcap), "log": str(log_path), "seconds": round(seconds, 2),
                  "actions": states, "tail": tail[-40:]}
        mcap.with_suffix(".json").write_text(json.dumps(record, indent=1))
        self.post_message(RunFinished(code, mcap, log_path, seconds))

    def _show_plan(self, plan: Any) -> None:
        table = self.query_one("#run-actions", DataTable)
        for action in plan.actions:
            self.states[action.id] = "waiting"
            table.add_row(action.id, ",".join(action.pids), action.verb, "waiting", key=action.id)
        self.query_one("#run-progress", ProgressBar).update(total=max(1, len(plan.actions)), progress=0)

    def on_run_output(self, message: RunOutput) -> None:
        self.query_one("#run-log", RichLog).write(Text.from_ansi(message.line))
        found = action_state(message.line, self.states)
        if found is None:
            return
        action_id, state = found
        self.states[action_id] = state
        table = self.query_one("#run-actions", DataTable)
        colour = {"done": "green", "failed": "red", "skipped": "magenta", "running": "yellow"}.get(state, "")
        table.update_cell(action_id, "state", Text(state, style=colour))
        finished = sum(1 for s in self.states.values() if s in ("done", "failed", "skipped"))
        self.query_one("#run-progress", ProgressBar).update(progress=finished)

    def on_run_finished(self, message: RunFinished) -> None:
        self.result = message
        self.process = None
        done = sum(1 for s in self.states.values() if s == "done")
        failed = [a for a, s in self.states.items() if s == "failed"]
        skipped = [a for a, s in self.states.items() if s == "skipped"]
        style = "bold green" if message.returncode == 0 else "bold red"
        summary = Text.assemble(
            ("Run finished: " if message.returncode == 0 else f"Run ended with exit code {message.returncode}: ",
             style),
            f"{done}/{len(self.states)} actions done",
            f", failed: {', '.join(failed)}" if failed else "",
            f", skipped: {', '.join(skipped)}" if skipped else "",
            f" in {message.seconds:.1f} s\nMCAP: {message.mcap}\nlog: {message.log}",
        )
        self.query_one("#run-summary", Static).update(summary)
        self._list_runs()

    def action_stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            self.notify("Run stopped.")

    def on_unmount(self) -> None:
        self.action_stop()

    def action_back(self) -> None:
        self.dismiss(None)
