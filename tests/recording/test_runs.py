"""Checking recordings and recovering the recording of a run killed with SIGKILL."""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from mcap.reader import make_reader

from wecook_core.errors import InputError
from wecook_core.execution.schedule.observer import RunEvent
from wecook_core.recording.check import check_recording, recover_recording
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import McapRecorder

CHILD = """
import sys
from wecook_core.recording.writer import McapRecorder
from wecook_core.recording.synthetic_run import synthetic_run

def said(n):
    print(f"flushed {n}", flush=True)

rec = McapRecorder(sys.argv[1], flush_every_s=0.2, on_flush=said)
synthetic_run(rec, actions=1000, seconds_per_action=1.0, state_hz=30, wall_per_sim=0.5)
print("finished", flush=True)
"""


def recorded(path: Path, **kwargs: object) -> Path:
    synthetic_run(McapRecorder(path, time_origin_ns=0), actions=3, seconds_per_action=0.5, **kwargs)  # type: ignore[arg-type]
    return path


def test_a_finished_run_passes(tmp_path: Path) -> None:
    report = check_recording(recorded(tmp_path / "ok.mcap", fail=("a2",)))
    assert report.problems == ()
    assert report.ok
    assert report.actions == {"a1": "done", "a2": "failed: synthetic failure", "a3": "done"}
    assert report.messages["/joint_states"] == report.messages["/tf"] > 0  # one message for both arms
    assert report.attachments == ("plan.yaml",) and "seed" in report.metadata["wecook"]
    assert report.duration_s == pytest.approx(1.5, abs=0.05)


def test_event_sequence_problems_are_found(tmp_path: Path) -> None:
    path = tmp_path / "bad.mcap"
    with McapRecorder(path, time_origin_ns=0) as rec:
        synthetic_run(rec, actions=1, seconds_per_action=0.2, end=False)
        rec.on_event(5.0, RunEvent("action_start", "a7", agent="P1"))
        rec.on_event(5.1, RunEvent("action_end", "a9", agent="P2"))
        rec.on_event(4.0, RunEvent("run_end"))
        rec.on_event(5.2, RunEvent("wait", "a7"))
    problems = check_recording(path).problems
    assert any("a9 ends without having started" in p for p in problems), problems
    assert any("a7 started but never ended" in p for p in problems), problems
    assert any("run_end is not the last event" in p for p in problems), problems
    assert any("/plan/events: log time goes back" in p for p in problems), problems


def test_missing_topics_and_corruption_are_found(tmp_path: Path) -> None:
    path = tmp_path / "bare.mcap"
    with McapRecorder(path, time_origin_ns=0) as rec:
        rec.on_start((), "wecook_plan: 1\n", 0, {})
        rec.on_event(0.0, RunEvent("run_end"))
    problems = check_recording(path).problems
    assert "/tf: no messages" in problems and "/joint_states: no messages" in problems
    good = recorded(tmp_path / "good.mcap", state_hz=5)
    data = bytearray(good.read_bytes())
    middle = len(data) // 3
    data[middle:middle + 64] = bytes(64)  # zero some bytes inside a chunk
    broken = tmp_path / "broken.mcap"
    broken.write_bytes(bytes(data))
    report = check_recording(broken)
    assert not report.ok and any("unreadable after byte" in p for p in report.problems), report.problems
    with pytest.raises(InputError, match="no such recording"):
        check_recording(tmp_path / "missing.mcap")
    junk = tmp_path / "junk.mcap"
    junk.write_text("hello, world\n")
    assert check_recording(junk).problems[0].startswith("not an MCAP file")
    assert len(check_recording(junk).problems) == 1


@pytest.mark.slow
def test_recovering_a_finished_file_keeps_everything(tmp_path: Path) -> None:
    source = recorded(tmp_path / "ok.mcap")
    report = recover_recording(source, tmp_path / "copy.mcap")
    assert report.complete and report.closed_actions == ()
    assert report.attachments == 1 and report.metadata == 1
    original = check_recording(source)
    assert report.messages == original.messages
    assert check_recording(tmp_path / "copy.mcap").ok


def test_truncated_file_recovers_whole_chunks(tmp_path: Path) -> None:
    path = tmp_path / "cut.mcap"
    rec = McapRecorder(path, flush_every_s=3600, time_origin_ns=0)
    synthetic_run(rec, actions=2, seconds_per_action=0.5, end=False)
    rec.flush()
    flushed = rec.flushed_messages
    before = path.stat().st_size
    rec.on_event(2.0, RunEvent("action_start", "a3", agent="P1"))
    rec.flush()
    after = path.stat().st_size
    with open(path, "r+b") as f:  # a torn write: half of the last chunk made it to disk
        f.truncate((before + after) // 2)
    report = recover_recording(path, tmp_path / "out.mcap")
    assert not report.complete and report.stopped != "end of file"
    assert report.total == flushed + 1  # plus the run_end that recovery adds
    assert check_recording(tmp_path / "out.mcap").ok


@pytest.mark.slow
def test_sigkilled_run_is_recovered_up_to_the_last_flush(tmp_path: Path) -> None:
    path = tmp_path / "killed.mcap"
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path)], stdout=subprocess.PIPE, text=True,
                             cwd=Path(__file__).resolve().parents[2])
    assert child.stdout is not None
    flushed: list[int] = []
    deadline = time.monotonic() + 30
    try:
        while len(flushed) < 4 and time.monotonic() < deadline:
            ready, _, _ = select.select([child.stdout], [], [], 1.0)
            if ready:
                line = child.stdout.readline()
                assert line.startswith("flushed"), line
                flushed.append(int(line.split()[1]))
    finally:
        os.kill(child.pid, signal.SIGKILL)
        child.wait()
    assert child.returncode == -signal.SIGKILL
    assert len(flushed) == 4, "the child did not flush in time"
    assert flushed[-1] > flushed[0] > 0
    killed = check_recording(path)
    assert not killed.ok and any("no footer" in p for p in killed.problems)
    with open(path, "rb") as f, pytest.raises(Exception):  # noqa: B017 (the seeking reader rejects it)
        make_reader(f).get_summary()
    out = tmp_path / "recovered.mcap"
    report = recover_recording(path, out)
    assert not report.complete
    assert report.total >= flushed[-1]
    assert report.attachments == 1 and report.metadata == 1
    check = check_recording(out)
    assert check.ok, check.problems
    assert sum(check.messages.values()) == report.total
    interrupted = [a for a, status in check.actions.items() if status.startswith("failed: run interrupted")]
    assert list(report.closed_actions) == interrupted
    with open(out, "rb") as f:
        events = [json.loads(m.data) for _, c, m in make_reader(f).iter_messages(topics=["/plan/events"])]
    assert events[-1]["kind"] == "run_end" and events[-1]["data"] == {"recovered": True}


def test_a_skipped_action_fails_without_starting(tmp_path: Path) -> None:
    path = tmp_path / "skip.mcap"
    with McapRecorder(path, time_origin_ns=0) as rec:
        synthetic_run(rec, actions=1, seconds_per_action=0.2, fail=("a1",), end=False)
        rec.on_event(1.0, RunEvent("action_failed", "a2", agent="P2", detail="skipped: needs a1, which failed"))
        rec.on_event(1.0, RunEvent("run_end"))
    report = check_recording(path)
    assert report.ok, report.problems
    assert report.actions == {"a1": "failed: synthetic failure", "a2": "failed: skipped: needs a1, which failed"}
