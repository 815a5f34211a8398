"""The third layer of the PyBullet world (:mod:`wecook_core.execution.world`): the primitives grasp, engage,
actuate and place (and release), each a program of :mod:`wecook_core.execution.executor`. A primitive whose
goals fail is retried with new samples, up to ``attempts`` rounds of ``samples`` samples; then it fails with its
reason.
"""

from __future__ import annotations

import contextlib
import math
from collections import Counter
from collections.abc import Sequence

import numpy as np
import pybullet as p

from wecook_core.execution.planning_scene import Riding
from wecook_core.execution.program import WAIT, ActionFailed, Program
from wecook_core.execution.robot import attach, detach
from wecook_core.execution.scene import SIM_HZ
from wecook_core.execution.skills import Step, TSRSpec, Waypoint, actuation_path, evaluate
from wecook_core.execution.tsr import TSR, xyzrpy_to_matrix
from wecook_core.execution.world.moves import YIELD_SECONDS, Accept, ArmMotion, Rank
from wecook_core.model import Category
from wecook_core.plan import PlanAction

APPROACH_OPENING = 0.008
"""Metres per finger beyond the grip width the fingers open to approach an object."""
HAND_SPAN = 0.22
"""Metres: the Panda hand's length along its finger axis (it lies across an object it takes from above)."""
HAND_CLEAR_HEIGHT = 0.04
"""Metres above the table from which an object can be in the way of a hand taking something from above."""
DROP_INSIDE = 0.6
"""Share of a destination's half extents, about its middle, that what is tipped into it must fall within."""
FREE_MARGIN = 0.1
"""Metres of clearance around an object put down on a free spot beyond which spots count as equally roomy
(room for the hand to take it again)."""


