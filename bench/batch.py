"""`wecook batch`: speed-up of two Ray workers against one, memory per worker, and Ray's overhead against a plain
loop, all in one run on the shared scenarios (import, analyze, export; every stage redone with force)."""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path
from typing import Any

from wecook_core.batch.engine import BatchRun, run_batch
from wecook_core.batch.manifest import read_manifest
from wecook_core.batch.stages import StageOptions
from wecook_core.resources import shared_dir

STAGES = ("import", "analyze", "export")


def _run(items: Any, engine: str, workers: int | None, root: Path) -> BatchRun:
    return run_batch(items, STAGES, root, engine=engine, workers=workers,  # type: ignore[arg-type]
                     options=StageOptions(force=True))


def run() -> list[dict[str, object]]:
    scenarios = shared_dir() / "data" / "scenarios"
    if not scenarios.is_dir():
        return [{"benchmark": "batch", "value": "skipped", "note": f"{scenarios} is missing"}]
    try:
        import ray  # noqa: F401
    except ImportError:
        return [{"benchmark": "batch", "value": "skipped", "note": "ray is not installed (extra 'batch')"}]
    items = read_manifest(scenarios)
    root = Path(tempfile.mkdtemp(prefix="wecook-bench-batch-"))
    try:
        loop = _run(items, "local", None, root / "local")
        one = _run(items, "ray", 1, root / "ray1")
        two = _run(items, "ray", 2, root / "ray2")
        small = _run(items[:1], "local", None, root / "small-local")
        small_ray = _run(items[:1], "ray", 1, root / "small-ray")
    finally:
        shutil.rmtree(root, ignore_errors=True)
    peaks: dict[int, float] = {}
    for results in two.results.values():
        for r in results:
            peaks[r.pid] = max(peaks.get(r.pid, 0.0), r.peak_rss_mb)
    n = len(items)
    return [
        {"benchmark": f"{n} videos, plain loop in-process", "value": loop.seconds, "unit": "s",
         "note": "baseline of the Ray rows"},
        {"benchmark": f"{n} videos, Ray, 1 worker", "value": one.seconds, "unit": "s",
         "ratio_vs_baseline": one.seconds / loop.seconds, "note": "vs the plain loop: Ray's overhead"},
        {"benchmark": f"{n} videos, Ray, 2 workers", "value": two.seconds, "unit": "s",
         "ratio_vs_baseline": one.seconds / two.seconds, "note": "ratio: speed-up against 1 worker (same run)"},
        {"benchmark": "peak memory per worker (2 workers)", "value": max(peaks.values(), default=0.0),
         "unit": "MiB", "note": f"{len(peaks)} worker processes; largest peak RSS"},
        {"benchmark": "1 video, Ray (1 worker) vs plain loop", "value": small_ray.seconds, "unit": "s",
         "ratio_vs_baseline": small_ray.seconds / small.seconds,
         "note": f"small batch: Ray start-up dominates (loop {small.seconds:.1f} s)"},
    ]
