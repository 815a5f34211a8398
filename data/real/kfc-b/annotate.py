"""Make objects.csv of kfc-b from keyframes.yaml with the box mode's own core: each track is a
:class:`BoxTrack` of the keyframes read by eye, interpolated between them, and carried from its last keyframe to
its shot's end by :func:`track_from_last_keyframe` (OpenCV's MIL, as the box mode's ``t``), never across a cut.

    cd REPO && .venv/bin/python data/real/kfc-b/annotate.py   # reads the video from the shared directory
    cd REPO && .venv/bin/python data/real/kfc-b/annotate.py --only 25 31   # re-make those tracks, keep the rest

``--only``: the tracker's randomness cannot be seeded (OpenCV's MIL draws its own samples), so re-making every
track after changing a few keyframes would move the tails of the others too; with ``--only`` the rows of every
other track are copied from the existing objects.csv unchanged.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import yaml

from wecook_core.formats.native import read_objects_csv, write_objects_csv
from wecook_core.observations.tracking import BoxTrack, TrackParams, track_from_last_keyframe
from wecook_core.resources import shared_dir

HERE = Path(__file__).resolve().parent
FPS = 30.0


def tracks(video: Path, only: set[int] | None = None) -> list[BoxTrack]:
    spec = yaml.safe_load((HERE / "keyframes.yaml").read_text())["tracks"]
    made = []
    for track_id, item in enumerate(spec, start=1):
        if only is not None and track_id not in only:
            continue
        first, end = item["shot"]
        keys = {int(f): tuple(float(v) for v in box) for f, box in item["keys"].items()}
        assert all(first <= f < end for f in keys), (item["label"], first, end)
        track = BoxTrack(track_id, item["label"], keys)
        last = max(keys)
        if last < end - 1:
            params = TrackParams(max_seconds=(end - 1 - last) / FPS)
            try:
                track = track_from_last_keyframe(video, track, FPS, params)
            except cv2.error as error:  # MIL cannot start on a box at the frame's edge: keep the keyframes
                print(f"{track_id:3} {item['label']}: the tracker did not start ({str(error).splitlines()[-1]})")
        made.append(track)
    return made


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", type=int, nargs="+", help="re-make only these tracks (ids from 1)")
    args = parser.parse_args()
    only = set(args.only) if args.only else None
    video = shared_dir() / "data" / "real" / "kfc-b" / "video.mp4"
    made = tracks(video, only)
    for t in made:
        lost = f", lost at {t.lost_at}" if t.lost_at is not None else ""
        print(f"{t.track_id:3} {t.label:<14} keys {sorted(t.keyframes)} tracked {len(t.tracked)}{lost}")
    objects = [t.object_track() for t in made]
    if only is not None:  # every other track as it is in objects.csv
        kept = [track for track in read_objects_csv(HERE / "objects.csv") if track.track_id not in only]
        objects = sorted(kept + objects, key=lambda track: track.track_id)
    write_objects_csv(HERE / "objects.csv", objects)


if __name__ == "__main__":
    main()
