"""The annotations of the real clip kfc-b (data/real/kfc-b, ours) against its video, read in place from the
shared directory: boxes inside the frame and within the video, a category for every label, the truth parses and
names only boxed objects, and a session of them can be made. Skipped, saying so, when the clip is absent."""

from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.formats.native import read_objects_csv
from wecook_core.knowledge.categories import load_categories
from wecook_core.perception.evaluation import object_names
from wecook_core.resources import REPO_DIR, shared_dir
from wecook_core.session.store import create_session, open_session
from wecook_core.trees.treefile import read_tree_file

OURS = REPO_DIR / "data" / "real" / "kfc-b"
VIDEO = shared_dir() / "data" / "real" / "kfc-b" / "video.mp4"
SIZE, FRAMES = (224, 224), 3035

needs_clip = pytest.mark.skipif(not VIDEO.is_file(), reason=f"the kfc-b video is not here ({VIDEO})")


def test_boxes_lie_inside_the_frame_and_every_label_has_a_category() -> None:
    tracks = read_objects_csv(OURS / "objects.csv")
    assert len(tracks) >= 40
    table = load_categories(extra=[OURS / "categories.yaml"])
    for track in tracks:
        boxes = track.boxes
        assert (boxes[:, 0] >= 0).all() and (boxes[:, 1] >= 0).all(), track.label
        assert (boxes[:, 2] <= SIZE[0]).all() and (boxes[:, 3] <= SIZE[1]).all(), track.label
        assert (boxes[:, 2] > boxes[:, 0]).all() and (boxes[:, 3] > boxes[:, 1]).all(), track.label
        assert track.frames.min() >= 0 and track.frames.max() < FRAMES, track.label
        assert table.categorize(track.label.replace("_", " ")) is not None, track.label
    covered = {int(f) for t in tracks for f in t.frames}
    assert max(covered) - min(covered) >= 1350  # the annotated span, at least 45 s of boxes within 61.6 s


def test_the_truth_parses_and_names_only_boxed_objects() -> None:
    truth = read_tree_file(OURS / "truth.yaml")
    assert len(truth) >= 20 and max(s.end for s in truth) <= 1850
    labels = {t.label for t in read_objects_csv(OURS / "objects.csv")}
    assert set().union(*(object_names(s.tree) for s in truth)) <= labels


@needs_clip
def test_a_session_of_the_annotations_opens_on_the_shared_video(tmp_path: Path) -> None:
    path = create_session(tmp_path, "kfc-b", VIDEO, OURS / "objects.csv", OURS / "hands.csv",
                          categories=OURS / "categories.yaml")
    open_session(path)  # replays and checks the inputs by their hashes
    text = Path(path, "session.yaml").read_text()
    assert "kfc-b" in text and "objects.csv" in text and "categories.yaml" in text
