"""`wecook analyze NAME [--root DIR]`: run the perception pipeline on a session and write its results.

Loads the session's inputs and corrections, finds the video's shot cuts (when the video is readable), runs
every stage (:func:`wecook_core.pipeline.analyze`), writes ``trees.yaml`` and ``graph.yaml`` into the session
folder and prints what was found, per tree case, and which segments are unsure and why.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(sub: Any) -> None:
    parser = sub.add_parser("analyze", help="segment, associate, recognise: write a session's trees and graph",
                            description="Run the perception pipeline on a session (with its corrections) and "
                                        "write sessions/NAME/trees.yaml and graph.yaml.")
    parser.add_argument("name", help="session name (a folder under --root) or a session folder")
    parser.add_argument("--root", default=None,
                        help="folder holding the sessions (default: $WECOOK_SESSIONS, else ./sessions)")
    parser.add_argument("--knowledge", default=None, help="commonsense tables (default: the shipped ones)")
    parser.set_defaults(func=run)


def session_path(name: str, root: str | Path | None) -> Path:
    """A session's folder: ``NAME`` itself when it is a folder path, else ``ROOT/NAME``."""
    from wecook_core.session.store import check_name, sessions_root

    direct = Path(name)
    if ("/" in name or name.startswith(".")) and direct.is_dir():
        return direct
    return sessions_root(root) / check_name(name)


def run(args: argparse.Namespace) -> int:
    from collections import Counter

    from wecook_core.errors import InputError
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.model import SegmentStatus
    from wecook_core.perception.params import Params
    from wecook_core.perception.pipeline import analyze
    from wecook_core.session.store import open_session
    from wecook_core.trees.graph import CASES, case_of, write_graph_file
    from wecook_core.trees.treefile import write_tree_file

    path = session_path(args.name, args.root)
    if not path.is_dir():
        raise InputError(path, "no such session folder")
    session = open_session(path)
    obs = session.load_observations()
    knowledge = load_knowledge(Path(args.knowledge) if args.knowledge else None)
    params = getattr(session, "params", None) or Params()
    corrections = session.corrections
    analysis = analyze(obs, knowledge, params, corrections, shots=cached_shot_cuts(path, obs.video.path))
    write_tree_file(session.trees_path, analysis.trees)
    write_graph_file(session.graph_path, analysis.graph)

    counts = Counter(case_of(action, obs.categories) for action in analysis.actions)
    rejected = sum(1 for s in corrections.status.values() if s is SegmentStatus.REJECTED)
    seconds = sum(analysis.seconds.values())
    print(f"{path.name}: {len(analysis.segmentation.segments)} segments, {len(analysis.trees)} trees, "
          f"{len(analysis.graph.nodes)} graph nodes, {len(analysis.graph.edges)} edges "
          f"({seconds:.2f} s)")
    print("  " + "  ".join(f"{case} {counts.get(case, 0)}" for case in CASES))
    if rejected:
        print(f"  {rejected} rejected segment(s) left out")
    if analysis.shots:
        print(f"  {len(analysis.shots)} shot cut(s) at frames {', '.join(map(str, analysis.shots))}")
    if analysis.unsure:
        print(f"  {len(analysis.unsure)} segment(s) unsure, for review:")
        for start, reason in list(analysis.unsure.items())[:10]:
            print(f"    frame {start}: {reason}")
        if len(analysis.unsure) > 10:
            print(f"    ... and {len(analysis.unsure) - 10} more")
    print(f"  wrote {session.trees_path} and {session.graph_path}")
    return 0


SHOTS_FILE = "shots.json"
"""The session's cache of its video's shot cuts (finding them decodes the whole video)."""


def cached_shot_cuts(session: Path, video: str) -> tuple[int, ...]:
    """The video's shot cuts, from ``session/shots.json`` when it was made from this very file (path, size
    and modification time), else found (:func:`wecook_core.perception.shots.shot_cuts`) and written there."""
    import contextlib
    import json

    from wecook_core.perception.shots import shot_cuts

    source = Path(video)
    if not source.is_file():
        return ()
    stat = source.stat()
    key = {"video": str(source.resolve()), "size": stat.st_size, "mtime_ns": stat.st_mtime_ns}
    cache = session / SHOTS_FILE
    try:
        data = json.loads(cache.read_text(encoding="utf-8"))
        if {k: data.get(k) for k in key} == key and isinstance(data.get("cuts"), list):
            return tuple(int(c) for c in data["cuts"])
    except (OSError, ValueError, TypeError):
        pass
    cuts = shot_cuts(source)
    with contextlib.suppress(OSError):  # a read-only session still analyses
        cache.write_text(json.dumps({**key, "cuts": list(cuts)}) + "\n", encoding="utf-8")
    return cuts
