from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from wecook_core.model import SegmentStatus
from wecook_core.session.journal import Journal, JournalChangedError, check_correction


def verb(segment: int, word: str, hand: str = "RH_P1") -> dict[str, object]:
    return {"op": "set_verb", "segment": segment, "hand": hand, "verb": word}


def test_every_op_folds_into_corrections(tmp_path: Path) -> None:
    journal = Journal(tmp_path / "journal.jsonl")
    journal.record({"op": "set_hand_object", "segment": 0, "hand": "LH_P1", "object": "bowl"})
    journal.record({"op": "set_hand_object", "segment": 30, "hand": "LH_P1", "object": None})
    journal.record({"op": "set_object_object", "segment": 0, "object": "knife", "targets": ["tomato", "board"]})
    journal.record(verb(0, "peel"))
    journal.record(verb(0, "cut"))  # later wins
    journal.record({"op": "set_status", "segment": 0, "status": "accepted"})
    for op, frame in [("split", 50), ("split", 70), ("merge", 30), ("merge", 70)]:  # merging a split undoes it
        journal.record({"op": op, "frame": frame})
    c = journal.corrections
    assert c.hand_object == {(0, "LH_P1"): "bowl", (30, "LH_P1"): None}
    assert c.object_object == {(0, "knife"): ("tomato", "board")}
    assert c.verbs == {(0, "RH_P1"): "cut"}
    assert c.status == {0: SegmentStatus.ACCEPTED}
    assert (c.splits, c.merges) == (frozenset({50}), frozenset({30}))
    assert [e.seq for e in journal.entries] == list(range(1, 11))


def test_undo_redo_and_a_new_correction_forgetting_the_redo(tmp_path: Path) -> None:
    journal = Journal(tmp_path / "journal.jsonl")
    assert journal.undo() is None and journal.redo() is None
    for word in ("cut", "peel", "stir"):
        journal.record(verb(0, word))
    assert journal.undo() is not None and journal.undo() is not None
    assert journal.corrections.verbs == {(0, "RH_P1"): "cut"}
    redo = journal.redo()
    assert redo is not None and redo.op == "redo" and redo.fields == {"target": 2}
    assert journal.corrections.verbs == {(0, "RH_P1"): "peel"}
    journal.record(verb(0, "roll"))
    assert not journal.can_redo
    assert journal.undo() is not None and journal.undo() is not None and journal.undo() is not None
    assert journal.corrections.verbs == {} and not journal.can_undo and journal.undo() is None
    assert [e.op for e in journal.entries][-3:] == ["undo", "undo", "undo"]


def test_undo_and_redo_survive_reopening(tmp_path: Path) -> None:
    path = tmp_path / "journal.jsonl"
    journal = Journal(path)
    for frame in (10, 20, 30):
        journal.record({"op": "split", "frame": frame})
    journal.undo()
    journal.undo()
    again = Journal(path)
    assert again.warnings == []
    assert again.corrections.splits == frozenset({10})
    assert again.can_undo and again.can_redo
    again.redo()
    assert Journal(path).corrections.splits == frozenset({10, 20})
    third = Journal(path)
    third.redo()
    third.undo()
    third.undo()
    third.undo()
    assert Journal(path).corrections.splits == frozenset()
    assert Journal(path).can_redo and not Journal(path).can_undo


def test_the_line_is_on_disk_and_fsynced_before_record_returns(tmp_path: Path, monkeypatch: pytest.MonkeyPatch
                                                                ) -> None:
    path = tmp_path / "journal.jsonl"
    journal = Journal(path)
    synced: list[bytes] = []
    real_fsync = os.fsync

    def fsync(fd: int) -> None:
        real_fsync(fd)
        synced.append(path.read_bytes())

    monkeypatch.setattr(os, "fsync", fsync)
    entry = journal.record(verb(12, "stir"))
    assert len(synced) == 1
    line = synced[0].decode()
    assert line.endswith("\n") and json.loads(line) == {"seq": 1, "time": entry.time, "op": "set_verb",
                                                        "segment": 12, "hand": "RH_P1", "verb": "stir"}


