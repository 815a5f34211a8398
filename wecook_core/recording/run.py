"""One recorded run: the recording staged, the plan executed with the observers, the recording settled.

:func:`recorded_run` is the one lifecycle of a recording, used by ``wecook execute`` (and so the workbench, which
runs ``wecook execute --jsonl``) and by the batch's execute stage. A run that replaces an existing recording
writes to a hidden file beside it (:func:`staging_path`) and moves it onto the old one only when the run has
ended (:func:`settle_recording`): the user's old file is never lost, and no temporary file is left behind.

What is kept, by how the run ended:

- it ended, or was interrupted (Ctrl-C, SIGTERM) with the running actions failed ``interrupted``: kept, except
  that a replacement is kept only when its run finished (an interrupted one leaves the old recording whole);
- it never started (an :class:`~wecook_core.errors.InputError`, e.g. a robot PyBullet cannot load): removed;
- it crashed midway: a new recording is kept (``wecook runs recover`` reads it), a replacement is removed.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from wecook_core.errors import InputError
from wecook_core.execution.schedule.fanout import FanOut
from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, RunObserver, Vec3
from wecook_core.files import fsync_dir
from wecook_core.recording.writer import McapRecorder, layout_path

if TYPE_CHECKING:
    from wecook_core.execution.schedule.executor import RunResult
    from wecook_core.plan import Plan

INTERRUPTED = "interrupted"
"""The detail of the events closing the story of a run stopped by Ctrl-C or SIGTERM."""
PRIVATE_MODE = 0o666
"""The mode a file created the ordinary way gets, before the umask (``mkstemp`` makes its file private)."""


@dataclass(frozen=True)
class RecordedRun:
    """What :func:`recorded_run` did."""

    result: RunResult
    recording: Path | None
    """The recording of the run (kept), or None when it was not recorded."""


def staging_path(target: Path) -> Path:
    """Where a run replacing the recording ``target`` is written until it ends: a new hidden file beside it, so
    that the old recording stays whole until the new one replaces it (:func:`settle_recording`)."""
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part.mcap", dir=target.parent)
    os.close(fd)
    return Path(name)


def settle_recording(written: Path, target: Path, *, keep: bool) -> None:
    """The end of a recording written to ``written`` for ``target``: with ``keep``, made durable and moved onto
    ``target`` (replacing what was there in one step); else removed (``target`` is left as it was)."""
    if written == target and keep:
        return
    if not keep:  # a new file of this run, or the hidden one beside the target
        written.unlink(missing_ok=True)
        layout_path(written).unlink(missing_ok=True)
        return
    with written.open("rb") as handle:
        os.fsync(handle.fileno())
    os.chmod(written, PRIVATE_MODE & ~_umask())
    os.replace(written, target)
    if layout_path(written).exists():
        os.replace(layout_path(written), layout_path(target))
    fsync_dir(target.parent)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


class _Running:
    """A RunObserver keeping what a story closed on interruption needs: the actions running, the time now."""

    def __init__(self, plan: Plan) -> None:
        self.agents = {a.id: a.pids[0] for a in plan.actions}
        self.running: set[str] = set()
        """Action ids started and not ended."""
        self.time = 0.0

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None:
        pass

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        self.time = t

    def on_event(self, t: float, event: RunEvent) -> None:
        self.time = max(self.time, t)
        if event.action_id is None:
            return
        if event.kind == "action_start":
            self.running.add(event.action_id)
        elif event.kind in ("action_end", "action_failed"):
            self.running.discard(event.action_id)

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None:
        pass

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        pass

    def on_end(self, t: float) -> None:
        self.time = max(self.time, t)

    def close_story(self, recorder: RunObserver | None, observers: Sequence[RunObserver]) -> None:
        """Each running action failed ``interrupted`` (told to the recorder and the observers), then the run's
        end (told to the recorder), in the plan's order."""
        for aid in [a for a in self.agents if a in self.running]:
            event = RunEvent("action_failed", aid, agent=self.agents[aid], detail=INTERRUPTED)
            for observer in (*((recorder,) if recorder is not None else ()), *observers):
                observer.on_event(self.time, event)
        if recorder is not None:
            recorder.on_event(self.time, RunEvent("run_end", detail=INTERRUPTED))


