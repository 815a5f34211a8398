from __future__ import annotations

import itertools

from handmade_scenes import cutting, handing_over, holding, observations, pouring, squeezing, still, transferring

from wecook_core.model import ActionKind, Category, Corrections, Segment, Segmentation
from wecook_core.perception.association.associate import associate_segments
from wecook_core.perception.params import Params
from wecook_core.perception.recognition.actions import handover_events, hold_spans, recognize_actions, transfer_events


def recognise(obs, cuts, knowledge, corrections=None):
    edges = [0, *cuts, obs.video.frame_count]
    segmentation = Segmentation({}, tuple(Segment(a, b) for a, b in itertools.pairwise(edges)))
    associations, timeline = associate_segments(obs, segmentation.segments, Params(), corrections)
    return recognize_actions(obs, segmentation, associations, knowledge, Params(), corrections, timeline)


def test_a_held_knife_near_a_tomato_on_a_board_cuts_it(knowledge):
    per_segment = recognise(cutting(), [30, 60, 120], knowledge)
    assert per_segment[0].actions == ()
    action = per_segment[2].action_of("RH_P1")
    assert action is not None and action.kind is ActionKind.TOOL
    assert (action.verb, action.held, action.targets) == ("cut", "knife", ("tomato", "chopping_board"))
    assert action.scores[0][0] == "cut" and per_segment[2].rankings["RH_P1"] == action.scores


def test_a_knife_near_nothing_is_a_grasp(knowledge):
    knife = (300, 100, 380, 115)
    obs = observations(30, {"knife": (Category.TOOL, [still(0, 30, knife)]),
                            "pot": (Category.CONTAINER, [still(0, 30, (500, 300, 600, 400))])},
                       {"RH_P1": [still(0, 30, (290, 95, 320, 125))]})
    (only,) = recognise(obs, [], knowledge)
    assert [(a.kind, a.held, a.verb) for a in only.actions] == [(ActionKind.GRASP, "knife", None)]


def test_a_still_hand_on_a_lifted_lemon_squeezes_it(knowledge):
    (only,) = recognise(squeezing(), [], knowledge)
    action = only.action_of("LH_P1")
    assert action is not None
    assert (action.kind, action.verb, action.held, action.targets) == (ActionKind.HAND, "squeeze", None, ("lemon",))


def test_a_held_oil_bottle_over_a_pot_pours(knowledge):
    per_segment = recognise(pouring(), [30, 90], knowledge)
    action = per_segment[1].action_of("RH_P1")
    assert action is not None
    assert (action.kind, action.verb, action.held, action.targets) == (ActionKind.TOOL, "pour", "oil", ("pot",))


def test_an_ingredient_carried_by_a_spoon_to_another_container_is_a_transfer(knowledge):
    obs = transferring()
    _associations, timeline = associate_segments(obs, (Segment(0, 150),), Params())
    (event,) = transfer_events(obs, timeline, Params())
    assert (event.ingredient, event.source, event.destination, event.hand, event.carrier) == \
        ("meat", "bowl", "pot", "RH_P1", "spoon")
    assert event.start <= 5 and event.end >= 100
    per_segment = recognise(obs, [45, 90, 105], knowledge)
    kinds = [s.action_of("RH_P1").kind for s in per_segment]
    assert kinds[:3] == [ActionKind.TRANSFER] * 3
    assert per_segment[1].action_of("RH_P1").targets == ("meat", "bowl", "pot")


def test_an_object_passing_between_persons_is_a_handover(knowledge):
    obs = handing_over()
    _, timeline = associate_segments(obs, (Segment(0, 120),), Params())
    (event,) = handover_events(timeline, Params())
    assert (event.obj, event.giver, event.receiver) == ("knife", "RH_P1", "LH_P2")
    assert 40 <= event.start < event.end <= 65
    per_segment = recognise(obs, [40, 55, 70], knowledge)
    exchange = per_segment[2]
    action = exchange.action_of("RH_P1")
    assert action is not None and action.kind is ActionKind.HANDOVER
    assert action.partner is not None and (action.partner.kind, action.partner.hand) == (ActionKind.GRASP, "LH_P2")
    assert exchange.partners == ("LH_P2",) and exchange.action_of("LH_P2") is None


