"""`wecook batch` while it runs: one batch per sessions folder, progress per video, `batch.json` whole and up to
date as each video finishes, SIGTERM on a Ray batch, the hand detector kept across videos."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import pytest

from wecook_core.batch.engine import BatchRun, run_batch
from wecook_core.batch.lock import batch_lock
from wecook_core.batch.manifest import BatchItem
from wecook_core.batch.progress import Progress, Tracker
from wecook_core.batch.report import ReportWriter
from wecook_core.batch.stages import StageResult
from wecook_core.batch.video import StageStarted
from wecook_core.errors import InputError
from wecook_tui.cli import main

ROOT = Path(__file__).parents[2]


@pytest.fixture(scope="module")
def demo_manifest(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from wecook_core.synth import demo_dir

    d = demo_dir()
    path = tmp_path_factory.mktemp("manifest") / "m.csv"
    path.write_text("name,video,objects,hands,truth\n" + "".join(
        f"v{i},{d / 'video.mp4'},{d / 'objects.csv'},{d / 'hands.csv'},{d / 'truth.yaml'}\n" for i in range(4)))
    return path


def _items(manifest: Path, n: int) -> list[BatchItem]:
    from wecook_core.batch.manifest import read_manifest

    return list(read_manifest(manifest))[:n]


def test_a_manifest_named_from_here_gives_absolute_paths_for_workers_elsewhere(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "in").mkdir()
    (tmp_path / "in" / "m.csv").write_text("name,video,objects,hands\na,v.mp4,o.csv,h.csv\n")
    monkeypatch.chdir(tmp_path)
    from wecook_core.batch.manifest import read_manifest

    [item] = read_manifest("in/m.csv")
    assert item.video == tmp_path / "in" / "v.mp4" and item.hands == tmp_path / "in" / "h.csv"


# ------------------------------------------------------------------------------------------------ the lock


def test_a_second_batch_on_the_same_sessions_refuses_naming_the_first(
        tmp_path: Path, demo_manifest: Path, capsys: pytest.CaptureFixture[str]) -> None:
    root = tmp_path / "s"
    root.mkdir()
    with batch_lock(root, "first.yaml"):
        code = main(["batch", str(demo_manifest), "--root", str(root), "--engine", "local"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert str(root / "batch.lock") in err and f"process {os.getpid()}" in err and "first.yaml" in err, err
    assert sorted(p.name for p in root.iterdir()) == ["batch.lock"], "the second batch made nothing"
    with batch_lock(root, "again.yaml") as path:  # released by the first, even though its file stays
        assert "again.yaml" in path.read_text()


def test_wait_waits_for_the_batch_holding_the_sessions(tmp_path: Path, demo_manifest: Path) -> None:
    root = tmp_path / "s"
    root.mkdir()
    released: list[float] = []
    holding = threading.Event()

    def hold() -> None:
        with batch_lock(root, "first.yaml"):
            holding.set()
            time.sleep(1.0)
            released.append(time.monotonic())

    holder = threading.Thread(target=hold)
    holder.start()
    holding.wait(10)
    with pytest.raises(InputError, match="another batch is running"):
        run_batch(_items(demo_manifest, 1), [], root, engine="local")
    run_batch(_items(demo_manifest, 1), [], root, engine="local", wait=True)
    ended = time.monotonic()
    holder.join()
    assert released and ended >= released[0], "wait=True ran only once the first batch let go"


# --------------------------------------------------------------------------------------------- progress


def test_progress_says_each_running_videos_stage_and_eta() -> None:
    plans = {"a": ("import", "analyze"), "b": ("import", "analyze"), "c": ("import", "analyze")}
    tracker = Tracker(plans, workers=2)
    now = time.time()
    tracker.add(StageStarted("a", "import", 0, plans["a"], now - 10))
    assert tracker.progress().eta is None, "no stage timed yet"
    tracker.add(StageResult("a", "import", "done", 4.0, started=now - 10))
    tracker.add(StageStarted("a", "analyze", 1, plans["a"], now - 6))
    tracker.add(StageResult("a", "analyze", "done", 6.0, started=now - 6))
    tracker.add(StageStarted("b", "import", 0, plans["b"], now - 1))
    progress = tracker.progress()
    assert (progress.done, progress.running) == (1, 1)
    [b] = progress.current
    assert (b.video, b.stage, b.index, b.stages) == ("b", "import", 0, 2)
    assert b.eta == pytest.approx(4.0 + 6.0 - 1.0, abs=0.2), "mean import + mean analyze - time spent"
    # the batch: b's 9 s and c's 10 s, over 2 workers
    assert progress.eta == pytest.approx((9.0 + 10.0) / 2, abs=0.2)


@pytest.mark.slow
def test_batch_json_is_whole_and_up_to_date_as_each_video_finishes(tmp_path: Path, demo_manifest: Path) -> None:
    items = _items(demo_manifest, 2)
    root = tmp_path / "s"
    writer = ReportWriter(root)
    seen: list[list[str]] = []
    stages_seen: list[tuple[str, str]] = []

    def on_video(run: BatchRun) -> None:
        writer(run)  # what the CLI does; then read the file as another program would
        seen.append([v["status"] for v in json.loads((root / "batch.json").read_text())["videos"]])

    def on_progress(progress: Progress) -> None:
        stages_seen.extend((v.video, v.stage) for v in progress.current)

    torn: list[str] = []
    stop = threading.Event()

    def read() -> None:
        while not stop.is_set():
            try:
                text = (root / "batch.json").read_text()
            except FileNotFoundError:
                continue
            try:
                json.loads(text)
            except ValueError:
                torn.append(text)

    reader = threading.Thread(target=read)
    reader.start()
    try:
        run_batch(items, ["import", "analyze", "export"], root, engine="local", on_video=on_video,
                  on_progress=on_progress)
    finally:
        stop.set()
        reader.join()
    assert not torn, "a reader saw a torn batch.json"
    assert seen[0] == ["done", "pending"] and seen[-1] == ["done", "done"], seen
    for video in ("v0", "v1"):
        assert [s for v, s in dict.fromkeys(stages_seen) if v == video] == ["import", "analyze", "export"]


@pytest.mark.slow
def test_the_command_says_each_videos_stage_and_eta_as_it_goes(tmp_path: Path, demo_manifest: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    two = tmp_path / "two.csv"
    two.write_text("\n".join(demo_manifest.read_text().splitlines()[:3]) + "\n")
    root = tmp_path / "s"
    assert main(["batch", str(two), "--root", str(root), "--engine", "local", "--stages", "import,analyze"]) == 0
    lines = capsys.readouterr().err.splitlines()
    assert any(line.startswith("v0 import done") and line.endswith("now v0: analyze 2/2") for line in lines), lines
    # by v1, import and analyze have been timed once: v1 has an ETA, and so has the batch
    v1 = next(line for line in lines if line.startswith("v1 import done"))
    assert "ETA" in v1.split("; now ")[0] and "now v1: analyze 2/2 ETA" in v1, v1
    assert [v["status"] for v in json.loads((root / "batch.json").read_text())["videos"]] == ["done", "done"]


# --------------------------------------------------------------------------------------------- SIGTERM


def _processes_using(folder: str) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if folder.encode() in (entry / "cmdline").read_bytes():
                    found.append(int(entry.name))
            except OSError:
                pass
    return found


@pytest.mark.slow
def test_sigterm_stops_a_ray_batch_cleanly(tmp_path: Path, demo_manifest: Path) -> None:
    """Was: Ray's handler dumped a native stack ('*** SIGTERM received') and the process aborted."""
    pytest.importorskip("ray")
    root = tmp_path / "s"
    ray_tmp = tempfile.mkdtemp(prefix="wrs", dir="/tmp")  # this batch's Ray, to check it is gone after
    process = subprocess.Popen(
        [sys.executable, "-m", "wecook_tui.cli", "batch", str(demo_manifest), "--root", str(root), "--workers", "2",
         "--stages", "import,analyze,export"], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
        env={**os.environ, "RAY_TMPDIR": ray_tmp})
    deadline = time.monotonic() + 180
    while not list(root.glob("*/batch/import.json")) and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.05)
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=120)
    text = err.decode(errors="replace")
    assert process.returncode == 130, text[-3000:]
    assert "SIGTERM received" not in text and "Traceback" not in text, text[-3000:]
    assert "batch stopped" in text
    report = json.loads((root / "batch.json").read_text())
    assert "pending" in [v["status"] for v in report["videos"]], "stopped before the end, and says so"
    for video in report["videos"]:
        if video["status"] == "done":
            assert (root / video["name"] / "batch" / "export.json").exists()
    assert not list(root.rglob("*.tmp")), "no temporary file left"
    time.sleep(1)
    left = _processes_using(ray_tmp)
    if not left:
        shutil.rmtree(ray_tmp, ignore_errors=True)
    assert not left, "the batch's Ray is shut down"


