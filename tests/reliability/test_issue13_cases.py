"""Issue 13, case by case through the command line: each bad input gives one line naming the file and the place,
exit code 2, no traceback, and leaves what the user has untouched."""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml
from grey_video import write_grey_video

from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_tui.cli import main

BIG = "1" + "0" * 25
BODY = [v for x, y in [(0, -30), (0, -20), (-10, -20), (-12, -5), (-14, 8), (10, -20), (12, -5), (14, 8)]
        for v in (30 + x, 30 + y, 0.9)]


def fails_cleanly(argv: list[str], named: str | Path, capsys: pytest.CaptureFixture[str], *, says: str = "") -> str:
    """Run ``wecook argv``: exit 2 and exactly one stderr line, naming ``named`` (and saying ``says``)."""
    assert main([str(a) for a in argv]) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("wecook: error: "), err
    assert str(named) in lines[0] and says in lines[0], lines[0]
    return lines[0]


@pytest.fixture
def inputs(tmp_path: Path) -> dict[str, Path]:
    folder = tmp_path / "in"
    folder.mkdir()
    video = write_grey_video(folder / "take.avi", 20, (96, 64), 10.0)
    objects = folder / "objects.csv"
    objects.write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,whisk,10,10,20,20\n0,2,pan,40,30,90,60\n")
    hands = folder / "openpose"
    hands.mkdir()
    for f in range(20):
        (hands / f"take_{f:012d}_keypoints.json").write_text(json.dumps({"people": [{"pose_keypoints_2d": BODY}]}))
    return {"video": video, "objects": objects, "hands": hands, "root": tmp_path / "sessions"}


def new(inputs: dict[str, Path], objects: Path | None = None, hands: Path | None = None) -> list[object]:
    return ["new", "s", "--video", inputs["video"], "--objects", objects or inputs["objects"],
            "--hands", hands or inputs["hands"], "--root", inputs["root"]]


# ------------------------------------------------------------------------------------------ importers

OBJECT_FILES: dict[str, tuple[str, str]] = {
    "csv_frame_1e25": ("o.csv", f"frame,track_id,label,x1,y1,x2,y2\n{BIG},1,pot,1,1,2,2\n"),
    "mot_frame_1e25": ("m.txt", f"{BIG},1,1,1,5,5,1,1\n"),
    "mot_id_1e25": ("m.txt", f"1,{BIG},1,1,5,5,1,1\n"),
    "cvat_frame_1e25": ("c.xml", f'<annotations><track id="1" label="pot"><box frame="{BIG}" xtl="1" ytl="1" '
                                 'xbr="2" ybr="2"/></track></annotations>'),
    "cvat_frame_1e9": ("c.xml", '<annotations><track id="1" label="pot"><box frame="0" xtl="1" ytl="1" xbr="2" '
                                'ybr="2"/><box frame="1000000000" xtl="1" ytl="1" xbr="2" ybr="2"/></track>'
                                '</annotations>'),
    "cvat_track_nested": ("c.xml", '<annotations><meta><track id="1" label="pot"><box frame="0" xtl="1" ytl="1" '
                                   'xbr="2" ybr="2"/></track></meta></annotations>'),
    "cocovid_frame_1e25": ("v.json", json.dumps({"images": [{"id": 1, "frame_id": int(BIG)}], "annotations": [],
                                                 "categories": []})),
    "cocovid_100000_deep": ("v.json", "[" * 100_000 + "]" * 100_000),
    "csv_keypoint_1e308": ("o.csv", "frame,track_id,label,x1,y1,x2,y2\n0,1,pot,1,1,2,1e308\n"),
}


