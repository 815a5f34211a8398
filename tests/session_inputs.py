"""Small real inputs for session tests: an MJPG video, a native objects CSV, an OpenPose folder, categories."""

from __future__ import annotations

import json
from pathlib import Path

from grey_video import write_grey_video

W, H, FRAMES, FPS = 96, 64, 20, 10.0


def make_inputs(folder: Path) -> dict[str, Path]:
    folder.mkdir(parents=True, exist_ok=True)
    video = folder / "take.avi"
    write_grey_video(video, FRAMES, (W, H), FPS)
    objects = folder / "objects.csv"
    objects.write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,whisk,10,10,20,20\n0,2,pan,40,30,90,60\n")
    hands = folder / "openpose"
    hands.mkdir(exist_ok=True)
    body = [v for x, y in [(0, -30), (0, -20), (-10, -20), (-12, -5), (-14, 8), (10, -20), (12, -5), (14, 8)]
            for v in (30 + x, 30 + y, 0.9)]
    for f in range(FRAMES):
        (hands / f"take_{f:012d}_keypoints.json").write_text(json.dumps({"people": [{"pose_keypoints_2d": body}]}))
    categories = folder / "categories.yaml"
    categories.write_text("objects:\n  whisk: tool\n  pan: container\n")
    return {"video": video, "objects": objects, "hands": hands, "categories": categories}
