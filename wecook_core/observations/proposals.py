"""Box proposals on one frame: a small COCO detector (YOLOX-nano, ONNX, run on the CPU by onnxruntime) finds
objects, class-agnostically, and its COCO class becomes a hint for the box's name.

The model and its provenance are in ``assets/detector/`` (``SOURCE.md``: upstream repository, commit, licence,
sha256). Pre- and post-processing follow the upstream sample (``yolox/yolox_onnx.py``): BGR pixels, not
normalised, resized with the aspect kept into the top-left of a 416x416 image padded with grey 114; outputs
decoded on the stride 8, 16 and 32 grids; score = objectness x class probability; non-maximum suppression across
classes. The workbench's box mode shows the proposals; the user keeps, names and tracks them as drawn boxes.

:func:`propose_boxes` is a pure function of the frame and the parameters (the loaded model is cached, and the CPU
run is deterministic).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from wecook_core.errors import InputError
from wecook_core.resources import ASSETS_DIR

DETECTOR_DIR = ASSETS_DIR / "detector"
MODEL_PATH = DETECTOR_DIR / "yolox_nano.onnx"
CLASSES_PATH = DETECTOR_DIR / "coco_classes.txt"
INPUT_SIZE = (416, 416)
"""The model's input, (height, width) pixels."""
STRIDES = (8, 16, 32)
PAD_VALUE = 114
INSTALL_HINT = "box proposals need onnxruntime: `pip install -e '.[proposals]'`"

HINTS: dict[str, str] = {
    "diningtable": "chopping board",
    "frisbee": "plate",
    "refrigerator": "fridge",
    "wine glass": "glass",
    "hot dog": "sausage",
    "vase": "jar",
    "pottedplant": "herb",
    "cell phone": "phone",
    "sports ball": "ball",
}
"""A COCO class (as the model names it) -> the kitchen label it suggests, where the two differ (otherwise the
class itself): seen from above, a worktop or a board is a "diningtable", a flat round dish a "frisbee"."""

Box = tuple[float, float, float, float]


@dataclass(frozen=True)
class ProposalParams:
    """What the detector's raw boxes must pass to be proposed."""

    min_score: float = 0.05
    """Objectness x class probability, 0-1 (upstream filters at 0.1 before NMS and draws from 0.3). Few kitchen
    things are COCO classes, so their scores are low: lower finds more of them, and more clutter. On tasty-a (every
    5th frame, NMS 0.6, at most 9): 0.1 gives 3.1 proposals a frame and recall 0.46 at IoU 0.5, 0.05 5.1 and 0.53,
    0.02 8.2 and 0.59."""
    nms_iou: float = 0.6
    """Boxes overlapping a better one by more than this IoU are dropped, whatever their classes. Looser than
    upstream's 0.45: in a kitchen, things lie in things (meat in a pan filling the pan), and their boxes overlap
    (on tasty-a, 0.45 loses a fifth of the recall)."""
    max_proposals: int = 9
    """At most this many, best score first: each can be kept with one digit, and a frame stays readable (on
    tasty-a, 15 would add 0.005 to the recall at 0.05)."""
    min_side: float = 0.03
    """A box narrower or shorter than this fraction of the frame's shorter side is dropped."""
    ignore: tuple[str, ...] = ("person",)
    """COCO classes never proposed: people are found as hands, not boxed as objects."""


@dataclass(frozen=True)
class Proposal:
    """One box the detector proposes on a frame."""

    box: Box
    """x1, y1, x2, y2 in pixels of the frame, top-left origin, clipped to the frame."""
    score: float
    """Objectness x class probability, 0-1."""
    coco_class: str
    """The detector's class (one of the 80 COCO names); only a hint, the proposal is class-agnostic."""

    @property
    def hint(self) -> str:
        """The label this proposal suggests for its box (the COCO class in kitchen words)."""
        return HINTS.get(self.coco_class, self.coco_class)


@cache
def coco_classes() -> tuple[str, ...]:
    """The model's 80 class names, in its output order."""
    return tuple(line.strip() for line in CLASSES_PATH.read_text(encoding="utf-8").splitlines() if line.strip())


@cache
def _session(path: Path) -> Any:
    try:
        import onnxruntime
    except ImportError as error:
        raise InputError(None, f"{INSTALL_HINT} ({error})") from None
    options = onnxruntime.SessionOptions()
    options.log_severity_level = 3
    # One thread: the workbench's UI keeps the other core, and on a busy machine (2 cores, load 8) one thread ran a
    # frame in 69 ms where onnxruntime's default (a thread per core) took 127 ms.
    options.intra_op_num_threads = 1
    options.inter_op_num_threads = 1
    return onnxruntime.InferenceSession(str(path), sess_options=options, providers=["CPUExecutionProvider"])


def letterbox(frame: np.ndarray, size: tuple[int, int] = INPUT_SIZE) -> tuple[np.ndarray, float]:
    """The model's input for a BGR frame (1x3xHxW float32, pixel values 0-255 unchanged) and the scale from frame
    pixels to input pixels: the frame resized with its aspect kept into the top-left corner, grey elsewhere."""
    if frame.ndim == 2:
        frame = cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)
    height, width = frame.shape[:2]
    ratio = min(size[0] / height, size[1] / width)
    new_w, new_h = int(width * ratio), int(height * ratio)
    padded = np.full((size[0], size[1], 3), PAD_VALUE, dtype=np.uint8)
    padded[:new_h, :new_w] = cv2.resize(frame, (new_w, new_h), interpolation=cv2.INTER_LINEAR)
    return np.ascontiguousarray(padded.transpose(2, 0, 1)[None], dtype=np.float32), ratio


