"""The primitives of the world (:mod:`wecook_core.execution.world`) against a plain-Python scene and arms (no
simulator; they are its :class:`~wecook_core.execution.world.protocols.Scene` and ``Arm``): what the scene says
is held, the one retry policy. The engage goal: ``test_world_fake_engage.py``; the roles:
``test_world_fake_roles.py``."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import numpy as np
import pytest

from wecook_core.execution.schedule.program import WAIT, WORK, ActionFailed, Program
from wecook_core.execution.skills.library import Half, load_skills, object_kind
from wecook_core.execution.skills.tsr import sample
from wecook_core.execution.world.fingers import FINGER_CLEARANCE
from wecook_core.execution.world.primitives import Primitives
from wecook_core.execution.world.protocols import Cell, Hand, Riding
from wecook_core.execution.world.roles import RolePlayer
from wecook_core.model import Category
from wecook_core.plan import PlanAction, SceneObject

SKILLS = load_skills()
OBJECTS = (
    SceneObject("knife", Category.TOOL, "box", (0.24, 0.03, 0.025), -0.1, 0.15),
    SceneObject("bowl", Category.CONTAINER, "cylinder", (0.16, 0.16, 0.07), 0.1, -0.1),
    SceneObject("spoon", Category.TOOL, "box", (0.18, 0.03, 0.02), 0.15, 0.2),
    SceneObject("rice", Category.INGREDIENT, "box", (0.04, 0.04, 0.03), 0.1, -0.1),
)


def _at(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    T[:2, :2] = [[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]
    T[:3, 3] = [x, y, z]
    return T


class FakeScene:
    """Objects as boxes at poses; what rides on a hand is where that hand is; every call is logged in order."""

    hz = 20
    table_height = 0.0

    def __init__(self, objects: tuple[SceneObject, ...] = OBJECTS, inside: dict[str, str] | None = None):
        self.objects = {o.name: o for o in objects}
        self.poses = {o.name: _at(o.x, o.y, o.size[2] / 2, o.yaw) for o in objects}
        self.inside = inside if inside is not None else {"rice": "bowl"}
        self.bases = {"P1": _at(-0.6, 0.0, 0.0), "P2": _at(0.6, 0.0, 0.0, math.pi)}
        self.hands = {pid: Hand() for pid in self.bases}
        self.ees: dict[str, np.ndarray] = {}
        self.calls: list[tuple[str | None, str, str]] = []
        self.ticks = 0
        self.picked: dict[str, np.ndarray] = {}
        self.arm_collisions: dict[tuple[str, str], bool] = {}

    @property
    def time(self) -> float:
        return self.ticks / self.hz

    def event(self, kind, action, pid, detail="", primitive=None) -> None:
        self.calls.append((pid, kind, f"{primitive} {detail}"))

    def log(self, level, text) -> None:
        self.calls.append((None, level, text))

    def hold(self, seconds: float) -> Program:
        for _ in range(max(int(seconds * self.hz), 1)):
            yield WORK

    def sync(self) -> None:
        self.calls.append((None, "sync", ""))

    def names(self):
        return list(self.objects)

    def pose(self, name):
        for pid, hand in self.hands.items():
            for r in hand.riding:
                if r.name == name:
                    return self.ees[pid] @ r.T_ee_obj
        return self.poses[name].copy()

    def half(self, name):
        return Half() if name is None else Half(*(s / 2 for s in self.objects[name].size))

    def kind(self, name):
        o = self.objects[name]
        return object_kind(o.category, o.size, o.shape == "cylinder")

    def category(self, name):
        return self.objects[name].category

    def shape(self, name):
        return self.objects[name].shape

    def size(self, name):
        return self.objects[name].size

    def supports(self, name):
        return [self.inside[name]] if name in self.inside else []

    def container_of(self, name):
        return self.inside.get(name)

    def contents(self, name):
        return [n for n, c in self.inside.items() if c == name]

    def boxes(self, names):
        out = []
        for n in names:
            centre, half = self.pose(n)[:3, 3], np.array(self.objects[n].size) / 2
            out.append(np.array([centre - half, centre + half]))
        return out

    def base(self, pid):
        return self.bases[pid]

    def meet(self, giver, receiver):
        a, b = self.bases[giver][:3, 3], self.bases[receiver][:3, 3]
        return _at((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, SKILLS.meet_height, math.atan2(b[1] - a[1], b[0] - a[0]))

    def facing(self, name, pid):
        T, base = self.pose(name), self.bases[pid][:3, 3]
        return _at(*T[:3, 3], math.atan2(base[1] - T[1, 3], base[0] - T[0, 3]))

    def upright(self, name):
        return self.pose(name)

    def drop(self, pid):
        return self.bases[pid] @ _at(SKILLS.drop_distance, 0.0, 0.0, math.pi)

    def hand(self, pid):
        return self.hands[pid]

    def holder_of(self, name, pid):
        return next((k for k, h in self.hands.items() if k != pid and any(r.name == name for r in h.riding)), None)

    def picked_from(self, name):
        return self.picked.get(name)

    def attach(self, pid, name):
        self.calls.append((pid, "attach", name))
        self.picked[name] = self.pose(name)
        T_ee_obj = np.linalg.inv(self.ees[pid]) @ self.pose(name)
        hand = self.hands[pid]
        hand.carried, hand.constraint, hand.riding = name, 1, [Riding(name, T_ee_obj)]

    def detach(self, pid):
        self.calls.append((pid, "detach", str(self.hands[pid].carried)))
        for r in self.hands[pid].riding:  # let go where it is
            self.poses[r.name] = self.pose(r.name)
        hand = self.hands[pid]
        hand.carried, hand.constraint, hand.riding = None, None, []

    def ride(self, pid, name, T_ee_obj=None):
        T = np.linalg.inv(self.ees[pid]) @ self.pose(name) if T_ee_obj is None else T_ee_obj
        for hand in self.hands.values():
            hand.riding = [r for r in hand.riding if r.name != name]
        self.hands[pid].riding.append(Riding(name, T))

    def drop_riding(self, pid, names):
        gone = set(names)
        for r in self.hands[pid].riding:
            if r.name in gone:
                self.poses[r.name] = self.pose(r.name)
        self.hands[pid].riding = [r for r in self.hands[pid].riding if r.name not in gone]

    def collide_with_arm(self, pid, name, *, enabled):
        self.arm_collisions[(pid, name)] = enabled

    def set_collisions(self, pairs, *, enabled):
        self.calls.append((None, "collisions", f"{sorted(pairs)} {enabled}"))


class FakeArm:
    """Reaches every pose ``reachable`` takes; the first ``failing_transits`` planned moves find no path."""

    def __init__(self, pid: str, scene: FakeScene, reachable=lambda T: True, failing_transits: int = 0):
        self.pid, self.scene, self.reachable, self.failing_transits = pid, scene, reachable, failing_transits
        self.rest = scene.bases[pid] @ _at(0.1, 0.0, 0.5)
        scene.ees[pid] = self.rest.copy()
        self.rng = np.random.default_rng(0)
        self.goals: dict[bytes, np.ndarray] = {}

    def _log(self, op: str, what: str = "") -> None:
        self.scene.calls.append((self.pid, op, what))

    def q(self):
        return np.array([*self.scene.ees[self.pid][:3, 3], 0.0, 0.0, 0.0, 0.0])

    def ee(self):
        return self.scene.ees[self.pid].copy()

    def set_grip(self, width):
        self.scene.hands[self.pid].grip = width
        self._log("grip", f"{width:.3f}")

    def close_on(self, name, width):
        self.set_grip(width)
        return width, width

    def goal_samples(self, tsrs, T_eff_ee, n, accept=None, rank=None, spin=False):
        drawn = [sample(tsrs[int(self.rng.integers(len(tsrs)))], self.rng) @ T_eff_ee for _ in range(n * 12)]
        out = [T for T in drawn if accept is None or accept(T)][:n]
        return sorted(out, key=rank) if rank is not None else out

    def ik_goal(self, targets, ignore, check=True):
        for T in targets:
            if self.reachable(T):
                q = np.array([*T[:3, 3], float(len(self.goals)), 0.0, 0.0, 0.0])
                self.goals[q.tobytes()] = T
                return q, T
        return None

    def no_goal(self, what, count, accept=None):
        self._log("no goal", what)
        return f"no reachable {what} in {count} TSR samples"

    def clear_blockers(self):
        pass

    def away_from_other(self, near):
        return None

    def transit(self, goal, ignore=(), what="move") -> Program:
        self._log("transit", what)
        if self.failing_transits:
            self.failing_transits -= 1
            raise ActionFailed(f"{what}: no path (timeout)")
        yield WORK
        self.scene.ees[self.pid] = self.goals[goal.tobytes()].copy()

    def cartesian_path(self, q, poses, ignore, what, margin=-0.01):
        return [q, *(q for _ in poses)], [0.1 for _ in poses], list(range(1, len(poses) + 1))

    def linear(self, poses, ignore=None, holds=None, fingers=None, what="straight move", margin=-0.01,
               reached=None) -> Program:
        self._log("linear", what)
        for j, T in enumerate(poses):
            yield WORK
            self.scene.ees[self.pid] = T.copy()
            if reached is not None:
                reached(j)
            if fingers is not None and fingers[j] is not None:
                self.set_grip(fingers[j])
            if holds is not None and holds[j] > 0:
                yield from self.scene.hold(holds[j])

    def let_other_move(self, limit=4.0) -> Program:
        self._log("let other move")
        yield WAIT

    def park(self, what="move to rest") -> Program:
        self._log("park", what)
        yield WORK
        self.scene.ees[self.pid] = self.rest.copy()

    def home(self) -> Program:
        self._log("home")
        yield WORK
        self.scene.ees[self.pid] = self.rest.copy()

    @contextlib.contextmanager
    def margin_to_other(self, metres) -> Iterator[None]:
        self._log("margin", f"{metres}")
        yield
        self._log("margin", "back")

    def forget_motion(self):
        pass


class FakeWorld:
    """The scheduler's world over the fakes."""

    def __init__(self, scene: FakeScene, arms: dict[str, FakeArm], attempts: int = 3):
        self.scene, self.arms = scene, arms
        self.cell = Cell(scene, arms, SKILLS, attempts=attempts, samples=6)
        self.primitives = Primitives(self.cell)
        self.roles = RolePlayer(self.cell, self.primitives)

    @property
    def time(self):
        return self.scene.time

    @property
    def dt(self):
        return 1 / self.scene.hz

    def step(self):
        self.scene.ticks += 1

    def program(self, action, pid, meeting):
        return self.roles.program(action, pid, meeting)

    def recover(self, pid):
        return self.roles.recover(pid)

    def action_boundary(self, action, kind):
        pass