def test_holding_the_board_while_the_other_person_cuts_on_it(knowledge):
    per_segment = recognise(holding(), [30, 90], knowledge)
    middle = per_segment[1]
    action = middle.action_of("LH_P1")
    assert action is not None and action.kind is ActionKind.HOLDING and action.held == "chopping_board"
    partner = action.partner
    assert partner is not None
    assert (partner.hand, partner.verb, partner.held, partner.targets) == ("RH_P2", "cut", "knife", ("tomato",))
    assert middle.partners == ("RH_P2",)


def test_a_verb_correction_replaces_the_recognised_verb(knowledge):
    corrections = Corrections(verbs={(60, "RH_P1"): "peel"})
    per_segment = recognise(cutting(), [30, 60, 120], knowledge, corrections)
    assert per_segment[2].action_of("RH_P1").verb == "peel"
    assert per_segment[1].action_of("RH_P1").verb != "peel"


def test_hold_spans_bridge_short_gaps():
    import numpy as np

    labels = np.array([0] * 10 + [-1] * 3 + [0] * 10 + [-1] * 20 + [0] * 5)
    assert hold_spans(labels, 0, 8) == [(0, 23)]


def test_a_brief_still_hand_on_a_bottle_only_grasps_it_a_long_one_on_an_egg_peels_it(knowledge):
    # hands squeeze lemons, not oil: a short pause on a bottle is a grasp, since the commonsense share of the
    # hand verbs is small; an ingredient held still for longer than min_action_s is worked by the hand
    # whatever that share (peel the egg), and rolling, which moves the hand, is never what a still hand does
    bottle = (300, 150, 320, 190)
    obs = observations(20, {"oil": (Category.INGREDIENT, [still(0, 20, bottle)])},
                       {"RH_P1": [still(0, 20, (295, 160, 325, 190))]})
    (only,) = recognise(obs, [], knowledge)
    assert [(a.kind, a.held) for a in only.actions] == [(ActionKind.GRASP, "oil")]
    egg = observations(90, {"egg": (Category.INGREDIENT, [still(0, 90, bottle)])},
                       {"RH_P1": [still(0, 90, (295, 160, 325, 190))]})
    (only,) = recognise(egg, [], knowledge)
    (action,) = only.actions
    assert action.kind is ActionKind.HAND and action.targets == ("egg",)
    assert action.verb in ("squeeze", "peel", "wrap") and "roll" not in dict(action.scores)


def test_a_lemon_carried_across_the_table_is_grasped_not_squeezed(knowledge):
    lemon = [(0, 60, (100, 150, 130, 180), (500, 150, 530, 180))]
    hand = [(0, 60, (105, 160, 135, 190), (505, 160, 535, 190))]
    obs = observations(60, {"lemon": (Category.INGREDIENT, lemon)}, {"LH_P1": hand})
    (only,) = recognise(obs, [], knowledge)
    assert [(a.kind, a.held) for a in only.actions] == [(ActionKind.GRASP, "lemon")]


def circling(frame_count: int = 150, *, with_hand: bool = True):
    """A whisk goes round in circles (radius 15 px, one turn a second) inside a pot over 30-120, brought there
    and taken back by RH_P1 (or, without the hand, the detector never sees the hand)."""
    import math

    pot = (300, 300, 450, 420)
    rest, centre = (100, 100, 120, 160), (375, 330)
    whisk = [(0, 30, rest, (365, 300, 385, 360))]
    hand = [(0, 30, (95, 95, 125, 125), (360, 295, 390, 325))]
    for frame in range(30, 120):
        angle = 2 * math.pi * (frame - 30) / 30
        x, y = centre[0] + 15 * math.cos(angle), centre[1] + 15 * math.sin(angle)
        whisk.append(still(frame, frame + 1, (x - 10, y - 30, x + 10, y + 30)))
        hand.append(still(frame, frame + 1, (x - 15, y - 35, x + 15, y - 5)))
    whisk.append((120, frame_count, whisk[-1][2], rest))
    hand.append((120, frame_count, hand[-1][2], (95, 95, 125, 125)))
    return observations(frame_count, {"pot": (Category.CONTAINER, [still(0, frame_count, pot)]),
                                      "whisk": (Category.TOOL, whisk)}, {"RH_P1": hand} if with_hand else {})


