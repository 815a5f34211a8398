from __future__ import annotations

import sys
from pathlib import Path

import pytest

from wecook_core.formats.detect import HAND_FORMATS, OBJECT_FORMATS
from wecook_tui import cli
from wecook_tui.commands import session as command

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core"))
from session_inputs import make_inputs


def new(root: Path, inputs: dict[str, Path], name: str = "take1", *extra: str) -> int:
    return cli.main(["new", name, "--video", str(inputs["video"]), "--objects", str(inputs["objects"]),
                     "--hands", str(inputs["hands"]), "--categories", str(inputs["categories"]),
                     "--root", str(root), *extra])


def test_new_prints_what_it_found_and_sessions_lists_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                                        ) -> None:
    inputs = make_inputs(tmp_path / "in")
    root = tmp_path / "sessions"
    assert new(root, inputs, "take1", "--hands-format", "openpose") == 0
    out = capsys.readouterr().out
    assert "20 frames at 10 fps (2.0 s), 96x64" in out
    assert "whisk  tool" in out and "pan    container" in out
    assert "LH_P1  frames 0-19, 20 detections" in out
    assert "wecook open take1" in out
    assert (root / "take1" / "session.yaml").is_file()
    assert cli.main(["sessions", "--root", str(root)]) == 0
    listing = capsys.readouterr().out.splitlines()
    assert listing[0].split() == ["#", "NAME", "CREATED", "CORRECTIONS", "VIDEO"]
    assert listing[1].split()[:2] == ["1", "take1"] and listing[1].split()[3] == "0"
    assert listing[1].endswith(str(inputs["video"].resolve()))


def test_bad_input_exits_2_with_one_line_and_no_session(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                                        ) -> None:
    inputs = make_inputs(tmp_path / "in")
    inputs["objects"].write_text("frame,track_id,label,x1,y1,x2,y2\n3,1,whisk,10,10,20\n")
    root = tmp_path / "sessions"
    assert new(root, inputs) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "objects.csv:line 2" in err and err.startswith("wecook: error:")
    assert not root.exists() or list(root.iterdir()) == []
    assert new(root, inputs, "no/slash") == 2
    assert "bad session name" in capsys.readouterr().err


def test_gaps_and_warnings_are_shown(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    inputs = make_inputs(tmp_path / "in")
    for f in range(1, 19):  # the person is missing for 1.8 s
        (inputs["hands"] / f"take_{f:012d}_keypoints.json").write_text('{"people": []}')
    root = tmp_path / "sessions"
    assert new(root, inputs, "gappy") == 0
    out = capsys.readouterr().out
    assert "18 missing inside" in out and "\ngaps" not in out
    from wecook_core.knowledge.categories import load_categories
    from wecook_core.observations.importer import InputChecks, import_observations

    strict = import_observations(inputs["video"], inputs["objects"], inputs["hands"],
                                 categories=load_categories([inputs["categories"]]),
                                 checks=InputChecks(max_gap_seconds=1.0))
    text = command.describe(strict, inputs["objects"], inputs["hands"])
    assert "\ngaps     2 longer than the limit" in text and "  LH_P1  frames 1-18 (1.8 s)" in text
    assert "warning: " in text and "is missing" not in text  # the gaps are not repeated as warnings
    (inputs["hands"] / f"take_{19:012d}_keypoints.json").unlink()
    (inputs["hands"] / f"take_{25:012d}_keypoints.json").write_text((inputs["hands"] / "take_000000000000"
                                                                     "_keypoints.json").read_text())
    assert new(root, inputs, "late") == 2  # frame 25 is past the video's end
    assert "frame 25" in capsys.readouterr().err


def test_sessions_and_pick_with_no_sessions(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    assert cli.main(["sessions", "--root", str(tmp_path)]) == 0
    assert "no sessions in" in capsys.readouterr().out
    monkeypatch.setenv("WECOOK_SESSIONS", str(tmp_path))
    assert cli.main([]) == 0
    assert "wecook demo" in capsys.readouterr().out


def test_pick_lists_sessions_when_not_in_a_terminal(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    inputs = make_inputs(tmp_path / "in")
    assert new(tmp_path / "s", inputs, "one") == 0
    capsys.readouterr()
    monkeypatch.setenv("WECOOK_SESSIONS", str(tmp_path / "s"))
    assert cli.main([]) == 0
    out = capsys.readouterr().out
    assert "one" in out and "wecook open NAME" in out


def test_command_choices_match_the_importers() -> None:
    assert command.OBJECT_FORMATS == OBJECT_FORMATS and command.HAND_FORMATS == HAND_FORMATS


def test_new_with_mot_boxes_a_labels_file_and_a_forced_format(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                                              ) -> None:
    inputs = make_inputs(tmp_path / "in")
    inputs["objects"] = tmp_path / "in" / "boxes.dat"
    inputs["objects"].write_text("1,7,10,10,10,10,1\n2,7,11,10,10,10,1\n")
    labels = tmp_path / "in" / "names.txt"
    labels.write_text("7,Whisk\n")
    root = tmp_path / "sessions"
    assert new(root, inputs, "mot", "--objects-format", "mot") == 2  # no labels.txt beside it
    assert "--labels" in capsys.readouterr().err
    assert new(root, inputs, "mot", "--objects-format", "mot", "--labels", str(labels)) == 0
    out = capsys.readouterr().out
    assert "(mot): 1 tracks" in out and "whisk  tool        frames 0-1, 2 boxes (label 'Whisk')" in out
    from wecook_core.session.store import open_session

    session = open_session(root / "mot")
    assert session.inputs["labels"].path == str(labels.resolve())
    assert session.load_observations().objects[0].label == "Whisk"


@pytest.mark.slow
def test_demo_without_a_terminal_prints_trees_graph_and_scores(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from wecook_tui.cli import main

    assert main(["demo", "--root", str(tmp_path), "--headless"]) == 0
    out = capsys.readouterr().out
    assert "(HP (HP (H RH_P1) (O knife)) (AP (A cut)" in out
    assert "wecook_graph: 1" in out and "sequences:" in out
    assert "against the truth: precision" in out
    assert (tmp_path / "demo" / "trees.yaml").is_file() and (tmp_path / "demo" / "graph.yaml").is_file()
