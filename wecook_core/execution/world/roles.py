"""The roles of the world (:mod:`wecook_core.execution.world`), written against its :class:`~.protocols.Scene`,
:class:`~.protocols.Arm` and :class:`~.primitives.Primitives`: an action's roles as primitives.
An individual action grasps its tool (or ingredient), engages and actuates through its skill's steps, and puts
the tool back; a handover's giver and receiver, and a holding's holder and actor, meet through the action's
:class:`~wecook_core.execution.schedule.executor.Meeting`. Each action first claims the table area it works in.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Sequence

import numpy as np

from wecook_core.execution.schedule.program import ActionFailed, Meeting, Program, waiting
from wecook_core.execution.skills.library import skill_name
from wecook_core.execution.skills.tsr import TSR
from wecook_core.execution.world.frames import levelled, skill_frame, tilted
from wecook_core.execution.world.primitives import Missed, Primitives
from wecook_core.execution.world.protocols import Cell
from wecook_core.model import Category
from wecook_core.plan import PlanAction

Role = Callable[[PlanAction, str, Meeting], Program]
"""A collaboration's role: the action, the person playing it, where the roles meet."""

ZONE_MARGIN = 0.08
"""Metres around the objects of an action that its arm may sweep over while working."""
HAND_OVER_ROOM = 0.02
"""Metres, beyond the receiver's clearance, between the two hands' grasp points on a tool handed over mid-air."""
ZONE_WAIT_SECONDS = 120.0
"""Longest wait for the other arm to leave an overlapping zone (then the action goes ahead, reservations still
keep the arms apart)."""


