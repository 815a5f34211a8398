"""`wecook open NAME` and `wecook demo`: the review workbench (Textual, imported only when the command runs)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from wecook_core.errors import InputError

DEMO_NAME = "demo"


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
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


def session_path(name: str, root: Path | None) -> Path:
    """The folder of session ``name``: a path to a session folder, or a name under the sessions root."""
    from wecook_core.session.store import sessions_root

    given = Path(name)
    if (given / "session.yaml").is_file():
        return given
    path = sessions_root(root) / name
    if not (path / "session.yaml").is_file():
        raise InputError(path, "no such session (create one with `wecook new NAME --video V --objects F "
                         "--hands H`, or try `wecook demo`)")
    return path


def demo_session(root: Path | None) -> Path:
    """The demo session, created from ``wecook_core/assets/demo`` the first time."""
    from wecook_core.session.store import create_session, sessions_root
    from wecook_core.synth import demo_dir

    path = sessions_root(root) / DEMO_NAME
    if (path / "session.yaml").is_file():
        return path
    assets = Path(demo_dir())
    return Path(create_session(sessions_root(root), DEMO_NAME, assets / "video.mp4", assets / "objects.csv",
                               assets / "hands.csv"))


def quiet_decoders() -> None:
    """FFmpeg and OpenCV log to stderr, where the terminal UI draws: silence them before cv2 loads."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    os.environ.setdefault("OPENCV_LOG_LEVEL", "OFF")


def launch(path: Path) -> int:
    quiet_decoders()
    from wecook_tui.app import WecookApp

    WecookApp(path).run()
    return 0


def run(args: argparse.Namespace) -> int:
    quiet_decoders()
    return launch(session_path(args.name, args.root))


def run_demo(args: argparse.Namespace) -> int:
    quiet_decoders()
    path = demo_session(args.root)
    if args.headless or not (sys.stdin.isatty() and sys.stdout.isatty()):
        return report_demo(path)
    return launch(path)


def report_demo(path: Path) -> int:
    """Analyse the demo session (with its corrections) and print trees, graph and scores against the truth."""
    from rich.console import Console
    from rich.table import Table

    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.perception.evaluation import evaluate
    from wecook_core.perception.pipeline import analyze
    from wecook_core.session.store import open_session
    from wecook_core.synth import demo_dir
    from wecook_core.trees.graph import dump_graph, write_graph_file
    from wecook_core.trees.notation import format_tree
    from wecook_core.trees.treefile import read_tree_file, write_tree_file

    console = Console(highlight=False)
    session = open_session(path)
    for warning in session.warnings:
        console.print(f"[yellow]warning:[/] {warning}")
    obs = session.load_observations()
    analysis = analyze(obs, load_knowledge(), session.params, session.corrections)
    write_tree_file(session.trees_path, analysis.trees)
    write_graph_file(session.graph_path, analysis.graph)
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
    scores = evaluate(analysis.trees, read_tree_file(Path(demo_dir()) / "truth.yaml"))
    console.print(f"[bold]against the truth:[/] precision {scores.precision:.3f}, recall {scores.recall:.3f} "
                  f"({scores.correct} correct of {scores.predicted} predicted, {scores.truth} true)")
    console.print(f"wrote {session.trees_path} and {session.graph_path}; review them with `wecook open {path}`")
    return 0