def world(**arms) -> FakeWorld:
    scene = FakeScene()
    return FakeWorld(scene, {pid: FakeArm(pid, scene, **arms.get(pid, {})) for pid in ("P1", "P2")})


def run(program: Program, limit: int = 10_000) -> int:
    """Drive ``program`` to its end; the number of ticks it took."""
    for n, _ in enumerate(program):
        assert n < limit
    return n


def until_waiting(program: Program, limit: int = 10_000) -> None:
    """Drive ``program`` until it yields WAIT."""
    for _ in range(limit):
        if next(program) == WAIT:
            return
    raise AssertionError("never waited")


def ops(w: FakeWorld, pid: str) -> list[str]:
    return [op if not what else f"{op} {what}" for p, op, what in w.scene.calls if p == pid]


ACTION = PlanAction("a1", ("P1",), "stir", "spoon", (), "bowl")


def test_grasp_then_release_changes_what_the_scene_says_is_held():
    w = world()
    scene, start = w.scene, w.scene.pose("knife")
    run(w.primitives.grasp(ACTION, "P1", "knife"))
    assert scene.hand("P1").carried == "knife" and scene.holder_of("knife", "P2") == "P1"
    assert np.allclose(scene.picked_from("knife"), start)
    assert scene.pose("knife")[2, 3] == pytest.approx(start[2, 3] + SKILLS.lift)  # lifted with the hand
    assert scene.hand("P1").grip < 0.03  # closed on the handle
    assert ops(w, "P1")[-3:] == ["attach knife", "linear lift knife", "primitive_end grasp knife"]
    assert [op for op in ops(w, "P1") if op.startswith(("transit", "linear"))][:2] == \
        ["transit grasp knife", "linear approach knife"]
    run(w.primitives.release("P1"))
    assert scene.hand("P1").carried is None and scene.holder_of("knife", "P2") is None
    assert scene.arm_collisions[("P1", "knife")] is True
    assert scene.pose("knife")[2, 3] == pytest.approx(start[2, 3] + SKILLS.lift)  # let go where it was
    assert ops(w, "P1")[-2:] == ["detach knife", "linear retreat"]


