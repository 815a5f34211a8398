"""`wecook analyze NAME [--root DIR]`: run the perception pipeline on a session and write its results.

Loads the session's inputs and corrections, finds the video's shot cuts (cached in the session), runs every stage
(:func:`wecook_core.workflows.analyse_session`), writes ``trees.yaml`` and ``graph.yaml`` into the session folder
and prints what was found, per tree case, and which segments are unsure and why.
"""

from __future__ import annotations

import argparse
import sys
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


def run(args: argparse.Namespace) -> int:
    from collections import Counter

    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.model import SegmentStatus
    from wecook_core.session.store import find_session
    from wecook_core.trees.graph import CASES, case_of
    from wecook_core.workflows import analyse_session

    path = find_session(args.name, args.root)
    knowledge = load_knowledge(Path(args.knowledge) if args.knowledge else None)
    done = analyse_session(path, knowledge)
    session, obs, analysis = done.session, done.observations, done.analysis
    for warning in session.warnings:  # torn or repeated journal lines, changed inputs: as export says them
        print(f"wecook: warning: {warning}", file=sys.stderr)
    counts = Counter(case_of(action, obs.categories) for action in analysis.actions)
    rejected = sum(1 for s in analysis.corrections.status.values() if s is SegmentStatus.REJECTED)
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
