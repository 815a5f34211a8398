"""Issue 28, operating-system errors: a full disk (EFBIG under a file-size limit), a read-only folder (EACCES,
as root too: the child drops to an unprivileged user), a folder given for a file (EISDIR) and a memory limit
each get one line naming the file and the cause, exit 2, no traceback, and, where it can be known, before the
long work starts."""

from __future__ import annotations

import os
import shutil
import stat
import tempfile
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest
from test_issue28_writes import run_child

from wecook_tui.cli import main

NOBODY = 65534


def _one_line(err: str) -> str:
    lines = [line for line in err.strip().splitlines() if not line.startswith("pybullet build time")]  # its banner
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder any user can read, holding inputs and a session ``kitchen`` under ``sessions/`` (analysed)."""
    from session_inputs import make_inputs

    folder = Path(tempfile.mkdtemp(prefix="wecook-issue28-"))
    os.chmod(folder, 0o755)
    inputs = make_inputs(folder / "in")
    root = folder / "sessions"
    assert main(["new", "kitchen", "--root", str(root), "--video", str(inputs["video"]), "--objects",
                 str(inputs["objects"]), "--hands", str(inputs["hands"])]) == 0
    assert main(["analyze", "kitchen", "--root", str(root)]) == 0
    for path in folder.rglob("*"):
        os.chmod(path, os.stat(path).st_mode | stat.S_IROTH | (stat.S_IXOTH if path.is_dir() else 0))
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def _inputs(made: Path) -> list[str]:
    return ["--video", str(made / "in" / "take.avi"), "--objects", str(made / "in" / "objects.csv"),
            "--hands", str(made / "in" / "openpose")]


def _cli(argv: list[str]) -> str:
    return f"""
        import sys
        from wecook_tui.cli import main
        code = main({argv!r})
        print("exit", code)
        sys.stdout.flush()
    """


@pytest.fixture
def no_detection(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    import wecook_core.observations.hands_detect as hands_detect

    def never(*args: object, **kwargs: object) -> None:
        raise AssertionError("the detection ran before the output was checked")

    monkeypatch.setattr(hands_detect, "detect_hands", never)
    yield


@pytest.mark.parametrize("option", ["-o", "--detections"])
def test_hands_into_a_folder_fails_at_once(tmp_path: Path, made: Path, option: str, no_detection: None,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    """``hands -o DIR --force`` raised IsADirectoryError after the whole detection (issue 28)."""
    folder = tmp_path / "out"
    folder.mkdir()
    output = str(folder) if option == "-o" else str(tmp_path / "h.csv")
    argv = ["hands", str(made / "in" / "take.avi"), "-o", output, "--force"]
    if option == "--detections":
        argv += ["--detections", str(folder)]
    assert main(argv) == 2
    line = _one_line(capsys.readouterr().err)
    assert str(folder) in line and "is a folder" in line


def test_a_full_disk_in_new_is_one_line_and_leaves_nothing(tmp_path: Path, made: Path) -> None:
    root = tmp_path / "sessions"
    done = run_child(_cli(["new", "full", "--root", str(root), *_inputs(made)]), cwd=Path(__file__).parent,
                     fsize=200)
    assert "exit 2" in done.stdout, done.stderr
    line = _one_line(done.stderr)
    assert "file too large" in line and str(root) in line
    assert [p.name for p in root.iterdir()] == []


def test_a_full_disk_in_analyze_and_export_keeps_the_old_files(made: Path, tmp_path: Path) -> None:
    session = tmp_path / "sessions" / "kitchen"
    shutil.copytree(made / "sessions" / "kitchen", session)
    trees = (session / "trees.yaml").read_bytes()
    (session / "plans" / "plan.yaml").write_text("the user's plan, about 300 bytes long " * 8 + "\n")
    plan = (session / "plans" / "plan.yaml").read_bytes()
    for argv, named in ((["analyze", "kitchen"], session / "trees.yaml"),
                        (["export", "kitchen"], session / "plans" / "plan.yaml")):
        done = run_child(_cli([*argv, "--root", str(tmp_path / "sessions")]), cwd=Path(__file__).parent,
                         fsize=min(len(trees), len(plan)) // 2)
        assert "exit 2" in done.stdout, done.stderr
        line = _one_line(done.stderr)
        assert str(named) in line and "file too large" in line, line
    assert (session / "trees.yaml").read_bytes() == trees
    assert (session / "plans" / "plan.yaml").read_bytes() == plan
    assert not [p for p in session.rglob(".*") if p.name.endswith((".tmp", ".part.mcap"))]


def _unprivileged() -> list[str]:
    """The command starting a child as a user without the right to write a folder it does not own: nobody, by
    util-linux's setpriv, when the tests run as root (root may write anywhere)."""
    if os.geteuid() != 0:
        return []
    return ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups"]


