"""Issue 28, files a user keeps: written whole or not at all (temp beside them, fsync, rename), a reader never sees
a torn one, and no temporary file is left when a write fails or a command is stopped by SIGTERM.

A full disk is a file-size limit (``RLIMIT_FSIZE``, with SIGXFSZ ignored, so a write past it fails EFBIG) in a
child process: it works as root too, where a read-only folder does not."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import numpy as np

from wecook_core.model import ActionGraph, HandTrack, TreeSpan
from wecook_core.observations.hands_detect import DetectedHands, write_detections_csv, write_hands
from wecook_core.trees.notation import parse_tree
from wecook_core.trees.treefile import dump_tree_spans, read_tree_file, write_tree_file

ROOT = Path(__file__).resolve().parents[2]


def run_child(code: str, *, cwd: Path, fsize: int | None = None,
              user: list[str] | None = None) -> subprocess.CompletedProcess[str]:
    """``code`` run by a fresh interpreter importing this worktree (and the tests' helpers), under a file-size
    limit of ``fsize`` bytes when given, started by the command ``user`` when given (another user's)."""
    prelude = "import resource, signal\n"
    if fsize is not None:
        prelude += (f"signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
                    f"resource.setrlimit(resource.RLIMIT_FSIZE, ({fsize}, {fsize}))\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "tests")])}
    return subprocess.run([*(user or []), sys.executable, "-c", prelude + textwrap.dedent(code)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def _spans(n: int, verb: str = "cut") -> list[TreeSpan]:
    tree = parse_tree(f"(HP (HP (H RH_P1) (O knife)) (AP (A {verb}) (O tomato)))")
    return [TreeSpan(10 * i, 10 * i + 5, tree) for i in range(n)]


def test_a_tree_file_is_never_cut_short_by_a_full_disk(tmp_path: Path) -> None:
    """Under a 1,024-byte file-size limit the old trees.yaml stayed cut to 1,024 bytes (issue 28)."""
    trees = tmp_path / "trees.yaml"
    write_tree_file(trees, _spans(40))
    old = trees.read_bytes()
    assert len(old) > 2048
    done = run_child(f"""
        from wecook_core.trees.treefile import write_tree_file
        from test_issue28_writes import _spans
        try:
            write_tree_file({str(trees)!r}, _spans(80, "peel"))
        except OSError as error:
            print("refused", error.errno)
    """, cwd=Path(__file__).parent, fsize=1024)
    assert "refused" in done.stdout, done.stderr
    assert trees.read_bytes() == old
    assert sorted(p.name for p in tmp_path.iterdir()) == ["trees.yaml"]  # no temporary file left


def test_a_reader_never_sees_a_torn_tree_file(tmp_path: Path) -> None:
    trees = tmp_path / "trees.yaml"
    versions = {dump_tree_spans(_spans(n)) for n in (1500, 1501)}
    write_tree_file(trees, _spans(1500))
    stop = threading.Event()
    torn: list[int] = []
    reads = 0

    def read() -> None:
        nonlocal reads
        while not stop.is_set():
            text = trees.read_text()
            reads += 1
            if text not in versions:
                torn.append(len(text))

    reader = threading.Thread(target=read)
    reader.start()
    try:
        for i in range(150):
            write_tree_file(trees, _spans(1500 + i % 2))
    finally:
        stop.set()
        reader.join()
    assert reads > 0 and not torn, f"{len(torn)} torn reads of {reads}"
    assert len(read_tree_file(trees)) == 1501


def test_the_session_files_are_written_through_the_one_atomic_helper(tmp_path: Path, monkeypatch) -> None:
    """trees.yaml, graph.yaml, the hands and detections CSVs, PDDL and session.yaml all go through write_atomic."""
    import wecook_core.files as files
    from wecook_core.plan.pddl import PddlExport, write_pddl
    from wecook_core.session.store import _write_yaml
    from wecook_core.trees.graph import write_graph_file

    written: list[str] = []
    real = files.write_atomic

    def watch(path, *args, **kwargs):  # type: ignore[no-untyped-def]
        written.append(Path(path).name)
        return real(path, *args, **kwargs)

    monkeypatch.setattr(files, "write_atomic", watch)
    import wecook_core.session.store as store
    import wecook_core.trees.treefile as treefile

    for module in (treefile, store):  # the modules that import it by name
        monkeypatch.setattr(module, "write_atomic", watch)
    write_tree_file(tmp_path / "trees.yaml", _spans(2))
    write_graph_file(tmp_path / "graph.yaml", ActionGraph((), {}, ()))
    _write_yaml(tmp_path / "session.yaml", {"a": 1})
    write_pddl(PddlExport("(domain)", "(problem)", (), (), {}), tmp_path / "pddl")
    write_hands(_found(), "video.mp4", tmp_path / "hands.csv")
    write_detections_csv(tmp_path / "detections.csv", ())
    assert written == ["trees.yaml", "graph.yaml", "session.yaml", "domain.pddl", "problem.pddl", "plan.pddl",
                       "hands.csv", "detections.csv"]
    assert (tmp_path / "hands.csv").read_text().splitlines()[0] == "frame,hand,x,y,x1,y1,x2,y2"
    assert oct((tmp_path / "trees.yaml").stat().st_mode & 0o777) == oct(0o666 & ~_umask())  # not made private


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _found(frames: int = 400) -> DetectedHands:
    f = np.arange(frames)
    xy = np.stack([f * 0.5, f * 0.25], axis=1).astype(float)
    boxes = np.concatenate([xy - 5, xy + 5], axis=1)
    return DetectedHands((HandTrack("RH_P1", f, xy, boxes),), (), frames, frames, 0)


def test_a_failed_hands_write_keeps_the_old_csv_and_leaves_no_partial(tmp_path: Path) -> None:
    """``.real.csv.partial`` was left after a failed ``hands``, and a detections CSV was cut short."""
    hands, detections = tmp_path / "real.csv", tmp_path / "det.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n" + "0,RH_P1,1,1,0,0,2,2\n" * 200)
    detections.write_text("frame,hand,detector_label,score,x,y,x1,y1,x2,y2\n" + "0,RH_P1,Right,0.9,1,1,0,0,2,2\n" * 200)
    old_hands, old_detections = hands.read_bytes(), detections.read_bytes()
    done = run_child(f"""
        from test_issue28_writes import _found
        from wecook_core.observations.hands_detect import write_hands
        from wecook_core.formats.native import write_hands_csv
        for call in (lambda: write_hands(_found(), "v.mp4", {str(hands)!r}),
                     lambda: write_hands_csv({str(detections)!r}, _found().tracks)):
            try:
                call()
            except OSError as error:
                print("refused", error.errno)
    """, cwd=Path(__file__).parent, fsize=4096)
    assert done.stdout.count("refused") == 2, done.stderr
    assert hands.read_bytes() == old_hands and detections.read_bytes() == old_detections
    assert sorted(p.name for p in tmp_path.iterdir()) == ["det.csv", "real.csv"]


def test_sigterm_during_new_leaves_no_half_made_session(tmp_path: Path) -> None:
    """``sessions/.NAME.creating-XXXX/`` was left after SIGTERM during ``new`` (SIGINT cleaned it)."""
    root = tmp_path / "sessions"
    done = run_child(f"""
        import os, signal, time
        from pathlib import Path
        from session_inputs import make_inputs
        import wecook_core.session.store as store
        from wecook_tui.cli import main

        inputs = make_inputs(Path({str(tmp_path / "in")!r}))
        real = store._write_yaml

        def killed(path, data):
            real(path, data)
            os.kill(os.getpid(), signal.SIGTERM)  # SIGTERM while the session folder is being built
            time.sleep(5)

        store._write_yaml = killed
        code = main(["new", "kitchen", "--root", {str(root)!r}, "--video", str(inputs["video"]),
                     "--objects", str(inputs["objects"]), "--hands", str(inputs["hands"])])
        print("exit", code)
    """, cwd=Path(__file__).parent)
    assert "exit 143" in done.stdout, (done.stdout, done.stderr)
    assert "terminated" in done.stderr and "Traceback" not in done.stderr
    assert sorted(p.name for p in root.iterdir()) == []
