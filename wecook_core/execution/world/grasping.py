"""Grasping and letting go (primitives of the world, :mod:`wecook_core.execution.world`, written against its
:class:`~.protocols.Scene` and :class:`~.protocols.Arm`): the grasp TSRs of an object's kind, the grasp
(pre-grasp, straight approach, close, attach, lift) and the release."""

from __future__ import annotations

import contextlib
from collections.abc import Generator, Sequence

import numpy as np

from wecook_core.execution.schedule.program import ActionFailed, Program, Tick, waiting
from wecook_core.execution.skills.library import evaluate
from wecook_core.execution.skills.tsr import TSR
from wecook_core.execution.world.fingers import FULL_OPEN, open_around
from wecook_core.execution.world.frames import levelled, skill_frame, tilted
from wecook_core.execution.world.protocols import YIELD_SECONDS, Accept, Cell, Rank
from wecook_core.execution.world.retry import retrying
from wecook_core.plan import PlanAction

APPROACH_OPENING = 0.008
"""Metres per finger beyond the grip width the fingers open to approach an object."""


def grasp_tsrs(cell: Cell, name: str, pid: str, kinds: Sequence[str] | None = None, flip: bool = False,
               crowded: bool = False) -> list[TSR]:
    """The grasp TSRs of ``name`` (of its kind, or of ``kinds``); ``flip``: each object-framed one also turned
    half round about z (either end of a tool); ``crowded``: with the bounds for a crowded table, where a grasp
    has them."""
    scene = cell.scene
    out = []
    for kind in kinds or [scene.kind(name)]:
        for spec in cell.skills.grasps[kind]:
            spec = spec.on_a_crowded_table() if crowded else spec
            T0_w, sizes = skill_frame(scene, spec, {"object": name}, pid)
            if not spec.frame.startswith("object"):
                out.append(spec.tsr(T0_w, sizes))
                continue
            if flip:
                out.append(from_above(spec.tsr(T0_w @ np.diag([-1.0, -1.0, 1.0, 1.0]), sizes)))
            out.append(from_above(spec.tsr(T0_w, sizes)))
    return out


def from_above(region: TSR) -> TSR:
    """An object-framed grasp of an object lying tilted, taken from above: the TSR frame stood upright
    (:func:`~.frames.levelled`) at its origin on the object (the grasp point on a tool's handle). Taken along its
    own leaning axis, a whisk resting tilted on the spoon beside it brought the hand's low side into the table."""
    if not tilted(region.T0_w):
        return region
    return TSR(levelled(region.T0_w), region.Tw_e, region.Bw)


