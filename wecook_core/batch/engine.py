"""Running a batch: one task per video and stage, on Ray or in this process.

On Ray (``engine="ray"``), ``ray.init()`` starts an embedded local cluster with ``workers`` CPUs (or joins
``address``); every stage is one remote task declaring its CPU and memory, submitted when the video's previous
stage has finished, so the videos flow through the stages independently and a failed video stops only its own
later stages. A worker process keeps what it loaded (the knowledge tables, PyBullet, a hand detector) for the
next task it runs. ``engine="local"`` runs the same tasks one after another in this process: the baseline the
benchmark compares against, and the fallback where Ray is not installed.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from wecook_core.batch.manifest import BatchItem
from wecook_core.batch.stages import StageOptions, StageResult, run_stage, stages_for
from wecook_core.errors import InputError

GIB = 1 << 30
MEMORY: dict[str, float] = {"hands": 1.5, "import": 1.0, "analyze": 1.0, "export": 0.5, "execute": 1.5}
"""GiB of memory each stage's task declares to Ray (it schedules no more at once than fit)."""


@dataclass(frozen=True)
class Progress:
    """How far a batch is, after each finished task."""

    videos: int
    done: int
    """Videos whose every stage is done (or cached)."""
    failed: int
    running: int
    """Tasks submitted and not yet finished."""
    elapsed: float
    """Seconds since the batch began."""
    last: StageResult | None = None

    @property
    def eta(self) -> float | None:
        """Seconds left at the pace so far (None before the first video is finished)."""
        finished = self.done + self.failed
        if not finished or finished >= self.videos:
            return None if not finished else 0.0
        return self.elapsed / finished * (self.videos - finished)


@dataclass(frozen=True)
class BatchRun:
    """Every stage result of a batch, per video in manifest order."""

    items: tuple[BatchItem, ...]
    results: dict[str, tuple[StageResult, ...]] = field(default_factory=dict)
    seconds: float = 0.0
    engine: str = "local"
    workers: int = 1


def run_batch(items: Sequence[BatchItem], stages: Sequence[str], root: str | Path, *,
              options: StageOptions | None = None, engine: Literal["ray", "local"] = "ray",
              workers: int | None = None, address: str | None = None,
              on_progress: Callable[[Progress], None] | None = None) -> BatchRun:
    """Run ``stages`` for every item under the sessions folder ``root``."""
    root = Path(root).resolve()
    root.mkdir(parents=True, exist_ok=True)
    options = options or StageOptions()
    plans = {item.name: stages_for(item, stages) for item in items}
    began = time.perf_counter()
    results: dict[str, list[StageResult]] = {item.name: [] for item in items}
    by_name = {item.name: item for item in items}

    def report(last: StageResult | None, running: int) -> None:
        if on_progress is None:
            return
        done = sum(1 for n, r in results.items() if len(r) == len(plans[n]) and all(_ok(x) for x in r))
        failed = sum(1 for r in results.values() if any(x.status == "failed" for x in r))
        on_progress(Progress(len(items), done, failed, running, time.perf_counter() - began, last))

    def finish(result: StageResult) -> str | None:
        """Record ``result``; the video's next stage, or None (all done, or a failure skips the rest)."""
        mine = results[result.video]
        mine.append(result)
        todo = plans[result.video][len(mine):]
        if result.status == "failed":
            mine.extend(StageResult(result.video, s, "skipped", error=f"{result.stage} failed") for s in todo)
            return None
        return todo[0] if todo else None

    report(None, 0)
    if engine == "local":
        for item in items:
            stage = plans[item.name][0] if plans[item.name] else None
            while stage is not None:
                result = run_stage(item, stage, root, options)
                stage = finish(result)
                report(result, 0)
        count = 1
    elif engine == "ray":
        count = _run_on_ray(items, plans, root, options, workers, address, finish, report, by_name)
    else:
        raise InputError(None, f"unknown engine {engine!r} (ray or local)")
    return BatchRun(tuple(items), {k: tuple(v) for k, v in results.items()}, time.perf_counter() - began,
                    engine, count)


def _ok(result: StageResult) -> bool:
    return result.status in ("done", "cached")


def _run_on_ray(items: Sequence[BatchItem], plans: dict[str, tuple[str, ...]], root: Path, options: StageOptions,
                workers: int | None, address: str | None, finish: Callable[[StageResult], str | None],
                report: Callable[[StageResult | None, int], None], by_name: dict[str, BatchItem]) -> int:
    try:
        import ray
    except ImportError:
        raise InputError(None, "Ray is not installed: pip install 'wecook[batch]', or use --engine local") from None
    started_here = not ray.is_initialized()
    if started_here:
        kwargs: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False, "logging_level": "ERROR",
                                  "configure_logging": False}
        if address is None:
            import os

            kwargs["num_cpus"] = workers or os.cpu_count() or 1
            kwargs["object_store_memory"] = 80 * (1 << 20)
        ray.init(address=address, **kwargs)
    try:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        limit = max(1, workers or cpus)
        task = ray.remote(max_retries=0)(run_stage)
        pending: dict[Any, tuple[str, str]] = {}
        queue: deque[tuple[BatchItem, str]] = deque((item, plans[item.name][0]) for item in items
                                                    if plans[item.name])

        def fill() -> None:
            while queue and len(pending) < limit:
                item, stage = queue.popleft()
                ref = task.options(num_cpus=1, memory=int(MEMORY.get(stage, 1.0) * GIB),
                                   name=f"{item.name}:{stage}").remote(item, stage, root, options)
                pending[ref] = (item.name, stage)

        fill()
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                name, stage = pending.pop(ref)
                try:
                    result: StageResult = ray.get(ref)
                except Exception as error:  # the worker died (out of memory, killed)
                    result = StageResult(name, stage, "failed", error=f"worker lost: {type(error).__name__}")
                nxt = finish(result)
                if nxt is not None:
                    queue.appendleft((by_name[name], nxt))  # finish a started video before starting another
                fill()
                report(result, len(pending))
        return min(limit, cpus)
    finally:
        if started_here:
            ray.shutdown()