@pytest.mark.parametrize("case", sorted(OBJECT_FILES))
def test_bad_object_file(case: str, inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    name, text = OBJECT_FILES[case]
    path = inputs["video"].parent / name
    path.write_text(text)
    (path.parent / "labels.txt").write_text("1,pot\n")
    fails_cleanly(new(inputs, objects=path), path, capsys)
    assert not inputs["root"].exists() or not any(inputs["root"].iterdir())  # nothing left behind


def test_bom_csv_reads_its_header(inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    path = inputs["video"].parent / "bom.csv"
    path.write_text("\ufeffframe,track_id,label,x1,y1,x2,y2\n0,1,whisk,10,10,20,20\n0,2,pan,40,30,90,60\n")
    assert main([str(a) for a in new(inputs, objects=path)]) == 0, capsys.readouterr().err


def test_fifo_as_objects_does_not_hang(inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    fifo = inputs["video"].parent / "fifo"
    os.mkfifo(fifo)
    fails_cleanly(new(inputs, objects=fifo), fifo, capsys, says="FIFO")
    fails_cleanly(new(inputs, hands=fifo), fifo, capsys, says="FIFO")
    argv = new(inputs)
    argv[argv.index("--video") + 1] = fifo
    fails_cleanly(argv, fifo, capsys, says="FIFO")
    fails_cleanly([*new(inputs), "--categories", fifo], fifo, capsys, says="FIFO")
    fails_cleanly(["eval", fifo, fifo], fifo, capsys)


def _openpose(inputs: dict[str, Path], damage: Callable[[Path], Path]) -> tuple[Path, Path]:
    folder = inputs["video"].parent / "op"
    shutil.copytree(inputs["hands"], folder)
    return folder, damage(folder)


def _replace(folder: Path, make: Callable[[Path], object]) -> Path:
    file = folder / "take_000000000005_keypoints.json"
    file.unlink()
    make(file)
    return file


OPENPOSE_DAMAGE: dict[str, Callable[[Path], Path]] = {
    "keypoints_file_is_a_folder": lambda f: _replace(f, Path.mkdir),
    "keypoints_file_is_a_dangling_link": lambda f: _replace(f, lambda p: p.symlink_to(f / "gone")),
    "json_100000_deep": lambda f: _replace(f, lambda p: p.write_text("[" * 100_000 + "]" * 100_000)),
    "frame_1e25_in_the_name": lambda f: (f / f"take_{BIG}_keypoints.json").write_text("{}") and f,
    "keypoint_1e308": lambda f: _replace(f, lambda p: p.write_text(json.dumps(
        {"people": [{"pose_keypoints_2d": [1e308, *BODY[1:]]}]}))),
}


@pytest.mark.parametrize("case", sorted(OPENPOSE_DAMAGE))
def test_bad_openpose_folder(case: str, inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    folder, _ = _openpose(inputs, OPENPOSE_DAMAGE[case])
    fails_cleanly(new(inputs, hands=folder), folder, capsys)


# ---------------------------------------------------------------------------------------------- plans

def _bomb() -> str:
    lines = ["wecook_plan: 1", "a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 10)]
    return "\n".join([*lines, "agents:", "  - pid: *a9", ""])


PLANS: dict[str, tuple[str | bytes, str]] = {
    "not_utf8": (b"wecook_plan: 1\n# caf\xe9\n", "not UTF-8"),
    "10000_levels_deep": ("wecook_plan: 1\nagents: " + "[" * 10_000 + "]" * 10_000 + "\n", "nested deeper"),
    "alias_bomb": (_bomb(), "aliases"),
    "nan_base_position": (ONE_ARM_CUTS.replace("position: [-0.5", "position: [.nan"), "base.position[0]"),
    "inf_yaw": (ONE_ARM_CUTS.replace("yaw: 0.0}}", "yaw: .inf}}"), "base.yaw"),
    "nan_table_size": (ONE_ARM_CUTS.replace("size: [1.0, 0.8]", "size: [.nan, 0.8]"), "scene.table.size"),
    "inf_table_height": (ONE_ARM_CUTS.replace("height: 0.0", "height: -.inf"), "scene.table.height"),
    "huge_base_position": (ONE_ARM_CUTS.replace("position: [-0.5", "position: [1e300"), "base.position"),
    "robot_etc_passwd": (ONE_ARM_CUTS.replace("franka_panda/panda.urdf", "/etc/passwd"), "agents[0].robot"),
    "robot_not_urdf_xml": (ONE_ARM_CUTS.replace("franka_panda/panda.urdf", "/etc/x.urdf"), "agents[0].robot"),
}


@pytest.mark.parametrize("case", sorted(PLANS))
def test_bad_plan(case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text, says = PLANS[case]
    path = tmp_path / "plan.yaml"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    line = fails_cleanly(["execute", path, "--no-record"], path, capsys, says=says)
    assert len(line) < 300  # the alias bomb's message was 92 MB
    assert not (tmp_path / "runs").exists()


# ------------------------------------------------------------------------------------------- sessions

def _session(tmp_path: Path, inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> Path:
    assert main([str(a) for a in new(inputs)]) == 0
    capsys.readouterr()
    return inputs["root"] / "s"


def _set(key: str, value: object) -> Callable[[dict[str, object]], None]:
    def edit(meta: dict[str, object]) -> None:
        params = meta["params"]
        assert isinstance(params, dict)
        params[key] = value
    return edit


SESSIONS: dict[str, tuple[Callable[[dict[str, object]], None] | bytes, str]] = {
    "params_a_list": (lambda m: m.__setitem__("params", [1, 2]), "params"),
    "k_max_lots": (_set("k_max", "lots"), "params.k_max"),
    "lamb_negative": (_set("lamb", -1), "params.lamb"),
    "k_a_list": (_set("k", [1, 2]), "params.k"),
    "k_per_minute_1e9": (_set("k_per_minute", 1e9), "params.k_per_minute"),
    "unknown_format": (lambda m: m["inputs"]["objects"].__setitem__("format", "bogus"),  # type: ignore[index]
                       "inputs.objects.format"),
    "not_utf8": (b"wecook_session: 1\nname: s\xe9\n", "not UTF-8"),
}


@pytest.mark.parametrize("case", sorted(SESSIONS))
def test_bad_session_yaml(case: str, tmp_path: Path, inputs: dict[str, Path],
                          capsys: pytest.CaptureFixture[str]) -> None:
    session = _session(tmp_path, inputs, capsys)
    edit, says = SESSIONS[case]
    meta_path = session / "session.yaml"
    if isinstance(edit, bytes):
        meta_path.write_bytes(edit)
    else:
        meta = yaml.safe_load(meta_path.read_text())
        edit(meta)
        meta_path.write_text(yaml.safe_dump(meta))
    fails_cleanly(["export", "s", "--root", inputs["root"]], meta_path, capsys, says=says)
    assert main(["sessions", "--root", str(inputs["root"])]) == 0  # listing still works


def test_journal_that_is_a_folder(tmp_path: Path, inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    session = _session(tmp_path, inputs, capsys)
    (session / "journal.jsonl").unlink()
    (session / "journal.jsonl").mkdir()
    fails_cleanly(["export", "s", "--root", inputs["root"]], session / "journal.jsonl", capsys)


def test_root_that_is_a_file(inputs: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    root = inputs["video"]
    argv = new(inputs)
    argv[argv.index("--root") + 1] = root
    fails_cleanly(argv, root, capsys, says="not a folder")
    fails_cleanly(["sessions", "--root", root], root, capsys, says="not a folder")
    fails_cleanly(["export", "s", "--root", root], root, capsys, says="not a folder")


def test_synth_does_not_overwrite_a_scenario(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "scen"
    folder.mkdir()
    (folder / "objects.csv").write_text("the user's boxes\n")
    fails_cleanly(["synth", folder, "--no-video", "--duration", "4"], folder, capsys, says="--force")
    assert (folder / "objects.csv").read_text() == "the user's boxes\n"
    fails_cleanly(["synth", folder / "objects.csv", "--no-video"], folder / "objects.csv", capsys)
