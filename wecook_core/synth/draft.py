"""One task of a synthetic script being written (:mod:`wecook_core.synth.script`): its hand phases and object
events are kept apart until the task is known to fit, then committed to the script."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable

import numpy as np

from wecook_core.model import Action
from wecook_core.synth.events import Effect, PositionEvent, Resize, Turn
from wecook_core.synth.motion import Hold, Move, Phase, Work


class Draft:
    """One task being written: its phases and events are kept apart until the task is known to fit."""

    def __init__(self, fps: float, rng: np.random.Generator) -> None:
        self.fps = fps
        self.rng = rng
        self.phases: dict[str, list[Phase]] = defaultdict(list)
        self.moves: dict[str, list[PositionEvent]] = defaultdict(list)
        self.turns: dict[str, list[Turn]] = defaultdict(list)
        self.sizes: dict[str, list[Resize]] = defaultdict(list)
        self.marks: dict[str, list[int]] = defaultdict(list)
        self.effects: list[Effect] = []
        self.actions: list[Action] = []
        self.commits: list[Callable[[], None]] = []
        self.busy: dict[str, int] = {}
        """Object name -> first frame it is free again."""
        self.end = 0

    def frames(self, seconds: float) -> int:
        return max(1, round(seconds * self.fps))

    def span(self, low: float, high: float) -> int:
        return self.frames(self.rng.uniform(low, high))

    # hands
    def move(self, hand: str, t: int, p0: np.ndarray, p1: np.ndarray, pace: float = 1.0) -> int:
        distance = float(np.hypot(*(np.asarray(p1) - np.asarray(p0))))
        seconds = (0.35 + distance / 380.0) * pace * self.rng.uniform(0.9, 1.15)
        end = t + self.frames(seconds)
        bulge = self.rng.normal(0.0, 0.07) * distance
        skew = self.rng.uniform(0.8, 1.2)
        self.phases[hand].append(Move(t, end, point(p0), point(p1), bulge, skew))
        self.end = max(self.end, end)
        return end

    def hold(self, hand: str, t: int, p: np.ndarray, frames: int) -> int:
        self.phases[hand].append(Hold(t, t + frames, point(p)))
        self.end = max(self.end, t + frames)
        return t + frames

    def work(self, hand: str, t: int, p: np.ndarray, pattern: str, axis: np.ndarray, amplitude: float,
             frequency: float, frames: int, drift: float = 0.0) -> int:
        axis = np.asarray(axis, dtype=float) / max(float(np.hypot(*axis)), 1e-9)
        phase = float(self.rng.uniform(0, 2 * np.pi)) if pattern in ("saw", "shake", "squeeze") else 0.0
        self.phases[hand].append(Work(t, t + frames, point(p), pattern, point(axis), amplitude, frequency, phase,
                                      drift))
        self.end = max(self.end, t + frames)
        return t + frames

    def use(self, name: str, until: int) -> None:
        self.busy[name] = max(self.busy.get(name, 0), until)


def point(p: np.ndarray | tuple[float, float]) -> tuple[float, float]:
    """``p`` as a tuple of two floats (pixels)."""
    return (float(p[0]), float(p[1]))