def test_a_failed_fsync_leaves_nothing_behind(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "journal.jsonl"
    journal = Journal(path)
    journal.record(verb(0, "cut"))
    real_fsync = os.fsync
    calls = []

    def failing(fd: int) -> None:
        calls.append(fd)
        if len(calls) == 1:
            raise OSError(5, "Input/output error")
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", failing)
    with pytest.raises(OSError, match="Input/output"):
        journal.record(verb(0, "peel"))
    assert journal.corrections.verbs == {(0, "RH_P1"): "cut"} and len(journal.entries) == 1
    assert len(path.read_bytes().splitlines()) == 1  # the line that was not acknowledged was cut off
    journal.record(verb(0, "stir"))
    reopened = Journal(path)
    assert reopened.warnings == [] and [e.seq for e in reopened.entries] == [1, 2]
    assert reopened.corrections.verbs == {(0, "RH_P1"): "stir"}


def test_a_torn_last_line_is_reported_skipped_and_set_aside(tmp_path: Path) -> None:
    path = tmp_path / "journal.jsonl"
    journal = Journal(path)
    journal.record(verb(0, "cut"))
    journal.record(verb(5, "peel"))
    with path.open("ab") as handle:
        handle.write(b'{"seq":3,"time":"2026-01-01T00:00:00Z","op":"set_ve')  # the crash
    torn = Journal(path)
    assert len(torn.warnings) == 1 and "last line is torn" in torn.warnings[0]
    assert torn.corrections.verbs == {(0, "RH_P1"): "cut", (5, "RH_P1"): "peel"}
    torn.record(verb(9, "stir"))
    assert (tmp_path / "journal.jsonl.torn").read_bytes().startswith(b'{"seq":3')
    healed = Journal(path)
    assert healed.warnings == []
    assert [e.seq for e in healed.entries] == [1, 2, 3]
    assert healed.corrections.verbs[(9, "RH_P1")] == "stir"


def test_a_complete_last_line_without_its_newline_counts(tmp_path: Path) -> None:
    path = tmp_path / "journal.jsonl"
    Journal(path).record(verb(0, "cut"))
    path.write_bytes(path.read_bytes().rstrip(b"\n"))
    journal = Journal(path)
    assert journal.warnings == [] and journal.corrections.verbs == {(0, "RH_P1"): "cut"}
    journal.record(verb(1, "dip"))
    assert len(path.read_bytes().splitlines()) == 2
    assert Journal(path).corrections.verbs == {(0, "RH_P1"): "cut", (1, "RH_P1"): "dip"}


def test_unreadable_lines_and_undo_that_does_not_fit_are_warnings(tmp_path: Path) -> None:
    path = tmp_path / "journal.jsonl"
    path.write_text(
        '{"seq":1,"time":"t","op":"set_verb","segment":0,"hand":"RH_P1","verb":"cut"}\n'
        "garbage\n"
        '{"seq":2,"time":"t","op":"set_verb","segment":0,"hand":"XX","verb":"cut"}\n'
        '{"seq":3,"time":"t","op":"undo","target":7}\n'
        '{"seq":1,"time":"t","op":"split","frame":3}\n'
        "[1]\n"
    )
    journal = Journal(path)
    assert len(journal.warnings) == 5
    assert "line 2" in journal.warnings[0] and "not JSON" in journal.warnings[0]
    assert "line 3" in journal.warnings[1] and "hand" in journal.warnings[1]
    assert "line 5" in journal.warnings[2] and "seq 1 again" in journal.warnings[2]
    assert "line 6" in journal.warnings[3]
    assert "undo of 7" in journal.warnings[4]
    assert journal.corrections.verbs == {(0, "RH_P1"): "cut"}
    assert journal.record(verb(1, "cut")).seq == 4


def test_a_second_writer_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "journal.jsonl"
    first, second = Journal(path), Journal(path)
    first.record(verb(0, "cut"))
    with pytest.raises(JournalChangedError, match="reopen"):
        second.record(verb(0, "peel"))
    assert Journal(path).corrections.verbs == {(0, "RH_P1"): "cut"}


@pytest.mark.parametrize(
    ("correction", "message"),
    [
        ({"op": "paint"}, "unknown correction op"),
        ({"op": "split"}, "missing field 'frame'"),
        ({"op": "split", "frame": -1}, "frame index"),
        ({"op": "split", "frame": True}, "frame index"),
        ({"op": "split", "frame": 3, "why": "x"}, "unexpected fields why"),
        ({"op": "set_verb", "segment": 0, "hand": "RH_P3", "verb": "cut"}, "hand must be one of"),
        ({"op": "set_verb", "segment": 0, "hand": "RH_P1", "verb": "juggle"}, "verb must be one of"),
        ({"op": "set_status", "segment": 0, "status": "great"}, "status must be one of"),
        ({"op": "set_object_object", "segment": 0, "object": "knife", "targets": "pot"}, "list of object names"),
        ({"op": "set_hand_object", "segment": 0, "hand": "RH_P1", "object": ""}, "object name"),
        ({"op": "set_hand_object", "segment": 0, "hand": "RH_P1"}, "missing field 'object'"),  # null, not absent
        ({"op": "set_object_object", "segment": 0, "object": None, "targets": []}, "object must be an object name"),
        ({"op": "set_verb", "segment": None, "hand": "RH_P1", "verb": "cut"}, "segment must be a frame index"),
        ({"op": "box_keyframe", "track": 0, "frame": 1, "box": [0, 0, 5, 5]}, "track must be a drawn track id"),
        ({"op": "box_keyframe", "track": 1, "frame": 1, "box": [0, 0, 0, 5]}, "x1 < x2"),
        ({"op": "box_keyframe", "track": 1, "frame": 1, "box": [0, 0, 2e6, 5]}, "box .x1, y1, x2, y2. of pixels"),
        ({"op": "box_keyframe", "track": 1, "frame": 1, "box": [0, 0, 5, 5], "label": ""}, "label must be an"),
        ({"op": "box_label", "track": 1, "label": None}, "label must be an object name"),
        ({"op": "box_tracked", "track": 1, "frames": [1], "boxes": "x"}, "boxes must be a list of boxes"),
        ({"op": "box_tracked", "track": 1, "frames": [-1], "boxes": []}, "frames must be a list of frame indices"),
        ({"op": "set_category", "label": "x", "category": "robot"}, "category must be one of"),
    ],
)
def test_malformed_corrections_are_refused(correction: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        check_correction(correction)


@pytest.mark.parametrize(
    "correction",
    [
        {"op": "set_hand_object", "segment": 0, "hand": "RH_P1", "object": None},
        {"op": "set_verb", "segment": 0, "hand": "RH_P1", "verb": "cut", "end": None},
        {"op": "box_keyframe", "track": 1, "frame": 1, "box": [0, 0, 5, 5]},
        {"op": "box_keyframe", "track": 1, "frame": 1, "box": [0, 0, 5, 5], "label": None},
        {"op": "box_tracked", "track": 1, "frames": [1], "boxes": [[0, 0, 5, 5]]},
        {"op": "box_tracked", "track": 1, "frames": [], "boxes": [], "lost_at": None},
    ],
)
def test_optional_fields_may_be_null_or_absent(correction: dict[str, object]) -> None:
    from wecook_core.session.corrections import parse, to_record

    parsed = parse(correction)
    assert to_record(parsed) == {k: v for k, v in correction.items() if not (k == "end" and v is None)} | (
        {"label": None} if correction["op"] == "box_keyframe" and "label" not in correction else {}) | (
        {"lost_at": None} if correction["op"] == "box_tracked" and "lost_at" not in correction else {})


def test_typed_corrections_round_trip_and_span_corrections_cover_their_action(tmp_path: Path) -> None:
    from wecook_core.model import Segment
    from wecook_core.session.corrections import SetStatus, SetVerb, Split, fold, parse, to_record

    path = tmp_path / "journal.jsonl"
    old = [{"seq": 1, "time": "t", "op": "set_verb", "segment": 0, "hand": "RH_P1", "verb": "peel"},
           {"seq": 2, "time": "t", "op": "set_status", "segment": 30, "status": "rejected"}]
    path.write_text("".join(json.dumps(line) + "\n" for line in old))  # a journal from before typed corrections
    journal = Journal(path)
    assert journal.applied_corrections == (SetVerb(0, "RH_P1", "peel"), SetStatus(30, SegmentStatus.REJECTED))
    whole = SetVerb(30, "LH_P1", "stir", end=90)
    journal.record(whole)
    journal.record(Split(45))
    assert json.loads(path.read_text().splitlines()[2])["end"] == 90
    again = Journal(path)
    assert again.applied_corrections[-2:] == (whole, Split(45))
    segments = (Segment(0, 30), Segment(30, 45), Segment(45, 60), Segment(60, 88), Segment(88, 100))
    folded = fold(again.applied_corrections, segments)
    assert {k: v for k, v in folded.verbs.items() if k[1] == "LH_P1"} == {
        (30, "LH_P1"): "stir", (45, "LH_P1"): "stir", (60, "LH_P1"): "stir"}  # not [88, 100): 2 of its 12 frames
    assert fold(again.applied_corrections).verbs[(30, "LH_P1")] == "stir"  # no segmentation: its first segment
    assert all(parse(to_record(c)) == c for c in again.applied_corrections)
    with pytest.raises(ValueError, match="end must be after segment"):
        parse({"op": "set_verb", "segment": 30, "hand": "LH_P1", "verb": "stir", "end": 30})
