"""tasty-a's hand-read boxes (960 boxes, 13 tracks, 480x480 at 5 fps) written in the shape each outside tool
exports, then imported with the real video: every format gives back what wecook's own CSV of them gives.

The shapes: MOT as PathTrack writes it (spaces, 1-based frames, x y w h); Label Studio annotated at its
default 24 fps (keyframe frames and times at 24 fps, percentages, a bare list of results); YouTube-VIS
(every frame a file name, per-instance bboxes with nulls); TAO through mmtracking (every fifth frame annotated,
as TAO's 1 fps of a 5 fps video: frame_index the video's frame, frame_id the index among annotated frames;
compared on those frames, the ones between being interpolated); CVAT for video with keyframes at the start of each run
and an outside box after it (wecook's own writer)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from wecook_core.formats.cvat_write import cvat_xml
from wecook_core.formats.native import read_objects_csv
from wecook_core.model import ObjectTrack
from wecook_core.observations.importer import import_observations
from wecook_core.resources import shared_dir

TASTY = shared_dir() / "data" / "real" / "tasty-a"
W = H = 480
FPS = 5.0
FRAMES = 269
TAO_STEP = 5


def _tracks() -> tuple[ObjectTrack, ...]:
    if not (TASTY / "video.mp4").is_file():
        pytest.skip(f"the shared real clip {TASTY} is absent")
    return read_objects_csv(TASTY / "objects.csv")


def _mot(tracks: tuple[ObjectTrack, ...], folder: Path) -> Path:
    lines = [f"{f + 1} {t.track_id} {b[0]:g} {b[1]:g} {b[2] - b[0]:g} {b[3] - b[1]:g} 1 -1 -1 -1"
             for t in tracks for f, b in zip(t.frames.tolist(), t.boxes.tolist(), strict=True)]
    (folder / "labels.txt").write_text("".join(f"{t.track_id},{t.label}\n" for t in tracks))
    path = folder / "gt.txt"
    path.write_text("\n".join(sorted(lines, key=lambda line: int(line.split()[0]))) + "\n")
    return path


def _labelstudio(tracks: tuple[ObjectTrack, ...], folder: Path) -> Path:
    rate = 24.0
    duration = FRAMES / FPS
    results = []
    for t in tracks:
        frames = t.frames.tolist()
        sequence = []
        for i, (f, b) in enumerate(zip(frames, t.boxes.tolist(), strict=True)):
            ls_frame = round(f / FPS * rate) + 1
            last_of_run = i + 1 == len(frames) or frames[i + 1] != f + 1
            sequence.append({"frame": ls_frame, "enabled": not last_of_run or f == FRAMES - 1, "rotation": 0,
                             "x": b[0] / W * 100, "y": b[1] / H * 100, "width": (b[2] - b[0]) / W * 100,
                             "height": (b[3] - b[1]) / H * 100, "time": ls_frame / rate})
        results.append({"value": {"framesCount": math.ceil(duration * rate), "duration": duration,
                                  "sequence": sequence, "labels": [t.label]},
                        "id": f"r{t.track_id}", "from_name": "box", "to_name": "video", "type": "videorectangle",
                        "origin": "manual"})
    path = folder / "result.json"
    path.write_text(json.dumps(results))
    return path


def _youtube_vis(tracks: tuple[ObjectTrack, ...], folder: Path) -> Path:
    names = [f"tasty-a/{f:05d}.jpg" for f in range(FRAMES)]
    labels = sorted({t.label for t in tracks})
    annotations = []
    for t in tracks:
        boxes: list[list[float] | None] = [None] * FRAMES
        for f, b in zip(t.frames.tolist(), t.boxes.tolist(), strict=True):
            boxes[f] = [b[0], b[1], b[2] - b[0], b[3] - b[1]]
        annotations.append({"id": t.track_id, "video_id": 1, "category_id": labels.index(t.label) + 1,
                            "iscrowd": 0, "height": H, "width": W, "length": 1, "bboxes": boxes,
                            "areas": [None if b is None else b[2] * b[3] for b in boxes],
                            "segmentations": [None] * FRAMES})
    data = {"info": {"description": "YouTube-VOS"}, "licenses": [],
            "videos": [{"id": 1, "width": W, "height": H, "length": FRAMES, "file_names": names}],
            "categories": [{"supercategory": "object", "id": i + 1, "name": n} for i, n in enumerate(labels)],
            "annotations": annotations}
    path = folder / "ytvis.json"
    path.write_text(json.dumps(data))
    return path


def _tao(tracks: tuple[ObjectTrack, ...], folder: Path) -> Path:
    annotated = sorted({f for t in tracks for f in t.frames.tolist() if f % TAO_STEP == 0})
    labels = sorted({t.label for t in tracks})
    images = [{"id": i, "video": "tasty-a", "width": W, "height": H, "file_name": f"tasty-a/frame{f + 1:04d}.jpg",
               "frame_index": f, "video_id": 0, "frame_id": i} for i, f in enumerate(annotated)]
    image_of = {f: i for i, f in enumerate(annotated)}
    annotations = [{"bbox": [b[0], b[1], b[2] - b[0], b[3] - b[1]], "iscrowd": 0, "id": len(annotated) * t.track_id + k,
                    "image_id": image_of[f], "category_id": labels.index(t.label) + 1, "track_id": t.track_id,
                    "video_id": 0, "instance_id": t.track_id}
                   for t in tracks for k, (f, b) in enumerate(zip(t.frames.tolist(), t.boxes.tolist(), strict=True))
                   if f % TAO_STEP == 0]
    data = {"videos": [{"id": 0, "width": W, "height": H, "name": "tasty-a"}], "images": images,
            "annotations": annotations, "categories": [{"id": i + 1, "name": n} for i, n in enumerate(labels)]}
    path = folder / "tao.json"
    path.write_text(json.dumps(data))
    return path


def _cvat(tracks: tuple[ObjectTrack, ...], folder: Path) -> Path:
    keyframes = {t.track_id: [f for i, f in enumerate(t.frames.tolist()) if i == 0 or t.frames[i - 1] != f - 1]
                 for t in tracks}
    path = folder / "annotations.xml"
    path.write_text(cvat_xml(tracks, size=(W, H), keyframes=keyframes))
    return path


@pytest.mark.parametrize("writer", [_mot, _labelstudio, _youtube_vis, _tao, _cvat])
def test_every_format_gives_back_tasty_as_boxes(tmp_path: Path, writer: object) -> None:
    objects = writer(_tracks(), tmp_path)  # type: ignore[operator]
    truth = import_observations(TASTY / "video.mp4", TASTY / "objects.csv", TASTY / "hands.csv").observations.objects
    imported = import_observations(TASTY / "video.mp4", objects, TASTY / "hands.csv")
    got = {t.track_id: t for t in imported.observations.objects}
    assert len(got) == len(truth) == 13
    for t in truth:
        mine = got[t.track_id] if writer is not _labelstudio else next(
            g for g in got.values() if g.label == t.label and g.frames[0] == t.frames[0])
        assert mine.label == t.label
        if writer is _tao:  # sampled every fifth frame: the samples are the boxes
            sampled = [f for f in t.frames.tolist() if f % TAO_STEP == 0]
            assert set(sampled) <= set(mine.frames.tolist())
            np.testing.assert_allclose([mine.box_at(f) for f in sampled], [t.box_at(f) for f in sampled], atol=1e-6)
            continue
        assert mine.frames.tolist() == t.frames.tolist()
        np.testing.assert_allclose(mine.boxes, t.boxes, atol=1e-6)
    if writer is _labelstudio:
        assert any("annotated at 24 fps, the video video.mp4 plays at 5 fps" in w for w in imported.warnings)
