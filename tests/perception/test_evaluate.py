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


BOWL_POUR = parse_tree("(HP (HP (H RH_P1) (O oil)) (AP (A pour) (O bowl)))")
BOWL_2_POUR = parse_tree("(HP (HP (H RH_P1) (O oil)) (AP (A pour) (O bowl_2)))")


def test_objects_match_by_class_unless_instances_are_asked_for() -> None:
    truth = [TreeSpan(0, 100, BOWL_POUR)]
    predicted = [TreeSpan(10, 90, BOWL_2_POUR)]
    assert evaluate(predicted, truth).correct == 1
    assert evaluate(predicted, truth, instances=True).correct == 0


def test_report_lists_missed_and_spurious_trees_and_counts_per_case() -> None:
    from wecook_core.perception.evaluation import report

    truth = [TreeSpan(0, 100, CUT), TreeSpan(100, 200, STIR), TreeSpan(200, 300, BOWL_POUR)]
    predicted = [TreeSpan(10, 90, CUT), TreeSpan(210, 290, BOWL_2_POUR), TreeSpan(300, 400, STIR),
                 TreeSpan(0, 300, GRASP)]
    result = report(predicted, truth)
    assert (result.scores.correct, result.scores.predicted, result.scores.truth) == (2, 3, 3)
    assert [s.start for s in result.missed] == [100] and [s.start for s in result.spurious] == [300]
    assert result.truth == {"tool": 2, "held": 1} and result.correct == {"tool": 1, "held": 1}
    assert result.predicted == {"tool": 2, "held": 1} and result.cases() == ["tool", "held"]


def test_cli_prints_the_case_table_and_the_mistakes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import json

    truth, pred = tmp_path / "truth.yaml", tmp_path / "pred.yaml"
    write_tree_file(truth, [TreeSpan(0, 100, CUT), TreeSpan(100, 200, STIR)])
    write_tree_file(pred, [TreeSpan(0, 100, CUT), TreeSpan(300, 400, STIR)])
    assert main(["eval", str(pred), str(truth)]) == 0
    out = capsys.readouterr().out
    assert "tool" in out and "missed" in out and "spurious" in out and "(A stir)" in out
    assert main(["eval", str(pred), str(truth), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["missed"] == [{"start": 100, "end": 200, "tree": "(HP (HP (H RH_P2) (O spoon)) (AP (A stir) (O pot)))"}]
    assert data["spurious"][0]["start"] == 300 and data["cases"]["tool"] == {"predicted": 2, "truth": 2, "correct": 1}


def test_loose_scores_tell_a_wrong_hand_from_a_wrong_object_and_leave_the_strict_score() -> None:
    from wecook_core.perception.evaluation import loose

    truth = [TreeSpan(0, 100, CUT), TreeSpan(100, 200, STIR), TreeSpan(200, 300, CUT)]
    predicted = [
        TreeSpan(0, 90, CUT),  # right
        TreeSpan(100, 190, parse_tree("(HP (HP (H LH_P1) (O spoon)) (AP (A stir) (O pot)))")),  # wrong hand
        TreeSpan(200, 290, parse_tree("(HP (HP (H LH_P1) (O knife)) (AP (A cut) (O bread)))")),  # hand and object
        TreeSpan(400, 500, CUT),  # nowhere near a truth tree: wrong under every view
    ]
    strict = evaluate(predicted, truth)
    views = loose(predicted, truth)
    assert strict.correct == 1 and (strict.predicted, strict.truth) == (4, 3)
    assert views["hands ignored"].correct == 2
    assert views["verbs only"].correct == 3
    assert views["verbs only"].precision == pytest.approx(3 / 4) and views["verbs only"].recall == 1.0
    assert evaluate(predicted, truth) == strict  # the views leave the strict score as it was


def test_verbs_only_keeps_the_collaboration_and_the_order() -> None:
    from wecook_core.perception.evaluation import verbs_only

    hold = parse_tree("(HP (HP (H LH_P1) (O board)) (CP (C holding) (HP (HP (H RH_P2) (O knife)) "
                      "(AP (A cut) (O meat)))))")
    assert [leaf.word for leaf in verbs_only(hold).children] == ["holding", "cut"]
    assert verbs_only(hold) != verbs_only(CUT) and verbs_only(CUT) != verbs_only(STIR)


def test_cli_loose(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    truth, pred = tmp_path / "truth.yaml", tmp_path / "pred.yaml"
    write_tree_file(truth, [TreeSpan(0, 100, CUT), TreeSpan(100, 200, STIR)])
    write_tree_file(pred, [TreeSpan(0, 100, parse_tree("(HP (HP (H LH_P1) (O knife)) (AP (A cut) (O tomato)))")),
                           TreeSpan(100, 200, parse_tree("(HP (HP (H RH_P2) (O fork)) (AP (A stir) (O pot)))"))])
    assert main(["eval", str(pred), str(truth), "--loose"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("precision 0.000  recall 0.000")
    assert out[1].split() == ["hands", "ignored:", "precision", "0.500", "recall", "0.500", "correct", "1"]
    assert out[2].split() == ["verbs", "only:", "precision", "1.000", "recall", "1.000", "correct", "2"]
    assert main(["eval", str(pred), str(truth), "--loose", "--json"]) == 0
    import json

    got = json.loads(capsys.readouterr().out)
    assert got["correct"] == 0 and got["loose"]["verbs only"]["correct"] == 2
    assert main(["eval", str(pred), str(truth), "--json"]) == 0
    assert "loose" not in json.loads(capsys.readouterr().out)
