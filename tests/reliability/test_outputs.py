"""Nothing the user has is overwritten: outputs that are folders or exist are refused (unless --force), files are
written atomically, two runs never share a recording; recovery keeps every intact chunk of a damaged recording
and says what was lost."""

from __future__ import annotations

import datetime as dt
from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_core.files import create_new, read_text, write_atomic
from wecook_core.plan import load_plan, write_plan
from wecook_core.recording.check import check_recording, recover_recording
from wecook_core.recording.recover import salvage
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import McapRecorder
from wecook_core.workflows import export_session_plan
from wecook_tui.cli import main
from wecook_tui.commands.execute import recording_path

PRECIOUS = "the user's own file\n"


@pytest.fixture
def precious(tmp_path: Path) -> Path:
    path = tmp_path / "mine.yaml"
    path.write_text(PRECIOUS)
    return path


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("rec") / "run.mcap"
    synthetic_run(McapRecorder(path, time_origin_ns=0, flush_every_s=0.0), actions=4, seconds_per_action=1.0)
    return path


def _one_line_exit_2(argv: list[str], named: Path, capsys: pytest.CaptureFixture[str]) -> str:
    assert main(argv) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and str(named) in lines[0], lines
    return lines[0]


def test_write_atomic_never_overwrites_unless_asked(precious: Path) -> None:
    with pytest.raises(InputError, match="exists; not overwritten"):
        write_atomic(precious, "new\n")
    assert precious.read_text() == PRECIOUS

    def broken(handle: object) -> None:
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_atomic(precious, broken, replace=True)
    assert precious.read_text() == PRECIOUS  # a failed write leaves the old file whole
    write_atomic(precious, "new\n", replace=True)
    assert precious.read_text() == "new\n"
    assert [p.name for p in precious.parent.iterdir()] == [precious.name]  # no temporary file left
    with pytest.raises(InputError, match="is a folder"):
        write_atomic(precious.parent, "x")


def test_create_new_is_exclusive_and_numbers(tmp_path: Path) -> None:
    first = create_new(tmp_path / "run.mcap")
    with pytest.raises(InputError, match="exists"):
        create_new(first)
    assert create_new(first, number=True) == tmp_path / "run-2.mcap"
    assert create_new(first, number=True) == tmp_path / "run-3.mcap"


def test_two_runs_of_one_plan_in_one_second_get_two_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM_CUTS)
    frozen = dt.datetime(2026, 12, 2, 3, 4, 5)

    class Clock(dt.datetime):
        @classmethod
        def now(cls, tz: dt.tzinfo | None = None) -> Clock:  # type: ignore[override]
            return frozen  # type: ignore[return-value]

    monkeypatch.setattr(dt, "datetime", Clock)
    a, b = recording_path(None, plan), recording_path(None, plan)
    assert a != b and a.exists() and b.exists()
    assert a.name == "plan-20261202-030405.mcap" and b.name == "plan-20261202-030405-2.mcap"


def test_write_plan_replaces_atomically_or_refuses(precious: Path) -> None:
    plan = load_plan(ONE_ARM_CUTS)
    with pytest.raises(InputError, match="exists"):
        write_plan(plan, precious, replace=False)
    assert precious.read_text() == PRECIOUS
    assert load_plan(read_text(write_plan(plan, precious))) == plan


def test_export_refuses_a_folder_or_an_existing_file_before_analysing(tmp_path: Path, precious: Path) -> None:
    with pytest.raises(InputError, match="is a folder"):
        export_session_plan(tmp_path / "no-session", tmp_path)
    with pytest.raises(InputError, match="pass --force"):
        export_session_plan(tmp_path / "no-session", precious)
    assert precious.read_text() == PRECIOUS
    with pytest.raises(InputError, match="no such session"):  # --force gets past the check
        export_session_plan(tmp_path / "no-session", precious, force=True)


