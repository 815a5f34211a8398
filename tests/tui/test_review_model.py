"""The view model (no Textual) and the key file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from tui_fake import fake_analyze, make_obs

from wecook_core.model import Corrections, Segment, SegmentStatus
from wecook_core.session.corrections import SetVerb
from wecook_tui import edits, review
from wecook_tui.keymap import load_keymap

SEGS = (Segment(0, 20), Segment(20, 40), Segment(40, 60))


def test_segment_index_clamps() -> None:
    assert [review.segment_index(SEGS, f) for f in (0, 19, 20, 59, 99, -3)] == [0, 0, 1, 2, 2, 0]


def test_status_explicit_then_corrected_then_unreviewed() -> None:
    corrections = Corrections(verbs={(20, "RH_P1"): "peel"}, status={0: SegmentStatus.REJECTED})
    assert review.status_of(corrections, 0) is SegmentStatus.REJECTED
    assert review.status_of(corrections, 20) is SegmentStatus.CORRECTED
    assert review.status_of(corrections, 40) is SegmentStatus.UNREVIEWED
    assert review.status_of(None, 0) is SegmentStatus.UNREVIEWED


def test_next_unreviewed_wraps_and_ends() -> None:
    status = Corrections(status={20: SegmentStatus.ACCEPTED})
    assert review.next_unreviewed(SEGS, status, 0) == 2
    assert review.next_unreviewed(SEGS, status, 2) == 0
    done = Corrections(status={s.start: SegmentStatus.ACCEPTED for s in SEGS})
    assert review.next_unreviewed(SEGS, done, 1) is None


def test_objects_near_hand_closest_first(tmp_path: Path) -> None:
    obs = make_obs(tmp_path / "v.avi")
    hand = review.hand_xy(obs, "RH_P1", 0)
    near = review.objects_near_hand(obs, "RH_P1", 0, SEGS[0])
    assert near[0][0] == "knife" and hand is not None
    distances = [d for _, d in near]
    assert distances == sorted(distances) and distances[0] == 0.0  # the hand is inside the knife's box
    assert {name for name, _ in near} == {"knife", "tomato", "chopping_board", "bowl"}


def test_link_candidates_never_tools_nor_the_held_object(tmp_path: Path) -> None:
    obs = make_obs(tmp_path / "v.avi")
    candidates = [name for name, _ in review.link_candidates(obs, "tomato", 0, SEGS[0])]
    assert candidates[0] == "chopping_board" and "knife" not in candidates and "tomato" not in candidates


def test_lanes_and_overlay_follow_the_analysis(tmp_path: Path) -> None:
    obs = make_obs(tmp_path / "v.avi")
    analysis = fake_analyze(obs, [SetVerb(20, "RH_P1", "peel")])
    lanes = review.lanes(analysis, ("LH_P1", "RH_P1"), 60)
    assert lanes[0].spans == ((0, 20, None), (20, 40, None), (40, 60, None))
    assert [label for _, _, label in lanes[1].spans] == ["cut", "peel", "cut"]
    overlay = review.overlay(obs, analysis.associations[0], 0, "RH_P1")
    assert {box.name for box in overlay.boxes if box.held} == {"knife"}
    assert len(overlay.links) == 3  # hand -> knife, knife -> tomato, knife -> board
    assert [hand.selected for hand in overlay.hands] == [True, False]
    assert review.segment_objects(analysis.associations[0], None, "RH_P1") == ("knife", "tomato", "chopping_board")
    assert np.isclose(overlay.hands[0].xy[0], 60.0)


def test_corrections_are_what_the_session_journals() -> None:
    from wecook_core.session.corrections import parse, to_record
    from wecook_core.session.journal import check_correction

    action = (SEGS[0].start, SEGS[2].end)
    records = [edits.set_status(SEGS[1], SegmentStatus.ACCEPTED), edits.set_verb(SEGS[0], "RH_P1", "peel"),
               edits.set_hand_object(SEGS[0], "LH_P1", None), edits.set_hand_object(SEGS[0], "LH_P1", "bowl"),
               edits.set_object_object(SEGS[2], "knife", ("tomato",)), edits.split(33), edits.merge(40),
               edits.set_verb(SEGS[1], "RH_P1", "peel", action)]
    assert [check_correction(r)[0] for r in records] == [
        "set_status", "set_verb", "set_hand_object", "set_hand_object", "set_object_object", "split", "merge",
        "set_verb"]
    assert all(parse(to_record(r)) == r for r in records)  # what the journal stores reads back the same
    whole = records[-1]
    assert (whole.segment, whole.end) == (SEGS[0].start, SEGS[2].end)  # the whole action's span
    assert records[1].end is None  # this segment only


def test_key_file(tmp_path: Path) -> None:
    path = tmp_path / "keys.toml"
    path.write_text('[keys]\naccept = "enter, a"\nundo = ["u", "ctrl+z"]\nbogus = "x"\nreject = 3\n')
    loaded = load_keymap(path, known_ids={"accept", "undo", "reject"})
    assert loaded.keymap == {"accept": "enter,a", "undo": "u,ctrl+z"}
    assert len(loaded.problems) == 2 and all(str(path) in p for p in loaded.problems)
    path.write_text("accept = 'y'\n")  # top-level entries work too
    assert load_keymap(path).keymap == {"accept": "y"}
    path.write_text("[keys\n")
    broken = load_keymap(path)
    assert broken.keymap == {} and "not a key file" in broken.problems[0]
    assert load_keymap(tmp_path / "absent.toml").keymap == {}