class Primitives(ArmMotion):
    def _grasp_tsrs(self, name: str, pid: str, kinds: Sequence[str] | None = None,
                    flip: bool = False) -> list[TSR]:
        out = []
        for kind in kinds or [self._kind(name)]:
            for spec in self.skills.grasps[kind]:
                T0_w, sizes = self.frame(spec, {"object": name}, pid)
                if spec.frame.startswith("object") and flip:
                    T0_w = T0_w @ np.diag([-1.0, -1.0, 1.0, 1.0])
                sizes["f"] = self.half(name)
                out.append(spec.tsr(T0_w, sizes))
                if flip and spec.frame.startswith("object"):
                    out.append(spec.tsr(self.pose(name), sizes))
        return out

    def grasp(self, action: PlanAction, pid: str, name: str, *, lift: bool = True, ignore_extra: Sequence[str] = (),
              tsrs: list[TSR] | None = None, accept: Accept | None = None, rank: Rank | None = None,
              primitive: str = "grasp") -> Program:
        """Pre-grasp (planned), straight approach, close, attach, lift (straight up)."""
        self._event("primitive_start", action, pid, name, primitive)
        body = self.bodies.objects[name]
        holder = self._holder_of(name, pid)
        if holder is not None and primitive != "take":  # in the other hand: wait until it is let go
            for _ in range(int(YIELD_SECONDS * SIM_HZ)):
                if self._holder_of(name, pid) is None:
                    break
                yield WAIT
            else:
                raise ActionFailed(f"{primitive} {name}: {holder} kept holding it")
        kind = self._kind(name)
        regions = tsrs or self._grasp_tsrs(name, pid)
        grip = min(max(evaluate(self.skills.grip[kind], {"f": self.half(name)}), 0.0), 0.04)
        self._set_grip(pid, min(grip + APPROACH_OPENING, 0.04))  # open just enough: neighbours stay clear
        support = [n for n, c in self.plan.scene.containing if n == name] + \
            [c for n, c in self.plan.scene.containing if n == name]
        ignore = [name, *support, *ignore_extra]
        approach = self.skills.approach_distance
        reason = "no reachable collision-free grasp"
        for attempt in range(self.attempts):
            if attempt:
                yield from self._let_other_move(pid)
                self._event("retry", action, pid, f"{primitive} {name}: attempt {attempt + 1} ({reason})", primitive)
            self._sync()
            candidates = self._goal_samples(regions, np.eye(4), self.samples, accept, rank)
            pre_goal = None
            blocked = None
            for G in candidates:
                found = self._ik_goal(pid, [G], ignore)
                if found is None:
                    continue
                pre = G.copy()
                pre[:3, 3] -= G[:3, 2] * approach
                found_pre = self._ik_goal(pid, [pre], ignore_extra)
                if found_pre is None:
                    continue
                try:  # the straight approach (and the lift) must be feasible from there
                    moves = [G, G @ _lifted(self.skills.lift, G)] if lift else [G]
                    self.cartesian_path(pid, found_pre[0], moves, ignore, f"approach {name}")
                except ActionFailed as error:
                    blocked = str(error)
                    continue
                pre_goal = (found_pre[0], pre, G)
                break
            if pre_goal is None:
                reason = blocked or self._no_goal(f"grasp of {name}", len(candidates), accept)
                continue
            try:
                yield from self.transit(pid, pre_goal[0], ignore_extra, what=f"{primitive} {name}")
                # the fingers close into the object without pushing it about: the constraint will hold it
                self._collide_with_arm(pid, name, enabled=False)
                yield from self.linear(pid, [pre_goal[2]], ignore=ignore, what=f"approach {name}")
            except ActionFailed as error:
                self._collide_with_arm(pid, name, enabled=True)
                reason = str(error)
                continue
            self._set_grip(pid, grip)
            yield from self._hold(0.2)
            self.picked_from[name] = self.pose(name)
            constraint, T_ee_obj = attach(self.client, self.bodies.arms[pid].body, body.body)
            hand = self.hands[pid]
            hand.carried, hand.constraint = name, constraint
            hand.riding = [Riding(name, T_ee_obj)]
            for content in self._contents(name):  # what lies in a container moves with it
                self._ride(pid, content)
            if lift:
                up = self.arms[pid].ee()
                up[2, 3] += self.skills.lift
                try:
                    yield from self.linear(pid, [up], ignore=[*ignore], what=f"lift {name}")
                except ActionFailed as error:  # let go, back off, try another grasp
                    reason = str(error)
                    yield from self.release(pid)
                    continue
            self._event("primitive_end", action, pid, name, primitive)
            return
        self._event("primitive_failed", action, pid, reason, primitive)
        raise ActionFailed(f"{primitive} {name}: {reason}")

    def release(self, pid: str, retreat: bool = True) -> Program:
        """Open, detach, move straight back along the approach."""
        hand = self.hands[pid]
        name = hand.carried
        self._set_grip(pid, 0.04)
        if hand.constraint is not None:
            detach(self.client, hand.constraint)
        for r in hand.riding[1:]:
            self._collide_with_arm(pid, r.name, enabled=True)
        hand.carried, hand.constraint, hand.riding = None, None, []
        yield from self._hold(0.15)
        if retreat:
            back = self.arms[pid].ee()
            back[:3, 3] -= back[:3, 2] * self.skills.approach_distance
            with contextlib.suppress(ActionFailed):
                yield from self.linear(pid, [back], ignore=[name] if name else [], what="retreat")
        if name is not None:
            self._collide_with_arm(pid, name, enabled=True)

    def engage(self, action: PlanAction, pid: str, spec: TSRSpec, roles: dict[str, str | None],
               meet: tuple[str, str] | None = None, accept: Accept | None = None, then: Step | None = None
               ) -> Program:
        """Carry the effector (the carried object, else the gripper) into a TSR, by a planned move. With
        ``then`` (the actuation that follows), only poses from which that actuation is feasible are chosen."""
        self._event("primitive_start", action, pid, spec.frame, "engage")
        reason = "no reachable collision-free pose"
        for attempt in range(self.attempts):
            if attempt:
                yield from self._let_other_move(pid)
                self._event("retry", action, pid, f"engage: attempt {attempt + 1} ({reason})", "engage")
            self._sync()
            q, reason = self._engage_goal(pid, spec, roles, meet, accept, then)
            if q is None:
                continue
            try:
                yield from self.transit(pid, q, what="engage")
            except ActionFailed as error:
                reason = str(error)
                continue
            self._event("primitive_end", action, pid, spec.frame, "engage")
            return
        self._event("primitive_failed", action, pid, reason, "engage")
        raise ActionFailed(f"engage {spec.frame}: {reason}")

    def _engage_goal(self, pid: str, spec: TSRSpec, roles: dict[str, str | None], meet: tuple[str, str] | None,
                     accept: Accept | None, then: Step | None) -> tuple[np.ndarray | None, str]:
        """Joints of a collision-free pose of the TSR from which ``then`` is feasible (its straight path, and
        what it tips falling into the destination), choosing the actuation's axis option; else None and why
        (the commonest reason over the samples)."""
        hand = self.hands[pid]
        T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
        T0_w, sizes = self.frame(spec, roles, pid, meet)
        region = spec.tsr(T0_w, sizes)
        rank = self._away_from_other(pid, T0_w[:3, 3]) if meet is None else None
        spin = bool(hand.riding) and self.plan.scene.object(hand.riding[0].name).shape in ("cylinder", "sphere")
        options = range(len(str(then.params.get("axis", "")).split(","))) if then is not None else range(0)

        landing: dict[int, list[int]] = {}

        def lands(G: np.ndarray) -> list[int]:
            """The actuation's axis options from ``G`` that tip what it lets go of into the destination (pure
            geometry, so it is checked on many samples before any IK; kept for the samples that pass)."""
            assert then is not None
            if id(G) in landing:  # only kept samples are stored: they stay alive, so their ids are not reused
                return landing[id(G)]
            good = [v for v in options
                    if self._falls_outside(pid, then, roles, self._actuation_waypoints(pid, then, roles, G, v)) is None]
            if good:
                landing[id(G)] = good
            return good

        tips = then is not None and roles.get("location") is not None and bool(self._tipped(pid, then, roles))
        keep = accept if not tips else (lambda G: (accept is None or accept(G)) and bool(lands(G)))
        candidates = self._goal_samples([region], T_eff_ee, self.samples, keep, rank, spin)
        if tips and not candidates:
            assert then is not None
            return None, f"no pose at {spec.frame} from which the {then.motion} tips into the {roles['location']}"
        why: Counter[str] = Counter()
        unreached = 0
        for G in candidates:
            found = self._ik_goal(pid, [G], [])
            if found is None:
                unreached += 1
                continue
            if then is None:
                return found[0], ""
            for variant in (lands(G) if tips else options):
                try:
                    waypoints = self._actuation_waypoints(pid, then, roles, G, variant)
                    self.cartesian_path(pid, found[0], [w.pose @ T_eff_ee for w in waypoints],
                                        self._touched(then, roles), "actuate")
                except ActionFailed as error:
                    why[str(error)] += 1
                    continue
                self.variants[pid] = variant
                return found[0], ""
        if then is None or unreached >= why.total():  # most samples were unreachable or in collision
            return None, self._no_goal(f"pose at {spec.frame}", len(candidates))
        self.goal_blockers = set()
        text, count = why.most_common(1)[0]
        return None, f"the {then.motion} from there: {text} ({count} of {why.total()} tries)"

    def _touched(self, step: Step, roles: dict[str, str | None]) -> list[str]:
        """The objects an actuation may touch: those of its contact pairs and what lies in them (the rice in the
        pot being stirred); every other object is an obstacle."""
        names = [name for pair in step.contacts for name in (roles.get(r) for r in pair) if name is not None]
        return [*names, *(c for name in names for c in self._contents(name))]

    def _tipped(self, pid: str, step: Step, roles: dict[str, str | None]) -> dict[str, Riding]:
        """What ``step`` lets go of that rides on the carried object (not the carried object itself)."""
        names = [roles.get(r) for r in step.release]
        return {r.name: r for r in self.hands[pid].riding[1:] if r.name in names}

    def _falls_outside(self, pid: str, step: Step, roles: dict[str, str | None],
                       waypoints: Sequence[Waypoint]) -> str | None:
        """Why what ``step`` lets go of (riding on the carried object) would miss the location, or None. It falls
        from where it is at the waypoint that lets go (from a carried container: from the middle of its
        opening), and must drop inside the middle of the location's footprint (:data:`DROP_INSIDE`)."""
        hand = self.hands[pid]
        target = roles.get("location")
        riding = self._tipped(pid, step, roles)
        if target is None or not riding:
            return None
        at = next((w for w in waypoints if w.lets_go), waypoints[-1])
        carrier = hand.riding[0]
        T_eff_ee = np.linalg.inv(carrier.T_ee_obj)
        if self.bodies.objects[carrier.name].category is Category.CONTAINER:
            opening = np.eye(4)
            opening[2, 3] = self.half(carrier.name).hz
            drops = {name: at.pose @ opening for name in riding}
        else:
            drops = {name: at.pose @ T_eff_ee @ r.T_ee_obj for name, r in riding.items()}
        T_target = self.pose(target)
        h = self.half(target)
        for name, T in drops.items():
            local = np.linalg.inv(T_target) @ T[:, 3]
            if abs(local[0]) > DROP_INSIDE * h.hx or abs(local[1]) > DROP_INSIDE * h.hy or local[2] < h.hz:
                return f"the {name} would fall outside the {target}"
        return None

    def _free_poses(self, name: str, region: TSR) -> list[np.ndarray]:
        """Object poses of ``region`` on a 2 cm grid (yaw in 45-degree steps within the bounds), the roomiest
        first. Room is the smaller of two clearances: the object's footprint to every other object, and the
        footprint of a hand taking it again (:data:`HAND_SPAN` across the object at its grasp point) to every
        object taller than :data:`HAND_CLEAR_HEIGHT`. Clearances beyond :data:`FREE_MARGIN` count as equally
        roomy; then the spot nearest the region's centre wins."""
        own = {r.name for h in self.hands.values() for r in h.riding if h.carried == name}
        half = np.array(self.bodies.objects[name].size) / 2
        corners = np.array([[sx * half[0], sy * half[1]] for sx in (-1, 1) for sy in (-1, 1)])
        holder = next((h for h in self.hands.values() if h.carried == name), None)
        if holder is not None and holder.riding:  # where the hand holds it now, in the object's frame
            T_obj_ee = np.linalg.inv(holder.riding[0].T_ee_obj)
            centre, across, along = T_obj_ee[:2, 3], T_obj_ee[:2, 1], T_obj_ee[:2, 0]
        else:
            centre = np.array([-0.55 * half[0] if self._kind(name) == "tool" else 0.0, 0.0])
            across, along = np.array([0.0, 1.0]), np.array([1.0, 0.0])
        hand = np.array([centre + sy * HAND_SPAN / 2 * across + sx * 0.03 * along
                         for sx in (-1, 1) for sy in (-1, 1)])
        others = [(np.array(p.getAABB(b.body, physicsClientId=self.client)), b) for n, b in self.bodies.objects.items()
                  if n not in own and n != name]
        boxes = np.array([box[:, :2] for box, _ in others]).reshape(-1, 2, 2)
        tall = np.array([box[:, :2] for box, _ in others if box[1, 2] - self.bodies.table_height > HAND_CLEAR_HEIGHT]
                        ).reshape(-1, 2, 2)

        def clearance(pts: np.ndarray, against: np.ndarray) -> float:
            if not len(against):
                return 1.0
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            sep = np.maximum(against[:, 0] - hi, lo - against[:, 1])
            overlap = np.all(sep < 0, axis=1)
            gap = np.maximum(sep, 0.0)
            return float(np.min(np.where(overlap, -1.0, np.hypot(gap[:, 0], gap[:, 1]))))

        B = region.Bw
        xs = np.arange(B[0, 0], B[0, 1] + 1e-9, 0.02)
        ys = np.arange(B[1, 0], B[1, 1] + 1e-9, 0.02)
        yaws = [y for y in np.radians([-90, -45, 0, 45, 90]) if B[5, 0] - 1e-9 <= y <= B[5, 1] + 1e-9] or [0.0]
        scored = []
        for yaw in yaws:
            for x in xs:
                for y in ys:
                    T = region.T0_w @ xyzrpy_to_matrix([x, y, (B[2, 0] + B[2, 1]) / 2, 0, 0, yaw]) @ region.Tw_e
                    R, t = T[:2, :2], T[:2, 3]
                    own_room = clearance(corners @ R.T + t, boxes)
                    room = min(own_room, clearance(hand @ R.T + t, tall))
                    if own_room > 0.0:  # where the hand has no room either, only after every roomy spot
                        tier = 0 if room > 0.0 else 1
                        scored.append((tier, -min(max(room, own_room * tier), FREE_MARGIN),
                                       math.hypot(x, y) + 0.01 * abs(yaw), T))
        scored.sort(key=lambda item: item[:3])
        return [item[3] for item in scored]

    def place(self, action: PlanAction | None, pid: str, target: np.ndarray | list[TSR], free: bool = False
              ) -> Program:
        """Put the carried object down at ``target`` (object pose, or TSRs of object poses): planned move above,
        straight down, release. ``free``: only where it stands clear of the other objects."""
        hand = self.hands[pid]
        name = hand.carried
        if name is None:
            return
        self._event("primitive_start", action, pid, name, "place")
        T_obj_ee = np.linalg.inv(hand.riding[0].T_ee_obj)
        regions = target if isinstance(target, list) else [TSR(target, np.eye(4), np.array(
            [[-0.01, 0.01], [-0.01, 0.01], [0.002, 0.006], [0, 0], [0, 0], [-0.1, 0.1]]))]
        reason = "no reachable place pose"
        for attempt in range(self.attempts):
            if attempt:
                yield from self._let_other_move(pid)
                self._event("retry", action, pid, f"place {name}: attempt {attempt + 1} ({reason})", "place")
            self._sync()
            if free:
                spots = self._free_poses(name, regions[0])
                goals = [T @ T_obj_ee for T in spots[attempt * self.samples:(attempt + 1) * self.samples]]
            else:
                goals = self._goal_samples(regions, T_obj_ee, self.samples)
            chosen = None
            blocked = None
            for G in goals:
                found = self._ik_goal(pid, [G], [], check=False)
                if found is None:
                    continue
                above = G.copy()
                above[2, 3] += self.skills.lift
                found_above = self._ik_goal(pid, [above], [])
                if found_above is None:
                    continue
                try:  # the straight way down must be feasible too
                    self.cartesian_path(pid, found_above[0], [G], [], f"put down {name}")
                except ActionFailed as error:
                    blocked = str(error)
                    continue
                chosen = (found_above[0], G)
                break
            if chosen is None:
                reason = blocked or self._no_goal(f"place pose for {name}", len(goals))
                continue
            try:
                yield from self.transit(pid, chosen[0], what=f"place {name}")
                yield from self.linear(pid, [chosen[1]], ignore=[], what=f"put down {name}")
            except ActionFailed as error:
                reason = str(error)
                continue
            yield from self.release(pid)
            self._event("primitive_end", action, pid, name, "place")
            return
        self._event("primitive_failed", action, pid, reason, "place")
        raise ActionFailed(f"place {name}: {reason}")

    def _actuation_waypoints(self, pid: str, step: Step, roles: dict[str, str | None], ee: np.ndarray,
                             variant: int | None = None) -> list[Waypoint]:
        """The effector waypoints of ``step`` starting with the hand at ``ee``; ``variant`` picks one of the
        step's axis options (default: the one the last engage chose)."""
        assert step.motion is not None
        hand = self.hands[pid]
        T_ee_eff = hand.riding[0].T_ee_obj if hand.riding else np.eye(4)
        E = ee @ T_ee_eff
        sizes = {"t": self.half(roles.get("tool")), "i": self.half(roles.get("ingredient")),
                 "l": self.half(roles.get("location"))}
        if step.contact is not None:
            sizes["f"] = self.half(roles.get(step.contact[1]))
        params = {k: (v if k == "axis" else evaluate(v, sizes)) for k, v in step.params.items()}
        if "axis" in params:
            options = str(params["axis"]).split(",")
            chosen = self.variants.get(pid, 0) if variant is None else variant
            params["axis"] = options[min(chosen, len(options) - 1)]
        contact_target = roles.get(step.contact[1]) if step.contact else None
        Rw = self._facing(contact_target, pid)[:3, :3] if contact_target is not None \
            else np.eye(3)
        if not step.contact:
            target = roles.get("location") or roles.get("ingredient")
            if target is not None:
                Rw = self._facing(target, pid)[:3, :3]
        return actuation_path(step.motion, params, E, Rw, grip=hand.grip, hand=ee[:3, 3])  # type: ignore[arg-type]

    def actuate(self, action: PlanAction, pid: str, step: Step, roles: dict[str, str | None]) -> Program:
        """The step's motion from where the hand is, its contact pairs passing through each other; then what it
        attaches rides on the tool, and what it lets go of must land in the location (else :class:`Missed`)."""
        assert step.motion is not None
        self._event("primitive_start", action, pid, step.motion, "actuate")
        hand = self.hands[pid]
        T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
        waypoints = self._actuation_waypoints(pid, step, roles, self.arms[pid].ee())
        tipped = list(self._tipped(pid, step, roles))
        let_go_at = next((j for j, w in enumerate(waypoints) if w.lets_go), len(waypoints) - 1)

        def let_go(j: int) -> None:  # what rides on the tool falls from here on
            if j == let_go_at:
                hand.riding = [r for r in hand.riding if r.name not in tipped]

        vessel = hand.riding[0].name if hand.riding else None
        pairs = self._contact_pairs(step, roles)
        for a, b in pairs:
            p.setCollisionFilterPair(a, b, -1, -1, 0, physicsClientId=self.client)
        try:
            for again in (False, True):  # what sticks in a tipped container: tip it once more
                if again:
                    stuck = [n for n in tipped if self._container_of(n) == vessel]
                    if not stuck:
                        break
                    self._event("retry", action, pid, f"{', '.join(stuck)} still in the {vessel}: tip again",
                                "actuate")
                    for n in stuck:
                        self._ride(pid, n)
                yield from self.linear(pid, [w.pose @ T_eff_ee for w in waypoints],
                                       ignore=self._touched(step, roles), holds=[w.hold for w in waypoints],
                                       fingers=[w.fingers for w in waypoints], what=f"actuate {step.motion}",
                                       reached=let_go if tipped else None)
                if not tipped:
                    break
                yield from self._hold(0.6)  # let it land
        except ActionFailed as error:
            self._event("primitive_failed", action, pid, str(error), "actuate")
            raise
        finally:
            for a, b in pairs:
                p.setCollisionFilterPair(a, b, -1, -1, 1, physicsClientId=self.client)
        self._attach(pid, step, roles)
        for name in tipped:
            self._collide_with_arm(pid, name, enabled=True)
            if hand.riding:
                p.setCollisionFilterPair(self.bodies.objects[hand.riding[0].name].body,
                                         self.bodies.objects[name].body, -1, -1, 1, physicsClientId=self.client)
        if hand.carried is not None and hand.carried in (roles.get(r) for r in step.release):
            dropped = hand.carried  # carried by hand into the location
            yield from self.release(pid)
            yield from self._hold(0.6)
            tipped.append(dropped)
        missed = self._missed(tipped, roles.get("location"))
        if missed is not None:
            self._event("primitive_failed", action, pid, missed, "actuate")
            raise Missed(f"actuate {step.motion}: {missed}")
        self._event("primitive_end", action, pid, step.motion, "actuate")

    def _contact_pairs(self, step: Step, roles: dict[str, str | None]) -> list[tuple[int, int]]:
        """Bodies of the step's contact pairs, and of the tool with what lies in a container it works in."""
        pairs = []
        for first, second in step.contacts:
            a, b = roles.get(first), roles.get(second)
            if a is not None and b is not None and a != b:
                for other in (b, *(c for c in self._contents(b) if c != a)):
                    pairs.append((self.bodies.objects[a].body, self.bodies.objects[other].body))
        return pairs

    def _attach(self, pid: str, step: Step, roles: dict[str, str | None]) -> None:
        """What the step attaches (a scooped ingredient) rides on the carried tool from now on, on its tip."""
        hand = self.hands[pid]
        for role in step.attach:
            name = roles.get(role)
            if name is not None and hand.riding:
                carrier = hand.riding[0]
                tool = self.half(carrier.name)
                ing = self.half(name)
                T_tool_ing = np.eye(4)
                T_tool_ing[:3, 3] = [0.6 * tool.hx, 0.0, tool.hz + ing.hz + 0.002]
                self._ride(pid, name, carrier.T_ee_obj @ T_tool_ing)
                p.setCollisionFilterPair(self.bodies.objects[carrier.name].body, self.bodies.objects[name].body,
                                         -1, -1, 0, physicsClientId=self.client)

    def _missed(self, names: Sequence[str], target: str | None) -> str | None:
        """Where the first of ``names`` that is not in ``target`` lies, or None (a transfer is done only when its
        ingredient is in its destination)."""
        for name in names:
            where = self._container_of(name)
            if target is not None and where != target:
                at = np.round(self.pose(name)[:2, 3], 2).tolist()
                return f"the {name} fell " + (f"into the {where}" if where else f"on the table at {at}") + \
                    f", not into the {target}"
        return None


class Missed(ActionFailed):
    """The motion ran but did not do its work (an ingredient missed its destination): trying it again from a new
    engage cannot help."""


def _lifted(height: float, T: np.ndarray) -> np.ndarray:
    """The transform that, right-multiplied onto ``T``, raises it by ``height`` along world z."""
    up = np.eye(4)
    up[:3, 3] = T[:3, :3].T @ np.array([0.0, 0.0, height])
    return up
