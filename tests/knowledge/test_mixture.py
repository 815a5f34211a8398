"""Tables mixed by corpus with objects in their roles: the mean of each corpus's P(O | A), an object counted
only in its role's relation, the file format, and the shipped tables."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.knowledge.corpus import Corpus
from wecook_core.knowledge.learning import Example
from wecook_core.knowledge.mixture import components, mixed_from_examples
from wecook_core.knowledge.recognize import Component, Knowledge, load_knowledge, rank, save_knowledge
from wecook_tui.cli import main

VERBS = ("cut", "wrap")
OBJECTS = ("knife", "egg", "meat")
ROLES = {"knife": "tool", "egg": "ingredient", "meat": "ingredient"}


def _example(action: str, objects: tuple[str, ...], group: str, source: str,
             relations: tuple[str, ...] = ()) -> Example:
    return Example(action, objects, group, source, relations)


def test_an_object_counts_only_in_its_roles_relation() -> None:
    # "wrap the meat in beaten egg": the egg is where the meat goes, not what is wrapped
    said = [_example("wrap", ("meat", "egg"), "r1", "book", ("object", "place")),
            _example("cut", ("knife", "meat"), "r2", "book", ("means", "object"))]
    parts, features = components(said, VERBS, OBJECTS, ROLES)
    (book,) = parts
    assert book.source == "book"
    wrap = VERBS.index("wrap")
    assert book.pair_counts[wrap].tolist() == [0, 0, 1]  # the egg in the place relation is not an egg wrapped
    assert book.totals[wrap] == 2  # but it is one of wrap's features
    assert features == 3  # (object, meat), (place, egg), (means, knife): at least the 3 objects


def test_records_without_relations_are_read_by_role_and_once_per_group() -> None:
    videos = [_example("cut", ("knife", "meat"), "v1", "videos"), _example("cut", ("knife", "meat"), "v1", "videos"),
              _example("cut", ("knife",), "v2", "videos")]
    (part,), _ = components(videos, VERBS, OBJECTS, ROLES)
    assert part.pair_counts[0].tolist() == [2, 0, 1] and part.totals[0] == 3


def test_each_corpus_has_one_vote_however_big() -> None:
    big = [_example("wrap", ("meat",), f"w{i}", "big") for i in range(100)]
    big += [_example("cut", ("knife",), f"c{i}", "big") for i in range(100)]
    small = [_example("cut", ("meat",), "s1", "small")]
    knowledge = mixed_from_examples(big + small, OBJECTS, Corpus(records=()), alpha=0.5, verbs=VERBS, roles=ROLES)
    assert [c.source for c in knowledge.components] == ["big", "small"]
    a, f = 0.5, knowledge.features
    assert knowledge.likelihood("meat", "cut") == pytest.approx((a / (100 + a * f) + (1 + a) / (1 + a * f)) / 2)
    assert knowledge.likelihood("meat", "wrap") == pytest.approx(((100 + a) / (100 + a * f) + a / (a * f)) / 2)
    pooled = Knowledge(VERBS, OBJECTS, knowledge.action_counts, knowledge.pair_counts, alpha=0.5,
                       prior_kind="uniform")
    # pooled, the big corpus's hundred cuts of other things drown the small one's "cut the meat"; mixed, it speaks
    assert dict(rank(pooled, ["meat"]))["cut"] < 0.02
    assert dict(rank(knowledge, ["meat"]))["cut"] > 0.25


def test_mixed_tables_round_trip(tmp_path: Path) -> None:
    records = [_example("wrap", ("meat", "egg"), "r1", "book", ("object", "place")),
               _example("cut", ("knife", "meat"), "v1", "videos")]
    knowledge = mixed_from_examples(records, OBJECTS, Corpus(records=()), alpha=0.1, verbs=VERBS, roles=ROLES)
    save_knowledge(knowledge, tmp_path / "k.json")
    loaded = load_knowledge(tmp_path / "k.json")
    assert loaded.features == knowledge.features and len(loaded.components) == 2
    assert np.allclose(loaded.log_likelihood, knowledge.log_likelihood)


def _with_components(tmp_path: Path, entries: object) -> Path:
    knowledge = Knowledge(VERBS, OBJECTS, np.array([1, 1]), np.zeros((2, 3), dtype=np.int64), prior_kind="uniform",
                          components=(Component("a", np.zeros((2, 3), dtype=np.int64), np.array([1, 1])),),
                          features=3)
    save_knowledge(knowledge, tmp_path / "good.json")
    data = json.loads((tmp_path / "good.json").read_text())
    data["components"] = entries
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize(("entries", "fragment"), [
    ("x", "list of components"),
    ([{"source": "a"}], "components\\[0\\]"),
    ([{"source": "a", "totals": [1, 1], "pair_counts": [[1, 0, 0], [0, 0, "x"]]}], "integers"),
    ([{"source": "a", "totals": [1], "pair_counts": [[0, 0, 0], [0, 0, 0]]}], "shape"),
    ([{"source": "a", "totals": [1, 1], "pair_counts": [[2, 0, 0], [0, 0, 0]]}], "within the totals"),
])
def test_malformed_components_name_the_file(tmp_path: Path, entries: object, fragment: str) -> None:
    path = _with_components(tmp_path, entries)
    with pytest.raises(InputError, match=fragment) as error:
        load_knowledge(path)
    assert str(path) in str(error.value)


def test_malformed_components_exit_2_on_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _with_components(tmp_path, [{"source": "a"}])
    assert main(["recognize", "--knowledge", str(path), "knife"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and str(path) in err and "components[0]" in err


def test_shipped_tables_mix_the_three_corpora() -> None:
    shipped = load_knowledge()
    sources = [c.source for c in shipped.components]
    assert len(sources) == 3 and "open-recipe-archive" in sources
    assert shipped.prior_kind == "uniform" and shipped.features >= len(shipped.objects)
    # the knife is cutting's tool in all three; a peeler peels
    assert rank(shipped, ["knife", "tomato", "chopping board"])[0][0] == "cut"
    assert rank(shipped, ["peeler", "potato"])[0][0] == "peel"