FINGER_TIPS = 0.007
"""Metres the Panda's fingertips reach below its grasp target."""


def _fingers_above_table(T: np.ndarray, opening: float = 0.03) -> bool:
    """Whether both fingertips of an ee at ``T``, ``opening`` apart from its axis, stay above the table."""
    tips = [T[:3, 3] + T[:3, :3] @ np.array([0.0, side * opening, FINGER_TIPS]) for side in (-1, 1)]
    return all(tip[2] > 0.0 for tip in tips)


def test_a_tool_lying_tilted_is_taken_from_above_not_along_its_leaning_axis():
    """A whisk knocked by the knife sawing beside it rests on its long edge, rolled 45 degrees; taken along its
    own z axis, the hand's low finger meets the table at every sample (s304 run seed 5: 'in the way: table
    (panda_hand), table (panda_leftfinger)'). Taken from above at its handle, it is grasped, the fingers opened
    wide enough to pass down beside it (rolled, it is wider across than its width)."""
    w = world(P1={"reachable": _fingers_above_table})
    lean = math.radians(45)
    tilted = w.scene.poses["knife"].copy()
    tilted[:3, :3] = tilted[:3, :3] @ np.array([[1, 0, 0], [0, math.cos(lean), -math.sin(lean)],
                                                 [0, math.sin(lean), math.cos(lean)]])
    tilted[2, 3] = (0.015 + 0.0125) * math.sin(lean)  # on its edge
    w.scene.poses["knife"] = tilted
    run(w.primitives.grasp(ACTION, "P1", "knife", lift=False))
    assert w.scene.hand("P1").carried == "knife"
    ee = w.scene.ees["P1"]
    assert ee[2, 2] < -0.999  # straight down
    handle = tilted @ np.array([-0.55 * 0.12, 0.0, 0.0, 1.0])  # its grasp point, on the leaning handle
    assert np.linalg.norm(ee[:2, 3] - handle[:2]) < 0.03
    grips = [float(what) for p, op, what in w.scene.calls if p == "P1" and op == "grip"]
    across = (0.015 + 0.0125) * math.sin(lean)  # half its width across, at its middle
    assert grips[-2] >= across + FINGER_CLEARANCE - 1e-3  # the opening it went down with (then it closed)
    flat = world(P1={"reachable": _fingers_above_table})  # lying flat, the grasp is as it was: along its z axis
    run(flat.primitives.grasp(ACTION, "P1", "knife", lift=False))
    assert flat.scene.ees["P1"][2, 2] < -0.999


