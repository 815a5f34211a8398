"""Joint-space motion planning behind a small interface that knows nothing of the simulator.

A :class:`MotionProblem` is a start, a goal, joint bounds and a ``collision_fn(q) -> bool`` (True = in
collision); an adapter (``planning_scene.py`` for PyBullet) builds that function. Backends are chosen by name:

- ``"rrtconnect"``: OMPL's RRTConnect (ompl 2.0.1 bindings) in a RealVectorStateSpace, then
  ``PathSimplifier.reduceVertices`` (a few ms; the full ``simplify`` costs ~100 ms).
- ``"birrt"``: a small pure-Python bidirectional RRT with random shortcutting, driven by
  ``sample_fn / distance_fn / extend_fn / collision_fn``; used where OMPL is unwanted and as a cross-check.

Every query has a wall-clock time limit and a seed; the same seed and problem give the same path (OMPL's
global RNG is re-seeded before each query; a query that hits its time limit may differ between runs).
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal, Protocol

import numpy as np

CollisionFn = Callable[[np.ndarray], bool]
Status = Literal["exact", "timeout", "invalid_start", "invalid_goal"]
BOUND_SLACK = 1e-3
"""Radians a start or goal may lie outside the joint bounds (it is clipped inside); further out it is invalid."""


@dataclass(frozen=True, eq=False)
class MotionProblem:
    start: np.ndarray
    """float64 (n,), radians / metres per joint."""
    goal: np.ndarray
    lower: np.ndarray
    """Joint lower bounds, (n,)."""
    upper: np.ndarray
    collision_fn: CollisionFn
    """True when the configuration collides (or is otherwise invalid)."""
    resolution: float = 0.03
    """Largest joint-space step (Euclidean, radians) between two checked states of a motion."""


@dataclass(frozen=True, eq=False)
class MotionResult:
    status: Status
    path: tuple[np.ndarray, ...] = ()
    """Waypoints from start to goal inclusive (empty unless ``status == "exact"``); straight segments between
    consecutive waypoints are collision-free at ``resolution``."""
    seconds: float = 0.0
    """Wall time of the query."""
    checks: int = 0
    """Collision checks made."""

    @property
    def ok(self) -> bool:
        return self.status == "exact"


class Planner(Protocol):
    def __call__(self, problem: MotionProblem, *, time_limit: float, seed: int) -> MotionResult: ...


@dataclass
class _Counter:
    fn: CollisionFn
    count: int = 0

    def __call__(self, q: np.ndarray) -> bool:
        self.count += 1
        return bool(self.fn(q))


def segment_free(collides: CollisionFn, a: np.ndarray, b: np.ndarray, resolution: float) -> bool:
    """True when every state on the straight segment a-b (``resolution`` apart, ends included) is free."""
    n = max(int(np.ceil(np.linalg.norm(b - a) / resolution)), 1)
    return all(not collides(a + (b - a) * (i / n)) for i in range(n + 1))


def path_free(collides: CollisionFn, path: Sequence[np.ndarray], resolution: float) -> bool:
    return all(segment_free(collides, a, b, resolution) for a, b in itertools.pairwise(path))


# --------------------------------------------------------------------------------------------- OMPL


def plan_rrtconnect(problem: MotionProblem, *, time_limit: float, seed: int) -> MotionResult:
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util as ou

    began = time.perf_counter()
    collides = _Counter(problem.collision_fn)
    if collides(problem.start):
        return MotionResult("invalid_start", seconds=time.perf_counter() - began, checks=collides.count)
    if collides(problem.goal):
        return MotionResult("invalid_goal", seconds=time.perf_counter() - began, checks=collides.count)
    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    ou.RNG.setSeed(int(seed) % (2**31 - 1) + 1)  # samplers created below draw their seeds from this
    n = len(problem.start)
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i in range(n):
        bounds.setLow(i, float(problem.lower[i]))
        bounds.setHigh(i, float(problem.upper[i]))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    buffer = np.empty(n)

    pending: list[BaseException] = []

    def valid(state: object) -> bool:
        """A Python bool (ompl 2.0.1 rejects np.bool_); never raises into C++: an exception (Ctrl-C, SIGTERM
        turned KeyboardInterrupt) is kept, every state is invalid from then on, and it is raised after solve."""
        if pending:
            return False
        try:
            for i in range(n):
                buffer[i] = state[i]  # type: ignore[index]
            return not collides(buffer.copy())
        except BaseException as error:
            pending.append(error)
            return False

    setup.setStateValidityChecker(valid)
    info = setup.getSpaceInformation()
    info.setStateValidityCheckingResolution(problem.resolution / max(space.getMaximumExtent(), 1e-9))
    start, goal = space.allocState(), space.allocState()
    for i in range(n):
        start[i] = float(problem.start[i])
        goal[i] = float(problem.goal[i])
    setup.setStartAndGoalStates(start, goal)
    setup.setPlanner(og.RRTConnect(info))
    status = setup.solve(float(time_limit))
    if pending:
        raise pending[0]
    if status != ob.PlannerStatus.EXACT_SOLUTION:
        return MotionResult("timeout", seconds=time.perf_counter() - began, checks=collides.count)
    path = setup.getSolutionPath()
    og.PathSimplifier(info).reduceVertices(path)
    waypoints = tuple(np.array([path.getState(k)[i] for i in range(n)]) for k in range(path.getStateCount()))
    return MotionResult("exact", waypoints, seconds=time.perf_counter() - began, checks=collides.count)


# ------------------------------------------------------------------------------------- pure Python


@dataclass
class BiRRT:
    """Bidirectional RRT (connect heuristic) over user functions, then random shortcutting."""

    sample_fn: Callable[[np.random.Generator], np.ndarray] | None = None
    distance_fn: Callable[[np.ndarray, np.ndarray], float] = field(
        default=lambda a, b: float(np.linalg.norm(a - b)))
    step: float = 0.3
    """Longest tree edge (joint-space distance)."""
    shortcut_rounds: int = 40

    def __call__(self, problem: MotionProblem, *, time_limit: float, seed: int) -> MotionResult:
        began = time.perf_counter()
        rng = np.random.default_rng(seed)
        collides = _Counter(problem.collision_fn)
        if collides(problem.start):
            return MotionResult("invalid_start", seconds=time.perf_counter() - began, checks=collides.count)
        if collides(problem.goal):
            return MotionResult("invalid_goal", seconds=time.perf_counter() - began, checks=collides.count)
        sample = self.sample_fn or (lambda g: g.uniform(problem.lower, problem.upper))
        res = problem.resolution

        def extend(a: np.ndarray, b: np.ndarray) -> np.ndarray:
            d = self.distance_fn(a, b)
            return b if d <= self.step else a + (b - a) * (self.step / d)

        start_tree: list[tuple[np.ndarray, int]] = [(problem.start, -1)]
        trees: list[list[tuple[np.ndarray, int]]] = [start_tree, [(problem.goal, -1)]]

        def nearest(tree: list[tuple[np.ndarray, int]], q: np.ndarray) -> int:
            return int(np.argmin([self.distance_fn(node, q) for node, _ in tree]))

        def grow(tree: list[tuple[np.ndarray, int]], target: np.ndarray, connect: bool) -> int | None:
            index = nearest(tree, target)
            last = None
            while True:
                near = tree[index][0]
                new = extend(near, target)
                if not segment_free(collides, near, new, res):
                    return last
                tree.append((new, index))
                index = last = len(tree) - 1
                if not connect or self.distance_fn(new, target) < 1e-12:
                    return last

        while time.perf_counter() - began < time_limit:
            a, b = trees
            new = grow(a, sample(rng), connect=False)
            if new is not None:
                reached = grow(b, a[new][0], connect=True)
                if reached is not None and self.distance_fn(b[reached][0], a[new][0]) < 1e-12:
                    half_a, half_b = _trace(a, new), _trace(b, reached)
                    path = half_a[::-1] + half_b[1:]
                    if a is not start_tree:
                        path = path[::-1]
                    path = self._shortcut(path, collides, res, rng)
                    return MotionResult("exact", tuple(path), seconds=time.perf_counter() - began,
                                        checks=collides.count)
            trees.reverse()
        return MotionResult("timeout", seconds=time.perf_counter() - began, checks=collides.count)

    def _shortcut(self, path: list[np.ndarray], collides: CollisionFn, res: float,
                  rng: np.random.Generator) -> list[np.ndarray]:
        for _ in range(self.shortcut_rounds):
            if len(path) <= 2:
                break
            i, j = sorted(rng.choice(len(path), size=2, replace=False))
            if j - i > 1 and segment_free(collides, path[i], path[j], res):
                path = path[: i + 1] + path[j:]
        return path


def _trace(tree: list[tuple[np.ndarray, int]], index: int) -> list[np.ndarray]:
    out = []
    while index >= 0:
        node, parent = tree[index]
        out.append(node)
        index = parent
    return out


PLANNERS: dict[str, Planner] = {"rrtconnect": plan_rrtconnect, "birrt": BiRRT()}


def plan_motion(problem: MotionProblem, *, planner: str = "rrtconnect", time_limit: float = 1.0,
                seed: int = 0) -> MotionResult:
    """Plan a collision-free joint path with the named backend; never runs past ``time_limit`` (plus setup)."""
    try:
        backend = PLANNERS[planner]
    except KeyError:
        raise ValueError(f"unknown planner {planner!r}; expected one of {sorted(PLANNERS)}") from None
    for name, status in (("start", "invalid_start"), ("goal", "invalid_goal")):
        q = getattr(problem, name)
        if np.any(q < problem.lower - BOUND_SLACK) or np.any(q > problem.upper + BOUND_SLACK):
            return MotionResult(status)  # type: ignore[arg-type]
    # a simulated joint may sit a hair outside its limit: bring it inside
    problem = replace(problem, start=np.clip(problem.start, problem.lower, problem.upper),
                      goal=np.clip(problem.goal, problem.lower, problem.upper))
    return backend(problem, time_limit=time_limit, seed=seed)
