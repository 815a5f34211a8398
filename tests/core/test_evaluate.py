from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.model import TreeSpan
from wecook_core.perception.evaluation import evaluate
from wecook_core.trees.notation import parse_tree
from wecook_core.trees.treefile import read_tree_file, write_tree_file
from wecook_tui.cli import main

CUT = parse_tree("(HP (HP (H RH_P1) (O knife)) (AP (A cut) (O tomato)))")
STIR = parse_tree("(HP (HP (H RH_P2) (O spoon)) (AP (A stir) (O pot)))")
GRASP = parse_tree("(HP (H RH_P1) (O knife))")


def test_counts_only_trees_with_actions_and_matches_once() -> None:
    truth = [TreeSpan(0, 100, CUT), TreeSpan(100, 200, STIR), TreeSpan(200, 250, GRASP)]
    predicted = [
        TreeSpan(10, 60, CUT),  # correct
        TreeSpan(60, 90, CUT),  # same truth tree again: not correct
        TreeSpan(300, 400, STIR),  # no overlap: not correct
        TreeSpan(0, 300, GRASP),  # no action: not counted
    ]
    scores = evaluate(predicted, truth)
    assert (scores.correct, scores.predicted, scores.truth) == (1, 3, 2)
    assert scores.precision == pytest.approx(1 / 3)
    assert scores.recall == pytest.approx(1 / 2)


def test_best_overlap_wins() -> None:
    truth = [TreeSpan(0, 50, CUT), TreeSpan(100, 150, CUT)]
    predicted = [TreeSpan(40, 140, CUT), TreeSpan(0, 45, CUT)]
    assert evaluate(predicted, truth).correct == 2


def test_empty_inputs() -> None:
    scores = evaluate([], [])
    assert (scores.precision, scores.recall, scores.correct) == (0.0, 0.0, 0)


def test_tree_file_round_trip_and_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    spans = [TreeSpan(0, 100, CUT), TreeSpan(100, 200, STIR)]
    truth, pred = tmp_path / "truth.yaml", tmp_path / "pred.yaml"
    write_tree_file(truth, spans)
    write_tree_file(pred, spans[:1])
    assert read_tree_file(truth) == tuple(spans)
    assert main(["eval", str(pred), str(truth), "--json"]) == 0
    out = capsys.readouterr().out
    assert '"precision": 1.0' in out and '"recall": 0.5' in out and '"truth": 2' in out


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("", "empty file"),
        ("{a: 1}", "expected a list"),
        ("- {start: 0, end: 10}\n", "entry 1: expected a mapping"),
        ('- {start: 10, end: 5, tree: "(HP (H RH_P1) (O knife))"}\n', "entry 1: start and end"),
        ('- {start: 0, end: 5, tree: "(HP (H RH_P1) (O knife))"}\n- {start: 0, end: 5, tree: "(HP (A x))"}\n',
         "entry 2: tree column"),
        ("- [unclosed\n", "not YAML"),
    ],
)
def test_bad_tree_files(tmp_path: Path, text: str, expected: str, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match=expected):
        read_tree_file(path)
    assert main(["eval", str(path), str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(path) in err
