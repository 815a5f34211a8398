"""Engaging and actuating (primitives of the world, :mod:`wecook_core.execution.world`, written against its
:class:`~.protocols.Scene` and :class:`~.protocols.Arm`): carrying the effector into a skill's TSR, chosen so
that the actuation that follows is feasible (:func:`engage_goal`, a query), and the actuation itself (its contact
pairs passing through each other, what it tips landing in the destination)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Generator, Sequence
from dataclasses import dataclass

import numpy as np

from wecook_core.execution.schedule.program import ActionFailed, PathBlocked, Program, Tick
from wecook_core.execution.skills.library import Step, TSRSpec, Waypoint, actuation_path, evaluate
from wecook_core.execution.world import sliding
from wecook_core.execution.world.frames import skill_frame
from wecook_core.execution.world.grasping import release
from wecook_core.execution.world.protocols import Accept, Cell, Riding, Roles, Scene
from wecook_core.execution.world.retry import retrying
from wecook_core.model import Category
from wecook_core.plan import PlanAction

DROP_INSIDE = 0.6
"""Share of a destination's half extents, about its middle, that what is tipped into it must fall within."""
CLEAR_MARGIN = 0.002
"""Metres an actuation's straight path keeps from every object it does not touch, on a pose chosen clear of its
neighbours (its contact pairs and what lies with them are passed through on purpose). Kinematic arms push what
they pass into even by a millimetre: a knife sawing meat 3 cm from a whisk, 1 mm into it at each stroke, walked
it 1 cm away and onto its edge (s304 run seed 0, a1 and a9)."""
TOUCH_MARGIN = -0.002
"""Metres it may pass into one when no pose keeps clear: it touches a neighbour, and may nudge it."""
BRUSH_MARGIN = -0.005
"""Metres it may pass into one when no pose only touches: it brushes a neighbour."""
GRAZE_MARGIN = -0.01
"""Metres it may pass into one when no pose even brushes (a crowded table): it grazes a neighbour and may push it
(the knife rolled the whisk onto the spoon beside it), so such poses come last."""
MARGINS = (CLEAR_MARGIN, TOUCH_MARGIN, BRUSH_MARGIN, GRAZE_MARGIN)
"""The margins an actuation's pose is sought with, in turn, the least intrusion first: every sample with one
before any with the next. A pose taken at the first margin some sample keeps pushes its neighbours least."""
TABLE_CLEARANCE = 0.005
"""Metres above the table that the carried object's lowest point keeps during an actuation: a spoon stirring a
low pan goes no deeper than the pan's floor lets it."""


class Missed(ActionFailed):
    """The motion ran but did not do its work (an ingredient missed its destination): trying it again from a new
    engage cannot help."""


@dataclass(frozen=True)
class EngageGoal:
    """Where an engage goes: the joints (None: no pose found) and the axis option of the actuation that follows
    (None: no actuation was checked); else why not."""

    q: np.ndarray | None
    variant: int | None = None
    reason: str = ""
    """Why no pose was found, when it is not that the samples were out of reach or blocked."""
    unreached: int | None = None
    """No pose as the samples, this many, were out of reach or blocked (the arm's report says by what)."""
    about_actuation: bool = False
    """``reason`` is the actuation's, not the goals' (what blocked the goals is no longer news)."""
    margin: float = CLEAR_MARGIN
    """How close the actuation from there may come to its neighbours (one of :data:`MARGINS`)."""
    slide: float = 0.0
    """Metres the pose was slid along the tool (:mod:`.sliding`; 0: a pose of the TSR itself)."""


