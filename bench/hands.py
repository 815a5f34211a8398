"""Hand detection throughput: frames per second of `detect_hands` (MediaPipe, full and lite models, without the
pose model: bench/pose.py has its cost) on a 640x360 video, against decoding the same video alone (the floor
any detector pays) measured in the same run.

The video is rendered here: the test photo's hand (tests/data/hand_four.png, Apache-2.0) and its mirror image
moving across a plain background, so both hands are present in every frame and the landmark model runs as it
does on a cooking video. When the shared real clip is there (read in place, never copied), its frames per
second and the share of frames with a hand are reported too.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from wecook_core.observations.hands_detect import DetectParams, detect_hands, native_stderr_silenced, read_frames
from wecook_core.resources import shared_dir

HAND = Path(__file__).resolve().parents[1] / "tests" / "data" / "hand_four.png"
FRAMES = 150


def render(path: Path, frames: int = FRAMES) -> None:
    hand = cv2.resize(cv2.imread(str(HAND)), None, fx=2, fy=2, interpolation=cv2.INTER_CUBIC)
    h, w = hand.shape[:2]
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 30.0, (640, 360))
    rng = np.random.default_rng(0)
    background = rng.integers(150, 210, size=(360, 640, 3), dtype=np.uint8)
    for i in range(frames):
        image = background.copy()
        x = 20 + (i * 2) % 240
        image[90:90 + h, x:x + w] = hand
        x2 = 440 - (i * 2) % 200
        image[120:120 + h, x2:x2 + w] = hand[:, ::-1]
        writer.write(image)
    writer.release()


def _decode_fps(path: Path) -> float:
    frames, _, _, _ = read_frames(path)
    started = time.perf_counter()
    count = sum(1 for _ in frames)
    return count / (time.perf_counter() - started)


def _detect(path: Path, model: str) -> tuple[float, float]:
    started = time.perf_counter()
    found = detect_hands(path, DetectParams(model=model, pose=False))
    seconds = time.perf_counter() - started
    return found.frames_read / seconds, found.frames_with_hands / max(found.frames_read, 1)


def run() -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    with tempfile.TemporaryDirectory() as folder, native_stderr_silenced():
        video = Path(folder) / "hands640.mp4"
        render(video)
        decode = _decode_fps(video)
        rows.append({"benchmark": "decode only, 640x360", "value": decode, "unit": "frames/s",
                     "ratio_vs_baseline": 1.0, "note": f"baseline; {FRAMES} frames"})
        full = None
        for model in ("full", "lite"):
            fps, share = _detect(video, model)
            full = full or fps
            rows.append({"benchmark": f"detect_hands {model}, 640x360", "value": fps, "unit": "frames/s",
                         "ratio_vs_baseline": fps / decode,
                         "note": f"{1000 / fps:.0f} ms a frame; hands in {share:.0%} of frames; "
                                 f"{fps / full:.2f}x the full model"})
        real = shared_dir() / "data" / "real" / "tasty-a" / "video.mp4"
        if real.is_file():
            decode_real = _decode_fps(real)
            for model in ("full", "lite"):
                fps, share = _detect(real, model)
                rows.append({"benchmark": f"detect_hands {model}, real 480x480 clip", "value": fps,
                             "unit": "frames/s", "ratio_vs_baseline": fps / decode_real,
                             "note": f"{1000 / fps:.0f} ms a frame; a hand in {share:.0%} of frames; "
                                     f"vs decoding it ({decode_real:.0f} frames/s)"})
    return rows
