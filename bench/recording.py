"""Recording overhead: run time with an MCAP recorder over run time without one (target: ratio < 1.15).

With the real executor (``wecook_core.execution.executor.execute_plan``) and a demo plan, the same plan and seed
run twice per repetition: once with an observer that drops everything, once with :class:`McapRecorder` (the
median of the repetitions is reported). When either is missing, a synthetic run of the same message rates stands
in (:mod:`wecook_core.execution.synthetic_run`: 30 states/s of simulated time with two 9-link arms and five
objects, events, logs and images at action boundaries), paced at 20x real time like the simulation; the note
says which was measured.

Run: ``.venv/bin/python -m bench.recording``.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from wecook_core.execution.observer import FrameInfo, Quat, RunEvent, Vec3
from wecook_core.execution.recorder import McapRecorder
from wecook_core.execution.synthetic_run import synthetic_run
from wecook_core.resources import ASSETS_DIR

REPEATS = 3
SPEEDUP = 20.0
"""Simulated seconds per wall second the synthetic stand-in is paced at (the executor's measured rate)."""


class Discard:
    """A RunObserver that drops everything: the baseline."""

    def __init__(self) -> None:
        self.messages = 0

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int, metadata: Mapping[str, str]) -> None:
        pass

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        self.messages += 1 + len(joints)

    def on_event(self, t: float, event: RunEvent) -> None:
        self.messages += 1

    def on_log(self, t: float, level: Any, message: str) -> None:
        self.messages += 1

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        self.messages += 1

    def on_end(self, t: float) -> None:
        pass


def _demo_plan() -> Path | None:
    for candidate in (ASSETS_DIR / "demo" / "plan.yaml", ASSETS_DIR / "demo_plan.yaml"):
        if candidate.is_file():
            return candidate
    return None


def _runner() -> tuple[str, Callable[[Any], float]]:
    """(description, run(observer) -> simulated seconds)."""
    plan_path = _demo_plan()
    try:
        from wecook_core.execution.bullet_world import BulletWorld  # noqa: F401 (the executor needs it)
        from wecook_core.execution.executor import execute_plan
    except ImportError:
        plan_path = None
    if plan_path is not None:
        from wecook_core.plan import read_plan

        plan = read_plan(plan_path)

        def run_real(observer: Any) -> float:
            return float(execute_plan(plan, observer, seed=0).sim_time)

        return f"real executor on {plan_path.relative_to(ASSETS_DIR.parent)}", run_real

    def run_synthetic(observer: Any) -> float:
        return synthetic_run(observer, actions=6, seconds_per_action=2.0, state_hz=30.0,
                             wall_per_sim=1.0 / SPEEDUP).sim_seconds

    return f"synthetic stream paced at {SPEEDUP:.0f}x real time (no executor or demo plan available)", run_synthetic


def run() -> list[dict[str, object]]:
    what, run_once = _runner()
    without, with_rec, sizes, counts, sims = [], [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(REPEATS):
            clock = time.perf_counter()
            sims.append(run_once(Discard()))
            without.append(time.perf_counter() - clock)
            path = Path(tmp) / f"run{k}.mcap"
            recorder = McapRecorder(path)
            clock = time.perf_counter()
            run_once(recorder)
            recorder.close()
            with_rec.append(time.perf_counter() - clock)
            sizes.append(path.stat().st_size)
            counts.append(recorder.message_count)
    base, rec = statistics.median(without), statistics.median(with_rec)
    sim = statistics.median(sims)
    ratio = rec / base
    verdict = "meets" if ratio < 1.15 else "misses"
    return [
        {"benchmark": "run time without recording", "value": base, "unit": "s", "ratio_vs_baseline": 1.0,
         "note": f"baseline; {what}; {sim:.1f} s simulated; median of {REPEATS}"},
        {"benchmark": "run time with MCAP recording", "value": rec, "unit": "s", "ratio_vs_baseline": ratio,
         "note": f"{verdict} the < 1.15 target; {statistics.median(counts):.0f} messages, flushed every 1 s"},
        {"benchmark": "recording size", "value": statistics.median(sizes) / max(sim, 1e-9) / 1024,
         "unit": "KiB per simulated s", "ratio_vs_baseline": None, "note": "zstd chunks, JSON messages"},
    ]


if __name__ == "__main__":
    for row in run():
        print(row)