def engage(cell: Cell, action: PlanAction, pid: str, spec: TSRSpec, roles: Roles,
           meet: tuple[str, str] | None = None, accept: Accept | None = None, then: Step | None = None,
           chose: Callable[[int, float], None] | None = None) -> Program:
    """Carry the effector (the carried object, else the gripper) into a TSR, by a planned move. With ``then``
    (the actuation that follows), only poses from which that actuation is feasible are chosen, and ``chose`` is
    told the axis option of ``then`` and the margin each chosen pose goes with."""
    scene, arm = cell.scene, cell.arms[pid]
    scene.event("primitive_start", action, pid, spec.frame, "engage")

    def attempt(_k: int) -> Generator[Tick, None, str | None]:
        goal = engage_goal(cell, pid, spec, roles, meet, accept, then)
        if goal.q is None:
            if goal.unreached is not None:
                return arm.no_goal(f"pose at {spec.frame}", goal.unreached)
            if goal.about_actuation:
                arm.clear_blockers()
            return goal.reason
        if goal.variant is not None and chose is not None:
            chose(goal.variant, goal.margin)
        if goal.slide and then is not None:
            scene.log("info", f"{pid}: no pose at {spec.frame} let the {then.motion} pass its neighbours: the "
                              f"{roles.get('tool')} slid {100 * goal.slide:.1f} cm along itself")
        try:
            yield from arm.transit(goal.q, what="engage")
        except ActionFailed as error:
            return str(error)
        return None

    yield from retrying(scene, arm, cell.attempts, action, "engage", f"engage {spec.frame}", spec.frame, attempt,
                        "no reachable collision-free pose")


def engage_goal(cell: Cell, pid: str, spec: TSRSpec, roles: Roles, meet: tuple[str, str] | None,
                accept: Accept | None, then: Step | None) -> EngageGoal:
    """Joints of a collision-free pose of the TSR from which ``then`` is feasible (its straight path, and what it
    tips falling into the destination), with the actuation's axis option and margin: a path clear of the
    neighbours first, then one intruding on them as little as any sample's does (:data:`MARGINS`); when no
    sample's passes, a tool working an ingredient is slid along itself (:mod:`.sliding`: :data:`~.sliding.SLIDE`,
    :data:`~.sliding.SLIDE_SAMPLES` times the samples, the clearest first); else why not (the commonest reason
    over the samples). A query: it reads the scene and asks the arm for
    samples, IK and straight paths, and reports nothing (:func:`engage` does)."""
    scene, arm = cell.scene, cell.arms[pid]
    hand = scene.hand(pid)
    T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
    T0_w, sizes = skill_frame(scene, spec, roles, pid, meet)
    T0_w = over_contents(scene, spec, roles, T0_w)
    region = spec.tsr(T0_w, sizes)
    rank = arm.away_from_other(T0_w[:3, 3]) if meet is None else None
    spin = bool(hand.riding) and scene.shape(hand.riding[0].name) in ("cylinder", "sphere")
    options = range(len(str(then.params.get("axis", "")).split(","))) if then is not None else range(0)

    landing: dict[int, list[int]] = {}

    def lands(G: np.ndarray) -> list[int]:
        """The actuation's axis options from ``G`` that tip what it lets go of into the destination (pure
        geometry, so it is checked on many samples before any IK; kept for the samples that pass)."""
        assert then is not None
        if id(G) in landing:  # only kept samples are stored: they stay alive, so their ids are not reused
            return landing[id(G)]
        good = [v for v in options
                if falls_outside(scene, pid, then, roles, actuation_waypoints(scene, pid, then, roles, G, v)) is None]
        if good:
            landing[id(G)] = good
        return good

    tips = then is not None and roles.get("location") is not None and bool(tipped(scene, pid, then, roles))
    keep = accept if not tips else (lambda G: (accept is None or accept(G)) and bool(lands(G)))
    candidates = arm.goal_samples([region], T_eff_ee, cell.samples, keep, rank, spin)
    if tips and not candidates:
        assert then is not None
        return EngageGoal(None, None, f"no pose at {spec.frame} from which the {then.motion} tips into the "
                                      f"{roles['location']}")
    why: Counter[str] = Counter()
    unreached = 0

    def check(q: np.ndarray, waypoints: list[Waypoint], margin: float, last: bool) -> bool | None:
        """Whether the actuation's path from ``q`` keeps ``margin`` (None: it fails whatever the margin)."""
        assert then is not None
        try:
            arm.cartesian_path(q, [w.pose @ T_eff_ee for w in waypoints], touched(scene, then, roles), "actuate",
                               margin=margin)
        except PathBlocked as error:  # may yet do, nearer its neighbours
            if last:
                why[str(error)] += 1
            return False
        except ActionFailed as error:
            why[str(error)] += 1
            return None
        return True

    def first(goals: Sequence[tuple[np.ndarray, float]]) -> EngageGoal | None:
        """The first of ``goals`` (each with the metres it was slid) whose actuation keeps the first margin of
        :data:`MARGINS` any of them keeps."""
        nonlocal unreached
        assert then is not None
        nearer: list[tuple[np.ndarray, list[Waypoint], int, float]] = []  # (joints, waypoints, variant, slide)
        for G, slide in goals:
            found = arm.ik_goal([G], [])
            if found is None:
                unreached += 1
                continue
            for variant in (lands(G) if tips else options):
                waypoints = actuation_waypoints(scene, pid, then, roles, G, variant)
                ok = check(found[0], waypoints, MARGINS[0], False)
                if ok:
                    return EngageGoal(found[0], variant, margin=MARGINS[0], slide=slide)
                if ok is False:
                    nearer.append((found[0], waypoints, variant, slide))
        for k, margin in enumerate(MARGINS[1:], start=2):  # touching a neighbour, else brushing, else grazing it
            blocked = []
            for q, waypoints, variant, slide in nearer:
                ok = check(q, waypoints, margin, k == len(MARGINS))
                if ok:
                    return EngageGoal(q, variant, margin=margin, slide=slide)
                if ok is False:
                    blocked.append((q, waypoints, variant, slide))
            nearer = blocked
        return None

    if then is None:
        for G in candidates:
            found = arm.ik_goal([G], [])
            if found is not None:
                return EngageGoal(found[0])
            unreached += 1
        return EngageGoal(None, unreached=len(candidates))
    goal = first([(G, 0.0) for G in candidates])
    if goal is None and sliding.slides(scene, pid, then, roles):  # the tool slid along itself, clearest first
        drawn = arm.goal_samples([region], T_eff_ee, sliding.SLIDE_SAMPLES * cell.samples, keep, None, spin)
        touching = {*touched(scene, then, roles), *(r.name for r in hand.riding)}
        step = then
        goal = first(sliding.slid(scene, pid, step, roles, drawn,
                                  lambda G: actuation_waypoints(scene, pid, step, roles, G, 0),
                                  [n for n in scene.names() if n not in touching]))
    if goal is not None:
        return goal
    if unreached >= why.total():  # most samples were unreachable or in collision
        return EngageGoal(None, unreached=len(candidates))
    text, count = why.most_common(1)[0]
    return EngageGoal(None, None, f"the {then.motion} from there: {text} ({count} of {why.total()} tries)",
                      about_actuation=True)


