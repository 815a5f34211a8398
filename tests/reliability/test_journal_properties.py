"""The journal, read back after arbitrary damage (random lines, torn tails, deep or huge JSON), never raises:
unreadable lines are warnings, the readable ones are kept, and the next correction still lands."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from contract import keeps_contract, mutated
from hypothesis import given
from hypothesis import strategies as st

from wecook_core.errors import InputError
from wecook_core.formats.fields import MAX_FRAME
from wecook_core.session.journal import Journal, read_journal

GOOD = (
    '{"seq":1,"time":"2026-01-01T00:00:00.000000Z","op":"split","frame":40}\n'
    '{"seq":2,"time":"2026-01-01T00:00:01.000000Z","op":"set_verb","segment":0,"hand":"RH_P1","verb":"cut"}\n'
    '{"seq":3,"time":"2026-01-01T00:00:02.000000Z","op":"undo","target":2}\n'
)
value = st.one_of(st.none(), st.booleans(), st.integers(-(10**30), 10**30), st.floats(), st.text(max_size=10),
                  st.lists(st.integers(), max_size=3))
line = st.one_of(
    st.binary(max_size=80),
    st.dictionaries(st.sampled_from(["seq", "time", "op", "frame", "segment", "hand", "verb", "object", "targets",
                                     "status", "target", "x"]), value, max_size=6).map(json.dumps),
    st.builds(lambda op, seq, frame: json.dumps({"seq": seq, "op": op, "frame": frame}),
              st.sampled_from(["split", "merge", "undo", "redo", "set_status", "nope"]),
              st.integers(-2, 10**20), st.integers(-2, 10**20)),
    st.just("[" * 5000 + "]" * 5000), st.just('{"seq": ' + "9" * 5000 + "}"),
)


def _check(path: Path) -> None:
    entries, warnings, _ = read_journal(path)
    assert all(w.count("\n") == 0 for w in warnings)
    seqs = [e.seq for e in entries]
    assert len(seqs) == len(set(seqs)) and all(s >= 1 for s in seqs)
    for entry in entries:
        for key in ("frame", "segment"):
            if key in entry.fields:
                assert 0 <= entry.fields[key] <= MAX_FRAME
    journal = Journal(path)
    before = len(journal.entries)
    journal.record({"op": "split", "frame": 7})
    assert len(Journal(path).entries) == before + 1  # a damaged journal still takes (and keeps) a correction


@given(lines=st.lists(line, max_size=8), tail=st.binary(max_size=20))
def test_random_lines(tmp_path: Path, lines: list[str | bytes], tail: bytes) -> None:
    path = tmp_path / "journal.jsonl"
    path.write_bytes(b"".join((x if isinstance(x, bytes) else x.encode()).replace(b"\n", b" ") + b"\n"
                              for x in lines) + tail)
    _check(path)


@given(data=mutated(GOOD.encode()))
def test_mutated_journal(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "journal.jsonl"
    path.write_bytes(data)
    _check(path)


@pytest.mark.parametrize("kind", ["folder", "fifo", "dangling"])
def test_journal_that_is_not_a_file(tmp_path: Path, kind: str) -> None:
    import os

    path = tmp_path / "journal.jsonl"
    if kind == "folder":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)
    else:
        path.symlink_to(tmp_path / "gone")
    error = keeps_contract(lambda: Journal(path), path)
    assert isinstance(error, InputError)
