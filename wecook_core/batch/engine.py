"""Running a batch: one task per video, its stages in-process, on Ray or in this process.

On Ray (``engine="ray"``), ``ray.init()`` starts an embedded local cluster with ``workers`` CPUs, or joins a
running one at ``address`` (``auto``, ``HOST:PORT``, or ``ray://HOST:PORT`` through Ray Client); the videos'
files must then lie where every node reads them at the same path (shared storage), as must the sessions
folder. Each video is one remote task declaring one CPU and the memory of its largest stage; it runs the
video's stages one after another (:func:`~wecook_core.batch.video.run_video`) and streams an event back as each
stage begins and ends (a Ray generator task; through Ray Client, which has none, at the video's end), so
progress is live and a finished video is reported (and
``batch.json`` rewritten, through ``on_video``) the moment it ends. At most ``workers`` videos are in flight;
the largest videos go first, so the last ones to finish are short. A worker process keeps what it loaded (the
knowledge tables, a hand detector, the imported modules) for every next video it runs.

``engine="local"`` runs the same video tasks one after another in this process: the baseline the benchmark
compares against, and the fallback where Ray is not installed.

A batch holds the sessions folder's lock (:mod:`~wecook_core.batch.lock`) from start to end. Interrupted (Ctrl-C,
or SIGTERM turned into a KeyboardInterrupt by the caller), it cancels the running tasks (each gets a
KeyboardInterrupt, so its stage's temporary files are removed), shuts its Ray down and re-raises; the videos
finished so far keep their stamps and are in ``batch.json``.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

from wecook_core.batch.lock import batch_lock
from wecook_core.batch.manifest import BatchItem
from wecook_core.batch.progress import Progress, Tracker
from wecook_core.batch.stages import StageOptions, StageResult, stages_for
from wecook_core.batch.video import VideoEvent, run_video
from wecook_core.errors import InputError

GIB = 1 << 30
MEMORY: dict[str, float] = {"hands": 1.5, "import": 1.0, "analyze": 1.0, "export": 0.5, "execute": 1.5}
"""GiB of memory each stage needs; a video's task declares its largest stage's to Ray (it schedules no more
at once than fit)."""
CANCEL_WAIT_S = 10.0
"""Seconds an interrupted batch waits for its cancelled tasks to clean up before shutting Ray down."""


@dataclass(frozen=True)
class BatchRun:
    """Every stage result of a batch, per video in manifest order (a video not finished yet has none)."""

    items: tuple[BatchItem, ...]
    results: dict[str, tuple[StageResult, ...]] = field(default_factory=dict)
    seconds: float = 0.0
    engine: str = "local"
    workers: int = 1


def run_batch(items: Sequence[BatchItem], stages: Sequence[str], root: str | Path, *,
              options: StageOptions | None = None, engine: Literal["ray", "local"] = "ray",
              workers: int | None = None, address: str | None = None,
              on_progress: Callable[[Progress], None] | None = None,
              on_video: Callable[[BatchRun], None] | None = None,
              manifest: str | Path | None = None, wait: bool = False) -> BatchRun:
    """Run ``stages`` for every item under the sessions folder ``root``. ``on_video`` gets the run so far each
    time a video finishes, and the whole run at the end; ``manifest`` names the batch in its lock; ``wait``:
    wait for another batch holding the folder instead of refusing."""
    if engine not in ("ray", "local"):
        raise InputError(None, f"unknown engine {engine!r} (ray or local)")
    root = Path(root).resolve()
    root.mkdir(parents=True, exist_ok=True)
    options = options or StageOptions()
    items = tuple(items)
    plans = {item.name: stages_for(item, stages) for item in items}
    with batch_lock(root, manifest, wait=wait):
        tracker = Tracker(plans, workers or 1)
        count = 1

        def snapshot() -> BatchRun:
            finished = {n: tuple(r) for n, r in tracker.results.items() if tracker.finished(n)}
            return BatchRun(items, finished, time.perf_counter() - tracker.began, engine, count)

        def take(event: VideoEvent) -> bool:
            finished = tracker.add(event)
            if on_progress is not None:
                on_progress(tracker.progress(event if isinstance(event, StageResult) else None))
            if finished and on_video is not None:
                on_video(snapshot())
            return finished

        def started(workers_now: int) -> None:
            nonlocal count
            count = tracker.workers = workers_now

        if on_progress is not None:
            on_progress(tracker.progress())
        try:
            if engine == "local":
                for item in items:
                    for event in run_video(item, plans[item.name], root, options):
                        take(event)
            else:
                _run_on_ray(items, plans, root, options, workers, address, take, tracker, started)
        except BaseException:  # interrupted: the report says what finished, the rest pending
            if on_video is not None:
                with contextlib.suppress(Exception):
                    on_video(snapshot())
            raise
        run = BatchRun(items, {n: tuple(r) for n, r in tracker.results.items()},
                       time.perf_counter() - tracker.began, engine, count)
        if on_video is not None:
            on_video(run)
        return run


def _cost(item: BatchItem) -> int:
    """How long ``item`` may take, roughly: the bytes of its video and boxes (the largest go first)."""
    total = 0
    for path in (item.video, item.objects):
        with contextlib.suppress(OSError):
            total += path.stat().st_size
    return total


def _video_task(item: BatchItem, stages: tuple[str, ...], root: Path,
                options: StageOptions) -> Iterator[VideoEvent]:
    """The Ray task of one video: its events, stamped with the node that ran them."""
    import ray

    node = ray.get_runtime_context().get_node_id()
    for event in run_video(item, stages, root, options):
        yield replace(event, node=node)


def _video_task_whole(item: BatchItem, stages: tuple[str, ...], root: Path,
                      options: StageOptions) -> list[VideoEvent]:
    """The Ray task of one video through Ray Client, which has no generator tasks: its events at its end."""
    return list(_video_task(item, stages, root, options))


def _lost(tracker: Tracker, name: str, error: BaseException | str) -> list[StageResult]:
    """The results of a video whose task died: its current stage failed, the later ones skipped."""
    todo = tracker.plans[name][len(tracker.results[name]):]
    if not todo:
        return []
    why = error if isinstance(error, str) else f"worker lost: {type(error).__name__}"
    return [StageResult(name, todo[0], "failed", error=why)] + [
        StageResult(name, s, "skipped", error=f"{todo[0]} failed") for s in todo[1:]]


@contextlib.contextmanager
def _ray(workers: int | None, address: str | None) -> Iterator[Any]:
    """Ray, initialised for the batch (and shut down after it) unless it already was; the SIGTERM handler of
    the caller is kept (``ray.init`` installs its own, which aborts the process)."""
    try:
        import ray
    except ImportError:
        raise InputError(None, "Ray is not installed: pip install 'wecook[batch]', or use --engine local") from None
    if ray.is_initialized():
        yield ray
        return
    kwargs: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False, "logging_level": "ERROR",
                              "configure_logging": False}
    if address is None:
        kwargs["num_cpus"] = workers or os.cpu_count() or 1
        kwargs["object_store_memory"] = 80 * (1 << 20)
    main = threading.current_thread() is threading.main_thread()
    handler = signal.getsignal(signal.SIGTERM) if main else None
    try:
        ray.init(address=address, **kwargs)
    except (ConnectionError, ValueError, RuntimeError) as error:
        lines = [line.strip() for line in str(error).splitlines() if line.strip()] or [type(error).__name__]
        why = lines[0] if len(lines) == 1 else f"{lines[0].rstrip(':')}: {lines[-1]}"  # a server's traceback: its end
        raise InputError(None, f"cannot join the Ray cluster at {address}: {why}") from None
    finally:
        if main and handler is not None:
            signal.signal(signal.SIGTERM, handler)
    try:
        yield ray
    finally:
        ray.shutdown()


def _run_on_ray(items: Sequence[BatchItem], plans: dict[str, tuple[str, ...]], root: Path, options: StageOptions,
                workers: int | None, address: str | None, take: Callable[[VideoEvent], bool], tracker: Tracker,
                started: Callable[[int], None]) -> None:
    with _ray(workers, address) as ray:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        limit = max(1, min(workers or cpus, cpus))
        started(limit)
        client = address is not None and address.startswith("ray://")
        task = ray.remote(num_cpus=1, max_retries=0)(_video_task_whole if client else _video_task)
        queue: deque[BatchItem] = deque(sorted((i for i in items if plans[i.name]), key=_cost, reverse=True))
        pending: dict[Any, str] = {}

        def fill() -> None:
            while queue and len(pending) < limit:
                item = queue.popleft()
                memory = max(MEMORY.get(s, 1.0) for s in plans[item.name])
                gen = task.options(memory=int(memory * GIB), name=f"wecook:{item.name}").remote(
                    item, plans[item.name], root, options)
                pending[gen] = item.name

        def drop(gen: Any, error: BaseException | str) -> None:
            name = pending.pop(gen)
            for result in _lost(tracker, name, error):
                take(result)

        try:
            fill()
            while pending:
                ready, _ = ray.wait(list(pending), num_returns=1)
                for gen in ready:
                    if client:  # a list of the video's events, at its end
                        try:
                            events = ray.get(gen)
                        except Exception as error:
                            drop(gen, error)
                        else:
                            pending.pop(gen)
                            for event in events:
                                take(event)
                        fill()
                        continue
                    try:
                        event = ray.get(next(gen))
                    except StopIteration:
                        drop(gen, "the task ended before its last stage")
                    except Exception as error:  # the worker died (out of memory, killed)
                        drop(gen, error)
                    else:
                        if take(event):
                            pending.pop(gen)
                    fill()
        except BaseException:
            for gen in pending:
                with contextlib.suppress(Exception):
                    ray.cancel(gen)
            with contextlib.suppress(Exception):
                ray.wait(list(pending), num_returns=len(pending), timeout=CANCEL_WAIT_S)
            raise
