"""Box tracking: frames per second of `propagate` (OpenCV's MIL tracker plus the loss check) on a 640x360
video, against decoding it alone in the same run; and memory over video length: the peak of traced
allocations while tracking a video 4x as long, as a ratio to the short one's (flat: about 1)."""

from __future__ import annotations

import tempfile
import time
import tracemalloc
from pathlib import Path

import cv2
import numpy as np

from wecook_core.observations.hands_detect import read_frames
from wecook_core.observations.tracking import propagate

SIZE = (640, 360)


def render(path: Path, frames: int) -> tuple[float, float, float, float]:
    """A patterned square circling over a textured background; returns its box on frame 0."""
    rng = np.random.default_rng(0)
    background = cv2.GaussianBlur(rng.integers(0, 255, (SIZE[1], SIZE[0], 3), dtype=np.uint8), (0, 0), 3)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 30.0, SIZE)
    first = None
    for i in range(frames):
        image = background.copy()
        angle = i / 60.0
        x, y = int(300 + 150 * np.cos(angle)), int(160 + 90 * np.sin(angle))
        cv2.rectangle(image, (x, y), (x + 60, y + 60), (30, 30, 220), -1)
        cv2.circle(image, (x + 30, y + 30), 14, (240, 240, 40), -1)
        writer.write(image)
        first = first or (float(x), float(y), float(x + 60), float(y + 60))
    writer.release()
    assert first is not None
    return first


def _decode_fps(path: Path) -> float:
    frames, _, _, _ = read_frames(path)
    started = time.perf_counter()
    count = sum(1 for _ in frames)
    return count / (time.perf_counter() - started)


def run() -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    with tempfile.TemporaryDirectory() as folder:
        short, long = Path(folder) / "short.avi", Path(folder) / "long.avi"
        box = render(short, 150)
        render(long, 600)
        decode = _decode_fps(short)
        started = time.perf_counter()
        boxes, lost = propagate(short, 0, box, 30.0)
        fps = len(boxes) / (time.perf_counter() - started)
        rows.append({"benchmark": "decode only, 640x360", "value": decode, "unit": "frames/s",
                     "ratio_vs_baseline": 1.0, "note": "baseline; 150 frames"})
        rows.append({"benchmark": "propagate MIL, 640x360", "value": fps, "unit": "frames/s",
                     "ratio_vs_baseline": fps / decode,
                     "note": f"{1000 / fps:.0f} ms a frame; followed {len(boxes)} of 149 frames"
                             + (f", lost at {lost}" if lost is not None else "")})
        peaks = []
        for path in (short, long):
            tracemalloc.start()
            found, _ = propagate(path, 0, box, 30.0)
            peaks.append((tracemalloc.get_traced_memory()[1], len(found)))
            tracemalloc.stop()
        (short_peak, short_n), (long_peak, long_n) = peaks
        rows.append({"benchmark": "tracking memory, 600 vs 150 frames", "value": long_peak / 2**20, "unit": "MiB peak",
                     "ratio_vs_baseline": long_peak / short_peak,
                     "note": f"baseline 150 frames: {short_peak / 2**20:.1f} MiB; frames tracked {long_n} vs "
                             f"{short_n}"})
    return rows