def test_execute_record_refuses_a_folder_or_an_existing_file(tmp_path: Path, precious: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM_CUTS)
    _one_line_exit_2(["execute", str(plan), "--record", str(tmp_path)], tmp_path, capsys)
    assert "pass --force" in _one_line_exit_2(["execute", str(plan), "--record", str(precious)], precious, capsys)
    assert precious.read_text() == PRECIOUS


@pytest.mark.slow
def test_runs_recover_refuses_a_folder_or_an_existing_file(tmp_path: Path, precious: Path, recording: Path,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    _one_line_exit_2(["runs", "recover", str(recording), "-o", str(tmp_path)], tmp_path, capsys)
    _one_line_exit_2(["runs", "recover", str(recording), "-o", str(precious)], precious, capsys)
    assert precious.read_text() == PRECIOUS
    default = recording.with_name(recording.stem + ".recovered.mcap")
    default.unlink(missing_ok=True)
    assert main(["runs", "recover", str(recording)]) == 0
    _one_line_exit_2(["runs", "recover", str(recording)], default, capsys)  # a second time: refused
    assert main(["runs", "recover", str(recording), "-o", str(precious), "--force"]) == 0
    assert check_recording(precious).ok
    default.unlink()


@pytest.mark.slow
def test_a_flipped_byte_costs_one_chunk_and_is_reported(tmp_path: Path, recording: Path) -> None:
    data = bytearray(recording.read_bytes())
    whole = salvage(recording)
    total = sum(check_recording(recording).messages.values())
    assert whole.damage == () and whole.footer
    damaged = tmp_path / "flipped.mcap"
    data[len(data) // 2] ^= 0xFF  # in the middle of the data section: inside a chunk
    damaged.write_bytes(bytes(data))
    report = recover_recording(damaged, tmp_path / "out.mcap")
    assert report.finished and not report.complete
    kept = report.total  # the run had finished: recovery added no events
    assert total - 10 <= kept < total  # one chunk of a few messages lost, not the rest of the file
    assert any("chunk" in line and "bytes" in line for line in report.lost), report.lost
    lost = next(line for line in report.lost if line.startswith("lost "))
    assert lost.startswith(f"lost {total - kept} of {total} messages")
    assert check_recording(tmp_path / "out.mcap").ok


def test_a_torn_recording_says_the_run_had_not_finished(tmp_path: Path, recording: Path) -> None:
    data = recording.read_bytes()
    torn = tmp_path / "torn.mcap"
    torn.write_bytes(data[: len(data) // 3])
    report = recover_recording(torn, tmp_path / "out.mcap")
    assert not report.finished and not report.complete and report.lost
    assert check_recording(tmp_path / "out.mcap").ok


@pytest.mark.slow
def test_damaged_record_boundaries_cost_at_most_one_chunk(tmp_path: Path, recording: Path) -> None:
    import struct

    data = recording.read_bytes()
    total = sum(check_recording(recording).messages.values())
    starts, at = [], 8
    while at < len(data) - 8:
        starts.append(at)
        at += 9 + struct.unpack_from("<Q", data, at + 1)[0]
    chunk = next(s for s in starts if data[s] == 0x06 and s > starts[3])
    for flip in (3, 10, chunk, chunk + 1, chunk + 60):  # the magic, the header's length, a chunk
        damaged = bytearray(data)
        damaged[flip] ^= 0xFF
        path = tmp_path / f"flip{flip}.mcap"
        path.write_bytes(bytes(damaged))
        report = recover_recording(path, tmp_path / f"flip{flip}.out.mcap")
        assert report.finished and report.lost, flip
        assert report.total >= total - 10, (flip, report.lost)
        problems = check_recording(tmp_path / f"flip{flip}.out.mcap").problems
        assert all("/plan/events" in p for p in problems), (flip, problems)  # only a lost event can show
        assert not problems or any("/plan/events" in line for line in report.lost), (flip, report.lost)
