"""The writer of a synthetic script: the :class:`Script` it fills, and the mechanics every task shares (who and
what is free when, taking an object and visiting stations with it, committing a drafted task)."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from wecook_core.model import Action
from wecook_core.synth.draft import Draft, point
from wecook_core.synth.events import Effect, PositionEvent, Resize, Ride, Turn
from wecook_core.synth.layout import Body, Layout, Thing, extent
from wecook_core.synth.motion import Phase, rotation


@dataclass(eq=False)
class Script:
    """Everything the scheduler decided; positions are resolved per frame by :mod:`wecook_core.synth.scene`."""

    layout: Layout
    fps: float
    frames: int
    phases: dict[str, list[Phase]] = field(default_factory=lambda: defaultdict(list))
    """Hand -> its phases, in time order."""
    moves: dict[str, list[PositionEvent]] = field(default_factory=lambda: defaultdict(list))
    """Object name -> position events, in time order."""
    turns: dict[str, list[Turn]] = field(default_factory=lambda: defaultdict(list))
    sizes: dict[str, list[Resize]] = field(default_factory=lambda: defaultdict(list))
    marks: dict[str, list[int]] = field(default_factory=lambda: defaultdict(list))
    """Object name -> frames where it was worked once more (a cut, a peel): drawn, not detected."""
    effects: list[Effect] = field(default_factory=list)
    actions: list[Action] = field(default_factory=list)
    """The true actions (one tree each), plus the receiver's carry after a handover (a GRASP)."""
    tasks: list[str] = field(default_factory=list)
    """Task kinds in the order they were scheduled."""
    initial_homes: dict[str, np.ndarray] = field(default_factory=dict)
    """Object name -> where it lay at the start (handovers move ``Thing.home`` while scheduling)."""


TAIL_SECONDS = 1.5
"""Idle time after the last task."""


def angle_of(d: np.ndarray) -> float:
    return float(np.arctan2(d[1], d[0]))


def reach_out(box_half: np.ndarray, direction: np.ndarray) -> float:
    """Distance from a box's centre to its edge along ``direction`` (a unit vector)."""
    dx, dy = abs(float(direction[0])), abs(float(direction[1]))
    return min(box_half[0] / dx if dx > 1e-9 else np.inf, box_half[1] / dy if dy > 1e-9 else np.inf)


def half_extent(thing: Thing, angle: float | None = None, scale: tuple[float, float] = (1.0, 1.0)) -> np.ndarray:
    size = (thing.kind.size[0] * scale[0], thing.kind.size[1] * scale[1])
    return extent(size, thing.angle if angle is None else angle, thing.kind.round)


class Writer:
    """Schedules tasks onto the persons and writes each into the script."""

    def __init__(self, layout: Layout, fps: float, rng: np.random.Generator, limit: int | None) -> None:
        self.layout = layout
        self.fps = fps
        self.rng = rng
        self.limit = limit
        self.script = Script(layout, fps, 0)
        self.script.initial_homes = {name: thing.home.copy() for name, thing in layout.things.items()}
        self.free: dict[str, int] = {b.person: round(rng.uniform(0.4, 1.2) * fps) for b in layout.bodies}
        self.object_free: dict[str, int] = defaultdict(int)
        self.dough_scale = (1.0, 1.0)

    # ---- helpers
    def thing(self, name: str) -> Thing:
        return self.layout.things[name]

    def owner(self, group: str) -> str:
        first = self.layout.groups[group][0]
        return self.thing(first).owner or "P1"

    def body(self, person: str) -> Body:
        return self.layout.body(person)

    def pause(self) -> int:
        return round(self.rng.uniform(0.3, 1.3) * self.fps)

    def start_after(self, persons: tuple[str, ...], objects: tuple[str, ...]) -> int:
        return self.ready(persons, objects) + self.pause()

    def ready(self, persons: tuple[str, ...], objects: tuple[str, ...]) -> int:
        return max([self.free[p] for p in persons] + [self.object_free[o] for o in objects])

    def grip_point(self, thing: Thing, grip: np.ndarray, angle: float | None = None) -> np.ndarray:
        return thing.home + rotation(thing.angle if angle is None else angle) @ grip

    def commit(self, draft: Draft, persons: tuple[str, ...], kind: str) -> bool:
        if self.limit is not None and draft.end + round(TAIL_SECONDS * self.fps) > self.limit:
            return False
        s = self.script
        for hand, phases in draft.phases.items():
            s.phases[hand].extend(phases)
        for name, moves in draft.moves.items():
            s.moves[name].extend(moves)
        for name, turns in draft.turns.items():
            s.turns[name].extend(turns)
        for name, sizes in draft.sizes.items():
            s.sizes[name].extend(sizes)
        for name, marks in draft.marks.items():
            s.marks[name].extend(marks)
        s.effects.extend(draft.effects)
        s.actions.extend(draft.actions)
        for person in persons:
            self.free[person] = max(self.free[person], draft.end)
        for name, until in draft.busy.items():
            self.object_free[name] = max(self.object_free[name], until)
        for change in draft.commits:
            change()
        s.tasks.append(kind)
        s.frames = max(s.frames, draft.end)
        return True

    # ---- the common shape of a task: take an object, visit stations, put it back
    def take(
        self, draft: Draft, hand: str, t: int, thing: Thing, grip: np.ndarray,
        stations: list[Callable[[int], int]], poses: list[tuple[np.ndarray, float]],
        back: tuple[np.ndarray, float] | None = None,
    ) -> tuple[int, int, int, list[int]]:
        """Reach ``thing``, grasp it at ``grip`` (local frame), visit each pose (hand position, object angle)
        and run its station there (which returns the frame it ends), carry it to ``back`` (default: home),
        release and return to rest. Returns (grasp frame, release frame, end frame, station start frames)."""
        body = self.body(hand[-2:])
        rest = np.asarray(body.rests[hand])
        start_point = self.grip_point(thing, grip)
        t1 = draft.move(hand, t, rest, start_point)
        t = draft.hold(hand, t1, start_point, draft.span(0.15, 0.3))
        here, angle = start_point, thing.angle
        starts = []
        for (pose, pose_angle), station in zip(poses, stations, strict=True):
            if float(np.hypot(*(pose - here))) > 0.5:
                end = draft.move(hand, t, here, pose, pace=1.1)
                if abs(pose_angle - angle) > 1e-6:
                    draft.turns[thing.name].append(Turn(t, end, pose_angle))
                t = end
            here, angle = pose, pose_angle
            starts.append(t)
            t = station(t)
        home_point, home_angle = back if back is not None else (start_point, thing.angle)
        if float(np.hypot(*(home_point - here))) > 0.5:
            end = draft.move(hand, t, here, home_point, pace=1.1)
            if abs(home_angle - angle) > 1e-6:
                draft.turns[thing.name].append(Turn(t, end, home_angle))
            t = end
        release = draft.hold(hand, t, home_point, draft.span(0.15, 0.3))
        end = draft.move(hand, release, home_point, rest)
        vector = -np.asarray(grip, dtype=float)
        draft.moves[thing.name].append(Ride(t1, release, hand, thing.name, point(vector)))
        draft.use(thing.name, end)
        return t1, release, end, starts
