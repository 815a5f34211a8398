"""Boxes drawn in the box mode and categories given to unknown labels are journaled corrections: one fold
replays them, undo and redo take them back and bring them again, reopening keeps them, and the analysis of a
session made from a video alone runs on them."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from wecook_core.formats.native import read_objects_csv
from wecook_core.model import Category, SegmentStatus
from wecook_core.observations.tracking import BoxTrack
from wecook_core.session.boxes import (
    DropBoxKeyframe,
    SetBoxKeyframe,
    SetBoxLabel,
    SetBoxTracked,
    SetCategory,
    fold_boxes,
    tracked,
    with_drawn,
)
from wecook_core.session.corrections import SetStatus, fold, parse, to_record
from wecook_core.session.store import create_session, open_session
from wecook_core.synth import demo_dir
from wecook_core.trees.notation import format_tree
from wecook_core.workflows import analyse_session


def test_box_corrections_round_trip_and_fold_like_the_box_mode() -> None:
    ops = [SetBoxKeyframe(1, 0, (10.0, 10.0, 50.0, 40.0), "tomato"), SetBoxKeyframe(1, 10, (30.0, 10.0, 70.0, 40.0)),
           SetBoxTracked(1, (11, 12), ((31.0, 10.0, 71.0, 40.0), (32.5, 10.0, 72.5, 40.0)), 13),
           SetBoxKeyframe(2, 5, (1.0, 2.0, 3.0, 4.0)), SetBoxLabel(2, "bowl"), SetCategory("gizmo", Category.TOOL)]
    for op in ops:
        assert parse(json.loads(json.dumps(to_record(op)))) == op
    one, two = fold_boxes(ops)
    expected = (BoxTrack(1, "tomato").with_keyframe(0, (10, 10, 50, 40)).with_keyframe(10, (30, 10, 70, 40)))
    assert one.keyframes == expected.keyframes and one.label == "tomato" and one.lost_at == 13
    assert one.boxes()[5] == (20.0, 10.0, 60.0, 40.0) and one.boxes()[12] == (32.5, 10.0, 72.5, 40.0)
    assert (two.track_id, two.label) == (2, "bowl")
    # A keyframe after the tracked run makes it stale; dropping the only keyframe removes the box.
    (again,) = fold_boxes([*ops, SetBoxKeyframe(1, 20, (0.0, 0.0, 9.0, 9.0)), DropBoxKeyframe(2, 5)])
    assert not again.tracked and sorted(again.keyframes) == [0, 10, 20]
    # Segment corrections do not see them, nor they segment corrections.
    assert fold([*ops, SetStatus(0, SegmentStatus.ACCEPTED)]).status == {0: SegmentStatus.ACCEPTED}
    with pytest.raises(ValueError, match="x1 < x2"):
        parse({"op": "box_keyframe", "track": 1, "frame": 0, "box": [5, 5, 1, 9]})
    with pytest.raises(ValueError, match="category"):
        parse({"op": "set_category", "label": "gizmo", "category": "spoon"})
    with pytest.raises(ValueError, match="track id"):
        parse({"op": "box_label", "track": 0, "label": "x"})


@pytest.mark.slow
def test_a_video_alone_gets_its_trees_from_drawn_boxes_kept_across_undo_redo_and_reopening(tmp_path: Path) -> None:
    """The demo's video and hands without its boxes; its boxes drawn back as a keyframe each plus the tracked
    rest give the trees the imported boxes give."""
    demo = Path(demo_dir())
    imported = analyse_session(create_session(tmp_path, "imported", demo / "video.mp4", demo / "objects.csv",
                                              demo / "hands.csv"), write=False)
    path = create_session(tmp_path, "alone", demo / "video.mp4", None, demo / "hands.csv")
    session = open_session(path)
    assert "objects" not in session.inputs and session.load_observations().objects == ()
    assert analyse_session(path, write=False).analysis.trees == ()
    for i, track in enumerate(read_objects_csv(demo / "objects.csv"), 1):
        frames = [int(f) for f in track.frames]
        boxes = {f: tuple(float(v) for v in b) for f, b in zip(frames, track.boxes, strict=True)}
        session.record(SetBoxKeyframe(i, frames[0], boxes[frames[0]], track.label))  # type: ignore[arg-type]
        drawn = BoxTrack(i, track.label, {frames[0]: boxes[frames[0]]}, {f: boxes[f] for f in frames[1:]})
        session.record(tracked(i, drawn))  # type: ignore[arg-type]
    done = analyse_session(path, write=False)
    assert [t.name for t in done.observations.objects] == [t.name for t in imported.observations.objects]
    assert done.observations.categories == imported.observations.categories
    trees = [format_tree(t.tree) for t in done.analysis.trees]
    assert trees and trees == [format_tree(t.tree) for t in imported.analysis.trees]
    # Undo takes the last tracked run back (one box then ends at its first frame), redo brings it again.
    assert isinstance(session.undo(), SetBoxTracked)
    last = fold_boxes(session.applied_corrections)[-1]
    assert not last.tracked
    assert isinstance(session.redo(), SetBoxTracked)
    reopened = open_session(path)
    assert fold_boxes(reopened.applied_corrections) == fold_boxes(session.applied_corrections)
    assert [format_tree(t.tree) for t in analyse_session(path, write=False).analysis.trees] == trees


@pytest.mark.slow
def test_a_category_given_for_an_unknown_label_is_applied_and_no_longer_asked(tmp_path: Path) -> None:
    demo = Path(demo_dir())
    objects = tmp_path / "objects.csv"
    objects.write_text((demo / "objects.csv").read_text().replace(",onion,", ",puzzle piece,"))
    path = create_session(tmp_path, "odd", demo / "video.mp4", objects, demo / "hands.csv")
    session = open_session(path)
    assert session.uncategorised == ("puzzle piece",)
    obs = session.load_observations()
    assert obs.categories["puzzle_piece"] is Category.INGREDIENT
    session.record(SetCategory("puzzle piece", Category.TOOL))
    assert open_session(path).uncategorised == ()
    drawn = with_drawn(obs, session.applied_corrections)
    assert drawn.observations.categories["puzzle_piece"] is Category.TOOL and drawn.unknown == ()
    # A drawn box with a label nothing knows is listed until answered.
    box = SetBoxKeyframe(1, 0, (1.0, 1.0, 20.0, 20.0), "zorblax")
    assert with_drawn(obs, [box]).unknown == ("zorblax",)
    unnamed = with_drawn(obs, [SetBoxKeyframe(1, 0, (1.0, 1.0, 20.0, 20.0))])  # not named yet: not asked about
    assert unnamed.unknown == () and unnamed.observations.categories["object"] is Category.INGREDIENT
    answered = with_drawn(obs, [box, SetCategory("zorblax", Category.CONTAINER)])
    assert answered.unknown == () and answered.observations.categories["zorblax"] is Category.CONTAINER
