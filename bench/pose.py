"""The pose model's cost per frame against the hand model's, measured in the same run on the same frames.

Both run over the hand video bench/hands.py renders (640x360) and, when the shared real clip is there (read in
place), over tasty-a (480x480, top-down). Decoding is done once beforehand, so each figure is the model alone;
the ratio is pose ms / hand ms (full hand model, two bodies looked for). The share of frames with a hand is
also given with and without the pose model, which names hands but must never lose any.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from bench.hands import render
from wecook_core.observations.hands_detect import (
    DetectParams,
    HandDetector,
    detect_hands,
    native_stderr_silenced,
    read_frames,
)
from wecook_core.observations.pose_detect import PoseDetector
from wecook_core.resources import shared_dir


def _costs(path: Path) -> tuple[float, float, int]:
    frames, _, fps, _ = read_frames(path)
    images = list(frames)
    with HandDetector(DetectParams()) as hands:
        started = time.perf_counter()
        for index, image in images:
            hands.detect(index, image)
        hand = (time.perf_counter() - started) / len(images)
    with PoseDetector(fps) as bodies:
        started = time.perf_counter()
        for index, image in images:
            bodies.detect(index, image)
        pose = (time.perf_counter() - started) / len(images)
    return hand, pose, len(images)


def _rows(path: Path, name: str) -> list[dict[str, object]]:
    hand, pose, count = _costs(path)
    return [
        {"benchmark": f"hand model, {name}", "value": 1000 * hand, "unit": "ms/frame", "ratio_vs_baseline": 1.0,
         "note": f"baseline; {count} frames"},
        {"benchmark": f"pose model (2 bodies), {name}", "value": 1000 * pose, "unit": "ms/frame",
         "ratio_vs_baseline": pose / hand, "note": "vs the hand model on the same frames"},
    ]


def run() -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    with tempfile.TemporaryDirectory() as folder, native_stderr_silenced():
        video = Path(folder) / "hands640.mp4"
        render(video)
        rows += _rows(video, "640x360")
        real = shared_dir() / "data" / "real" / "tasty-a" / "video.mp4"
        if real.is_file():
            rows += _rows(real, "real 480x480 clip")
            without = detect_hands(real, DetectParams(pose=False))
            with_pose = detect_hands(real, DetectParams(pose=True))
            share = with_pose.frames_with_hands / max(with_pose.frames_read, 1)
            rows.append({"benchmark": "frames with a hand, tasty-a, with pose", "value": share, "unit": "fraction",
                         "ratio_vs_baseline": share / max(without.frames_with_hands / without.frames_read, 1e-9),
                         "note": f"baseline: without pose, {without.frames_with_hands}/{without.frames_read}; "
                                 f"bodies in {with_pose.frames_with_bodies} frames"})
    return rows
