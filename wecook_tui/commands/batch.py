"""`wecook batch MANIFEST`: the same stages as `new`, `analyze`, `export`, `execute`, for many videos, on Ray.

Each video gets its own session under ``--root``, made exactly as the one-video commands make it. A second run
skips the stages whose inputs and parameters are unchanged (``--force`` redoes them); a failed video is
reported and the others go on. ``batch.json`` in the sessions folder is rewritten as each video finishes; at
the end, a table. One batch at a time on a sessions folder (a second one refuses, naming the first, or waits
with ``--wait``). Ctrl-C or SIGTERM stop it cleanly (exit 130): the running videos are cancelled, Ray is shut
down, and what finished is kept and reported.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

DEFAULT_STAGES = "import,hands,analyze,export"


def register(sub: Any) -> None:
    parser = sub.add_parser("batch", help="run the stages for every video of a manifest (Ray)",
                            description="Import, detect hands, analyse, export and execute many videos, one "
                                        "session each. MANIFEST: a YAML or CSV file (name, video, objects, hands, "
                                        "truth, categories) or a folder of scenario folders.")
    parser.add_argument("manifest", help="manifest file (YAML or CSV) or a folder of scenario folders")
    parser.add_argument("--stages", default=DEFAULT_STAGES,
                        help=f"comma-separated stages among import,hands,analyze,export,execute "
                             f"(default: {DEFAULT_STAGES}; hands runs only for videos without hands)")
    parser.add_argument("--root", default=None,
                        help="folder holding the sessions (default: $WECOOK_SESSIONS, else ./sessions)")
    parser.add_argument("--workers", type=int, default=None,
                        help="most videos at once (default: every CPU of the local Ray, or of the cluster)")
    parser.add_argument("--address", default=None,
                        help="join this running Ray cluster instead of starting one: auto, HOST:PORT (its GCS, "
                             "`ray start --head --port`), or ray://HOST:PORT (Ray Client); the videos and --root "
                             "must be on storage every node reads at the same path")
    parser.add_argument("--wait", action="store_true",
                        help="wait for another batch running on the same sessions folder instead of refusing")
    parser.add_argument("--engine", choices=("ray", "local"), default="ray",
                        help="ray (default), or local: one task after another in this process")
    parser.add_argument("--force", action="store_true", help="redo stages even when their inputs are unchanged")
    parser.add_argument("--seed", type=int, default=0, help="run seed of the execute stage")
    parser.add_argument("--no-record", action="store_true", help="execute without an MCAP recording")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from rich.console import Console

    from wecook_core.batch.engine import run_batch
    from wecook_core.batch.manifest import read_manifest
    from wecook_core.batch.report import ReportWriter
    from wecook_core.batch.stages import StageOptions, stages_for
    from wecook_core.errors import InputError
    from wecook_core.session.store import sessions_root

    items = read_manifest(args.manifest)
    stages = tuple(s.strip() for s in args.stages.split(",") if s.strip())
    for item in items:
        stages_for(item, stages)  # unknown stage names stop here, before anything runs
    if args.workers is not None and args.workers < 1:
        raise InputError(None, f"--workers {args.workers}: at least 1")
    root = sessions_root(args.root)
    console = Console(stderr=True)
    show = _Display(console, len(items))
    options = StageOptions(seed=args.seed, force=args.force, record=not args.no_record)
    writer = ReportWriter(root)
    _stop_on_sigterm()
    try:
        with show:
            run_batch(items, stages, root, options=options, engine=args.engine, workers=args.workers,
                      address=args.address, on_progress=show.update, on_video=writer, manifest=args.manifest,
                      wait=args.wait)
    except KeyboardInterrupt:
        done = 0 if writer.report is None else sum(v.status != "pending" for v in writer.report.videos)
        where = f", reported in {root / 'batch.json'}" if writer.report is not None else ""
        print(f"wecook: batch stopped: {done}/{len(items)} videos finished and kept{where}", file=sys.stderr)
        raise
    report = writer.report
    assert report is not None
    path = root / "batch.json"
    out = Console()
    if not out.is_terminal:
        out = Console(width=160)
    out.print(_table(report))
    scores = ""
    if report.recall is not None:
        scores = f"; precision {report.precision:.2f}, recall {report.recall:.2f}"
    print(f"{len(report.videos) - report.failed}/{len(report.videos)} videos done in {report.seconds:.1f} s "
          f"on {report.engine} ({report.workers} workers){scores}; report: {path}")
    for video in report.videos:
        if video.error:
            print(f"wecook: {video.name}: {video.error}", file=sys.stderr)
    return 0 if report.failed == 0 else 1


class BatchStopped(KeyboardInterrupt):
    """SIGTERM stopped the batch; handled wherever Ctrl-C is (a subclass, see execute's ``RunStopped``)."""


def _stop_on_sigterm() -> None:
    """SIGTERM stops the batch as Ctrl-C does (Ray's own handler would abort the process)."""
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        def stop(signum: int, frame: object) -> None:
            signal.signal(signal.SIGTERM, signal.SIG_IGN)  # one stop is enough
            raise BatchStopped

        signal.signal(signal.SIGTERM, stop)


def _eta(seconds: float | None) -> str:
    return "" if seconds is None else f"ETA {seconds:.0f} s"


class _Display:
    """The whole batch (videos done, running, failed, ETA) and each running video (its stage, ETA): a rich
    progress display on a terminal, a line per finished stage otherwise."""

    def __init__(self, console: Any, videos: int) -> None:
        self.console = console
        self.bar: Any = None
        self.videos = videos
        self.rows: dict[str, Any] = {}
        if console.is_terminal:
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                TimeElapsedColumn(), TextColumn("{task.fields[eta]}"), console=console)
            self.task = self.bar.add_task("videos", total=videos, eta="")

    def __enter__(self) -> _Display:
        if self.bar is not None:
            self.bar.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()

    def update(self, progress: Any) -> None:
        text = f"videos: {progress.done} done, {progress.running} running, {progress.failed} failed"
        if self.bar is not None:
            self.bar.update(self.task, completed=progress.done + progress.failed, description=text,
                            eta=_eta(progress.eta))
            running = {v.video: v for v in progress.current}
            for name in [n for n in self.rows if n not in running]:
                self.bar.remove_task(self.rows.pop(name))
            for name, video in running.items():
                line = f"  {name}: {video.stage} ({video.index + 1}/{video.stages})"
                if name not in self.rows:
                    self.rows[name] = self.bar.add_task(line, total=video.stages, eta="")
                self.bar.update(self.rows[name], completed=video.index, description=line, eta=_eta(video.eta))
        elif progress.last is not None:
            last = progress.last
            detail = f": {last.error}" if last.error else ""
            now = "; ".join(f"{v.video}: {v.stage} {v.index + 1}/{v.stages} {_eta(v.eta)}".rstrip()
                            for v in progress.current[:4])
            more = f" (+{len(progress.current) - 4})" if len(progress.current) > 4 else ""
            print(f"{last.video} {last.stage} {last.status} ({last.seconds:.1f} s){detail}; {text} "
                  f"{_eta(progress.eta)}".rstrip() + (f"; now {now}{more}" if now else ""),
                  file=sys.stderr, flush=True)


def _table(report: Any) -> Any:
    from rich.table import Table

    table = Table(title="batch")
    for column in ("video", "status", "stages", "seconds", "trees", "actions", "done", "P", "R", "error"):
        table.add_column(column)

    def num(value: Any, digits: int = 0) -> str:
        return "-" if value is None else f"{value:.{digits}f}" if digits else str(value)

    for v in report.videos:
        counts: dict[str, int] = {}
        for s in v.stages:
            counts[s.status] = counts.get(s.status, 0) + 1
        stages = ", ".join(f"{n} {status}" for status, n in counts.items())
        table.add_row(v.name, v.status, stages, f"{v.seconds:.1f}", num(v.trees), num(v.actions), num(v.done),
                      num(v.precision, 2), num(v.recall, 2), v.error)
    return table