def test_a_read_only_sessions_folder_is_said_before_any_work(made: Path) -> None:
    """A read-only folder gave tracebacks in new, analyze, export and (after 11 s of detection) hands."""
    from wecook_core.execution.plan_samples import ONE_ARM_CUTS

    readonly = made / "readonly"
    readonly.mkdir(exist_ok=True)
    shutil.copytree(made / "sessions" / "kitchen", readonly / "kitchen", dirs_exist_ok=True)
    plan = readonly / "kitchen" / "plans" / "cuts.yaml"
    plan.write_text(ONE_ARM_CUTS)
    os.chmod(plan, 0o644)
    for path in (readonly / "kitchen", readonly / "kitchen" / "plans", readonly / "kitchen" / "runs", readonly):
        os.chmod(path, 0o555)
    try:
        cases = [
            (["new", "other", "--root", str(readonly), *_inputs(made)], readonly),
            (["analyze", "kitchen", "--root", str(readonly)], readonly / "kitchen"),
            (["export", "kitchen", "--root", str(readonly)], readonly / "kitchen" / "plans"),
            (["hands", str(made / "in" / "take.avi"), "-o", str(readonly / "h.csv")], readonly),
            (["execute", str(plan)], readonly / "kitchen" / "runs"),
            (["execute", str(plan), "--record", str(readonly / "kitchen" / "runs" / "r.mcap")],
             readonly / "kitchen" / "runs" / "r.mcap"),
        ]
        for argv, named in cases:
            code = """
                import wecook_core.observations.hands_detect as hands_detect
                import wecook_core.workflows as workflows
                def never(*args, **kwargs):
                    raise SystemExit("the long work ran before the output was checked")
                hands_detect.detect_hands = never
                workflows.analyse = never
                import wecook_core.execution.run as executor
                executor.execute_plan = never
            """
            done = run_child(textwrap.dedent(code) + textwrap.dedent(_cli(argv)), cwd=made, user=_unprivileged())
            assert "exit 2" in done.stdout, (argv, done.stdout, done.stderr)
            line = _one_line(done.stderr)
            assert str(named) in line and "permission denied" in line, (argv, line)
    finally:
        for path in (readonly, readonly / "kitchen", readonly / "kitchen" / "plans", readonly / "kitchen" / "runs"):
            os.chmod(path, 0o755)


def test_an_os_error_anywhere_is_one_line_naming_the_file(monkeypatch: pytest.MonkeyPatch, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    import errno

    def full(args: object) -> int:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / "scen" / "video.mp4"))

    def unnamed(args: object) -> int:
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr("wecook_tui.cli.build_parser", _parser_with("synth", full))
    assert main(["synth", str(tmp_path / "scen")]) == 2
    line = _one_line(capsys.readouterr().err)
    assert line == f"wecook: error: {tmp_path / 'scen' / 'video.mp4'}: no space left on the device"
    monkeypatch.setattr("wecook_tui.cli.build_parser", _parser_with("analyze", unnamed))
    assert main(["analyze", "kitchen"]) == 2  # the error names no file: the command's subject is named
    assert _one_line(capsys.readouterr().err) == "wecook: error: kitchen: the file system is read-only"


def _parser_with(command: str, func: object):  # type: ignore[no-untyped-def]
    from wecook_tui import cli

    real = cli.build_parser

    def build():  # type: ignore[no-untyped-def]
        parser = real()
        for action in parser._subparsers._group_actions:  # type: ignore[union-attr]
            action.choices[command].set_defaults(func=func)  # type: ignore[index]
        return parser

    return build


