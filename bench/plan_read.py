"""Plan reading: `wecook plan check` of a 10,000-action plan against plain YAML loads of the same file.

The plan: the demo's 11 actions copied over and over (ids ``a1_0, a1_1, ...``, ``after`` edges within each copy)
to 10,000 actions, written as ``wecook export`` writes a plan (2.1 MiB). Timed, best of ``REPEATS``:

- ``plan check``: what ``wecook plan check`` does (:func:`wecook_core.plan.schema.check_plan_file`: read, bound,
  JSON Schema, build, validate; then the reach and room findings), target under 3 s;
- baseline: ``yaml.load(text, yaml.CSafeLoader)``, libyaml's loader alone (nothing checked), in the same run; and
  once, PyYAML's pure-Python ``yaml.safe_load`` (what plan reading used before issue 26).

Run: ``.venv/bin/python -m bench.plan_read``.

Measured on 2026-12-04 (2 shared cores, load ~8): plan check 1.6 s, CSafeLoader alone 4.2 s (ratio 0.38),
yaml.safe_load alone 30 s (ratio 0.05); plan check before issue 26: 21.8 s.
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

from wecook_core.plan import Plan, dump_plan

ACTIONS = 10_000
REPEATS = 3


def big_plan(n: int = ACTIONS) -> Plan:
    """The demo's plan with its actions copied to ``n`` (each copy's ``after`` edges kept within the copy)."""
    from wecook_core.workflows import demo_plan

    base = demo_plan()
    actions = []
    copy = 0
    while len(actions) < n:
        ids = {a.id: f"{a.id}_{copy}" for a in base.actions}
        actions += [dataclasses.replace(a, id=ids[a.id], after=tuple(ids[d] for d in a.after))
                    for a in base.actions]
        copy += 1
    return dataclasses.replace(base, actions=tuple(actions[:n]))


def _best(fn: Callable[[], Any], repeats: int = REPEATS) -> float:
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        fn()
        times.append(time.perf_counter() - started)
    return min(times)


def run() -> list[dict[str, Any]]:
    from wecook_core.plan.schema import check_plan_file
    from wecook_tui.commands.plan import plan_findings

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "plan.yaml"
        path.write_text(dump_plan(big_plan()))
        text = path.read_text()
        size = len(text.encode()) / 2**20

        def check() -> None:
            plan = check_plan_file(path)
            assert len(plan.actions) == ACTIONS and not plan_findings(plan)

        check_s = _best(check)
        libyaml_s = _best(lambda: yaml.load(text, Loader=yaml.CSafeLoader))
        python_s = _best(lambda: yaml.safe_load(text), repeats=1)
    return [
        {"benchmark": f"plan check, {ACTIONS} actions ({size:.1f} MiB)", "value": check_s, "unit": "s",
         "ratio_vs_baseline": check_s / libyaml_s,
         "note": f"baseline: yaml.load with CSafeLoader alone {libyaml_s:.2f} s; target < 3 s"},
        {"benchmark": f"plan check vs yaml.safe_load, {ACTIONS} actions", "value": check_s, "unit": "s",
         "ratio_vs_baseline": check_s / python_s,
         "note": f"baseline: PyYAML's pure-Python safe_load alone {python_s:.2f} s"},
    ]


if __name__ == "__main__":
    for row in run():
        print(row)
