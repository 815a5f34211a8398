"""recorded_run: the one lifecycle of a recording (staged, run, settled), with the executor replaced by a
synthetic run so that each way a run can end is reached without a simulation."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import wecook_core.execution.run as executor
from wecook_core.errors import InputError
from wecook_core.execution.schedule.executor import ActionResult, RunResult
from wecook_core.execution.schedule.observer import RunEvent, RunObserver
from wecook_core.plan import load_plan
from wecook_core.recording.check import check_recording
from wecook_core.recording.run import recorded_run
from wecook_core.recording.synthetic_run import synthetic_run

PLAN = """\
wecook_plan: 1
agents:
- {pid: P1, robot: franka_panda/panda.urdf, base: {position: [-0.5, 0.0, 0.0], yaw: 0.0}}
- {pid: P2, robot: franka_panda/panda.urdf, base: {position: [0.5, 0.0, 0.0], yaw: 3.14159}}
scene:
  table: {size: [1.0, 0.8], height: 0.0}
  objects:
  - {name: knife, category: tool, shape: box, size: [0.2, 0.03, 0.025], pose: {x: 0.0, y: 0.15, yaw: 0.0}}
  - {name: tomato, category: ingredient, shape: sphere, size: [0.05, 0.05, 0.05], pose: {x: 0.0, y: 0.0}}
  containing: []
actions:
- {id: a1, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], location: null, after: []}
- {id: a2, pid: [P2], verb: cut, tool: knife, ingredients: [tomato], location: null, after: [a1]}
"""
OLD = b"the user's recording, not to be lost\n"


def _executor(monkeypatch: pytest.MonkeyPatch, *, end: bool = True, then: BaseException | None = None,
              before: BaseException | None = None) -> list[dict[str, Any]]:
    """execute_plan replaced by a synthetic run of two actions (``end=False``: stopped once the second has
    started, then ``then`` raised); ``before``: raised before anything is reported. Returns the keywords of
    each call."""
    calls: list[dict[str, Any]] = []

    def run(plan: object, observer: RunObserver, **kwargs: Any) -> RunResult:
        calls.append(kwargs)
        if before is not None:
            raise before
        synthetic_run(observer, actions=2 if end else 1, seconds_per_action=0.2, end=end)
        if not end:
            observer.on_event(0.3, RunEvent("action_start", "a2", agent="P2"))
        if then is not None:
            raise then
        return RunResult([ActionResult("a1", "done"), ActionResult("a2", "done")], 0.4, 0.01, 0)

    monkeypatch.setattr(executor, "execute_plan", run)
    return calls


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def _plan() -> Any:
    return load_plan(PLAN)


def test_a_run_replacing_a_recording_settles_it_only_at_the_end(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    record = tmp_path / "run.mcap"
    record.write_bytes(OLD)
    seen: list[bytes] = []
    calls = _executor(monkeypatch)
    told: list[str] = []
    done = recorded_run(_plan(), record, replace=True, over=lambda: seen.append(record.read_bytes()),
                        say=told.append, seed=4)
    assert seen == [OLD]  # the run was over, the old file still whole
    assert calls == [{"seed": 4}]
    assert done.recording == record and [a.status for a in done.result.actions] == ["done", "done"]
    assert check_recording(record).ok
    assert _leftovers(tmp_path) == ["run.layout.json", "run.mcap"]  # no hidden file left
    assert told == [f"recording: {record}"]


def test_the_old_recording_survives_a_run_that_crashes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    record = tmp_path / "run.mcap"
    record.write_bytes(OLD)
    _executor(monkeypatch, end=False, then=RuntimeError("the simulator crashed"))
    told: list[str] = []
    with pytest.raises(RuntimeError, match="crashed"):
        recorded_run(_plan(), record, replace=True, say=told.append)
    assert record.read_bytes() == OLD
    assert _leftovers(tmp_path) == ["run.mcap"]  # the half-made replacement and its layout are gone
    assert told == [f"no recording: {record} left as it was"]


def test_a_new_recording_of_a_crashed_run_is_kept_for_recovery(tmp_path: Path,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    record = tmp_path / "run.mcap"
    _executor(monkeypatch, end=False, then=RuntimeError("the simulator crashed"))
    with pytest.raises(RuntimeError):
        recorded_run(_plan(), record)
    report = check_recording(record)  # closed properly, though the story has no end
    assert "a1" in report.actions and not report.ok


def test_a_run_that_never_starts_leaves_no_recording(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for replace in (False, True):
        folder = tmp_path / str(replace)
        folder.mkdir()
        record = folder / "run.mcap"
        if replace:
            record.write_bytes(OLD)
        _executor(monkeypatch, before=InputError(None, "PyBullet cannot load the robot"))
        told: list[str] = []
        with pytest.raises(InputError):
            recorded_run(_plan(), record, replace=replace, say=told.append)
        assert _leftovers(folder) == (["run.mcap"] if replace else [])
        assert not replace or record.read_bytes() == OLD
        assert told == [f"no recording: {record} left as it was" if replace else "no recording"]


def test_an_interrupted_run_closes_its_story_and_keeps_its_recording(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    record = tmp_path / "run.mcap"
    _executor(monkeypatch, end=False, then=KeyboardInterrupt())
    events: list[tuple[str, str | None, str]] = []

    class Watch:
        def __getattr__(self, name: str) -> Callable[..., None]:
            return lambda *args: None

        def on_event(self, t: float, event: Any) -> None:
            events.append((event.kind, event.action_id, event.detail))

    with pytest.raises(KeyboardInterrupt):
        recorded_run(_plan(), record, [Watch()])  # type: ignore[list-item]
    assert events[-1] == ("action_failed", "a2", "interrupted")  # the observers hear it too
    report = check_recording(record)
    assert report.ok, report.problems
    assert report.actions["a2"] == "failed: interrupted" and report.actions["a1"].startswith("done")
    assert _leftovers(tmp_path) == ["run.layout.json", "run.mcap"]


def test_an_interrupted_replacement_keeps_the_previous_recording(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C on ``execute --record F --force`` (issue 28): the finished recording F stays; the interrupted run
    is dropped with its hidden files."""
    record = tmp_path / "run.mcap"
    record.write_bytes(OLD)
    _executor(monkeypatch, end=False, then=KeyboardInterrupt())
    told: list[str] = []
    with pytest.raises(KeyboardInterrupt):
        recorded_run(_plan(), record, replace=True, say=told.append)
    assert record.read_bytes() == OLD
    assert _leftovers(tmp_path) == ["run.mcap"]
    assert told == [f"no recording: {record} left as it was"]


def test_a_replacement_whose_file_cannot_be_finished_leaves_nothing(tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """A full disk while the recording is closed: the old recording stays, no ``.run.mcap.*.part.mcap``."""
    import errno

    from wecook_core.recording.writer import McapRecorder

    record = tmp_path / "run.mcap"
    record.write_bytes(OLD)
    _executor(monkeypatch)

    def full(self: McapRecorder) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(McapRecorder, "close", full)
    with pytest.raises(OSError):
        recorded_run(_plan(), record, replace=True)
    assert record.read_bytes() == OLD
    assert _leftovers(tmp_path) == ["run.mcap"]


def test_a_run_not_recorded_writes_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _executor(monkeypatch)
    done = recorded_run(_plan(), None, seed=1)
    assert done.recording is None and len(done.result.actions) == 2
    assert _leftovers(tmp_path) == []
