"""Labels outside the category table: categorised from the head noun and the commonsense corpus's nouns, and
what nothing knows is recorded, never an error (issue 11: "puzzle piece", "butternut squash")."""

from __future__ import annotations

from pathlib import Path

import yaml

from tests.grey_video import write_grey_video
from wecook_core.knowledge.categories import DEFAULT_CATEGORY, categorise_labels, parse_categories
from wecook_core.model import Category
from wecook_tui.cli import main

SMALL = parse_categories("objects:\n  knife: tool\n  bowl: container\n  colander: container\n  bread: ingredient\n",
                         "small")


def test_the_table_the_head_noun_and_x_of_y() -> None:
    found = categorise_labels(["Knife", "paring knife", "bowl of rice", "slice of bread"], SMALL)
    assert found.categories == {"Knife": Category.TOOL, "paring knife": Category.TOOL,
                                "bowl of rice": Category.CONTAINER, "slice of bread": Category.INGREDIENT}
    assert found.how == {"Knife": "table", "paring knife": "head noun 'knife'", "bowl of rice": "head noun 'bowl'",
                         "slice of bread": "head noun 'bread'"}
    assert found.unknown == ()


def test_the_corpus_nouns_name_what_the_table_lacks(knowledge) -> None:
    # The corpus (EPIC-KITCHENS) lists "sieve" and "strainer" as instances of its noun "colander".
    found = categorise_labels(["sieve", "metal strainer"], SMALL, knowledge)
    assert found.categories == {"sieve": Category.CONTAINER, "metal strainer": Category.CONTAINER}
    assert found.how["sieve"] == "corpus noun 'colander'"


def test_what_nothing_knows_is_recorded_and_defaulted(knowledge) -> None:
    found = categorise_labels(["puzzle piece", "gizmo", "puzzle piece", "butternut squash"], None, knowledge)
    assert found.unknown == ("puzzle piece", "gizmo")
    assert found.categories["gizmo"] == DEFAULT_CATEGORY == Category.INGREDIENT
    assert found.categories["butternut squash"] == Category.INGREDIENT and found.how["butternut squash"] != "unknown"


def test_wecook_new_with_unknown_labels_makes_the_session_and_records_them(tmp_path: Path, capsys) -> None:
    video = write_grey_video(tmp_path / "v.avi", 6, (64, 48), 5.0)
    objects = tmp_path / "boxes.csv"
    objects.write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,puzzle piece,0,0,9,9\n0,2,bowl,10,10,30,30\n")
    hands = tmp_path / "hands.csv"
    hands.write_text("frame,hand,x,y,x1,y1,x2,y2\n0,RH_P1,20,20,10,10,30,30\n")
    root = tmp_path / "sessions"
    assert main(["new", "s", "--video", str(video), "--objects", str(objects), "--hands", str(hands),
                 "--root", str(root)]) == 0
    out = capsys.readouterr().out
    assert "no category known for 'puzzle piece'" in out
    meta = yaml.safe_load((root / "s" / "session.yaml").read_text())
    assert meta["uncategorised"] == ["puzzle piece"]
