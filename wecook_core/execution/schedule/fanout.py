"""One RunObserver that forwards every call to several (the recorder and a progress display, say)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Literal

from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, RunObserver, Vec3


class FanOut:
    """Calls each observer in order. An observer's exception propagates (a broken recorder stops the run)."""

    def __init__(self, *observers: RunObserver) -> None:
        self.observers = tuple(observers)

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None:
        for o in self.observers:
            o.on_start(frames, plan_yaml, seed, metadata)

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        for o in self.observers:
            o.on_state(t, poses, joints)

    def on_event(self, t: float, event: RunEvent) -> None:
        for o in self.observers:
            o.on_event(t, event)

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None:
        for o in self.observers:
            o.on_log(t, level, message)

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        for o in self.observers:
            o.on_image(t, jpeg, width, height)

    def on_end(self, t: float) -> None:
        for o in self.observers:
            o.on_end(t)
