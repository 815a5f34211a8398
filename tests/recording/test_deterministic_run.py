"""A run is the plan's, the seed's and the simulated time's alone (issue 28): the same plan and seed recorded
twice, once on a machine made busy by other processes, gives the same messages on every channel."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mcap.reader import make_reader

from wecook_core.recording import writer
from wecook_core.recording.run import recorded_run
from wecook_core.workflows import demo_plan

BUSY = "import time\nend = time.monotonic() + 600\nwhile time.monotonic() < end:\n    pass\n"
"""A process that keeps a core busy (killed when the run ends)."""


def _messages(path: Path) -> list[tuple[str, int, bytes]]:
    with open(path, "rb") as f:
        return [(c.topic, m.log_time, m.data) for _, c, m in make_reader(f).iter_messages()]


@pytest.mark.sim
def test_the_same_plan_and_seed_record_the_same_messages_on_a_busy_machine(tmp_path: Path,
                                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    # the recording's time origin is the wall clock's now (Foxglove shows real dates): fixed here, so that the
    # two recordings can be compared message for message
    monkeypatch.setattr(writer.time, "time_ns", lambda: 1_700_000_000_000_000_000)
    plan = demo_plan()
    quiet = tmp_path / "quiet.mcap"
    quiet.touch()
    first = recorded_run(plan, quiet, seed=3)
    busy = [subprocess.Popen([sys.executable, "-c", BUSY]) for _ in range(2)]
    try:
        loaded = tmp_path / "loaded.mcap"
        loaded.touch()
        second = recorded_run(plan, loaded, seed=3)
    finally:
        for process in busy:
            process.kill()
            process.wait()
    assert [(a.action_id, a.status) for a in first.result.actions] == \
        [(a.action_id, a.status) for a in second.result.actions]
    a, b = _messages(quiet), _messages(loaded)
    topics = sorted({t for t, _, _ in a})
    assert {"/tf", "/joint_states", "/scene", "/plan/events", "/log"} <= set(topics)
    for topic in topics:  # per channel first, to say which one differs
        assert [m for m in a if m[0] == topic] == [m for m in b if m[0] == topic], topic
    assert a == b
