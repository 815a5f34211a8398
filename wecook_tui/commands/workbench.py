"""`wecook open NAME` and `wecook demo`: the review workbench (Textual, imported only when the command runs)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    opener = subparsers.add_parser("open", help="review and correct a session in the workbench")
    opener.add_argument("name", help="session name (in the sessions folder) or a session folder's path")
    opener.add_argument("--root", type=Path, default=None,
                        help="sessions folder (default: $WECOOK_SESSIONS or ./sessions)")
    opener.set_defaults(func=run)
    demo = subparsers.add_parser("demo", help="build the bundled demo session if missing, then open it")
    demo.add_argument("--root", type=Path, default=None, help="sessions folder (as for open)")
    demo.add_argument("--headless", action="store_true",
                      help="no workbench: analyse the demo and print its trees, graph and scores against the truth "
                           "(the default when there is no terminal)")
    demo.set_defaults(func=run_demo)


def quiet_decoders() -> None:
    """FFmpeg and OpenCV log to stderr, where the terminal UI draws: silence them before cv2 loads."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    os.environ.setdefault("OPENCV_LOG_LEVEL", "OFF")


def launch(path: Path) -> int:
    """Open the workbench on the session ``path``, holding its writer lock while it is open: a session open in
    another workbench (or written by another command) is refused at once, naming the holder (exit 2)."""
    quiet_decoders()
    from wecook_core.session.lock import WriterLock
    from wecook_core.session.paths import SessionPaths
    from wecook_tui.app import WecookApp

    lock = WriterLock.take(SessionPaths(path).journal)
    try:
        WecookApp(path).run()
    finally:
        lock.release()
    return 0


def run(args: argparse.Namespace) -> int:
    quiet_decoders()
    from wecook_core.session.store import find_session

    return launch(find_session(args.name, args.root))


def run_demo(args: argparse.Namespace) -> int:
    quiet_decoders()
    from wecook_core.workflows import demo_session

    path = demo_session(args.root)
    if args.headless or not (sys.stdin.isatty() and sys.stdout.isatty()):
        return report_demo(path)
    return launch(path)


def report_demo(path: Path) -> int:
    """Analyse the demo session (with its corrections) and print trees, graph and scores against the truth."""
    from rich.console import Console
    from rich.table import Table

    from wecook_core.trees.graph import dump_graph
    from wecook_core.trees.notation import format_tree
    from wecook_core.workflows import run_demo

    console = Console(highlight=False)
    report = run_demo(path.parent)
    session, obs, analysis = report.analysed.session, report.analysed.observations, report.analysed.analysis
    for warning in session.warnings:
        console.print(f"[yellow]warning:[/] {warning}")
    fps = obs.video.fps or 30.0
    console.print(f"[bold]demo session[/] {path}: {len(analysis.segmentation.segments)} segments, "
                  f"{len(analysis.trees)} trees")
    trees = Table("frames", "seconds", "tree", title="action trees", title_justify="left")
    for span in analysis.trees:
        trees.add_row(f"{span.start}-{span.end}", f"{span.start / fps:.1f}-{span.end / fps:.1f}",
                      format_tree(span.tree))
    console.print(trees)
    console.print("[bold]action graph[/]")
    console.print(dump_graph(analysis.graph), markup=False, soft_wrap=True)
    scores = report.scores
    console.print(f"[bold]against the truth:[/] precision {scores.precision:.3f}, recall {scores.recall:.3f} "
                  f"({scores.correct} correct of {scores.predicted} predicted, {scores.truth} true)")
    console.print(f"wrote {session.trees_path} and {session.graph_path}; review them with `wecook open {path}`")
    return 0