def over_contents(scene: Scene, spec: TSRSpec, roles: Roles, T0_w: np.ndarray) -> np.ndarray:
    """``T0_w`` raised so that a TSR over the top of an ingredient that is a container (the action names no
    ingredient: the tool works on what lies in or on its location, the food cut on a plate) stands over the top
    of what lies there: the tool engages what it works on, not the container under it."""
    name = roles.get("ingredient")
    if spec.frame.split(":", 1)[-1] != "ingredient" or name is None:
        return T0_w
    contents = scene.contents(name)
    if not contents:
        return T0_w
    top = max(box[1][2] for box in scene.boxes(contents))
    rise = top - (scene.pose(name)[2, 3] + scene.half(name).hz)
    if rise <= 0:
        return T0_w
    T = T0_w.copy()
    T[2, 3] += rise
    return T


def touched(scene: Scene, step: Step, roles: Roles) -> list[str]:
    """The objects an actuation may touch: those of its contact pairs, what lies in them (the rice in the pot
    being stirred), and what lies beside them in the same container (the onion next to the meat cut on a board: a
    knife brushes it as a person's does); every other object is an obstacle."""
    names = [name for pair in step.contacts for name in (roles.get(r) for r in pair) if name is not None]
    holders = {c for c in (scene.container_of(n) for n in names) if c is not None}
    near = [*holders, *(c for h in sorted(holders) for c in scene.contents(h))]
    return list(dict.fromkeys([*names, *(c for name in names for c in scene.contents(name)), *near]))


