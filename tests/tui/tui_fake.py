"""A tiny workspace built in the test: a short video, observations, a journal and an analysis that follows the
corrections. Used for widget-level tests that must not depend on the pipeline's numbers."""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

from wecook_core.model import (
    Action,
    ActionGraph,
    ActionKind,
    Associations,
    Category,
    Corrections,
    HandTrack,
    ObjectTrack,
    Observations,
    Segment,
    Segmentation,
    TreeSpan,
    VideoInfo,
)
from wecook_core.perception.pipeline import Analysis
from wecook_core.session.corrections import Correction, fold
from wecook_core.session.journal import Journal
from wecook_core.trees.notation import tree_of
from wecook_tui.frames import FrameSource
from wecook_tui.workspace import Opened

FRAMES = 60
SIZE = (320, 180)


def make_video(path: Path, frames: int = FRAMES, size: tuple[int, int] = SIZE) -> Path:
    """A lossless (FFV1) video at ``path`` (an .avi): its frames decode to exactly what was drawn, and drawn
    without text, so the snapshots do not change with OpenCV's version (its putText glyphs did, from 4 to 5)."""
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"FFV1"), 30.0, size)
    for i in range(frames):
        image = np.zeros((size[1], size[0], 3), np.uint8)
        image[:] = (40, 90, 140)
        cv2.circle(image, (20 + 4 * i % size[0], size[1] // 2), 12, (255, 255, 255), -1)
        for bit in range(6):  # the frame's number in binary, as squares (putText's glyphs change with OpenCV)
            if i >> bit & 1:
                image[6:14, 5 + 10 * bit:13 + 10 * bit] = (0, 255, 0)
        writer.write(image)
    writer.release()
    return path


def make_obs(video: Path, frames: int = FRAMES, size: tuple[int, int] = SIZE) -> Observations:
    idx = np.arange(frames, dtype=np.int64)

    def track(tid: int, name: str, box: tuple[float, float, float, float]) -> ObjectTrack:
        return ObjectTrack(tid, name.replace("_", " "), name, idx, np.tile(np.array(box, float), (frames, 1)))

    objects = (track(1, "knife", (40, 40, 90, 60)), track(2, "tomato", (150, 80, 180, 110)),
               track(3, "chopping_board", (120, 60, 240, 150)), track(4, "bowl", (250, 20, 300, 70)))
    xy = np.stack([np.linspace(60, 160, frames), np.full(frames, 55.0)], axis=1)
    left = xy[::-1] + np.array([0.0, 60.0])
    hands = (HandTrack("RH_P1", idx, xy, np.hstack([xy - 8, xy + 8])),
             HandTrack("LH_P1", idx, left, np.hstack([left - 8, left + 8])))
    categories = {"knife": Category.TOOL, "tomato": Category.INGREDIENT, "chopping_board": Category.CONTAINER,
                  "bowl": Category.CONTAINER}
    return Observations(VideoInfo(str(video), 30.0, frames, size[0], size[1]), objects, hands, categories)


class FakeSession:
    """A session without inputs: only a real journal (the same fold, undo and redo as a real session)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.params = None
        self.warnings: list[str] = []
        self.journal = Journal(path / "journal.jsonl")
        self.trees_path = path / "trees.yaml"
        self.graph_path = path / "graph.yaml"

    @property
    def applied_corrections(self) -> tuple[Correction, ...]:
        return self.journal.applied_corrections

    @property
    def corrections(self) -> Corrections:
        return self.journal.corrections

    def record(self, correction: Correction) -> None:
        self.journal.record(correction)

    def undo(self) -> Correction | None:
        taken = self.journal.applied[-1].correction if self.journal.can_undo else None
        self.journal.undo()
        return taken

    def redo(self) -> Correction | None:
        return self.journal.applied[-1].correction if self.journal.redo() is not None else None


def fake_analyze(obs: Observations, applied: Sequence[Correction]) -> Analysis:
    cuts = ({20, 40} | set(fold(applied).splits)) - set(fold(applied).merges)
    bounds = [0, *sorted(c for c in cuts if 0 < c < obs.video.frame_count), obs.video.frame_count]
    segs = tuple(Segment(a, b) for a, b in itertools.pairwise(bounds))
    corrections = fold(applied, segs)
    assocs, actions, trees = [], [], []
    for seg in segs:
        held = corrections.hand_object.get((seg.start, "RH_P1"), "knife")
        targets = corrections.object_object.get((seg.start, held or ""), ("tomato", "chopping_board"))
        assocs.append(Associations(seg, {"RH_P1": held} if held else {}, {held: targets} if held else {},
                                   {"tomato": "chopping_board"}))
        verb = corrections.verbs.get((seg.start, "RH_P1"), "cut")
        if held:
            action = Action(ActionKind.TOOL, "RH_P1", seg.start, seg.end, verb=verb, held=held, targets=targets,
                            scores=((verb, 0.7), ("peel", 0.2)))
            actions.append(action)
            trees.append(TreeSpan(seg.start, seg.end, tree_of(action)))
    per_segment = tuple(FakeSegmentActions(seg, tuple(a for a in actions if a.start == seg.start)) for seg in segs)
    return Analysis(Segmentation({"RH_P1": tuple(bounds[1:-1])}, segs), tuple(assocs), per_segment,  # type: ignore[arg-type]
                    tuple(actions), tuple(trees), ActionGraph((), {}, ()), corrections)


@dataclass(frozen=True)
class FakeSegmentActions:
    segment: Segment
    actions: tuple[Action, ...]
    rankings: dict = field(default_factory=dict)


def fake_workspace(folder: Path) -> tuple[callable, callable]:  # type: ignore[valid-type]
    """(opener, analyzer) for ``WecookApp`` over a fake session in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    video = folder / "video.avi"
    if not video.exists():
        make_video(video)
    obs = make_obs(video)

    def opener(path: Path) -> Opened:
        path.mkdir(parents=True, exist_ok=True)
        return Opened(FakeSession(path), obs, None, FrameSource(obs.video.path), [])

    def analyzer(opened: Opened, corrections: Sequence[Correction]) -> Analysis:
        return fake_analyze(opened.observations, corrections)

    return opener, analyzer
