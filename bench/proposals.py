"""Box proposals (YOLOX-nano on onnxruntime, the box mode's `p`): class-agnostic recall at IoU 0.5 of the
proposals against tasty-a's boxes read by eye (read in place from the shared folder), on every 5th frame, and
milliseconds a frame, against decoding the frame alone, measured in the same run.

Recall counts each proposal for at most one box (a proposal over a pan full of turkey finds the pan or the turkey,
not both). tasty-a's pan fills most of the frame, and several ingredient boxes nearly the whole pan, so a
frame-wide box (the detector's "diningtable") finds many of them: the recall of the boxes under a quarter of the
frame is given apart, as is the recall per label.
"""

from __future__ import annotations

import time
from collections import defaultdict

import cv2

from wecook_core.formats.native import read_objects_csv
from wecook_core.observations.proposals import ProposalParams, propose_boxes, recalled
from wecook_core.resources import shared_dir

EVERY = 5
"""Frames sampled: 0, 5, 10, ..."""
SMALL = 0.25
"""A box under this fraction of the frame's area counts as small."""


def _frames(path: str) -> list:
    capture = cv2.VideoCapture(path)
    frames = []
    while True:
        ok, frame = capture.read()
        if not ok:
            break
        frames.append(frame)
    capture.release()
    return frames


def run() -> list[dict[str, object]]:
    folder = shared_dir() / "data" / "real" / "tasty-a"
    video = str(folder / "video.mp4")
    truth: dict[int, list[tuple[str, tuple[float, float, float, float]]]] = defaultdict(list)
    for track in read_objects_csv(folder / "objects.csv"):
        for frame, box in zip(track.frames.tolist(), track.boxes.tolist(), strict=True):
            truth[int(frame)].append((track.label, tuple(box)))
    _frames(video)  # the file in the page cache: the baseline times decoding, not the disk
    started = time.perf_counter()
    frames = _frames(video)
    decode_ms = 1000 * (time.perf_counter() - started) / len(frames)
    height, width = frames[0].shape[:2]
    sample = [i for i in range(0, len(frames), EVERY) if truth.get(i)]
    propose_boxes(frames[sample[0]])  # the model loads once, before the clock runs
    rows: list[dict[str, object]] = [
        {"benchmark": f"decode a frame, {width}x{height} (tasty-a)", "value": decode_ms, "unit": "ms/frame",
         "ratio_vs_baseline": 1.0, "note": f"baseline; {len(frames)} frames read in order"}]
    for params in (ProposalParams(), ProposalParams(min_score=0.02)):
        found = total = small_found = small_total = proposed = 0
        per_label: dict[str, list[int]] = defaultdict(lambda: [0, 0])
        started = time.perf_counter()
        results = {i: propose_boxes(frames[i], params) for i in sample}
        detect_ms = 1000 * (time.perf_counter() - started) / len(sample)
        for i, proposals in results.items():
            boxes = [box for _, box in truth[i]]
            hits = recalled([p.box for p in proposals], boxes)
            proposed += len(proposals)
            for k, (label, (x1, y1, x2, y2)) in enumerate(truth[i]):
                found, total = found + (k in hits), total + 1
                per_label[label][0] += k in hits
                per_label[label][1] += 1
                if (x2 - x1) * (y2 - y1) < SMALL * width * height:
                    small_found, small_total = small_found + (k in hits), small_total + 1
        labels = ", ".join(f"{label} {hit}/{n}" for label, (hit, n) in sorted(per_label.items()))
        where = f"min_score {params.min_score:g}, NMS {params.nms_iou:g}, {len(sample)} frames"
        rows.append({"benchmark": f"proposal recall at IoU 0.5, tasty-a ({where})", "value": found / total,
                     "unit": "recall", "note": f"{found}/{total} boxes; {proposed / len(sample):.1f} proposals a "
                                               f"frame; {labels}"})
        rows.append({"benchmark": f"proposal recall, boxes under 1/4 of the frame ({where})",
                     "value": small_found / small_total, "unit": "recall",
                     "note": f"{small_found}/{small_total} boxes"})
        rows.append({"benchmark": f"propose on a frame, CPU ({where})", "value": detect_ms, "unit": "ms/frame",
                     "ratio_vs_baseline": detect_ms / decode_ms,
                     "note": "YOLOX-nano 416x416, onnxruntime; letterbox, inference, decoding, NMS"})
    return rows
