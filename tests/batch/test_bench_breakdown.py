"""bench.batch's account of a run's wall time: every second of the worker slots between the first stage's start
and the last one's end is a stage's, idle while videos still waited, or idle at the end."""

from __future__ import annotations

from bench.batch import breakdown
from wecook_core.batch.engine import BatchRun
from wecook_core.batch.stages import StageResult


def _result(video: str, stage: str, started: float, seconds: float, pid: int) -> StageResult:
    return StageResult(video, stage, "done", seconds=seconds, pid=pid, started=started)


def test_two_slots_idle_between_and_after_videos_are_told_apart() -> None:
    began = 100.0
    results = {  # two slots: a and c on one, b on the other; a gap of 0.5 s before c; b idles from 106
        "a": (_result("a", "import", 102.0, 1.0, 1), _result("a", "analyze", 103.0, 2.0, 1)),
        "b": (_result("b", "import", 102.0, 4.0, 2),),
        "c": (_result("c", "import", 105.5, 3.0, 1),),
    }
    run = BatchRun((), results, seconds=9.5, engine="ray", workers=2)
    b = breakdown(run, began)
    assert b["startup"] == 2.0 and b["stages"] == 10.0 and b["shutdown"] == 1.0
    assert abs(b["overhead"] - 0.5) < 1e-9  # slot 1 idle 105.0-105.5 while c waited
    assert abs(b["tail"] - 2.5) < 1e-9  # slot 2 idle 106.0-108.5 once c had begun
    assert abs(2 * (108.5 - 102.0) - (b["stages"] + b["overhead"] + b["tail"])) < 1e-9


def test_one_slot_taken_in_turns_by_two_processes_has_no_idle_time() -> None:
    """A 1-worker run on a 2-CPU cluster: Ray gives the videos to either process; the slot is never idle."""
    results = {"a": (_result("a", "import", 1.0, 2.0, 1),), "b": (_result("b", "import", 3.0, 2.0, 2),)}
    b = breakdown(BatchRun((), results, seconds=5.0, engine="ray", workers=1), 0.0)
    assert b["overhead"] == 0.0 and b["tail"] == 0.0 and b["startup"] == 1.0
