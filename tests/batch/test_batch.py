"""`wecook batch`: manifests, resumable stages, failure isolation, and the same results as one video at a time."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.batch.one_by_one import one_session_at_a_time
from wecook_core.batch.engine import run_batch
from wecook_core.batch.manifest import BatchItem, read_manifest
from wecook_core.batch.report import build_report, write_report
from wecook_core.batch.stages import StageOptions, run_stage, stages_for
from wecook_core.errors import InputError
from wecook_core.resources import shared_dir
from wecook_tui.cli import main

SCENARIOS = shared_dir() / "data" / "scenarios"

needs_shared = pytest.mark.skipif(not (SCENARIOS / "s301").is_dir(), reason="../shared/data/scenarios is missing")


@pytest.fixture(scope="module")
def demo_inputs() -> dict[str, Path]:
    from wecook_core.synth import demo_dir

    folder = demo_dir()
    return {"video": folder / "video.mp4", "objects": folder / "objects.csv", "hands": folder / "hands.csv",
            "truth": folder / "truth.yaml"}


# ------------------------------------------------------------------------------------------ manifests


def test_yaml_csv_and_folder_manifests_give_the_same_items(tmp_path: Path, demo_inputs: dict[str, Path]) -> None:
    d = demo_inputs
    (tmp_path / "m.yaml").write_text(
        f"videos:\n  - {{name: a, video: {d['video']}, objects: {d['objects']}, hands: {d['hands']}, "
        f"truth: {d['truth']}}}\n  - {{name: b, video: {d['video']}, objects: {d['objects']}}}\n")
    (tmp_path / "m.csv").write_text(
        f"name,video,objects,hands,truth\na,{d['video']},{d['objects']},{d['hands']},{d['truth']}\n"
        f"b,{d['video']},{d['objects']},,\n")
    from_yaml, from_csv = read_manifest(tmp_path / "m.yaml"), read_manifest(tmp_path / "m.csv")
    assert from_yaml == from_csv
    assert from_yaml[0] == BatchItem("a", d["video"], d["objects"], d["hands"], d["truth"])
    assert from_yaml[1].hands is None
    assert stages_for(from_yaml[0], ["import", "hands", "analyze"]) == ("import", "analyze")
    assert stages_for(from_yaml[1], ["import", "hands", "analyze"]) == ("hands", "import", "analyze")


@needs_shared
def test_a_folder_of_scenarios_is_a_manifest() -> None:
    items = read_manifest(SCENARIOS)
    assert [i.name for i in items] == sorted(p.name for p in SCENARIOS.iterdir() if (p / "video.mp4").exists())
    assert all(i.objects.name == "objects.xml" and i.hands is not None and i.hands.name == "openpose"
               and i.truth is not None for i in items)


@pytest.mark.parametrize(("text", "expected"), [
    ("videos:\n  - {name: a, video: v.mp4}\n", "video 1: `objects` is missing"),
    ("videos:\n  - {name: a, video: v.mp4, objects: o.csv, colour: red}\n", "video 1: unknown field 'colour'"),
    ("videos:\n  - {name: a, video: v.mp4, objects: o.csv}\n  - {name: a, video: w.mp4, objects: o.csv}\n",
     "video 2: name 'a' is also video 1"),
    ("videos:\n  - {name: ../up, video: v.mp4, objects: o.csv}\n", "video 1: bad session name"),
    ("videos: []\n", "lists no videos"),
    ("videos: [unclosed\n", "malformed YAML"),
])
def test_a_bad_manifest_is_one_line_naming_the_file_and_the_row(tmp_path: Path, text: str, expected: str) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(text)
    with pytest.raises(InputError) as error:
        read_manifest(path)
    assert str(path) in str(error.value) and expected in str(error.value)


def test_unknown_stage_and_bad_workers_exit_2(tmp_path: Path, demo_inputs: dict[str, Path],
                                              capsys: pytest.CaptureFixture[str]) -> None:
    d = demo_inputs
    manifest = tmp_path / "m.csv"
    manifest.write_text(f"name,video,objects,hands\na,{d['video']},{d['objects']},{d['hands']}\n")
    assert main(["batch", str(manifest), "--root", str(tmp_path / "s"), "--stages", "import,cook"]) == 2
    assert "unknown stage 'cook'" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


# ------------------------------------------------------------------------------------- stages, resume


@pytest.mark.slow
def test_stages_are_skipped_when_nothing_changed_and_redone_when_an_input_does(
        tmp_path: Path, demo_inputs: dict[str, Path]) -> None:
    d = demo_inputs
    item = BatchItem("demo", d["video"], d["objects"], d["hands"], d["truth"])
    root = tmp_path / "sessions"
    first = run_batch([item], ["import", "analyze"], root, engine="local")
    assert [r.status for r in first.results["demo"]] == ["done", "done"]
    trees = (root / "demo" / "trees.yaml").read_text()
    again = run_batch([item], ["import", "analyze"], root, engine="local")
    assert [r.status for r in again.results["demo"]] == ["cached", "cached"]
    assert (root / "demo" / "trees.yaml").read_text() == trees
    # a correction in the journal changes what analyze reads: analyze runs again, import does not
    with (root / "demo" / "journal.jsonl").open("a") as journal:
        journal.write(json.dumps({"seq": 1, "time": "2026-12-02T00:00:00Z", "op": "set_status", "segment": 0,
                                  "status": "accepted"}) + "\n")
    third = run_batch([item], ["import", "analyze"], root, engine="local")
    assert [r.status for r in third.results["demo"]] == ["cached", "done"]
    forced = run_batch([item], ["import", "analyze"], root, engine="local", options=StageOptions(force=True))
    assert [r.status for r in forced.results["demo"]] == ["done", "done"]
    kept = [p.name for p in root.iterdir() if p.name.startswith(".demo.replaced-")]
    assert len(kept) == 1, "--force keeps the replaced session beside the new one"


@pytest.mark.slow
def test_a_failed_video_stops_only_its_own_stages(tmp_path: Path, demo_inputs: dict[str, Path]) -> None:
    d = demo_inputs
    good = BatchItem("good", d["video"], d["objects"], d["hands"], d["truth"])
    bad = BatchItem("bad", d["video"], tmp_path / "no-such-objects.csv", d["hands"])
    run = run_batch([bad, good], ["import", "analyze", "export"], tmp_path / "s", engine="local")
    assert [r.status for r in run.results["bad"]] == ["failed", "skipped", "skipped"]
    assert "no-such-objects.csv" in run.results["bad"][0].error and "\n" not in run.results["bad"][0].error
    assert [r.status for r in run.results["good"]] == ["done", "done", "done"]
    report = build_report(run, tmp_path / "s")
    assert report.failed == 1 and report.videos[1].actions and report.videos[1].actions > 0
    assert report.recall is not None and report.recall > 0.5  # the demo's own truth
    data = json.loads(write_report(report, tmp_path / "s").read_text())
    assert [v["status"] for v in data["videos"]] == ["failed", "done"]


@pytest.mark.slow
def test_a_session_the_user_made_is_never_replaced_without_force(tmp_path: Path,
                                                                 demo_inputs: dict[str, Path]) -> None:
    d = demo_inputs
    root = tmp_path / "s"
    assert main(["new", "mine", "--video", str(d["video"]), "--objects", str(d["objects"]),
                 "--hands", str(d["hands"]), "--root", str(root)]) == 0
    result = run_stage(BatchItem("mine", d["video"], d["objects"], d["hands"]), "import", root, StageOptions())
    assert result.status == "failed" and "not made by a batch" in result.error
    assert (root / "mine" / "session.yaml").exists()


@pytest.mark.slow
def test_a_killed_batch_resumes_and_loses_no_finished_result(tmp_path: Path, demo_inputs: dict[str, Path]) -> None:
    d = demo_inputs
    manifest = tmp_path / "m.csv"
    rows = [f"v{i},{d['video']},{d['objects']},{d['hands']}" for i in range(3)]
    manifest.write_text("name,video,objects,hands\n" + "\n".join(rows) + "\n")
    root = tmp_path / "s"
    command = [sys.executable, "-m", "wecook_tui.cli", "batch", str(manifest), "--root", str(root), "--engine",
               "local", "--stages", "import,analyze,export"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               cwd=Path(__file__).parents[2])
    deadline = time.monotonic() + 120
    while not (root / "v0" / "batch" / "export.json").exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    process.send_signal(signal.SIGKILL)
    process.wait()
    finished = {p.parent.parent.name + "/" + p.stem for p in root.glob("*/batch/*.json")}
    assert "v0/export" in finished
    before = {name: (root / name.split("/")[0] / "batch" / f"{name.split('/')[1]}.json").read_text()
              for name in finished}
    run = run_batch(read_manifest(manifest), ["import", "analyze", "export"], root, engine="local")
    for name, stamp in before.items():
        video, stage = name.split("/")
        result = next(r for r in run.results[video] if r.stage == stage)
        assert result.status == "cached", name
        assert (root / video / "batch" / f"{stage}.json").read_text() == stamp
    assert all(r.status in ("done", "cached") for rs in run.results.values() for r in rs)
    assert os.path.exists(root / "v2" / "plans" / "plan.yaml")


# ---------------------------------------------------------------------------------- Ray vs one by one


@needs_shared
@pytest.mark.slow
def test_ray_with_two_workers_gives_what_one_video_at_a_time_gives(tmp_path: Path) -> None:
    pytest.importorskip("ray")
    names = ["s301", "s303", "s304"]
    one_by_one = one_session_at_a_time(tmp_path / "one", names)
    items = [i for i in read_manifest(SCENARIOS) if i.name in names]
    batch_root = tmp_path / "batch"
    finished: list[list[str]] = []
    run = run_batch(items, ["import", "analyze", "export"], batch_root, engine="ray", workers=2,
                    on_video=lambda so_far: finished.append(sorted(so_far.results)))
    assert run.workers == 2
    # streamed: each video reported as it finished, one more each time, then the whole run
    assert [len(f) for f in finished] == [1, 2, 3, 3], finished
    assert len({r.pid for rs in run.results.values() for r in rs}) >= 2, "tasks ran in two worker processes"
    for name in names:
        assert [r.status for r in run.results[name]] == ["done", "done", "done"], run.results[name]
        for file in ("trees.yaml", "graph.yaml", "plans/plan.yaml"):
            assert (batch_root / name / file).read_text() == (one_by_one / name / file).read_text(), (name, file)


@pytest.mark.slow
def test_a_video_without_hands_gets_them_detected_as_wecook_new_detects_them(tmp_path: Path) -> None:
    """The hands stage runs MediaPipe on a video with a real hand (tests/data, Apache-2.0) and writes the hands
    where `wecook new` without --hands writes them; the session is then made from them."""
    pytest.importorskip("mediapipe")
    from tests.hand_video import hand_and_tomato

    video = tmp_path / "hand.avi"
    boxes = hand_and_tomato(video)
    objects = tmp_path / "objects.csv"
    objects.write_text("frame,track_id,label,x1,y1,x2,y2\n" + "".join(
        f"0,{i},{label},{x1},{y1},{x2},{y2}\n" for i, (label, (x1, y1, x2, y2)) in enumerate(boxes.items(), 1)))
    item = BatchItem("handy", video, objects)
    run = run_batch([item], ["hands", "import"], tmp_path / "batch", engine="local")
    assert [(r.stage, r.status) for r in run.results["handy"]] == [("hands", "done"), ("import", "done")], \
        run.results["handy"]
    assert main(["new", "handy", "--video", str(video), "--objects", str(objects), "--root",
                 str(tmp_path / "one")]) == 0
    detected = (tmp_path / "batch" / "handy.hands.csv").read_text()
    assert detected == (tmp_path / "one" / "handy.hands.csv").read_text()
    assert detected.count("\n") > 10  # a header and the hand on most frames
    again = run_batch([item], ["hands", "import"], tmp_path / "batch", engine="local")
    assert [r.status for r in again.results["handy"]] == ["cached", "cached"]