class RolePlayer:
    """Plays the roles of actions with the arms of ``cell`` through ``primitives``; keeps the table areas the
    running actions work in."""

    def __init__(self, cell: Cell, primitives: Primitives):
        self.cell = cell
        self.scene = cell.scene
        self.arms = cell.arms
        self.skills = cell.skills
        self.primitives = primitives
        self.zones: dict[str, np.ndarray] = {}
        """Action id -> the table area it works in, while it runs (see :meth:`_claim_zone`)."""
        self.zone_users: dict[str, set[str]] = {}
        self.collaborations: dict[str, tuple[Role, Role]] = {"handover": (self._giver, self._receiver),
                                                             "holding": (self._holder, self._actor)}
        """Verb -> the roles of its two persons, in ``action.pids`` order."""

    def _zone(self, action: PlanAction) -> np.ndarray:
        """The table area an action works in: ``[[x0, y0], [x1, y1]]`` around the objects it names (and the
        meeting point of a handover), grown by :data:`ZONE_MARGIN`."""
        names = {action.tool, action.location, action.source, *action.ingredients}
        if action.partner is not None:
            act = action.partner
            names |= {act.tool, act.location, act.source, *act.ingredients}
        boxes = [box[:, :2] for box in self.scene.boxes([n for n in names if n is not None])]
        if action.verb == "handover":
            meet = self.scene.meet(*action.pids[:2])[:2, 3]
            boxes.append(np.array([meet - 0.1, meet + 0.1]))
        if not boxes:
            return np.zeros((2, 2))
        stacked = np.stack(boxes)
        return np.array([stacked[:, 0].min(axis=0) - ZONE_MARGIN, stacked[:, 1].max(axis=0) + ZONE_MARGIN])

    def _claim_zone(self, action: PlanAction, pid: str) -> Program:
        """Wait until no action of the other arm works in an overlapping zone, then hold this action's zone."""
        if action.id in self.zones:
            return
        zone = self._zone(action)
        for _ in range(int(ZONE_WAIT_SECONDS * self.scene.hz)):
            busy = [owner for owner, z in self.zones.items() if owner != action.id
                    and np.all(zone[0] < z[1]) and np.all(z[0] < zone[1])]
            if not busy:
                break
            yield waiting(f"the other arm's region: {', '.join(busy)} works where {action.id} would")
        self.zones[action.id] = zone

    def program(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        """The role of ``pid`` in ``action``, inside the action's workspace zone (held until every role ends)."""
        yield from self._claim_zone(action, pid)
        self.zone_users.setdefault(action.id, set()).add(pid)
        try:
            yield from self._role(action, pid, meeting)
        finally:
            users = self.zone_users.get(action.id, set())
            users.discard(pid)
            if not users:
                self.zones.pop(action.id, None)

    def _role(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        """The collaboration's role of ``pid`` (the first of ``action.pids`` plays the first role), else the
        individual action."""
        roles = self.collaborations.get(action.verb)
        if roles is None:
            yield from self._individual(action, pid, action.verb, action.tool, action.ingredients, action.location,
                                        action.source)
            return
        first, second = roles
        yield from (first if pid == action.pids[0] else second)(action, pid, meeting)

    def _individual(self, action: PlanAction, pid: str, verb: str, tool: str | None, ingredients: Sequence[str],
                    location: str | None, source: str | None,
                    after_grasp: Callable[[], Program] | None = None,
                    after_work: Callable[[], None] | None = None) -> Program:
        tool_category = self.scene.category(tool) if tool else None
        skill = self.skills.skills.get(skill_name(verb, tool, tool_category))
        if skill is None:
            raise ActionFailed(f"no skill for {verb!r}")
        carried = tool if (skill.carry == "tool" or tool is not None) else None
        carried = carried or (ingredients[0] if ingredients else None)
        if carried is None:
            raise ActionFailed(f"{verb} needs an object to hold (a tool or an ingredient)")
        ingredient = ingredients[0] if ingredients else None
        if ingredient is None and carried != tool:
            ingredient = carried
        loc = location or (self.scene.container_of(ingredient) if ingredient else None) or ingredient
        roles: dict[str, str | None] = {"tool": carried, "ingredient": ingredient or loc, "location": loc,
                                        "source": source or (self.scene.container_of(ingredient) or ingredient
                                                             if ingredient else None)}
        home = self._rest(carried)
        yield from self.primitives.grasp(action, pid, carried)
        if after_grasp is not None:
            yield from after_grasp()
        k, second_tries = 0, 1
        while k < len(skill.steps):
            step = skill.steps[k]
            if step.primitive == "engage":
                assert step.tsr is not None
                after = skill.steps[k + 1] if k + 1 < len(skill.steps) else None
                yield from self.primitives.engage(action, pid, step.tsr, roles,
                                       then=after if after is not None and after.primitive == "actuate" else None)
            else:
                try:
                    yield from self.primitives.actuate(action, pid, step, roles)
                except ActionFailed as error:  # it failed before moving: engage anew (a new sample), then again
                    if isinstance(error, Missed) or not (second_tries and k > 0
                                                         and skill.steps[k - 1].primitive == "engage"):
                        raise
                    second_tries -= 1
                    self.scene.event("retry", action, pid, f"engage again for the {step.motion} ({error})",
                                     "actuate")
                    yield from self.arms[pid].let_other_move()
                    k -= 1
                    continue
            k += 1
        if after_work is not None:
            after_work()
        if self.scene.hand(pid).carried is not None:
            try:
                yield from self.primitives.place(action, pid, home)
            except ActionFailed as error:  # its spot is out of reach now: any free spot near it will do
                near = TSR(home, np.eye(4), np.array([[-0.12, 0.12], [-0.12, 0.12], [0.004, 0.004], [0, 0], [0, 0],
                                                      [-math.pi / 2, math.pi / 2]]))
                self.scene.event("retry", action, pid, f"place {carried} near its spot ({error})", "place")
                yield from self.primitives.place(action, pid, [near], free=True)
        yield from self.arms[pid].home()

    def _rest(self, name: str) -> np.ndarray:
        """Where ``name`` goes back to after the action: where it lies now, lying flat (a whisk pushed onto the
        spoon beside it rests tilted, and put back so its hand meets the table): turned about z as it lies, on
        its container's floor as it is, else on the table. A sphere's turn says nothing: it goes back as it is."""
        T = self.scene.pose(name)
        if not tilted(T) or self.scene.shape(name) == "sphere":
            return T
        rest = levelled(T)
        if self.scene.container_of(name) is None:
            rest[2, 3] = self.scene.table_height + self.scene.half(name).hz
        return rest

    def _mid_air(self, name: str) -> bool:
        """Whether ``name`` is handed over mid-air: a tool long enough for both hands on it, each grasping near its
        own end (:data:`HAND_OVER_ROOM` beyond the receiver's clearance between them); else on the table."""
        if self.scene.kind(name) != "tool":
            return False
        return 2 * 0.55 * self.scene.half(name).hx >= self.skills.receiver_clearance + HAND_OVER_ROOM

    def _giver(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        """Mid-air for long objects (tools): carry it to the meeting pose, wait until the receiver holds it, let
        go. Small objects (both grippers would not fit on them) are handed over on the table between the arms:
        put down at the meeting spot, then the receiver picks them up."""
        name = action.tool
        assert name is not None
        giver, receiver = action.pids
        yield from self.primitives.grasp(action, pid, name)
        meet = self.scene.meet(giver, receiver)
        if not self._mid_air(name):
            spot = meet.copy()
            spot[2, 3] = self.scene.table_height + self.scene.half(name).hz
            region = TSR(spot, np.eye(4), np.array([[-0.1, 0.1], [-0.25, 0.25], [0.002, 0.006], [0, 0], [0, 0],
                                                    [-math.pi, math.pi]]))
            yield from self.primitives.place(action, pid, [region], free=True)
            meeting.signal("at_meet")
            yield from self.arms[pid].home()
            meeting.signal("released")  # out of the way
            return

        reach = float(np.linalg.norm(self.scene.hand(pid).riding[0].T_ee_obj[:2, 3]))  # hand to object centre

        def on_giver_side(T_ee: np.ndarray) -> bool:
            """The tool along the giver-receiver line, the giver's hand on its own end."""
            local = np.linalg.inv(meet) @ T_ee
            return bool(local[0, 3] < -0.8 * reach)

        yield from self.primitives.engage(action, pid, self.skills.meet, {"tool": name}, meet=(giver, receiver),
                               accept=on_giver_side)
        meeting.signal("at_meet")
        yield from meeting.wait_for("taken", pid=pid)
        yield from self.scene.hold(0.2)
        yield from self.primitives.release(pid)
        yield from self.arms[pid].home()
        meeting.signal("released")  # and out of the way

    def _receiver(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        name = action.tool
        assert name is not None
        giver = action.pids[0]
        yield from meeting.wait_for("at_meet", pid=pid)
        if not self._mid_air(name):  # on the table: an ordinary grasp once the giver has let go
            yield from meeting.wait_for("released", pid=pid)
            yield from self.primitives.grasp(action, pid, name, primitive="take")
        else:
            giver_ee = self.arms[giver].ee()
            clearance = self.skills.receiver_clearance
            regions = self.primitives.grasp_tsrs(name, pid, flip=True)

            def clear_of_giver(T: np.ndarray) -> bool:
                """clear of the giver's hand"""
                return bool(np.linalg.norm(T[:3, 3] - giver_ee[:3, 3]) >= clearance)

            with self.arms[pid].margin_to_other(0.0):
                yield from self.primitives.grasp(action, pid, name, lift=False, tsrs=regions, accept=clear_of_giver,
                                                 primitive="take")
            self.scene.drop_riding(giver, [r.name for r in self.scene.hand(giver).riding])
            meeting.signal("taken")
            yield from meeting.wait_for("released", pid=pid)
        drop = self.skills.drop
        T0_w, sizes = skill_frame(self.scene, drop, {"tool": name}, pid)
        yield from self.primitives.place(action, pid, [drop.tsr(T0_w, sizes)], free=True)
        yield from self.arms[pid].home()

    def _held(self, action: PlanAction, pid: str) -> str:
        """What the holder of ``action`` takes hold of: the object it names, except food lying in or on a
        container, which is held steady by its container (a gripper closed on a cucumber covers it, and the
        partner's knife has nowhere to go)."""
        name = action.tool
        assert name is not None
        if self.scene.category(name) is not Category.INGREDIENT:
            return name
        container = self.scene.container_of(name)
        if container is None:
            return name
        self.scene.log("info", f"{action.id}: {pid} holds the {name} steady by the {container} it lies on")
        return container

    def _holder(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        yield from meeting.wait_for("tool_ready", pid=pid)  # the actor takes its tool first, then the container is held
        name = self._held(action, pid)
        kind = self.scene.kind(name)
        hold = {"open_container": "hold_rim", "flat_container": "hold_flat"}.get(kind)
        regions = self.primitives.grasp_tsrs(name, pid, kinds=[hold] if hold else None)
        # rims: each grasp in the library's order; boards: either end, sampled together
        groups = [regions] if kind == "flat_container" else [[r] for r in regions]
        centre = self.scene.pose(name)[:2, 3]
        actor = next(k for k in action.pids if k != pid)
        toward = self.scene.base(actor)[:2, 3] - centre
        toward /= max(float(np.linalg.norm(toward)), 1e-9)

        def far_side(T: np.ndarray) -> float:
            """Cosine of the angle, about the container, between the grip and the actor's base: the actor works
            on the side facing its base, so the grip farthest round from there is tried first."""
            grip = T[:2, 3] - centre
            return float(grip @ toward / max(float(np.linalg.norm(grip)), 1e-9))

        for k, group in enumerate(groups):
            try:
                yield from self.primitives.grasp(action, pid, name, lift=False, primitive="hold", tsrs=group,
                                                 rank=far_side)
                break
            except ActionFailed:
                if k == len(groups) - 1:
                    raise
        yield from self.scene.hold(self.skills.hold_time)
        meeting.signal("held")
        yield from meeting.wait_for("acted", pid=pid)
        yield from self.scene.hold(self.skills.hold_time)
        yield from self.primitives.release(pid)
        yield from self.arms[pid].home()

    def _actor(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        act = action.partner
        if act is None:
            raise ActionFailed("holding without the partner's action")
        def ready() -> Program:  # tool in hand, wait out of the holder's way
            with contextlib.suppress(ActionFailed):
                yield from self.arms[pid].park(what="wait at rest")
            meeting.signal("tool_ready")
            yield from meeting.wait_for("held", pid=pid)

        location = act.location or action.tool
        yield from self._individual(action, pid, act.verb, act.tool, act.ingredients, location, act.source,
                                    after_grasp=ready, after_work=lambda: meeting.signal("acted"))

    def recover(self, pid: str) -> Program:
        """After a failure: put what the hand carries down on a free spot near where it was picked up (else let
        it go where it is), then go home."""
        arm, hand = self.arms[pid], self.scene.hand(pid)
        arm.forget_motion()
        carried = hand.carried
        picked = self.scene.picked_from(carried) if carried is not None else None
        if carried is not None and hand.constraint is not None and picked is not None:
            near = TSR(picked, np.eye(4), np.array(
                [[-0.12, 0.12], [-0.12, 0.12], [0.004, 0.004], [0, 0], [0, 0], [-math.pi / 2, math.pi / 2]]))
            with contextlib.suppress(ActionFailed):
                yield from self.primitives.place(None, pid, [near], free=True)
        if hand.carried is not None or hand.riding:
            for r in hand.riding:
                self.scene.collide_with_arm(pid, r.name, enabled=True)
            self.scene.detach(pid)
            arm.set_grip(0.04)
        try:
            yield from arm.home()
        except ActionFailed as error:
            self.scene.log("warning", f"{pid} could not return home: {error}")
        arm.forget_motion()
