"""Object categories: parsing, matching free-text labels, layering user files, errors, the shipped table."""

from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.errors import InputError
from wecook_core.knowledge.categories import (
    ENV_VAR,
    CategoryTable,
    categorize_all,
    derive_categories,
    format_categories,
    load_categories,
    parse_categories,
)
from wecook_core.model import Category

T, C, ING = Category.TOOL, Category.CONTAINER, Category.INGREDIENT


def table(text: str) -> CategoryTable:
    return parse_categories(text, "t.yaml")


def test_parse_objects_section_and_flat_mapping() -> None:
    assert table("wecook_categories: 1\nobjects:\n  Rolling Pin: tool\n  bowl: Container\n").entries == {
        "rolling_pin": T, "bowl": C}
    assert table("tomato: ingredient\n").entries == {"tomato": ING}
    assert table("").entries == {}


@pytest.mark.parametrize(("text", "fragment", "place"), [
    ("objects:\n  knife: tool\n  pan: pot\n", "'pot' is not a category", "line 3"),
    ("objects: [knife]\n", "must map labels", "line 1"),
    ("- knife\n", "expected a mapping", "line 1"),
    ("objects:\n  knife: [tool]\n", "expected `label: category`", "line 2"),
    ("objects:\n  knife: tool\n bad: : :\n", "invalid YAML", "line 3"),
])
def test_bad_files_name_file_line_and_expectation(text: str, fragment: str, place: str) -> None:
    with pytest.raises(InputError, match=fragment) as error:
        table(text)
    assert error.value.path == "t.yaml"
    assert error.value.place == place


@pytest.mark.parametrize(("label", "category"), [
    ("knife", T), ("Knives", T), ("chef's knife", T), ("bread_knife_2", T),
    ("big red bowl", C), ("bowl_2", C), ("Chopping-Board", C),
    ("cherry tomatoes", ING), ("TOMATO_3", ING),
])
def test_categorize_normalises_and_falls_back_to_the_head_noun(label: str, category: Category) -> None:
    t = table("objects:\n  knife: tool\n  bowl: container\n  chopping board: container\n  tomato: ingredient\n")
    assert t.categorize(label) == category


def test_unknown_label() -> None:
    assert table("knife: tool\n").categorize("spaceship") is None


def test_categorize_all_lists_every_missing_label_with_a_hint(tmp_path: Path) -> None:
    t = table("knife: tool\ntomato: ingredient\n")
    assert t.categorize_all(["knife", "tomato_2"], "boxes.csv") == {"knife": T, "tomato_2": ING}
    with pytest.raises(InputError) as error:
        categorize_all(["knife", "gizmo", "widget", "gizmo"], tmp_path / "boxes.csv", t)
    message = str(error.value)
    assert message.startswith(str(tmp_path / "boxes.csv"))
    assert "'gizmo', 'widget'" in message and "knife" not in message
    assert ENV_VAR in message and "objects:" in message


def test_user_files_extend_and_override_later_wins(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    first = tmp_path / "a.yaml"
    first.write_text("objects:\n  gizmo: tool\n  bowl: ingredient\n")
    second = tmp_path / "b.yaml"
    second.write_text("objects:\n  bowl: container\n  widget: container\n")
    monkeypatch.delenv(ENV_VAR, raising=False)
    merged = load_categories([first, second])
    assert merged.categorize("gizmo") == T
    assert merged.categorize("bowl") == C
    assert merged.sources[-2:] == (str(first), str(second))
    env = tmp_path / "env.yaml"
    env.write_text("objects:\n  doohickey: ingredient\n  gizmo: container\n")
    monkeypatch.setenv(ENV_VAR, str(env))
    assert load_categories().categorize("doohickey") == ING
    assert load_categories([first]).categorize("gizmo") == T  # extra files come after the environment


def test_missing_user_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="cannot read") as error:
        load_categories([tmp_path / "nope.yaml"])
    assert error.value.path == str(tmp_path / "nope.yaml")


def test_derive_from_corpus_categories() -> None:
    derived = derive_categories(
        {"knife": "cutlery", "chopping_board": "utensils", "pot": "cookware", "tomato": "vegetables",
         "tap": "appliances"},
        aliases={"blade": "knife", "board": "chopping_board", "cherry_tomato": "tomato", "tomato": "tomato"},
        overrides={"chopping_board": C},
    )
    assert derived == {"knife": T, "blade": T, "board": C, "pot": C, "tomato": ING}


def test_format_round_trips() -> None:
    entries = {"knife": T, "rolling_pin": T, "bowl": C}
    assert table(format_categories(entries, "made by a test")).entries == entries


def test_shipped_table_covers_common_kitchen_objects(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(ENV_VAR, raising=False)
    shipped = load_categories()
    expected = {
        T: "knife spoon ladle spatula whisk peeler rolling_pin grater fork tongs foil plastic_wrap",
        C: "chopping_board cutting_board bowl pot pan plate tray cup jar bottle saucepan mug",
        ING: "tomato lemon dough onion carrot meat fish bread cheese oil salt butter egg potato olive courgette",
    }
    for category, names in expected.items():
        for name in names.split():
            assert shipped.categorize(name) == category, name
    assert shipped.categorize("wooden spoon_2") == T
    assert shipped.categorize("big red bowl") == C
