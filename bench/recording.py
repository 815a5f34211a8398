"""Recording overhead: run time with an MCAP recorder over run time without one (target: ratio < 1.15).

With the real executor (``wecook_core.execution.executor.execute_plan``) on the demo's plan
(:func:`wecook_core.workflows.demo_plan`, as ``wecook export demo`` writes it), the same plan and seed run twice
per repetition, interleaved: once with an observer that drops everything, once with :class:`McapRecorder`; the
medians of the process CPU times are compared (the machine is shared: wall times are noisier), and the time
spent inside the recorder's calls is reported too.

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
from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_core.execution.recorder import McapRecorder

REPEATS = 3


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


def _runner() -> tuple[str, Callable[[Any], float]]:
    """(description, run(observer) -> simulated seconds)."""
    from wecook_core.execution.executor import execute_plan
    from wecook_core.plan import load_plan
    from wecook_core.workflows import demo_plan

    execute_plan(load_plan(ONE_ARM_CUTS), Discard(), seed=0)  # warm up imports and URDF caches
    plan = demo_plan()

    def run_real(observer: Any) -> float:
        return float(execute_plan(plan, observer, seed=0).sim_time)

    return "real executor on the demo's plan", run_real


class Timed:
    """Forwards to an observer and adds up the time spent inside its calls."""

    def __init__(self, inner: Any) -> None:
        self.inner = inner
        self.seconds = 0.0

    def __getattr__(self, name: str) -> Any:
        method = getattr(self.inner, name)

        def timed(*args: Any, **kwargs: Any) -> Any:
            clock = time.perf_counter()
            try:
                return method(*args, **kwargs)
            finally:
                self.seconds += time.perf_counter() - clock

        return timed


def run() -> list[dict[str, object]]:
    what, run_once = _runner()
    repeats = REPEATS
    without, with_rec, inside, sizes, counts, sims = [], [], [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeats):  # interleaved, CPU time of this process: less sensitive to other load
            clock = time.process_time()
            sims.append(run_once(Discard()))
            without.append(time.process_time() - clock)
            path = Path(tmp) / f"run{k}.mcap"
            recorder = McapRecorder(path)
            timed = Timed(recorder)
            clock = time.process_time()
            run_once(timed)
            recorder.close()
            with_rec.append(time.process_time() - clock)
            inside.append(timed.seconds)
            sizes.append(path.stat().st_size)
            counts.append(recorder.message_count)
    base, rec = statistics.median(without), statistics.median(with_rec)
    sim = statistics.median(sims)
    ratio = rec / base
    own = statistics.median(inside)
    verdict = "meets" if ratio < 1.15 else "misses"
    return [
        {"benchmark": "run CPU time without recording", "value": base, "unit": "s", "ratio_vs_baseline": 1.0,
         "note": f"baseline; {what}; {sim:.1f} s simulated; median of {repeats}"},
        {"benchmark": "run CPU time with MCAP recording", "value": rec, "unit": "s", "ratio_vs_baseline": ratio,
         "note": f"{verdict} the < 1.15 target; {statistics.median(counts):.0f} messages, flushed every 1 s"},
        {"benchmark": "time inside the recorder", "value": own, "unit": "s", "ratio_vs_baseline": 1 + own / base,
         "note": "wall time spent in McapRecorder calls, as 1 + share of the baseline (least noisy estimate)"},
        {"benchmark": "recording size", "value": statistics.median(sizes) / max(sim, 1e-9) / 1024,
         "unit": "KiB per simulated s", "ratio_vs_baseline": None, "note": "zstd chunks, JSON messages"},
    ]


if __name__ == "__main__":
    for row in run():
        print(row)
