"""Box proposals (YOLOX-nano on onnxruntime): the letterbox and the decoding of the model's output against hand-made
answers, the shipped model against its recorded provenance, and the detector on real frames of tasty-a (read in
place from the shared folder) against the boxes read there by eye."""

from __future__ import annotations

import dataclasses
import hashlib
import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from wecook_core.errors import InputError
from wecook_core.formats.native import read_objects_csv
from wecook_core.observations import proposals
from wecook_core.observations.proposals import (
    DETECTOR_DIR,
    MODEL_PATH,
    Proposal,
    ProposalParams,
    coco_classes,
    decode,
    iou,
    letterbox,
    propose_at,
    recalled,
)


def test_the_model_is_the_one_its_source_file_names_under_its_licence() -> None:
    source = (DETECTOR_DIR / "SOURCE.md").read_text()
    for name in ("yolox_nano.onnx", "coco_classes.txt", "LICENSE"):
        digest = hashlib.sha256((DETECTOR_DIR / name).read_bytes()).hexdigest()
        assert re.search(rf"`{re.escape(name)}`.*`{digest}`", source), name
    assert "Kazuhito00/YOLOX-ONNX-TFLite-Sample" in source and "Apache-2.0" in source
    assert "Apache License" in (DETECTOR_DIR / "LICENSE").read_text()
    assert MODEL_PATH.stat().st_size > 3_000_000  # the weights, not a Git LFS pointer
    assert len(coco_classes()) == 80 and coco_classes()[45] == "bowl"


def test_the_letterbox_keeps_the_aspect_top_left_in_bgr_and_pads_grey() -> None:
    frame = np.zeros((240, 480, 3), dtype=np.uint8)
    frame[..., 0] = 200  # blue
    frame[:, 240:, 2] = 50  # red on the right half
    image, ratio = letterbox(frame)
    assert image.shape == (1, 3, 416, 416) and image.dtype == np.float32
    assert ratio == pytest.approx(416 / 480)
    assert image[0, 0, 0, 0] == 200 and image[0, 2, 0, 0] == 0  # channels stay B, G, R; values stay 0-255
    assert image[0, 2, 100, 400] == 50
    height = int(240 * ratio)
    assert (image[0, :, height:, :] == 114).all() and (image[0, 0, :height, :] == 200).all()


def output_with(rows: dict[int, tuple[float, float, float, float, float, int, float]]) -> np.ndarray:
    """A raw output (3549 x 85) that is empty but for ``rows``: index -> (dx, dy, log w, log h, objectness,
    class, class probability)."""
    output = np.zeros((3549, 85), dtype=np.float32)
    for index, (dx, dy, lw, lh, objectness, cls, prob) in rows.items():
        output[index, :5] = (dx, dy, lw, lh, objectness)
        output[index, 5 + cls] = prob
    return output


