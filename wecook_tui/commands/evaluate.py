"""`wecook eval PRED TRUTH [--json]`: tree precision and recall of one tree file against another."""

from __future__ import annotations

import argparse
import json
from typing import Any


def register(sub: Any) -> None:
    parser = sub.add_parser("eval", help="score a tree file against the ground truth",
                            description="Tree precision, recall, correct, predicted and truth counts "
                                        "(DESIGN.md, Evaluation).")
    parser.add_argument("pred", help="predicted tree file (YAML)")
    parser.add_argument("truth", help="ground-truth tree file (YAML)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from dataclasses import asdict

    from wecook_core.perception.evaluation import evaluate
    from wecook_core.trees.treefile import read_tree_file

    scores = evaluate(read_tree_file(args.pred), read_tree_file(args.truth))
    if args.json:
        print(json.dumps(asdict(scores)))
    else:
        print(f"precision {scores.precision:.3f}  recall {scores.recall:.3f}  "
              f"correct {scores.correct}  predicted {scores.predicted}  truth {scores.truth}")
    return 0