def test_a_container_grasped_carries_what_lies_in_it_and_lets_it_go_with_it():
    w = world()
    run(w.primitives.grasp(ACTION, "P1", "bowl"))
    assert [r.name for r in w.scene.hand("P1").riding] == ["bowl", "rice"]
    run(w.primitives.release("P1"))
    assert w.scene.hand("P1").riding == [] and w.scene.arm_collisions[("P1", "rice")] is True


def test_a_grasp_with_no_reachable_goal_is_retried_by_the_one_policy_then_fails_with_the_reason():
    w = world(P1={"reachable": lambda T: False})
    with pytest.raises(ActionFailed, match=r"^grasp knife: no reachable grasp of knife in 6 TSR samples$"):
        run(w.primitives.grasp(ACTION, "P1", "knife"))
    calls = ops(w, "P1")
    assert calls.count("let other move") == 2  # before each new attempt, the other arm may move away
    assert [c for c in calls if c.startswith("retry")] == [
        "retry grasp grasp knife: attempt 2 (no reachable grasp of knife in 6 TSR samples)",
        "retry grasp grasp knife: attempt 3 (no reachable grasp of knife in 6 TSR samples)"]
    assert calls[-1] == "primitive_failed grasp no reachable grasp of knife in 6 TSR samples"
    assert [c for _, c, _ in w.scene.calls].count("sync") == 3
    assert w.scene.hand("P1").carried is None and "transit grasp knife" not in calls


def test_a_retry_after_a_failed_move_succeeds_and_the_budget_is_the_cells():
    w = world(P1={"failing_transits": 1})
    run(w.primitives.grasp(ACTION, "P1", "knife"))
    calls = ops(w, "P1")
    assert "retry grasp grasp knife: attempt 2 (grasp knife: no path (timeout))" in calls
    assert calls.count("transit grasp knife") == 2 and w.scene.hand("P1").carried == "knife"
    once = world(P1={"failing_transits": 1})
    once.cell.attempts = 1
    with pytest.raises(ActionFailed, match="grasp knife: grasp knife: no path"):
        run(once.primitives.grasp(ACTION, "P1", "knife"))
    assert not [c for c in ops(once, "P1") if c.startswith("retry")]