def test_a_memory_limit_in_new_is_one_line(made: Path, tmp_path: Path) -> None:
    """MemoryError was a traceback (issue 28)."""
    objects = tmp_path / "objects.csv"
    objects.write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,whisk,10,10,20,20\n0,2,pan,40,30,90,60\n")
    code = """
        import resource
        import numpy as np
        import wecook_core.session.store as store
        def hungry(*args, **kwargs):
            soft, hard = resource.getrlimit(resource.RLIMIT_AS)
            resource.setrlimit(resource.RLIMIT_AS, (1 << 32, hard))  # 4 GiB of address space
            np.ones(1 << 30)  # 8 GiB
        store.create_session = hungry
    """ + _cli(["new", "m", "--root", str(tmp_path / "s"), "--video", str(made / "in" / "take.avi"),
                "--objects", str(objects), "--hands", str(made / "in" / "openpose")])
    done = run_child(code, cwd=Path(__file__).parent)
    assert "exit 2" in done.stdout, (done.stdout, done.stderr)
    line = _one_line(done.stderr)
    assert "out of memory" in line and str(made / "in" / "take.avi") in line


def test_a_video_that_fails_to_decode_for_lack_of_memory_says_so(tmp_path: Path) -> None:
    """Under a lower memory limit the decoder failed and the line said "not a readable video"."""
    from grey_video import write_grey_video

    video = write_grey_video(tmp_path / "big.avi", 3, (4000, 3000), 10.0)
    small = write_grey_video(tmp_path / "small.avi", 3, (64, 48), 10.0)
    done = run_child(f"""
        import resource
        from wecook_tui.cli import main
        import wecook_core.observations.hands_detect  # (OpenBLAS hangs when loaded past the limit)
        from wecook_core.formats.video import probe_video
        probe_video({str(small)!r})  # OpenCV loaded as the command loads it (its library fails to map past it)
        used = int(open("/proc/self/statm").read().split()[0]) * resource.getpagesize()
        resource.setrlimit(resource.RLIMIT_AS, (used + (40 << 20), resource.RLIM_INFINITY))
        print("exit", main(["hands", {str(video)!r}, "-o", {str(tmp_path / "h.csv")!r}]))
    """, cwd=Path(__file__).parent)
    assert "exit 2" in done.stdout, (done.stdout, done.stderr)
    assert _one_line(done.stderr) == f"wecook: error: {video}: out of memory (a memory limit: `ulimit -v`?)"


def test_a_full_disk_during_execute_record_is_one_line_and_keeps_the_old_recording(tmp_path: Path) -> None:
    """A full disk in ``execute --record`` was a traceback; with --force the old recording must stay whole and
    no hidden .part file be left."""
    from wecook_core.execution.plan_samples import ONE_ARM_CUTS

    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM_CUTS)
    record = tmp_path / "run.mcap"
    old = b"the finished recording\n" * 10
    record.write_bytes(old)
    code = """
        import wecook_core.execution.run as executor
        from wecook_core.execution.schedule.executor import ActionResult, RunResult
        from wecook_core.recording.synthetic_run import synthetic_run

        def run(plan, observer, **kwargs):  # a long synthetic run instead of the simulation
            synthetic_run(observer, actions=400, seconds_per_action=1.0)
            return RunResult([], 400.0, 0.1, 0)

        executor.execute_plan = run
    """
    cases = ((["--record", str(record), "--force"], str(record)),
             (["--record", str(tmp_path / "new.mcap")], str(tmp_path / "new.mcap")),
             ([], str(tmp_path / "runs" / "plan-")))  # the default recording, which only the error can name
    for argv, named in cases:
        done = run_child(textwrap.dedent(code) + textwrap.dedent(_cli(["execute", str(plan), *argv])),
                         cwd=Path(__file__).parent, fsize=64 << 10)
        assert "exit 2" in done.stdout, (done.stdout, done.stderr)
        line = done.stderr.strip().splitlines()[-1]
        assert "Traceback" not in done.stderr and "file too large" in line, done.stderr
        assert f"wecook: error: {named}" in line, line
    assert record.read_bytes() == old
    assert not [p.name for p in tmp_path.iterdir() if ".part" in p.name]
