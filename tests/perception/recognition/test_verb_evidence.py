"""What decides a verb besides the commonsense tables: the tool in the hand, the motion of an ingredient the
hand works, the handover a hold ends in, and where a held object lies at the ends of its hold."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from handmade_scenes import HAND_AWAY, at, observations, still

from wecook_core.model import ActionKind, Associations, Category, Segment, Segmentation
from wecook_core.perception.association.associate import associate_segments
from wecook_core.perception.params import Params
from wecook_core.perception.pipeline import analyze
from wecook_core.perception.recognition.actions import afforded, individual_action, recognize_actions
from wecook_core.perception.recognition.motion import motion_of, verbs_of
from wecook_core.trees.notation import format_tree


def recognise(obs, cuts, knowledge):
    edges = [0, *cuts, obs.video.frame_count]
    segmentation = Segmentation({}, tuple(Segment(a, b) for a, b in itertools.pairwise(edges)))
    associations, timeline = associate_segments(obs, segmentation.segments, Params())
    return recognize_actions(obs, segmentation, associations, knowledge, Params(), None, timeline)


def board_tables():
    """Tables where a board says "cut" far louder than a peeler says "peel": 232 cuts, all on boards (two of
    them with a peeler about), 20 peels with a peeler."""
    from wecook_core.knowledge.corpus import Corpus, Record
    from wecook_core.knowledge.learning import learn

    records = [Record("cut", ("knife", "cucumber", "chopping_board"), f"c{i}") for i in range(30)]
    records += [Record("cut", ("chopping_board",), f"b{i}") for i in range(200)]
    records += [Record("cut", ("peeler", "chopping_board"), f"x{i}") for i in range(2)]
    records += [Record("peel", ("peeler", "cucumber"), f"p{i}") for i in range(20)]
    records += [Record("stir", ("spoon", "pot"), f"s{i}") for i in range(6)]
    return learn(Corpus(tuple(records)), per_group=False, alpha=0.1)


def test_the_held_peeler_peels_the_cucumber_on_the_board_whatever_the_board_says() -> None:
    from wecook_core.knowledge.recognize import rank

    tables = board_tables()
    assert rank(tables, ["peeler", "cucumber", "chopping_board"])[0][0] == "cut"  # what the product says
    assert afforded(tables, "peeler") == ("peel",)
    assert "cut" in afforded(tables, "knife")
    board, cucumber = (100, 300, 400, 450), (200, 340, 260, 370)
    rest, work = (500, 300, 560, 315), (205, 345, 265, 360)
    hand_on, hand_work = (530, 295, 560, 325), (235, 340, 265, 370)
    obs = observations(150, {
        "chopping_board": (Category.CONTAINER, [still(0, 150, board)]),
        "cucumber": (Category.INGREDIENT, [still(0, 150, cucumber)]),
        "peeler": (Category.TOOL, [still(0, 30, rest), (30, 60, rest, work), still(60, 120, work),
                                   (120, 150, work, rest)])},
        {"RH_P1": [(0, 30, (580, 150, 620, 190), hand_on), (30, 60, hand_on, hand_work), still(60, 120, hand_work),
                   (120, 150, hand_work, hand_on)]})
    action = recognise(obs, [30, 60, 120], tables)[2].action_of("RH_P1")
    assert action is not None and (action.kind, action.held, action.verb) == (ActionKind.TOOL, "peeler", "peel")
    assert action.targets == ("cucumber", "chopping_board")


def worked(frame_count: int, stroke: float, seed: int = 0):
    """RH_P1 holds an egg (30 x 30 px) in the air over the whole video, moving it back and forth by
    ``stroke`` pixels once a second, boxes jittering by about a pixel."""
    rng = np.random.default_rng(seed)
    t = np.arange(frame_count) / 30.0
    dx = stroke * np.sin(2 * np.pi * t) + rng.normal(0, 1.0, frame_count)
    egg = [still(f, f + 1, at((300, 150, 330, 180), dx[f])) for f in range(frame_count)]
    hand = [still(f, f + 1, at((305, 160, 335, 190), dx[f])) for f in range(frame_count)]
    return observations(frame_count, {"egg": (Category.INGREDIENT, egg)}, {"RH_P1": hand})


def test_an_ingredient_stroked_by_the_hand_is_peeled_one_gripped_in_place_is_squeezed(knowledge) -> None:
    def boxes(obs):
        return obs.object("egg").boxes

    assert verbs_of(motion_of(boxes(worked(120, 0.0)), 30.0), "hand") == {"squeeze"}
    assert "peel" in verbs_of(motion_of(boxes(worked(120, 6.0)), 30.0), "hand")
    for stroke, verb in ((0.0, "squeeze"), (6.0, "peel")):
        (only,) = recognise(worked(120, stroke), [], knowledge)
        (action,) = only.actions
        assert (action.kind, action.targets, action.verb) == (ActionKind.HAND, ("egg",), verb)


def test_a_pause_with_what_is_then_handed_over_is_its_grasp_not_hand_work(knowledge) -> None:
    """RH_P1 takes the garlic, holds it still for 1.5 s, carries it to the middle, LH_P2 takes it away."""
    garlic, middle, right = (100, 200, 125, 225), (290, 200, 315, 225), (480, 200, 505, 225)
    p1, p1_mid = (95, 195, 125, 225), (285, 195, 315, 225)
    p2_mid, p2_far = (295, 195, 325, 225), (560, 100, 590, 130)
    obs = observations(150, {
        "garlic": (Category.INGREDIENT, [still(0, 60, garlic), (60, 90, garlic, middle), still(90, 100, middle),
                                         (100, 150, middle, right)])},
        {"RH_P1": [(0, 15, (60, 100, 90, 130), p1), still(15, 60, p1), (60, 90, p1, p1_mid), still(90, 100, p1_mid),
                   (100, 150, p1_mid, (60, 100, 90, 130))],
         "LH_P2": [(0, 80, p2_far, p2_mid), still(80, 100, p2_mid), (100, 150, p2_mid, at(right, -5, -5))]})
    per_segment = recognise(obs, [15, 60, 90, 100], knowledge)
    giver = [s.action_of("RH_P1") for s in per_segment]
    assert all(a is None or a.kind is not ActionKind.HAND for a in giver)
    assert any(a is not None and a.kind is ActionKind.HANDOVER and a.held == "garlic" for a in giver)
    assert giver[1] is not None and giver[1].kind is ActionKind.GRASP


def test_bread_lying_beside_a_cup_is_not_dipped_into_it_nor_a_knife_laid_down_beside_a_plate_cutting_it(
        knowledge) -> None:
    """RH_P1 grasps the bread lying 10 px below the cup, pauses, takes it over the bowl and dips it there;
    then takes the knife from the board and lays it down 10 px beside the plate."""
    cup, bowl, plate = (300, 300, 340, 340), (100, 80, 200, 160), (450, 300, 540, 390)
    bread, dipped = (300, 350, 340, 380), (130, 100, 170, 130)
    knife_on_board, knife_home = (100, 400, 170, 410), (460, 400, 530, 410)
    grip, over = at(bread, 5, 5), at(dipped, 5, 5)
    obs = observations(300, {
        "cup": (Category.CONTAINER, [still(0, 300, cup)]),
        "bowl": (Category.CONTAINER, [still(0, 300, bowl)]),
        "plate": (Category.CONTAINER, [still(0, 300, plate)]),
        "bread": (Category.INGREDIENT, [still(0, 50, bread), (50, 70, bread, dipped), still(70, 110, dipped),
                                        (110, 130, dipped, bread), still(130, 300, bread)]),
        "knife": (Category.TOOL, [still(0, 180, knife_on_board), (180, 210, knife_on_board, knife_home),
                                  still(210, 300, knife_home)])},
        {"RH_P1": [(0, 20, (600, 200, 630, 230), grip), still(20, 50, grip), (50, 70, grip, over),
                   still(70, 110, over), (110, 130, over, grip), (130, 150, grip, (600, 200, 630, 230)),
                   (150, 170, (600, 200, 630, 230), (95, 395, 125, 415)), still(170, 180, (95, 395, 125, 415)),
                   (180, 210, (95, 395, 125, 415), (455, 395, 485, 415)), still(210, 250, (455, 395, 485, 415)),
                   (250, 300, (455, 395, 485, 415), (600, 200, 630, 230))]})
    per_segment = recognise(obs, [20, 50, 70, 110, 130, 170, 180, 210, 250], knowledge)
    actions = [s.action_of("RH_P1") for s in per_segment]
    targets = {t for a in actions if a is not None for t in a.targets}
    assert "cup" not in targets and "plate" not in targets
    dip = actions[3]
    assert dip is not None and (dip.held, dip.targets) == ("bread", ("bowl",))


def sheet_tables():
    """Tables where foil mostly wraps (and is now and then cut), and a whisk and a brush now and then wrap."""
    from wecook_core.knowledge.corpus import Corpus, Record
    from wecook_core.knowledge.learning import learn

    records = [Record("wrap", ("foil", "dish"), f"w{i}") for i in range(20)]
    records += [Record("cut", ("foil",), f"c{i}") for i in range(3)]
    records += [Record("stir", ("whisk", "bowl"), f"s{i}") for i in range(30)]
    records += [Record("wrap", ("whisk",), f"x{i}") for i in range(6)]
    records += [Record("spread", ("brush", "dish"), f"b{i}") for i in range(10)]
    records += [Record("wrap", ("brush",), f"y{i}") for i in range(6)]
    return learn(Corpus(tuple(records)), per_group=False, alpha=0.1)


def test_a_sheet_of_foil_laid_over_a_dish_wraps_it() -> None:
    """Foil is held like a tool but only wraps; a whisk or a brush the tables also tie to wrap does not."""

    tables = sheet_tables()
    assert afforded(tables, "foil") == ("wrap",)
    assert "wrap" not in afforded(tables, "whisk")
    assert "wrap" not in afforded(tables, "brush")
    dish = (300, 250, 460, 370)
    foil_rest, foil_over = (60, 100, 160, 160), (290, 240, 470, 300)
    hand_rest, hand_over = (90, 110, 140, 160), (320, 245, 370, 295)
    obs = observations(120, {
        "dish": (Category.CONTAINER, [still(0, 120, dish)]),
        "foil": (Category.TOOL, [still(0, 20, foil_rest), (20, 50, foil_rest, foil_over), still(50, 90, foil_over),
                                 (90, 110, foil_over, at(foil_over, 10, 60)), still(110, 120, at(foil_over, 10, 60))]),
    }, {"RH_P1": [still(0, 20, hand_rest), (20, 50, hand_rest, hand_over), still(50, 90, hand_over),
                  (90, 110, hand_over, at(hand_over, 10, 60)), (110, 120, at(hand_over, 10, 60), HAND_AWAY)]})
    trees = [format_tree(t.tree) for t in analyze(obs, tables, Params()).trees]
    assert "(HP (HP (H RH_P1) (O foil)) (AP (A wrap) (O dish)))" in trees, trees


@pytest.mark.parametrize(("ingredient", "container", "verb"), [
    ("chicken", "bowl", "dip"), ("salt", "bowl", "sprinkle"), ("spinach", "pan", "dip"), ("oil", "pot", "pour"),
    ("bread", "cup", "dip"), ("pepper", "pan", "sprinkle"), ("water", "pan", "pour"),
])
def test_a_held_ingredient_over_a_container_is_named_by_what_it_is_not_by_what_receives_it(
        knowledge, ingredient: str, container: str, verb: str) -> None:
    """Rule C3a: held over a container, and its own motion saying nothing (``moves`` None), the ingredient
    decides between pour, sprinkle and dip. The container receives all three; the recipes name a destination
    with pour far more often ("pour into a bowl") than with sprinkle or dip, and with it in the ranking every
    ingredient over a bowl or a pan was poured (the old code: chicken, salt, spinach and bread)."""
    links = Associations(Segment(0, 60), {"RH_P1": ingredient}, {ingredient: (container,)}, {})
    categories = {ingredient: Category.INGREDIENT, container: Category.CONTAINER}
    action, ranking = individual_action("RH_P1", links, categories, knowledge)
    assert action is not None and (action.held, action.targets, action.verb) == (ingredient, (container,), verb), \
        ranking
    assert {v for v, _ in ranking} == {"pour", "sprinkle", "dip"}
