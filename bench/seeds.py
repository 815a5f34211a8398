"""Issue 25's second bar: the demo plan and the shared scenarios' plans, every action done on run seeds
:data:`SEEDS`, no joint over its velocity or acceleration limit in any recorded step.

- ``seeds_sweep_done``: share of the actions done over the demo's plan and the plans of the four shared
  scenarios (:func:`bench.motion.scenario_plans`), each run at every seed of :data:`SEEDS`, recorded as MCAP and
  checked by ``wecook runs check`` (joint limits included); the note names every failure, the recorded steps
  over a limit and the recordings failing the check; ratio: against every action done (1.0).

Measured on 2026-12-04 (2 shared cores): at 4a959e4 318/320 (s304 seed 5: a6's grasp of the whisk, left on its
edge by the knife, failed, a11 skipped); with the tilted-tool grasp 319/320 (s304 seed 0 a11: the spoon's grasp
blocked by the whisk the saw had pushed beside it); with the margin ladder of the actuations 320/320; with the
fingers opened wider only around tilted boxes (afca5ba, for synthetic plan 9) 319/320 (s304 seed 5 a11: the
spoon's grasp blocked by the whisk). No recorded step over a joint limit, no arm contact, every recording passing
the check, in all four. At c71b40f (plans of 312 actions) 311/312, the same failure; with the crowded table's
grasp bounds and the slide of an engage 312/312 (the last attempt at the spoon, every sample of its bounds
blocked by the whisk, takes it slid along the handle and turned), again no step over a limit, no arm contact,
every recording passing.

Run: ``.venv/bin/python -m bench.seeds`` (all), or ``python -m bench.seeds s304 5`` (plans named ``demo`` or
``s30x``, then seeds) to repeat one run; each run's line is printed as it ends.
"""

from __future__ import annotations

import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from wecook_core.execution.run import execute_plan
from wecook_core.plan import Plan
from wecook_core.recording.check import check_recording
from wecook_core.recording.writer import McapRecorder

SEEDS = tuple(range(6))
"""Run seeds of the bar."""


@dataclass(frozen=True)
class SeedRun:
    """One recorded run of a plan at a seed, checked."""

    plan: str
    seed: int
    done: int
    total: int
    failures: tuple[str, ...]
    over_limit: int
    """Recorded steps over a joint's position, velocity or acceleration limit."""
    check_ok: bool
    arm_contacts: int
    sim: float
    wall: float

    def line(self) -> str:
        return (f"{self.plan} seed {self.seed}: {self.done}/{self.total} done, over limit {self.over_limit}, "
                f"check {'ok' if self.check_ok else 'FAILS'}, contacts {self.arm_contacts}, {self.sim:.0f} sim s "
                f"in {self.wall:.0f} wall s" + ("".join(f"\n    {f}" for f in self.failures)))


def named_plans(names: Sequence[str] = ()) -> list[tuple[str, Plan]]:
    """The demo's plan (``demo``) and the shared scenarios' plans by name (all when ``names`` is empty)."""
    from bench.motion import scenario_plans
    from wecook_core.workflows import demo_plan

    plans = [("demo", demo_plan())] if not names or "demo" in names else []
    if not names or any(n != "demo" for n in names):
        plans += [(n, p) for n, p in scenario_plans() if not names or n in names]
    return plans


def recorded_run(name: str, plan: Plan, seed: int, folder: Path) -> SeedRun:
    path = folder / f"{name}-{seed}.mcap"
    began = time.perf_counter()
    result = execute_plan(plan, McapRecorder(path), seed=seed, images=False)
    wall = time.perf_counter() - began
    report = check_recording(path)
    path.unlink()
    return SeedRun(name, seed, sum(a.status == "done" for a in result.actions), len(result.actions),
                   tuple(f"{a.action_id} {a.status}: {a.reason[:110]}" for a in result.actions if a.status != "done"),
                   sum(" over its limit " in p for p in report.problems), report.ok, result.arm_contacts,
                   result.sim_time, wall)


def sweep(plans: Sequence[tuple[str, Plan]], seeds: Sequence[int] = SEEDS, echo: bool = False) -> list[SeedRun]:
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, plan in plans:
            for seed in seeds:
                out.append(recorded_run(name, plan, seed, Path(tmp)))
                if echo:
                    print(out[-1].line(), flush=True)
    return out


def run() -> list[dict[str, object]]:
    runs = sweep(named_plans())
    done, total = sum(r.done for r in runs), sum(r.total for r in runs)
    failures = [f"{r.plan} seed {r.seed} {f}" for r in runs for f in r.failures]
    bad = [f"{r.plan} seed {r.seed}" for r in runs if not r.check_ok]
    return [{"benchmark": "seeds_sweep_done", "value": round(done / total, 4), "unit": "share of actions",
             "ratio_vs_baseline": round(done / total, 4),
             "note": f"demo and s301-s304 at run seeds {SEEDS[0]}-{SEEDS[-1]}, recorded: {done}/{total} done, "
                     f"recorded steps over a joint limit {sum(r.over_limit for r in runs)}, arm contacts "
                     f"{sum(r.arm_contacts for r in runs)}, recordings failing `runs check`: "
                     f"{', '.join(bad) or 'none'}; " + ("; ".join(failures) or "no failures")}]


if __name__ == "__main__":
    args = sys.argv[1:]
    names = [a for a in args if not a.isdigit()]
    seeds = [int(a) for a in args if a.isdigit()] or list(SEEDS)
    sweep(named_plans(names), seeds, echo=True)