# -------------------------------------------------------------------------------------- the hand detector


@pytest.mark.slow
def test_a_hand_detector_kept_for_the_next_video_finds_what_a_new_one_finds(tmp_path: Path) -> None:
    pytest.importorskip("mediapipe")
    import cv2

    from tests.hand_video import hand_and_tomato
    from wecook_core.observations.hands_detect import DetectParams, HandDetector, detect_hands, write_hands

    first = tmp_path / "a.avi"
    hand_and_tomato(first)
    frames = []
    capture = cv2.VideoCapture(str(first))
    while (frame := capture.read())[0]:
        frames.append(frame[1])
    capture.release()
    second = tmp_path / "b.avi"  # the same frames from the middle on, then the start: the hand jumps
    writer = cv2.VideoWriter(str(second), cv2.VideoWriter_fourcc(*"MJPG"), 10.0, frames[0].shape[1::-1])
    for image in frames[len(frames) // 2:] + frames[: len(frames) // 2]:
        writer.write(image)
    writer.release()
    params = DetectParams()
    fresh = detect_hands(second, params)
    with HandDetector(params) as kept:
        detect_hands(first, params, detector=kept)
        reused = detect_hands(second, params, detector=kept)
    assert reused.assigned == fresh.assigned
    csv = [write_hands(found, second, tmp_path / f"{name}.csv").read_text()
           for name, found in (("fresh", fresh), ("reused", reused))]
    assert csv[0] == csv[1]  # the hands file the hands stage writes
    assert fresh.frames_with_hands > 10
