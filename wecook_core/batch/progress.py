"""How far a batch is: the whole batch and each running video (its stage, its ETA).

The driver feeds every event of the videos (:class:`~wecook_core.batch.video.StageStarted`, a
:class:`~wecook_core.batch.stages.StageResult`) to a :class:`Tracker`, which answers a :class:`Progress`.
ETAs come from the mean wall time of each stage over the stages done so far in this batch: a video's ETA is
the mean of its stages still to run less the time already spent in the current one, the batch's is the work
left (every unfinished video's) spread over the workers. Before a stage has been done once, its ETA is None.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

from wecook_core.batch.stages import StageResult
from wecook_core.batch.video import StageStarted, VideoEvent


@dataclass(frozen=True)
class VideoProgress:
    """A running video."""

    video: str
    stage: str
    """The stage it is in."""
    index: int
    """That stage's place among the video's stages, from 0."""
    stages: int
    """How many stages the video runs."""
    elapsed: float
    """Seconds since the video's first stage began."""
    eta: float | None
    """Seconds until its last stage ends, at this batch's mean stage times (None: a stage not timed yet)."""


@dataclass(frozen=True)
class Progress:
    """How far a batch is, after each event."""

    videos: int
    done: int
    """Videos whose every stage is done (or cached)."""
    failed: int
    running: int
    """Videos started and not yet finished."""
    elapsed: float
    """Seconds since the batch began."""
    last: StageResult | None = None
    """The stage result that made this report (None when a stage began)."""
    current: tuple[VideoProgress, ...] = ()
    """Every running video, in the order they started."""
    eta: float | None = None
    """Seconds until the batch ends (0 when it has; None before every stage it needs has been timed)."""


class Tracker:
    """The driver's view of a batch, fed one event at a time."""

    def __init__(self, plans: Mapping[str, Sequence[str]], workers: int) -> None:
        self.plans = {name: tuple(plan) for name, plan in plans.items()}
        self.workers = max(1, workers)
        self.results: dict[str, list[StageResult]] = {name: [] for name in plans}
        self.began = time.perf_counter()
        self._current: dict[str, StageStarted] = {}
        self._first: dict[str, float] = {}
        self._times: dict[str, list[float]] = {}

    def add(self, event: VideoEvent) -> bool:
        """Take one event; True when it finished its video (every stage has a result)."""
        if isinstance(event, StageStarted):
            self._current[event.video] = event
            self._first.setdefault(event.video, event.started)
            return False
        mine = self.results[event.video]
        mine.append(event)
        if event.status == "done":
            self._times.setdefault(event.stage, []).append(event.seconds)
        plan = self.plans[event.video]
        if len(mine) >= len(plan):
            self._current.pop(event.video, None)
            return True
        current = self._current.get(event.video)
        if current is not None:  # on to its next stage (its StageStarted follows at once)
            self._current[event.video] = replace(current, stage=plan[len(mine)], index=len(mine),
                                                 started=time.time())
        return False

    def finished(self, name: str) -> bool:
        return len(self.results[name]) >= len(self.plans[name])

    def _mean(self, stage: str) -> float | None:
        times = self._times.get(stage)
        return sum(times) / len(times) if times else None

    def _left(self, stages: Sequence[str], spent: float) -> float | None:
        means = [self._mean(s) for s in stages]
        if any(m is None for m in means):
            return None
        return max(0.0, sum(m for m in means if m is not None) - spent)

    def progress(self, last: StageResult | None = None) -> Progress:
        now = time.time()
        done = sum(1 for n, r in self.results.items() if self.finished(n)
                   and all(x.status in ("done", "cached") for x in r))
        failed = sum(1 for r in self.results.values() if any(x.status == "failed" for x in r))
        current = []
        for name, started in self._current.items():
            eta = self._left(started.stages[started.index:], now - started.started)
            current.append(VideoProgress(name, started.stage, started.index, len(started.stages),
                                         now - self._first.get(name, started.started), eta))
        work: float | None = sum(v.eta for v in current if v.eta is not None)
        if any(v.eta is None for v in current):
            work = None
        for name, plan in self.plans.items():
            if work is None:
                break
            if name not in self._current and not self.finished(name):
                left = self._left(plan, 0.0)
                work = None if left is None else work + left
        eta = None if work is None else work / self.workers
        return Progress(len(self.plans), done, failed, len(current), time.perf_counter() - self.began, last,
                        tuple(current), eta)
