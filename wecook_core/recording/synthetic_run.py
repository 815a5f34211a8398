"""A synthetic run: the calls an executor makes on a RunObserver, at the executor's rates, without a simulation.

For testing recorders and progress displays, and for measuring recording overhead on its own. The two "arms"
are chains of links whose joints follow sine waves; the actions start and end on schedule (``fail`` names
actions that fail instead); the images are said to come from :data:`CAMERA` at :data:`CAMERA_POSE` (in the
metadata and in every state's poses, as :class:`~wecook_core.recording.camera.CameraObserver` does).
Deterministic for a given seed.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, RunObserver, Shape, Vec3
from wecook_core.recording.camera import FRAME, Pinhole, optical_pose

LINKS = 9
"""Links per synthetic arm (like a Panda: link0..link7 and the hand)."""
OBJECTS: tuple[str, ...] = ("knife", "tomato", "chopping_board", "pot", "spoon")
CAMERA = Pinhole(320, 240, 55.0)
"""The camera the synthetic images are said to come from."""
CAMERA_POSE = optical_pose((0.0, -1.1, 0.9), (0.0, 0.0, 0.1))


@dataclass(frozen=True)
class SyntheticRunStats:
    states: int
    events: int
    logs: int
    images: int
    sim_seconds: float


def synthetic_frames() -> tuple[FrameInfo, ...]:
    frames = [FrameInfo("table", (Shape("box", (1.0, 0.8, 0.04), ((0.0, 0.0, -0.02), (0, 0, 0, 1)),
                                        (0.6, 0.45, 0.3, 1.0)),))]
    for agent in ("P1", "P2"):
        for k in range(LINKS):
            frames.append(FrameInfo(f"{agent}/link{k}", (Shape("cylinder", (0.08, 0.08, 0.12)),)))
    for name in OBJECTS:
        frames.append(FrameInfo(f"object/{name}", (Shape("box", (0.05, 0.05, 0.05), color=(0.8, 0.2, 0.2, 1.0)),)))
    return tuple(frames)


def _poses(t: float, q: dict[str, np.ndarray]) -> dict[str, tuple[Vec3, Quat]]:
    poses: dict[str, tuple[Vec3, Quat]] = {"table": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))}
    for agent, sign in (("P1", -1.0), ("P2", 1.0)):
        x, z = sign * 0.5, 0.0
        angle = 0.0
        for k in range(LINKS):
            angle += float(q[agent][k % len(q[agent])]) * 0.2
            x -= sign * 0.08 * math.sin(angle)
            z += 0.08 * math.cos(angle)
            half = angle / 2
            poses[f"{agent}/link{k}"] = ((x, 0.0, z), (0.0, math.sin(half), 0.0, math.cos(half)))
    for i, name in enumerate(OBJECTS):
        poses[f"object/{name}"] = ((0.1 * math.sin(t + i), 0.05 * i - 0.1, 0.03), (0.0, 0.0, 0.0, 1.0))
    poses[FRAME] = CAMERA_POSE
    return poses


def synthetic_run(observer: RunObserver, *, actions: int = 6, seconds_per_action: float = 2.0,
                  state_hz: float = 30.0, wall_per_sim: float = 0.0, fail: Sequence[str] = (),
                  seed: int = 0, plan_yaml: str = "wecook_plan: 1\n", jpeg: bytes = b"\xff\xd8synthetic\xff\xd9",
                  end: bool = True, joint_names: Sequence[str] = ()) -> SyntheticRunStats:
    """Drive ``observer`` through a run of ``actions`` actions (ids ``a1``...), alternating arms.

    ``wall_per_sim``: wall seconds slept per simulated second (0: as fast as possible). ``end=False`` stops
    before ``run_end`` / ``on_end`` (as if the process died). ``joint_names``: the seven joints' names (default
    ``joint1``..``joint7``), e.g. a URDF's.
    """
    rng = np.random.default_rng(seed)
    joint_names = list(joint_names) or [f"joint{k + 1}" for k in range(7)]
    if len(joint_names) != 7:
        raise ValueError("a synthetic arm has seven joints")
    phase = {agent: rng.uniform(0, 2 * math.pi, 7) for agent in ("P1", "P2")}
    observer.on_start(synthetic_frames(), plan_yaml, seed, {"source": "synthetic", **CAMERA.metadata()})
    states = events = logs = images = 0
    dt = 1.0 / state_hz
    t = 0.0
    for n in range(actions):
        aid, agent = f"a{n + 1}", ("P1", "P2")[n % 2]
        observer.on_event(t, RunEvent("action_start", aid, agent=agent))
        observer.on_image(t, jpeg, CAMERA.width, CAMERA.height)
        events, images = events + 1, images + 1
        primitives = ("grasp", "engage", "actuate", "place")
        steps = max(int(seconds_per_action * state_hz), len(primitives))
        for step in range(steps):
            if step % (steps // len(primitives)) == 0 and step // (steps // len(primitives)) < len(primitives):
                primitive = primitives[step // (steps // len(primitives))]
                observer.on_event(t, RunEvent("primitive_start", aid, primitive, agent))
                observer.on_log(t, "info", f"{aid} {agent}: {primitive}")
                events, logs = events + 1, logs + 1
            q = {a: np.sin(t + phase[a]) for a in ("P1", "P2")}
            observer.on_state(t, _poses(t, q), {a: (joint_names, q[a].tolist()) for a in ("P1", "P2")})
            states += 1
            if wall_per_sim:
                time.sleep(dt * wall_per_sim)
            t += dt
        if aid in fail:
            observer.on_event(t, RunEvent("action_failed", aid, agent=agent, detail="synthetic failure"))
        else:
            observer.on_event(t, RunEvent("action_end", aid, agent=agent))
        observer.on_image(t, jpeg, CAMERA.width, CAMERA.height)
        events, images = events + 1, images + 1
    if end:
        observer.on_event(t, RunEvent("run_end"))
        observer.on_end(t)
        events += 1
    return SyntheticRunStats(states, events, logs, images, t)