def test_decoding_places_boxes_on_the_stride_grids_and_suppresses_across_classes() -> None:
    stride16 = 52 * 52  # the stride-8 rows come first (52 x 52 cells of a 416 input), then 26 x 26
    cell = stride16 + 3 * 26 + 5  # stride 16, cell x=5, y=3
    rows = {
        cell: (0.5, 0.5, math.log(4), math.log(4), 0.9, 45, 0.9),  # a bowl, 64 px square, centre (88, 56)
        cell + 1: (0.0, 0.5, math.log(4), math.log(4), 0.8, 41, 0.8),  # a cup over it, shifted 8 px: suppressed
        10: (0.5, 0.5, math.log(2), math.log(2), 0.9, 0, 0.9),  # a person: never proposed
        20: (0.5, 0.5, math.log(0.2), math.log(0.2), 0.9, 43, 0.9),  # a knife 1.6 px wide: too small
        30 * 52 + 40: (0.5, 0.5, math.log(5), math.log(3), 0.5, 60, 0.4),  # a table (stride 8), score 0.2
    }
    found = decode(output_with(rows), 0.5, (832, 600), ProposalParams())
    assert [(p.coco_class, p.hint) for p in found] == [("bowl", "bowl"), ("diningtable", "chopping board")]
    bowl, table = found
    assert bowl.box == (112.0, 48.0, 240.0, 176.0) and bowl.score == pytest.approx(0.81)  # /0.5: frame pixels
    assert table.box == pytest.approx((2 * (40.5 * 8 - 20), 2 * (30.5 * 8 - 12), 2 * (40.5 * 8 + 20),
                                       2 * (30.5 * 8 + 12)))
    assert decode(output_with(rows), 0.5, (832, 600), ProposalParams(min_score=0.5)) == (bowl,)
    with_cup = decode(output_with(rows), 0.5, (832, 600), ProposalParams(nms_iou=0.9))
    assert "cup" in [p.coco_class for p in with_cup]  # overlapping by about 0.78 IoU: kept at a looser NMS
    assert decode(output_with(rows), 0.5, (832, 600), ProposalParams(max_proposals=1)) == (bowl,)
    clipped = decode(output_with(rows), 0.5, (200, 150), ProposalParams())
    assert clipped[0].box == (112.0, 48.0, 200.0, 150.0)  # clipped to the frame
    with pytest.raises(dataclasses.FrozenInstanceError):
        bowl.score = 1.0  # type: ignore[misc]


def test_without_onnxruntime_the_error_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "onnxruntime", None)
    with pytest.raises(InputError, match=r"onnxruntime.*\.\[proposals\]"):
        proposals._session.__wrapped__(MODEL_PATH)


def test_a_frame_outside_the_video_is_one_line_naming_the_frame(shared: Path) -> None:
    video = shared / "data" / "real" / "tasty-a" / "video.mp4"
    with pytest.raises(InputError, match=r"video\.mp4:frame 400: no such frame"):
        propose_at(video, 400)


@pytest.mark.parametrize(("frame", "label"), [(65, "small_bowl"), (210, "bowl")])
def test_the_detector_proposes_the_bowls_of_a_real_video(shared: Path, frame: int, label: str) -> None:
    folder = shared / "data" / "real" / "tasty-a"
    (track,) = [t for t in read_objects_csv(folder / "objects.csv") if t.label == label]
    truth = tuple(float(v) for v in track.boxes[list(track.frames).index(frame)])
    found = propose_at(folder / "video.mp4", frame)
    assert all(isinstance(p, Proposal) for p in found) and len(found) <= ProposalParams().max_proposals
    assert [p.score for p in found] == sorted((p.score for p in found), reverse=True)
    best = max(found, key=lambda p: iou(p.box, truth))
    assert iou(best.box, truth) >= 0.5 and best.hint == "bowl", found
    assert propose_at(folder / "video.mp4", frame) == found  # the same frame gives the same proposals


def test_recall_matches_each_proposal_to_one_truth_box_at_iou_half() -> None:
    assert iou((0, 0, 10, 10), (5, 0, 15, 10)) == pytest.approx(1 / 3) and iou((0, 0, 0, 0), (0, 0, 0, 0)) == 0.0
    truth = [(0.0, 0.0, 10.0, 10.0), (0.0, 0.0, 10.0, 11.0), (50.0, 50.0, 60.0, 60.0), (80.0, 80.0, 90.0, 90.0)]
    # One proposal over the two stacked boxes finds one of them; a second near-copy finds the other; a box
    # overlapping by 1/3 finds nothing.
    assert len(recalled([(0.0, 0.0, 10.0, 10.5)], truth)) == 1
    assert recalled([(0.0, 0.0, 10.0, 10.5), (0.0, 0.0, 10.0, 10.0), (55.0, 50.0, 65.0, 60.0)], truth) == {0, 1}
    assert recalled([(80.0, 80.0, 90.0, 90.0)], truth) == {3} and recalled([], truth) == frozenset()
    assert recalled([(55.0, 50.0, 65.0, 60.0)], truth, min_iou=0.3) == {2}