def tipped(scene: Scene, pid: str, step: Step, roles: Roles) -> dict[str, Riding]:
    """What ``step`` lets go of that rides on the carried object (not the carried object itself)."""
    names = [roles.get(r) for r in step.release]
    return {r.name: r for r in scene.hand(pid).riding[1:] if r.name in names}


def falls_outside(scene: Scene, pid: str, step: Step, roles: Roles, waypoints: Sequence[Waypoint]) -> str | None:
    """Why what ``step`` lets go of (riding on the carried object) would miss the location, or None. It falls
    from where it is at the waypoint that lets go (from a carried container: from the middle of its opening), and
    must drop inside the middle of the location's footprint (:data:`DROP_INSIDE`)."""
    hand = scene.hand(pid)
    target = roles.get("location")
    riding = tipped(scene, pid, step, roles)
    if target is None or not riding:
        return None
    at = next((w for w in waypoints if w.lets_go), waypoints[-1])
    carrier = hand.riding[0]
    T_eff_ee = np.linalg.inv(carrier.T_ee_obj)
    if scene.category(carrier.name) is Category.CONTAINER:
        opening = np.eye(4)
        opening[2, 3] = scene.half(carrier.name).hz
        drops = {name: at.pose @ opening for name in riding}
    else:
        drops = {name: at.pose @ T_eff_ee @ r.T_ee_obj for name, r in riding.items()}
    T_target = scene.pose(target)
    h = scene.half(target)
    for name, T in drops.items():
        local = np.linalg.inv(T_target) @ T[:, 3]
        if abs(local[0]) > DROP_INSIDE * h.hx or abs(local[1]) > DROP_INSIDE * h.hy or local[2] < h.hz:
            return f"the {name} would fall outside the {target}"
    return None


def actuation_waypoints(scene: Scene, pid: str, step: Step, roles: Roles, ee: np.ndarray, variant: int
                        ) -> list[Waypoint]:
    """The effector waypoints of ``step`` starting with the hand at ``ee``; ``variant`` picks one of the step's
    axis options."""
    assert step.motion is not None
    hand = scene.hand(pid)
    T_ee_eff = hand.riding[0].T_ee_obj if hand.riding else np.eye(4)
    E = ee @ T_ee_eff
    sizes = {"t": scene.half(roles.get("tool")), "i": scene.half(roles.get("ingredient")),
             "l": scene.half(roles.get("location"))}
    if step.contact is not None:
        sizes["f"] = scene.half(roles.get(step.contact[1]))
    params = {k: (v if k == "axis" else evaluate(v, sizes)) for k, v in step.params.items()}
    if "axis" in params:
        options = str(params["axis"]).split(",")
        params["axis"] = options[min(variant, len(options) - 1)]
    contact_target = roles.get(step.contact[1]) if step.contact else None
    Rw = scene.facing(contact_target, pid)[:3, :3] if contact_target is not None else np.eye(3)
    if not step.contact:
        target = roles.get("location") or roles.get("ingredient")
        if target is not None:
            Rw = scene.facing(target, pid)[:3, :3]
    path = actuation_path(step.motion, params, E, Rw, grip=hand.grip, hand=ee[:3, 3])  # type: ignore[arg-type]
    if not hand.riding or "down" not in params:
        return path
    half = scene.half(hand.riding[0].name)
    extent = np.array([half.hx, half.hy, half.hz])
    lowest = min(float(w.pose[2, 3] - np.abs(w.pose[2, :3]) @ extent) for w in path)
    short = scene.table_height + TABLE_CLEARANCE - lowest
    if short <= 0:
        return path
    params["down"] = max(0.0, float(params["down"]) - short)  # as deep as the table lets the carried object go
    return actuation_path(step.motion, params, E, Rw, grip=hand.grip, hand=ee[:3, 3])  # type: ignore[arg-type]