def _with_camera(observer: RunObserver, hz: float) -> RunObserver:
    """The observer wrapped by a camera rendering at ``hz`` images per simulated second (0: not wrapped)."""
    if not hz:
        return observer
    from wecook_core.recording.camera import CameraObserver

    return CameraObserver(observer, hz)


def recorded_run(plan: Plan, record: Path | None, observers: Sequence[RunObserver] = (), *, replace: bool = False,
                 camera_hz: float = 0.0, over: Callable[[], None] | None = None,
                 say: Callable[[str], None] | None = None, **run: Any) -> RecordedRun:
    """Execute ``plan`` (:func:`~wecook_core.execution.run.execute_plan` with the keywords ``run``) reported to
    ``observers``, recorded at ``record`` unless it is None.

    ``record`` is the recording's path, claimed by the caller (created empty, or checked free); with
    ``replace`` it holds a recording to be replaced, which stays whole until the run has ended (the new one is
    written beside it meanwhile). ``camera_hz``: a camera view rendered at that many images per simulated
    second (0: none). ``over`` is called first when the run is over, however it ended (a progress display
    stopped, say), then the recording is closed and settled and its fate told to ``say``.
    An interruption (KeyboardInterrupt) closes the story (running actions failed ``interrupted``), keeps the
    recording and propagates; so does every other exception, with the recording kept or removed as the module
    says.
    """
    from wecook_core.execution import run as executor  # looked up at call time (tests watch the executor)

    recorder: McapRecorder | None = None
    written: Path | None = None
    if record is not None:
        written = staging_path(record) if replace else record
        try:
            recorder = McapRecorder(written)
        except BaseException:
            settle_recording(written, record, keep=written == record)  # the hidden file is not left behind
            raise
    running = _Running(plan)
    everyone = FanOut(*((recorder,) if recorder is not None else ()), *observers, running)
    result: RunResult | None = None
    ended = unstarted = False
    """The run ended (or was stopped) with its story told: its recording is kept; it never started: it is not."""
    try:
        result = executor.execute_plan(plan, _with_camera(everyone, camera_hz), **run)
    except KeyboardInterrupt:
        running.close_story(recorder, observers)
        ended = True
        raise
    except InputError:
        unstarted = True
        raise
    except OSError as error:  # the recording's writes (a full disk): name the file the user knows
        _name(error, record)
        raise
    finally:
        if over is not None:
            over()
        if recorder is not None and written is not None and record is not None:
            closed = False
            try:
                recorder.close()
                closed = True
            except OSError as error:
                _name(error, record)
                raise
            finally:
                # A replacement is kept only when its run finished and its file is complete: an interrupted or
                # failed one leaves the old recording as it was. A new recording is kept as the module says.
                finished = result is not None and closed
                ended = finished if written != record else ended or result is not None
                settle_recording(written, record, keep=ended or (written == record and not unstarted))
                _tell(say, record, ended=ended, replaced=written != record, unstarted=unstarted)
    return RecordedRun(result, record)


def _name(error: OSError, record: Path | None) -> None:
    """Name the recording in an OS error of its writes (which name no file)."""
    if record is not None and error.errno is not None and error.filename is None:
        error.filename = str(record)


def _tell(say: Callable[[str], None] | None, record: Path, *, ended: bool, replaced: bool, unstarted: bool) -> None:
    if say is None:
        return
    if ended:
        say(f"recording: {record}")
    elif replaced:
        say(f"no recording: {record} left as it was")
    elif unstarted:
        say("no recording")
