"""`python -m bench [NAME ...]`: run the benchmarks and print one table (and `bench/results.json`)."""

from __future__ import annotations

import importlib
import json
import pkgutil
import sys
import time
import traceback
from pathlib import Path

from rich.console import Console
from rich.table import Table


def main(argv: list[str]) -> int:
    here = Path(__file__).parent
    names = argv or sorted(m.name for m in pkgutil.iter_modules([str(here)]) if not m.name.startswith("_"))
    console = Console(width=None if sys.stdout.isatty() else 200)
    table = Table(title="wecook benchmarks")
    for column in ("module", "benchmark", "value", "unit", "ratio vs baseline", "note"):
        table.add_column(column, overflow="fold")
    rows: list[dict[str, object]] = []
    failed = []
    for name in names:
        console.print(f"[bold]bench.{name}[/] ...")
        started = time.perf_counter()
        try:
            module = importlib.import_module(f"bench.{name}")
            results = module.run()
        except Exception:
            traceback.print_exc()
            failed.append(name)
            continue
        console.print(f"  done in {time.perf_counter() - started:.1f} s")
        for row in results:
            rows.append({"module": name, **row})
            ratio = row.get("ratio_vs_baseline")
            value = row.get("value")
            table.add_row(
                name,
                str(row.get("benchmark", "")),
                f"{value:.4g}" if isinstance(value, float) else str(value),
                str(row.get("unit", "")),
                f"{ratio:.3g}" if isinstance(ratio, float) else str(ratio or ""),
                str(row.get("note", "")),
            )
    console.print(table)
    (here / "results.json").write_text(json.dumps(rows, indent=1, default=str) + "\n")
    if failed:
        console.print(f"[red]failed: {', '.join(failed)}[/]")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
