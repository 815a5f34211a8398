"""MediaPipe's hand detector end to end, on a video rendered from a licensed hand photo (tests/data/README.md:
a crop of an image of the MediaPipe repository, Apache License 2.0). The synthetic renderer's hands are drawn
too plainly for MediaPipe to find any (0 of the demo video's 1,459 frames), so a real hand is moved instead."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from wecook_core.formats.native import read_hands_csv
from wecook_core.observations.hands_detect import DetectParams, HandDetector, detect_hands
from wecook_tui.cli import main

HAND = Path(__file__).resolve().parents[1] / "data" / "hand_four.png"
FRAMES = 12


def render(path: Path, frames: int = FRAMES, fps: float = 10.0) -> list[tuple[float, float]]:
    """A 640x360 video: the hand moving right on the left half, its mirror image moving left on the right
    half. Returns the centre of the photo's hand (left copy) per frame."""
    hand = cv2.resize(cv2.imread(str(HAND)), None, fx=2, fy=2, interpolation=cv2.INTER_CUBIC)
    h, w = hand.shape[:2]
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, (640, 360))
    centres = []
    for i in range(frames):
        image = np.full((360, 640, 3), 190, np.uint8)
        x = 40 + 5 * i
        image[100:100 + h, x:x + w] = hand
        x2 = 430 - 4 * i
        image[80:80 + h, x2:x2 + w] = hand[:, ::-1]
        writer.write(image)
        centres.append((x + w / 2, 100 + h / 2))
    writer.release()
    return centres


@pytest.fixture(scope="module")
def video(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[tuple[float, float]]]:
    path = tmp_path_factory.mktemp("hands") / "two_hands.mp4"
    return path, render(path)


@pytest.mark.slow
def test_the_photo_hand_is_found_with_both_models() -> None:
    image = cv2.resize(cv2.imread(str(HAND)), None, fx=3, fy=3)
    for model in ("full", "lite"):
        with HandDetector(DetectParams(model=model), static=True) as detector:
            found = detector.detect(0, image)
        assert len(found) == 1, model
        x1, y1, x2, y2 = found[0].box
        assert x1 < found[0].xy[0] < x2 and y1 < found[0].xy[1] < y2
        assert found[0].label == "Left" and found[0].score > 0.8  # MediaPipe's mirrored-image convention


@pytest.mark.parametrize("model", ["full", "lite"])
@pytest.mark.slow
def test_a_video_gives_both_hands_named_and_tracked(video, model: str) -> None:
    path, centres = video
    done: list[tuple[int, int]] = []
    found = detect_hands(path, DetectParams(model=model), progress=lambda n, total: done.append((n, total)))
    assert found.frames_read == FRAMES and done[-1] == (FRAMES, FRAMES)
    by_name = {t.hand: t for t in found.tracks}
    assert set(by_name) == {"LH_P1", "RH_P1"}
    right = by_name["RH_P1"]  # the photo's own hand: a right hand seen from the front
    assert len(right.frames) >= FRAMES - 1
    truth = np.array([centres[f] for f in right.frames])
    assert np.abs(right.xy - truth).max() < 40  # the hand's centre, not the photo's: within its size
    assert (by_name["LH_P1"].xy[:, 0] > 320).all()


@pytest.mark.slow
def test_wecook_hands_writes_a_csv_the_importer_reads(video, tmp_path: Path, capsys) -> None:
    path, _ = video
    out = tmp_path / "hands.csv"
    raw = tmp_path / "raw.csv"
    assert main(["hands", str(path), "-o", str(out), "--detections", str(raw), "--hand-model", "lite"]) == 0
    tracks = read_hands_csv(out)
    assert {t.hand for t in tracks} == {"LH_P1", "RH_P1"}
    header, first = raw.read_text().splitlines()[:2]
    assert header == "frame,hand,detector_label,score,x,y,x1,y1,x2,y2"
    assert first.split(",")[2] in ("Left", "Right") and 0.5 <= float(first.split(",")[3]) <= 1
    before = out.read_bytes()
    assert main(["hands", str(path), "-o", str(out)]) == 2  # never overwrites
    assert "not overwritten" in capsys.readouterr().err
    assert out.read_bytes() == before


@pytest.mark.slow
def test_wecook_new_without_hands_detects_them(video, tmp_path: Path, capsys) -> None:
    path, _ = video
    objects = tmp_path / "objects.csv"
    objects.write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,bowl,300,250,400,340\n11,1,bowl,300,250,400,340\n")
    root = tmp_path / "sessions"
    assert main(["new", "s", "--video", str(path), "--objects", str(objects), "--root", str(root),
                 "--hand-model", "lite"]) == 0
    assert {t.hand for t in read_hands_csv(root / "s.hands.csv")} == {"LH_P1", "RH_P1"}
    assert "hands.csv" in (root / "s" / "session.yaml").read_text()
    # Bad boxes are found before the slow detection, and nothing is written.
    bad = tmp_path / "bad.csv"
    bad.write_text("frame,track_id,label,x1,y1,x2,y2\n")
    assert main(["new", "t", "--video", str(path), "--objects", str(bad), "--root", str(root)]) == 2
    assert not (root / "t.hands.csv").exists() and not (root / "t").exists()


def test_a_video_without_hands_is_one_line(tmp_path: Path, capsys) -> None:
    path = tmp_path / "empty.mp4"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 5.0, (160, 120))
    for _ in range(3):
        writer.write(np.full((120, 160, 3), 128, np.uint8))
    writer.release()
    assert main(["hands", str(path), "-o", str(tmp_path / "h.csv")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "no hand found in any of the 3 frames" in err
    assert not (tmp_path / "h.csv").exists()
