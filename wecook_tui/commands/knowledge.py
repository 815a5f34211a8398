"""`wecook knowledge learn|evaluate` and `wecook recognize`: the commonsense model from the command line."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, TextIO

BATCH_HELP = (
    "rank many object lists: FILE ('-' for stdin) has one comma-separated object list per line; prints one "
    "JSON ranking per line, in order. An empty line gives an empty ranking `[]`; a line whose objects are "
    "all unknown gives the prior. Unknown objects are summed up on stderr at the end."
)


def register(sub: Any) -> None:
    knowledge = sub.add_parser("knowledge", help="learn or evaluate the commonsense tables",
                               description="Learn the commonsense model P(action | objects) from a corpus of "
                                           "(action, objects) records, or evaluate it on held-out records.")
    actions = knowledge.add_subparsers(dest="knowledge_command", metavar="ACTION", required=True)

    learn = actions.add_parser("learn", help="learn the tables from corpora and write them (and SOURCE.md)",
                               description="Read corpora (EPIC-KITCHENS folders, folders of Markdown recipes or "
                                           "CSV files `action,objects`, objects separated by `;`), fold their "
                                           "verbs into wecook's actions, count, and write commonsense.json, "
                                           "epic_categories.yaml and SOURCE.md.")
    _corpus_options(learn)
    learn.add_argument("-o", "--out", type=Path, default=None,
                       help="output folder (default: the shipped assets/knowledge)")
    learn.set_defaults(func=run_learn)

    extract = actions.add_parser("extract", help="write the (verb, objects) records of Markdown recipes as CSV",
                                 description="Read a folder of Markdown recipes (a `## Directions` list each, as "
                                             "on publicdomainrecipes.com or based.cooking; a folder holding "
                                             "`content/` works too), extract the verb and objects of every clause "
                                             "of their directions, and write them as a CSV corpus.")
    extract.add_argument("recipes", type=Path, metavar="PATH", nargs="?", default=None,
                         help="the Open Recipe Archive (its folder or .jsonl.gz; default: "
                              "../shared/data/recipes, written to ./open-recipe-archive.csv) or a folder of "
                              "Markdown recipes")
    extract.add_argument("-o", "--out", type=Path, default=None,
                         help="CSV to write (default: the shipped assets/knowledge/recipes.csv)")
    extract.add_argument("--origin", default=None,
                         help="where the recipes come from, for the CSV's `# source:` line (default: the "
                              "shipped corpus's description when writing the shipped file, else the folder)")
    extract.add_argument("--licence", default=None,
                         help="licence of the recipes, for the CSV's `# licence:` line (default: the shipped "
                              "corpus's, public domain, when writing the shipped file; else none)")
    extract.set_defaults(func=run_extract)

    evaluate = actions.add_parser("evaluate", help="held-out accuracy, macro precision and recall",
                                  description="Split the corpus by group (EPIC: video) with a seed, learn on "
                                              "the rest, predict the verb of each held-out record from its "
                                              "objects, and compare with always predicting the majority verb.")
    _corpus_options(evaluate)
    evaluate.add_argument("--fraction", type=float, default=0.2, help="fraction of groups held out (0.2)")
    evaluate.add_argument("--json", action="store_true", help="print one JSON object")
    evaluate.set_defaults(func=run_evaluate)

    recognize = sub.add_parser("recognize", help="rank actions for a set of objects",
                               description="Rank wecook's actions by P(A | objects) with the commonsense tables. "
                                           "Objects are free text ('chopping board', cherry_tomato, bowl_2).")
    recognize.add_argument("objects", nargs="*", metavar="OBJECT", help="object labels (commas also separate)")
    recognize.add_argument("--json", action="store_true", help="print a JSON list of {action, p}")
    recognize.add_argument("--batch", metavar="FILE", help=BATCH_HELP)
    recognize.add_argument("--knowledge", type=Path, default=None,
                           help="knowledge tables (default: the shipped assets/knowledge/commonsense.json)")
    recognize.add_argument("--candidates", default=None,
                           help="comma-separated verbs to rank among (default: all)")
    recognize.set_defaults(func=run_recognize)


def _corpus_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--corpus", type=Path, action="append", default=None, metavar="PATH",
                        help="EPIC-KITCHENS folder, folder of Markdown recipes or CSV file; repeat to combine "
                             "(default: ../shared/data/epic-kitchens, the shipped recipes.csv and "
                             "../shared/data/recipes, the Open Recipe Archive)")
    parser.add_argument("--alpha", type=float, default=None,
                        help="additive smoothing pseudo-count (default: 0.03 for the tables mixed by corpus, "
                             "1.0 with --pooled)")
    parser.add_argument("--pooled", action="store_true",
                        help="count all corpora together in one table (the tables before the Open Recipe Archive) "
                             "instead of one table per corpus, mixed, with each object in its role")
    parser.add_argument("--prior", choices=("uniform", "corpus"), default="uniform",
                        help="with --pooled, P(A): uniform, or learned from the action counts (uniform); the mixed "
                             "tables' is uniform")
    parser.add_argument("--held", type=float, default=None, metavar="SECONDS",
                        help="EPIC: a tool taken at most this long before an action and not put down since counts "
                             "as one of its objects (the held tool); 0 turns it off (default: "
                             "wecook_core.knowledge.corpus.HELD_S, 30)")
    parser.add_argument("--context", type=int, default=0,
                        help="EPIC: objects of 'take' records among this many before an action count as its "
                             "objects too (0)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the held-out split (0)")
    parser.add_argument("--per-record", dest="per_group", action="store_false",
                        help="count every record (default: a group, an EPIC video or a recipe, that repeats a verb "
                             "with an object counts once)")


def _held(args: argparse.Namespace) -> float:
    from wecook_core.knowledge.corpus import HELD_S

    return HELD_S if args.held is None else float(args.held)


def _corpora(args: argparse.Namespace) -> list[Path]:
    from wecook_core.knowledge.build import default_corpora

    return list(args.corpus or default_corpora())


def _check_pooled(args: argparse.Namespace) -> None:
    """``--prior corpus`` and ``--per-record`` describe pooled counts: without ``--pooled`` they would be
    ignored, so they are refused (exit 2)."""
    from wecook_core.errors import InputError

    if not args.pooled and (args.prior != "uniform" or not args.per_group):
        raise InputError(None, "--prior corpus and --per-record apply to pooled tables: add --pooled")


def run_learn(args: argparse.Namespace) -> int:
    from wecook_core.knowledge.build import KNOWLEDGE_DIR, build

    out = args.out or KNOWLEDGE_DIR
    _check_pooled(args)
    built = build(_corpora(args), out, alpha=args.alpha, context=args.context, held_s=_held(args), seed=args.seed,
                  prior=args.prior, per_group=args.per_group, mixed=not args.pooled)
    k = built.knowledge
    counts = ", ".join(f"{v} {n}" for v, n in zip(k.verbs, k.action_counts.tolist(), strict=True))
    unit = "groups" if args.per_group else "records"
    print(f"learned {unit} per action: {counts}; "
          f"{len(k.objects)} objects, {len(k.aliases)} aliases")
    if built.evaluation is not None:
        m, b = built.evaluation.model, built.evaluation.baseline
        print(f"held out (seed {built.evaluation.seed}): accuracy {m.accuracy:.3f} (majority {b.accuracy:.3f}), "
              f"macro precision {m.macro_precision:.3f} ({b.macro_precision:.3f}), macro recall "
              f"{m.macro_recall:.3f} ({b.macro_recall:.3f})")
        for source, metrics in built.evaluation.by_source:
            print(f"  held-out {source} records: accuracy {metrics.accuracy:.3f}, macro precision "
                  f"{metrics.macro_precision:.3f}, macro recall {metrics.macro_recall:.3f}")
        ceiling = built.evaluation.ceiling
        if ceiling is not None:
            print(f"  ceiling (learned from the held-out records): accuracy {ceiling.accuracy:.3f}, macro precision "
                  f"{ceiling.macro_precision:.3f}, macro recall {ceiling.macro_recall:.3f}")
        oracle = built.evaluation.oracle
        if oracle is not None:
            print(f"  objects oracle (most frequent verb per held-out object set): accuracy {oracle.accuracy:.3f}, "
                  f"macro precision {oracle.macro_precision:.3f}, macro recall {oracle.macro_recall:.3f}")
    for path in built.files:
        print(f"wrote {path}")
    return 0


def run_extract(args: argparse.Namespace) -> int:
    from wecook_core.errors import InputError
    from wecook_core.knowledge.archive import ARCHIVE_LICENCE, is_archive
    from wecook_core.knowledge.build import (
        ARCHIVE_ORIGIN,
        ARCHIVE_PATH,
        RECIPES_LICENCE,
        RECIPES_ORIGIN,
        RECIPES_PATH,
        default_archive,
        extract_archive,
        extract_recipes,
    )
    from wecook_core.knowledge.instructions import is_recipe_folder

    source = args.recipes or default_archive()
    if is_archive(source):
        out = args.out or ARCHIVE_PATH
        count = extract_archive(source, out, origin=args.origin or ARCHIVE_ORIGIN,
                                licence=args.licence or ARCHIVE_LICENCE)
        print(f"wrote {count} records to {out}")
        return 0
    if not is_recipe_folder(source):
        raise InputError(source, "expected a folder of Markdown recipes with a `## Directions` list")
    out = args.out or RECIPES_PATH
    shipped = out.resolve() == RECIPES_PATH.resolve()
    origin = args.origin if args.origin is not None else (RECIPES_ORIGIN if shipped else str(source))
    licence = args.licence if args.licence is not None else (RECIPES_LICENCE if shipped else "")
    count = extract_recipes(source, out, origin=origin, licence=licence)
    print(f"wrote {count} records to {out}" + ("" if licence else " (no licence declared: pass --licence)"))
    return 0


def run_evaluate(args: argparse.Namespace) -> int:
    from dataclasses import asdict

    from wecook_core.errors import InputError
    from wecook_core.knowledge.build import read_corpora
    from wecook_core.knowledge.evaluation import evaluate
    from wecook_core.knowledge.report import metrics_table

    _check_pooled(args)
    corpus = read_corpora(_corpora(args), context=args.context, held_s=_held(args))
    try:
        if args.pooled:
            result = evaluate(corpus, seed=args.seed, fraction=args.fraction,
                              alpha=1.0 if args.alpha is None else args.alpha, prior=args.prior,
                              per_group=args.per_group)
        else:
            from wecook_core.knowledge.mixture import ALPHA

            result = evaluate(corpus, seed=args.seed, fraction=args.fraction,
                              alpha=ALPHA if args.alpha is None else args.alpha, mixed=True)
    except ValueError as error:
        raise InputError(None, str(error)) from None
    if args.json:
        print(json.dumps(asdict(result)))
    else:
        kind = (f"pooled, prior {args.prior}, counted {'per group' if args.per_group else 'per record'}"
                if args.pooled else "mixed by corpus")
        print(f"{result.test_groups} groups held out (seed {result.seed}, {kind}): "
              f"{result.train_records} training records, {result.test_records} held-out records\n")
        print(metrics_table(result))
    return 0


def _split(values: Sequence[str]) -> list[str]:
    return [item.strip() for value in values for item in value.split(",") if item.strip()]


def run_recognize(args: argparse.Namespace) -> int:
    from wecook_core.errors import InputError
    from wecook_core.knowledge.recognize import load_knowledge, rank, unknown_objects

    knowledge = load_knowledge(args.knowledge)
    candidates = _split([args.candidates]) if args.candidates else None
    if candidates:
        wrong = [c for c in candidates if c not in knowledge.verbs]
        if wrong:
            raise InputError(None, f"--candidates: not verbs of the tables: {', '.join(wrong)} "
                                   f"(expected some of {', '.join(knowledge.verbs)})")
    if args.batch:
        if args.objects:
            raise InputError(None, "give objects or --batch FILE, not both")
        return _run_batch(knowledge, args.batch, candidates)
    objects = _split(args.objects)
    if not objects:
        raise InputError(None, "no objects given (e.g. `wecook recognize knife tomato`, or --batch FILE)")
    ranking = rank(knowledge, objects, candidates)
    unknown = unknown_objects(knowledge, objects)
    if unknown:
        print(f"wecook: ignored unknown objects: {', '.join(unknown)}", file=sys.stderr)
    if args.json:
        print(json.dumps([{"action": verb, "p": p} for verb, p in ranking]))
        return 0
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"P(action | {', '.join(o for o in objects if o not in unknown) or 'no known object'})")
    table.add_column("action")
    table.add_column("p", justify="right")
    for verb, p in ranking:
        table.add_row(verb, f"{p:.4f}")
    Console().print(table)
    return 0


def _lines(stream: TextIO) -> Iterator[list[str]]:
    for line in stream:
        yield [item.strip() for item in line.split(",") if item.strip()]


def _run_batch(knowledge: Any, name: str, candidates: list[str] | None) -> int:
    from wecook_core.errors import InputError
    from wecook_core.knowledge.recognize import rank_batch

    try:
        stream: TextIO = sys.stdin if name == "-" else open(name, encoding="utf-8")  # noqa: SIM115
    except OSError as error:
        raise InputError(name, f"cannot read: {error.strerror}") from None
    unknown: dict[str, int] = {}
    out = sys.stdout
    try:
        for number, item in enumerate(rank_batch(knowledge, _lines(stream), candidates, chunk=1024), start=1):
            out.write(_json(item.ranking))
            for label in item.unknown:
                unknown.setdefault(label, number)
    except UnicodeDecodeError as error:
        raise InputError(name, f"not UTF-8 text: {error.reason}") from None
    finally:
        if stream is not sys.stdin:
            stream.close()
    out.flush()
    if unknown:
        shown = ", ".join(f"{label!r} (line {line})" for label, line in list(unknown.items())[:10])
        more = f" and {len(unknown) - 10} more" if len(unknown) > 10 else ""
        print(f"wecook: ignored {len(unknown)} unknown objects: {shown}{more}", file=sys.stderr)
    return 0


def _json(ranking: Sequence[tuple[str, float]]) -> str:
    return "[" + ", ".join(f'{{"action": "{verb}", "p": {p!r}}}' for verb, p in ranking) + "]\n"
