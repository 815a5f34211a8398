"""`wecook eval PRED TRUTH [--json] [--instances] [--loose] [--categories FILE]`: tree precision and recall of
one tree file against another, the trees missed and spurious, and the counts per tree case; with --loose also
the scores with hands ignored and with verbs only."""

from __future__ import annotations

import argparse
import json
from typing import Any


def register(sub: Any) -> None:
    parser = sub.add_parser("eval", help="score a tree file against the ground truth",
                            description="Tree precision, recall, correct, predicted and truth counts "
                                        "(DESIGN.md, Evaluation), the missed and spurious trees, and the "
                                        "counts per case (tool, container, hand, held, transfer, holding, "
                                        "handover). Objects match by class (bowl_2 is a bowl) unless "
                                        "--instances.")
    parser.add_argument("pred", help="predicted tree file (YAML)")
    parser.add_argument("truth", help="ground-truth tree file (YAML)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--instances", action="store_true",
                        help="match objects by their exact names (bowl_2 is not bowl)")
    parser.add_argument("--loose", action="store_true",
                        help="also score with hands ignored and with verbs only, to see which part of the "
                             "trees is wrong (the strict score is unchanged)")
    parser.add_argument("--categories", default=None,
                        help="categories file for telling the cases apart (default: the shipped table)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from dataclasses import asdict
    from pathlib import Path

    from wecook_core.perception.evaluation import class_name, loose, object_names, report
    from wecook_core.trees.notation import format_tree
    from wecook_core.trees.treefile import read_tree_file

    predicted, truth = read_tree_file(args.pred), read_tree_file(args.truth)
    categories = None
    if args.categories:
        from wecook_core.knowledge.categories import load_categories

        table = load_categories(extra=[Path(args.categories)])
        names = {word for span in (*predicted, *truth) for word in object_names(span.tree)}
        categories = {name: found for name in names
                      if (found := table.categorize(class_name(name).replace("_", " "))) is not None}
    result = report(predicted, truth, instances=args.instances, categories=categories)
    scores = result.scores
    cases = result.cases()
    views = loose(predicted, truth, instances=args.instances) if args.loose else {}
    if args.json:
        def spans(items: Any) -> list[dict[str, Any]]:
            return [{"start": s.start, "end": s.end, "tree": format_tree(s.tree)} for s in items]

        print(json.dumps({
            **asdict(scores),
            "missed": spans(result.missed),
            "spurious": spans(result.spurious),
            "cases": {c: {"predicted": result.predicted.get(c, 0), "truth": result.truth.get(c, 0),
                          "correct": result.correct.get(c, 0)} for c in cases},
            **({"loose": {name: asdict(view) for name, view in views.items()}} if args.loose else {}),
        }))
        return 0
    print(f"precision {scores.precision:.3f}  recall {scores.recall:.3f}  "
          f"correct {scores.correct}  predicted {scores.predicted}  truth {scores.truth}")
    for name, view in views.items():
        print(f"{name + ':':<15} precision {view.precision:.3f}  recall {view.recall:.3f}  correct {view.correct}")
    if cases:
        print(f"\n{'case':<10} {'correct':>7} {'predicted':>9} {'truth':>5} {'precision':>9} {'recall':>6}")
        for case in cases:
            c, p, t = result.correct.get(case, 0), result.predicted.get(case, 0), result.truth.get(case, 0)
            print(f"{case:<10} {c:>7} {p:>9} {t:>5} {c / p if p else 0.0:>9.2f} {c / t if t else 0.0:>6.2f}")
    if result.missed or result.spurious:
        print(f"\n{'':<9} {'start':>6} {'end':>6}  tree")
        for label, items in (("missed", result.missed), ("spurious", result.spurious)):
            for span in items:
                print(f"{label:<9} {span.start:>6} {span.end:>6}  {format_tree(span.tree)}")
    return 0
