"""`wecook recognize` and `wecook knowledge learn|evaluate` from the command line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from wecook_core.knowledge.recognize import load_knowledge, rank
from wecook_tui.cli import main

CSV = "action,objects,group\nchop,knife;tomato,a\ncut,knife;onion,b\nstir,spoon;pot,a\nstir,spoon;sauce,c\n" \
      "pour,jug;pot,b\npour,oil;pan,c\nslice,knife;bread,d\nmix,spoon;bowl,d\n"


def test_recognize_json_is_the_ranking(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["recognize", "knife", "cherry tomato", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    expected = rank(load_knowledge(), ["knife", "cherry tomato"])
    assert [(item["action"], item["p"]) for item in printed] == [(v, pytest.approx(p)) for v, p in expected]


def test_recognize_table_and_unknown_objects(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["recognize", "spoon,pot", "spaceship"]) == 0
    out, err = capsys.readouterr()
    assert "stir" in out and "spaceship" in err


def test_recognize_needs_objects(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["recognize"]) == 2
    assert "no objects" in capsys.readouterr().err
    assert main(["recognize", "knife", "--candidates", "cut,dance"]) == 2
    assert "dance" in capsys.readouterr().err


def test_batch_one_json_ranking_per_line_in_order(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lines = ["knife, tomato", "", "spoon,pot", "gizmo", "rolling pin,dough"]
    batch = tmp_path / "batch.txt"
    batch.write_text("\n".join(lines) + "\n")
    assert main(["recognize", "--batch", str(batch)]) == 0
    out, err = capsys.readouterr()
    rows = [json.loads(line) for line in out.splitlines()]
    assert len(rows) == len(lines)
    assert rows[1] == []
    knowledge = load_knowledge()
    for line, row in zip(lines, rows, strict=True):
        if line:
            expected = rank(knowledge, [o.strip() for o in line.split(",")])
            assert [r["action"] for r in row] == [v for v, _ in expected]
            assert [r["p"] for r in row] == pytest.approx([p for _, p in expected])
    assert "'gizmo' (line 4)" in err


def test_batch_missing_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["recognize", "--batch", str(tmp_path / "none.txt")]) == 2
    assert "none.txt" in capsys.readouterr().err


@pytest.mark.slow
def test_learn_and_evaluate_own_corpus(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    corpus = tmp_path / "mine.csv"
    corpus.write_text(CSV)
    out = tmp_path / "tables"
    assert main(["knowledge", "learn", "--corpus", str(corpus), "-o", str(out)]) == 0
    assert "learned groups per action: cut 3," in capsys.readouterr().out
    assert main(["recognize", "--knowledge", str(out / "commonsense.json"), "knife", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)[0]["action"] == "cut"
    assert main(["knowledge", "evaluate", "--corpus", str(corpus), "--json", "--fraction", "0.5"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["test_groups"] == 2 and result["train_records"] + result["test_records"] == 8


def test_evaluate_corpus_prior(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    corpus = tmp_path / "mine.csv"
    corpus.write_text(CSV)
    assert main(["knowledge", "evaluate", "--corpus", str(corpus), "--pooled", "--prior", "corpus",
                 "--fraction", "0.5"]) == 0
    assert "prior corpus" in capsys.readouterr().out


@pytest.mark.parametrize("option", [["--prior", "corpus"], ["--per-record"]])
def test_pooled_options_without_pooled_are_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                   option: list[str]) -> None:
    """The mixed tables (the default) have a uniform prior and count per group: an option of the pooled tables
    would be silently ignored, so it is refused, and nothing is written."""
    corpus = tmp_path / "mine.csv"
    corpus.write_text(CSV)
    assert main(["knowledge", "learn", "--corpus", str(corpus), "-o", str(tmp_path / "t"), *option]) == 2
    assert "--pooled" in capsys.readouterr().err and not (tmp_path / "t").exists()


RECIPE = """---
title: "Rice jars"
---

## Ingredients

- rice

## Directions

1. Peel and cut the onions.
2. Using a spoon, transfer the rice into the jars.
"""


@pytest.mark.slow
def test_extract_recipes_then_learn_from_them(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    recipes = tmp_path / "recipes"
    recipes.mkdir()
    (recipes / "rice-jars.md").write_text(RECIPE)
    out = tmp_path / "records.csv"
    assert main(["knowledge", "extract", str(recipes), "-o", str(out), "--licence", "CC0 1.0"]) == 0
    assert "wrote 3 records" in capsys.readouterr().out
    text = out.read_text()
    assert "# licence: CC0 1.0" in text
    assert "peel,onion,rice-jars" in text and "transfer,spoon;rice;jar,rice-jars" in text
    assert main(["knowledge", "learn", "--corpus", str(out), "-o", str(tmp_path / "t")]) == 0
    assert "transfer 1" in capsys.readouterr().out
    assert main(["knowledge", "learn", "--corpus", str(recipes), "-o", str(tmp_path / "t2")]) == 0
    assert "transfer 1" in capsys.readouterr().out
    assert main(["knowledge", "extract", str(tmp_path), "-o", str(out)]) == 2
    assert "Markdown recipes" in capsys.readouterr().err


def test_learn_bad_corpus_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    corpus = tmp_path / "bad.csv"
    corpus.write_text("action,objects\ncut\n")
    assert main(["knowledge", "learn", "--corpus", str(corpus), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "bad.csv:line 2" in err and len(err.strip().splitlines()) == 1


def test_extract_the_recipe_archive_then_learn(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import gzip

    archive = tmp_path / "open-recipe-archive.jsonl.gz"
    recipes = [{"id": f"book{b}/r{i}", "ingredients": ["2 lemons", "sugar"],
                "steps": ["Cut the lemons with a knife.", "Squeeze them over the sugar in a bowl."]}
               for b in range(3) for i in range(2)]
    with gzip.open(archive, "wt", encoding="utf-8") as f:
        f.writelines(json.dumps(r) + "\n" for r in recipes)
    out = tmp_path / "archive.csv"
    assert main(["knowledge", "extract", str(archive), "-o", str(out)]) == 0
    assert "wrote 12 records" in capsys.readouterr().out
    text = out.read_text()
    assert "# licence: Unlicense" in text and "squeeze,lemon;sugar;bowl,book0/r0" in text
    assert main(["knowledge", "learn", "--corpus", str(out), "-o", str(tmp_path / "t")]) == 0
    assert "squeeze 6" in capsys.readouterr().out
