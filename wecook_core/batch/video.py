"""One video's stages, one after another in one process: the unit of work of a batch (one Ray task per video).

:func:`run_video` yields a :class:`StageStarted` before each stage and its :class:`StageResult` after it, so
the driver can show which stage each video is in while the task runs (on Ray the generator streams each event
back as it is yielded). A failed stage ends the video: its later stages are yielded ``skipped``. The stages
share a :class:`~wecook_core.batch.stages.Carry` (input digests, the analysis) and whatever the process
already loaded (the knowledge tables, a hand detector), so a worker pays for those once, not once per video.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from wecook_core.batch.manifest import BatchItem
from wecook_core.batch.stages import Carry, StageOptions, StageResult, run_stage


@dataclass(frozen=True)
class StageStarted:
    """A stage of a video has begun."""

    video: str
    stage: str
    index: int
    """Its place among the video's stages, from 0."""
    stages: tuple[str, ...]
    """Every stage the video runs, in order."""
    started: float
    """Wall clock (seconds since the epoch)."""
    pid: int = 0
    node: str = ""


VideoEvent = StageStarted | StageResult


def run_video(item: BatchItem, stages: Sequence[str], root: Path, options: StageOptions) -> Iterator[VideoEvent]:
    """Run ``stages`` (already ordered, see :func:`~wecook_core.batch.stages.stages_for`) for ``item``."""
    stages = tuple(stages)
    carry = Carry()
    for index, stage in enumerate(stages):
        yield StageStarted(item.name, stage, index, stages, time.time(), os.getpid())
        result = run_stage(item, stage, root, options, carry)
        yield result
        if result.status == "failed":
            for later in stages[index + 1:]:
                yield StageResult(item.name, later, "skipped", error=f"{stage} failed")
            return