def actuate(cell: Cell, action: PlanAction, pid: str, step: Step, roles: Roles, variant: int = 0,
            margin: float = GRAZE_MARGIN) -> Program:
    """The step's motion (its axis option ``variant``) from where the hand is, its contact pairs passing through
    each other and ``margin`` into its neighbours at the most (never less than :data:`TOUCH_MARGIN`: a pose chosen
    clear of them is reached within a millimetre of where it was planned); then what it attaches rides on the
    tool, and what it lets go of must land in the location (else :class:`Missed`)."""
    assert step.motion is not None
    scene, arm = cell.scene, cell.arms[pid]
    scene.event("primitive_start", action, pid, step.motion, "actuate")
    hand = scene.hand(pid)
    T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
    waypoints = actuation_waypoints(scene, pid, step, roles, arm.ee(), variant)
    tips = list(tipped(scene, pid, step, roles))
    let_go_at = next((j for j, w in enumerate(waypoints) if w.lets_go), len(waypoints) - 1)

    def let_go(j: int) -> None:  # what rides on the tool falls from here on
        if j == let_go_at:
            scene.drop_riding(pid, tips)

    vessel = hand.riding[0].name if hand.riding else None
    pairs = contact_pairs(scene, step, roles)
    scene.set_collisions(pairs, enabled=False)
    try:
        for again in (False, True):  # what sticks in a tipped container: tip it once more
            if again:
                stuck = [n for n in tips if scene.container_of(n) == vessel]
                if not stuck:
                    break
                scene.event("retry", action, pid, f"{', '.join(stuck)} still in the {vessel}: tip again", "actuate")
                for n in stuck:
                    scene.ride(pid, n)
            yield from arm.linear([w.pose @ T_eff_ee for w in waypoints], ignore=touched(scene, step, roles),
                                  holds=[w.hold for w in waypoints], fingers=[w.fingers for w in waypoints],
                                  what=f"actuate {step.motion}", margin=min(margin, TOUCH_MARGIN),
                                  reached=let_go if tips else None)
            if not tips:
                break
            yield from scene.hold(0.6)  # let it land
    except ActionFailed as error:
        scene.event("primitive_failed", action, pid, str(error), "actuate")
        raise
    finally:
        scene.set_collisions(pairs, enabled=True)
    _attach(scene, pid, step, roles)
    for name in tips:
        scene.collide_with_arm(pid, name, enabled=True)
        if hand.riding:
            scene.set_collisions([(hand.riding[0].name, name)], enabled=True)
    if hand.carried is not None and hand.carried in (roles.get(r) for r in step.release):
        dropped = hand.carried  # carried by hand into the location
        yield from release(cell, pid)
        yield from scene.hold(0.6)
        tips.append(dropped)
    missed = _missed(scene, tips, roles.get("location"))
    if missed is not None:
        scene.event("primitive_failed", action, pid, missed, "actuate")
        raise Missed(f"actuate {step.motion}: {missed}")
    scene.event("primitive_end", action, pid, step.motion, "actuate")


def contact_pairs(scene: Scene, step: Step, roles: Roles) -> list[tuple[str, str]]:
    """The step's contact pairs, and the tool with what lies in a container it works in."""
    pairs = []
    for first, second in step.contacts:
        a, b = roles.get(first), roles.get(second)
        if a is not None and b is not None and a != b:
            for other in (b, *(c for c in scene.contents(b) if c != a)):
                pairs.append((a, other))
    return pairs


def _attach(scene: Scene, pid: str, step: Step, roles: Roles) -> None:
    """What the step attaches (a scooped ingredient) rides on the carried tool from now on, on its tip."""
    hand = scene.hand(pid)
    for role in step.attach:
        name = roles.get(role)
        if name is not None and hand.riding:
            carrier = hand.riding[0]
            tool = scene.half(carrier.name)
            ing = scene.half(name)
            T_tool_ing = np.eye(4)
            T_tool_ing[:3, 3] = [0.6 * tool.hx, 0.0, tool.hz + ing.hz + 0.002]
            scene.ride(pid, name, carrier.T_ee_obj @ T_tool_ing)
            scene.set_collisions([(carrier.name, name)], enabled=False)


def _missed(scene: Scene, names: Sequence[str], target: str | None) -> str | None:
    """Where the first of ``names`` that is not in ``target`` lies, or None (a transfer is done only when its
    ingredient is in its destination)."""
    for name in names:
        where = scene.container_of(name)
        if target is not None and where != target:
            at = np.round(scene.pose(name)[:2, 3], 2).tolist()
            return f"the {name} fell " + (f"into the {where}" if where else f"on the table at {at}") + \
                f", not into the {target}"
    return None
