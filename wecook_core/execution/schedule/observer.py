"""What an execution run reports while it runs. The MCAP recorder and the terminal progress implement it.

The executor knows nothing of MCAP or the terminal: it calls these methods with plain data. Times are simulated
seconds since the start of the run. Poses are ``(position xyz metres, quaternion xyzw)`` in the world frame
(z up, table top at the height the scene states).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal, Protocol

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


@dataclass(frozen=True)
class Shape:
    """A primitive shape of a body or link, for drawing (Foxglove SceneUpdate)."""

    kind: Literal["box", "cylinder", "sphere"]
    size: Vec3
    """Metres: box full extents; cylinder (diameter, diameter, height); sphere (d, d, d)."""
    pose: tuple[Vec3, Quat] = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    """Pose of the shape in its frame."""
    color: tuple[float, float, float, float] = (0.7, 0.7, 0.7, 1.0)


@dataclass(frozen=True)
class FrameInfo:
    """A named frame (a link of an arm, an object, the table) and the shapes drawn in it."""

    frame_id: str
    """``"world"``-relative name, e.g. ``"P1/panda_link3"``, ``"object/knife"``, ``"table"``."""
    shapes: tuple[Shape, ...] = ()


@dataclass(frozen=True)
class RunEvent:
    """A step of the plan: an action or a primitive starting, ending or failing."""

    kind: Literal["action_start", "action_end", "action_failed", "primitive_start", "primitive_end",
                  "primitive_failed", "retry", "wait", "run_end"]
    action_id: str | None = None
    primitive: str | None = None
    """``grasp`` / ``engage`` / ``actuate`` / ``place`` (or a skill-specific name)."""
    agent: str | None = None
    """``P1`` / ``P2``."""
    detail: str = ""
    """Human-readable: the failure reason, the retry count, what is awaited."""
    data: Mapping[str, object] = field(default_factory=dict)


class RunObserver(Protocol):
    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None: ...

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        """Every frame's world pose, and each agent's joint names and positions (radians / metres)."""

    def on_event(self, t: float, event: RunEvent) -> None: ...

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None: ...

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        """A camera view of the scene (taken at action boundaries)."""

    def on_end(self, t: float) -> None: ...
