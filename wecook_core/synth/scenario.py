"""Synthetic cooking scenarios with known answers: :func:`synthesize` (pure) and :func:`write_scenario`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wecook_core.model import Action, Observations, TreeSpan, VideoInfo
from wecook_core.synth.detect import BodyDetections, detect_bodies, detect_objects, hand_tracks
from wecook_core.synth.scene import Scene, resolve
from wecook_core.synth.script import write_script
from wecook_core.trees.notation import tree_of

VIDEO_NAME = "video.mp4"


@dataclass(frozen=True, eq=False)
class Scenario:
    """A synthetic video's inputs and its true answers."""

    seed: int
    persons: int
    size: tuple[int, int]
    """Image width and height, pixels."""
    observations: Observations
    """What the pipeline starts from: video facts, object boxes, hand tracks, categories."""
    truth: tuple[TreeSpan, ...]
    """The true trees, by start frame: each from the grasp that starts its action to the release that ends it.
    Holding: the holder's grasp to release; handover: the giver's; a receiver's carry after a handover is a
    grasp-only tree (not counted by evaluation)."""
    actions: tuple[Action, ...]
    """The true actions, one per entry of ``truth``."""
    tasks: tuple[str, ...]
    """The script's task kinds in scheduling order (``cut``, ``holding``, ...)."""
    scene: Scene
    """True per-frame state, in the nominal 640x360 frame (what the renderer draws)."""
    bodies: tuple[BodyDetections, ...]
    """OpenPose-style keypoints of each person (output pixels), for :func:`write_openpose`."""

    @property
    def frames(self) -> int:
        return self.scene.frames

    @property
    def fps(self) -> float:
        return self.scene.fps


def synthesize(
    seed: int,
    persons: int = 2,
    *,
    duration_s: float | None = None,
    fps: float = 30.0,
    size: tuple[int, int] = (640, 360),
) -> Scenario:
    """A random scenario: the same seed gives the same scenario.

    Without ``duration_s`` the script does every task once (two persons: all eleven cases including holding
    and handover; one person: the nine individual ones) and lasts as long as that takes (40-60 s at two
    persons). With ``duration_s`` it repeats shuffled cycles until the time is full."""
    if persons not in (1, 2):
        raise ValueError("persons must be 1 or 2")
    if fps <= 0:
        raise ValueError("fps must be positive")
    width, height = int(size[0]), int(size[1])
    rng = np.random.default_rng(seed)
    limit = None if duration_s is None else max(1, round(duration_s * fps))
    script = write_script(rng, persons, fps, limit)
    scene = resolve(script, rng)
    objects = detect_objects(scene, (width, height), rng)
    bodies = detect_bodies(scene, (width, height), rng)
    hands = hand_tracks(bodies)
    categories = {path.name: path.category for path in scene.objects}
    video = VideoInfo(VIDEO_NAME, float(fps), scene.frames, width, height)
    observations = Observations(video, objects, hands, categories)
    actions = tuple(script.actions)
    truth = tuple(TreeSpan(a.start, a.end, tree_of(a)) for a in actions)
    return Scenario(seed, persons, (width, height), observations, truth, actions, tuple(script.tasks), scene,
                    bodies)