def test_a_tool_going_round_in_circles_in_a_pot_stirs_it(knowledge):
    from wecook_core.knowledge.recognize import rank

    per_segment = recognise(circling(), [30, 120], knowledge)
    action = per_segment[1].action_of("RH_P1")
    assert action is not None and (action.verb, action.held, action.targets) == ("stir", "whisk", ("pot",))
    # what commonsense alone would have said for a whisk over a pot (pour, on the EPIC tables)
    assert rank(knowledge, ["whisk", "pot"], ["stir", "pour"])[0][0] in ("stir", "pour")


def test_salt_shaken_over_a_pan_is_sprinkled_a_bottle_tipped_over_it_is_poured(knowledge):
    # commonsense (EPIC) ranks pour far above sprinkle for salt over a pan; the box's own motion decides
    from handmade_scenes import at
    from test_associate import PAN, shaking_over_the_pan

    (shaking,) = recognise(shaking_over_the_pan(), [40, 90], knowledge)[1:2]
    action = shaking.action_of("RH_P1")
    assert action is not None and (action.verb, action.held, action.targets) == ("sprinkle", "salt", ("pan",))
    upright, tipped = (360, 260, 380, 310), (375, 275, 425, 295)  # 20 x 50, then lying 50 x 20, moved on
    hand = (355, 250, 385, 280)
    bottle = [(0, 30, upright, upright), (30, 60, upright, tipped), (60, 90, tipped, tipped)]
    obs = observations(90, {"pan": (Category.CONTAINER, [still(0, 90, PAN)]),
                            "salt": (Category.INGREDIENT, bottle)},
                       {"RH_P1": [still(0, 30, hand), (30, 60, hand, at(hand, 30, 0)), still(60, 90, at(hand, 30, 0))]})
    (only,) = recognise(obs, [], knowledge)
    action = only.action_of("RH_P1")
    assert action is not None and (action.verb, action.held, action.targets) == ("pour", "salt", ("pan",))


def test_a_held_tool_is_never_poured_whatever_the_tables_say() -> None:
    """Tables that rank pour first for a knife, a tomato and a board (a corpus full of "pour tomato onto the
    board") still give a tool verb: pour, sprinkle and dip are done with the held ingredient itself."""
    from wecook_core.knowledge.corpus import Corpus, Record
    from wecook_core.knowledge.learning import learn

    records = [Record("pour", ("knife", "tomato", "chopping_board"), f"g{i}") for i in range(20)]
    records += [Record("cut", ("knife", "tomato"), "c0"), Record("stir", ("spoon", "pot"), "s0")]
    skewed = learn(Corpus(tuple(records)), per_group=False)
    assert skewed.verbs and rank_first(skewed, ["knife", "tomato", "chopping_board"]) == "pour"
    action = recognise(cutting(), [30, 60, 120], skewed)[2].action_of("RH_P1")
    assert action is not None and action.held == "knife" and action.verb == "cut"


def rank_first(knowledge, objects) -> str:
    from wecook_core.knowledge.recognize import rank

    return rank(knowledge, objects)[0][0]


def test_rankings_are_remembered_by_the_analysis_that_asked_for_them(monkeypatch):
    import numpy as np

    from wecook_core.knowledge.recognize import Knowledge, rank
    from wecook_core.perception.recognition import actions

    verbs, objects = ("cut", "stir", "pour"), ("knife", "spoon", "pot")
    cutting_table = Knowledge(verbs, objects, np.array([1, 1, 1]), np.array([[5, 0, 1], [0, 5, 1], [0, 0, 5]]))
    stirring_table = Knowledge(verbs, objects, np.array([1, 1, 1]), np.array([[0, 0, 1], [5, 5, 1], [0, 0, 5]]))
    cutting = actions.Ranker(cutting_table)
    first = cutting.rank(["knife"])
    assert first == rank(cutting_table, ["knife"], list(verbs)) and first[0][0] == "cut"
    assert cutting.rank(("knife",)) is first  # the same objects: remembered
    assert actions.Ranker(stirring_table).rank(["knife"])[0][0] == "stir"  # another table: its own ranking
    narrowed = cutting.rank(["knife"], ("stir", "pour"))
    assert narrowed == rank(cutting_table, ["knife"], ["stir", "pour"]) and len(narrowed) == 2
    assert actions.Ranker(cutting_table).rank(["knife"]) is not first  # nothing shared between analyses

    monkeypatch.setattr(actions, "RANKINGS_KEPT", 2)
    for names in (["pot"], ["spoon"], ["knife", "pot"]):
        assert cutting.rank(names) == rank(cutting_table, names, list(verbs))
        assert len(cutting._known) <= 2