def grasp(cell: Cell, action: PlanAction, pid: str, name: str, *, lift: bool = True,
          ignore_extra: Sequence[str] = (), tsrs: list[TSR] | None = None, accept: Accept | None = None,
          rank: Rank | None = None, primitive: str = "grasp") -> Program:
    """Pre-grasp (planned), straight approach, close, attach, lift (straight up). On a crowded table, when
    neighbours blocked every sample of the grasp's bounds, the last attempt takes its looser bounds for a crowded
    table (``crowded`` in the library): a spoon laid beside a board or a bowl on the crowded stand-ins of s301 and
    s304 was out of every sample of three attempts (7 actions failed or skipped); the looser bounds take it."""
    scene, arm, skills = cell.scene, cell.arms[pid], cell.skills
    scene.event("primitive_start", action, pid, name, primitive)
    holder = scene.holder_of(name, pid)
    if holder is not None and primitive != "take":  # in the other hand: wait until it is let go
        for _ in range(int(YIELD_SECONDS * scene.hz)):
            if scene.holder_of(name, pid) is None:
                break
            yield waiting(f"{holder} to let go of the {name}")
        else:
            raise ActionFailed(f"{primitive} {name}: {holder} kept holding it")
    kind = scene.kind(name)
    regions = tsrs or grasp_tsrs(cell, name, pid)
    crowds = tsrs is None and any(spec.crowded is not None for spec in skills.grasps[kind])
    failures: list[str] = []
    grip = min(max(evaluate(skills.grip[kind], {"f": scene.half(name)}), 0.0), FULL_OPEN)
    least = min(grip + APPROACH_OPENING, FULL_OPEN)
    arm.set_grip(least)  # open just enough: neighbours stay clear
    h = scene.half(name)
    # a box lying tilted is wider across the fingers than its width (round things are no wider than their radius)
    around = scene.shape(name) == "box" and tilted(scene.pose(name))

    def opening(G: np.ndarray) -> float:
        """How wide to open on the way down to ``G``: wider than the grip when the tilted box reaches farther."""
        return open_around(scene.pose(name), np.array([h.hx, h.hy, h.hz]), G, least) if around else least
    # never its own obstacle: the object, what it lies in and what lies in it (that rides along) are touched
    support = scene.supports(name)
    own = [name, *(scene.contents(name) if primitive != "hold" else ())]  # a holding hand keeps off the food
    ignore = [*own, *support, *ignore_extra]
    near = [*own, *ignore_extra]  # the pre-grasp may touch what it is about to take, never its neighbours
    approach = skills.approach_distance

    def attempt(k: int) -> Generator[Tick, None, str | None]:
        failed = yield from attempt_with(k)
        if failed is not None:
            failures.append(failed)
        return failed

    def attempt_with(k: int) -> Generator[Tick, None, str | None]:
        """Attempt ``k`` (:func:`attempt` keeps why each failed)."""
        pool = regions
        if crowds and k == cell.attempts - 1 and failures and _crowded_out(failures[-1], scene.names()):
            scene.log("info", f"{pid}: the {name}'s grasp samples were all blocked by its neighbours: the last "
                              "attempt takes the bounds for a crowded table")
            pool = grasp_tsrs(cell, name, pid, crowded=True)
        candidates = arm.goal_samples(pool, np.eye(4), cell.samples, accept, rank)
        pre_goal = None
        blocked = None
        for G in candidates:
            width = opening(G)
            if abs(width - scene.hand(pid).grip) > 1e-6:  # the goal is checked with the fingers that wide
                arm.set_grip(width)
            found = arm.ik_goal([G], ignore)
            if found is None:
                continue
            pre = G.copy()
            pre[:3, 3] -= G[:3, 2] * approach
            found_pre = arm.ik_goal([pre], near)
            if found_pre is None:
                continue
            try:  # the straight approach (and the lift) must be feasible from there
                moves = [G, G @ _lifted(skills.lift, G)] if lift else [G]
                arm.cartesian_path(found_pre[0], moves, ignore, f"approach {name}")
            except ActionFailed as error:
                blocked = str(error)
                continue
            pre_goal = (found_pre[0], pre, G)
            break
        if pre_goal is None:
            return blocked or arm.no_goal(f"grasp of {name}", len(candidates), accept)
        try:
            yield from arm.transit(pre_goal[0], near, what=f"{primitive} {name}")
            # the fingers close into the object without pushing it about: the constraint will hold it
            scene.collide_with_arm(pid, name, enabled=False)
            yield from arm.linear([pre_goal[2]], ignore=ignore, what=f"approach {name}")
        except ActionFailed as error:
            scene.collide_with_arm(pid, name, enabled=True)
            return str(error)
        arm.close_on(name, grip)  # each finger stops where it touches the part it takes
        yield from scene.hold(0.2)
        scene.attach(pid, name)
        for content in scene.contents(name):  # what lies in a container moves with it
            scene.ride(pid, content)
        if lift:
            up = arm.ee()
            up[2, 3] += skills.lift
            try:
                yield from arm.linear([up], ignore=[*ignore], what=f"lift {name}")
            except ActionFailed as error:  # let go, back off, try another grasp
                yield from release(cell, pid)
                return str(error)
        return None

    yield from retrying(scene, arm, cell.attempts, action, primitive, f"{primitive} {name}", name, attempt,
                        "no reachable collision-free grasp")


def release(cell: Cell, pid: str, retreat: bool = True) -> Program:
    """Open, detach, move straight back along the approach."""
    scene, arm = cell.scene, cell.arms[pid]
    hand = scene.hand(pid)
    name = hand.carried
    arm.set_grip(0.04)
    riding = [r.name for r in hand.riding[1:]]
    scene.detach(pid)
    for other in riding:
        scene.collide_with_arm(pid, other, enabled=True)
    yield from scene.hold(0.15)
    if retreat:
        back = arm.ee()
        back[:3, 3] -= back[:3, 2] * cell.skills.approach_distance
        with contextlib.suppress(ActionFailed):
            yield from arm.linear([back], ignore=[name] if name else [], what="retreat")
    if name is not None:
        scene.collide_with_arm(pid, name, enabled=True)


def _crowded_out(reason: str, names: Sequence[str]) -> bool:
    """Whether an arm's report of no grasp goal (``"... (in the way: a, b)"``, :meth:`~.protocols.Arm.no_goal`)
    names only objects of ``names`` as in the way: neighbours blocked every sample the arm reached, not the table
    or the other arm (for which looser bounds are no help)."""
    _, found, listed = reason.partition("(in the way: ")
    blockers = listed.removesuffix(")").split(", ") if found else []
    return bool(blockers) and all(b in names for b in blockers)


def _lifted(height: float, T: np.ndarray) -> np.ndarray:
    """The transform that, right-multiplied onto ``T``, raises it by ``height`` along world z."""
    up = np.eye(4)
    up[:3, 3] = T[:3, :3].T @ np.array([0.0, 0.0, height])
    return up