def _grids(size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Each output row's grid cell (x, y) and stride, in the model's order (stride 8 first, rows of cells)."""
    grids, strides = [], []
    for stride in STRIDES:
        ys, xs = np.mgrid[0 : size[0] // stride, 0 : size[1] // stride]
        grids.append(np.stack((xs.ravel(), ys.ravel()), axis=1))
        strides.append(np.full((xs.size, 1), stride))
    return np.concatenate(grids).astype(np.float32), np.concatenate(strides).astype(np.float32)


def decode(output: np.ndarray, ratio: float, frame_size: tuple[int, int], params: ProposalParams,
           classes: tuple[str, ...] | None = None, input_size: tuple[int, int] = INPUT_SIZE) -> tuple[Proposal, ...]:
    """The proposals of the model's raw output (N x 85: centre offsets, log sizes, objectness, 80 class
    probabilities, per grid cell) for a frame of ``frame_size`` (width, height) pixels letterboxed by ``ratio``."""
    classes = classes if classes is not None else coco_classes()
    rows = np.asarray(output, dtype=np.float32).reshape(-1, 5 + len(classes))
    grid, stride = _grids(input_size)
    if len(rows) != len(grid):
        raise ValueError(f"the detector gave {len(rows)} rows, its grid has {len(grid)}")
    centre = (rows[:, :2] + grid) * stride
    half = np.exp(rows[:, 2:4]) * stride / 2
    boxes = np.concatenate((centre - half, centre + half), axis=1) / ratio
    scores = rows[:, 4:5] * rows[:, 5:]
    best = scores.argmax(axis=1)
    score = scores[np.arange(len(rows)), best]
    width, height = frame_size
    boxes = np.clip(boxes, 0.0, [width, height, width, height])
    side = params.min_side * min(width, height)
    ignored = np.array([name in params.ignore for name in classes])
    keep = (score >= params.min_score) & ~ignored[best] & ((boxes[:, 2] - boxes[:, 0]) >= side) & (
        (boxes[:, 3] - boxes[:, 1]) >= side)
    index = np.flatnonzero(keep)
    if index.size == 0:
        return ()
    xywh = [[float(x1), float(y1), float(x2 - x1), float(y2 - y1)] for x1, y1, x2, y2 in boxes[index]]
    kept = cv2.dnn.NMSBoxes(xywh, score[index].tolist(), params.min_score, params.nms_iou)
    chosen = sorted((int(index[int(k)]) for k in np.asarray(kept).ravel()), key=lambda i: (-score[i], i))
    return tuple(Proposal(tuple(round(float(v), 1) for v in boxes[i]), round(float(score[i]), 3),  # type: ignore[arg-type]
                          classes[int(best[i])]) for i in chosen[: params.max_proposals])


def propose_boxes(frame: np.ndarray, params: ProposalParams | None = None) -> tuple[Proposal, ...]:
    """The boxes the detector proposes on one BGR frame (as OpenCV decodes it), best score first."""
    params = params or ProposalParams()
    if frame.ndim not in (2, 3) or frame.size == 0:
        raise ValueError(f"not an image: shape {frame.shape}")
    session = _session(MODEL_PATH)
    image, ratio = letterbox(frame)
    (output,) = session.run(None, {session.get_inputs()[0].name: image})
    height, width = frame.shape[:2]
    return decode(output[0], ratio, (width, height), params)


def frame_at(video: str | Path, frame: int) -> np.ndarray:
    """Frame ``frame`` (0-based) of the video, as OpenCV decodes it (BGR)."""
    capture = cv2.VideoCapture(str(video))
    try:
        if not capture.isOpened():
            raise InputError(video, "OpenCV cannot open this video")
        if frame > 0:
            capture.set(cv2.CAP_PROP_POS_FRAMES, frame)
        ok, image = capture.read()
    finally:
        capture.release()
    if not ok or image is None:
        raise InputError(video, "no such frame in the video", place=f"frame {frame}")
    return image


def iou(a: Box, b: Box) -> float:
    """Intersection over union of two boxes (x1, y1, x2, y2); 0 when both are empty."""
    inter = max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def recalled(proposed: Sequence[Box], truth: Sequence[Box], min_iou: float = 0.5) -> frozenset[int]:
    """The indices of the ``truth`` boxes that proposals find, class-agnostically: each proposal finds at most one
    truth box, one it overlaps by ``min_iou`` or more, assigned so that as many truth boxes as possible are found
    (one proposal over two objects counts once)."""
    from scipy.optimize import linear_sum_assignment

    if not proposed or not truth:
        return frozenset()
    hits = np.array([[iou(t, p) >= min_iou for p in proposed] for t in truth], dtype=float)
    rows, cols = linear_sum_assignment(hits, maximize=True)
    return frozenset(int(r) for r, c in zip(rows, cols, strict=True) if hits[r, c])


def propose_at(video: str | Path, frame: int, params: ProposalParams | None = None) -> tuple[Proposal, ...]:
    """The proposals on frame ``frame`` (0-based) of a video."""
    return propose_boxes(frame_at(video, frame), params)
