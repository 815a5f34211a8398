"""`wecook segment FILE --lamb L --k-max K [--columns 0,3,7] [--json]`: Greedy Gaussian Segmentation of a series.

FILE holds one sample per line, numbers separated by whitespace and/or commas (``#`` starts a comment).
Prints, for every number of breakpoints k, the interior breakpoints (0-based sample indices where a new
segment starts) and the objective, marking the k that the BIC rule chooses; ``--json`` prints exactly
``{"breakpoints_by_k": [[...], ...], "objective_by_k": [...], "seconds": ...}`` (``seconds``: the
algorithm's own run time).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any, TypeVar

T = TypeVar("T")


def _columns(text: str) -> list[int]:
    try:
        columns = [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected 0-based column numbers like 0,3,7, got {text!r}") from None
    if not columns or any(c < 0 for c in columns):
        raise argparse.ArgumentTypeError(f"expected 0-based column numbers like 0,3,7, got {text!r}")
    return columns


def _number(convert: Callable[[str], T], ok: Callable[[T], bool], expected: str) -> Callable[[str], T]:
    """An argparse ``type``: ``convert(text)`` when that works and the value is ``ok``, else "expected ..."."""

    def parse(text: str) -> T:
        try:
            value = convert(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
        if not ok(value):
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}")
        return value

    return parse


_positive_float = _number(float, lambda value: value > 0, "a number > 0")
_count = _number(int, lambda value: value >= 0, "a whole number >= 0")


def register(sub: Any) -> None:
    parser = sub.add_parser(
        "segment",
        help="Greedy Gaussian Segmentation of a numeric series (one sample per line)",
        description="Segment a numeric series with Greedy Gaussian Segmentation (Hallac, Nystrup, Boyd) for "
                    "every number of breakpoints up to --k-max. FILE: one sample per line, numbers separated "
                    "by whitespace or commas.",
    )
    parser.add_argument("file", metavar="FILE", help="numeric text file, rows = samples")
    parser.add_argument("--lamb", type=_positive_float, required=True,
                        help="covariance regularisation λ (squared units of the data)")
    parser.add_argument("--k-max", type=_count, required=True, help="most breakpoints to add")
    parser.add_argument("--columns", type=_columns, default=None,
                        help="0-based columns to use, comma separated (default: all)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import json

    from wecook_core.perception.segmentation import choose_k, ggs, load_series

    data = load_series(args.file, args.columns)
    result = ggs(data, args.k_max, args.lamb)
    if args.json:
        print(json.dumps({
            "breakpoints_by_k": [list(b) for b in result.breakpoints_by_k],
            "objective_by_k": list(result.objective_by_k),
            "seconds": result.seconds,
        }))
        return 0
    samples, features = data.shape
    chosen = choose_k(result, samples=samples, features=features)
    print(f"{args.file}: {samples} samples x {features} features, lamb {args.lamb:g}, "
          f"k up to {len(result.breakpoints_by_k) - 1} ({result.seconds:.3f} s)")
    print(f"{'k':>4}  {'objective':>18}  breakpoints")
    for k, (breaks, objective) in enumerate(zip(result.breakpoints_by_k, result.objective_by_k, strict=True)):
        mark = "*" if k == chosen else " "
        print(f"{k:>3}{mark}  {objective:>18.6f}  {' '.join(map(str, breaks)) or '-'}")
    print(f"* chosen by BIC: k = {chosen}")
    return 0
