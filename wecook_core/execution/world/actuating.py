"""Engaging and actuating (a layer of the PyBullet world, :mod:`wecook_core.execution.world`): carrying the
effector into a skill's TSR, chosen so that the actuation that follows is feasible, and the actuation itself (its
contact pairs passing through each other, what it tips landing in the destination)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Generator, Sequence

import numpy as np
import pybullet as p

from wecook_core.execution.planning_scene import Riding
from wecook_core.execution.program import ActionFailed, Program, Tick
from wecook_core.execution.skills import Step, TSRSpec, Waypoint, actuation_path, evaluate
from wecook_core.execution.world.grasping import Grasping
from wecook_core.execution.world.moves import Accept
from wecook_core.execution.world.retry import retrying
from wecook_core.model import Category
from wecook_core.plan import PlanAction

DROP_INSIDE = 0.6
"""Share of a destination's half extents, about its middle, that what is tipped into it must fall within."""


class Actuating(Grasping):
    def engage(self, action: PlanAction, pid: str, spec: TSRSpec, roles: dict[str, str | None],
               meet: tuple[str, str] | None = None, accept: Accept | None = None, then: Step | None = None
               ) -> Program:
        """Carry the effector (the carried object, else the gripper) into a TSR, by a planned move. With
        ``then`` (the actuation that follows), only poses from which that actuation is feasible are chosen."""
        self._event("primitive_start", action, pid, spec.frame, "engage")

        def attempt(_k: int) -> Generator[Tick, None, str | None]:
            q, reason = self._engage_goal(pid, spec, roles, meet, accept, then)
            if q is None:
                return reason
            try:
                yield from self.transit(pid, q, what="engage")
            except ActionFailed as error:
                return str(error)
            return None

        yield from retrying(self, action, pid, "engage", f"engage {spec.frame}", spec.frame, attempt,
                            "no reachable collision-free pose")

    def _engage_goal(self, pid: str, spec: TSRSpec, roles: dict[str, str | None], meet: tuple[str, str] | None,
                     accept: Accept | None, then: Step | None) -> tuple[np.ndarray | None, str]:
        """Joints of a collision-free pose of the TSR from which ``then`` is feasible (its straight path, and
        what it tips falling into the destination), choosing the actuation's axis option; else None and why
        (the commonest reason over the samples)."""
        hand = self.hands[pid]
        T_eff_ee = np.linalg.inv(hand.riding[0].T_ee_obj) if hand.riding else np.eye(4)
        T0_w, sizes = self.frame(spec, roles, pid, meet)
        T0_w = self._over_contents(spec, roles, T0_w)
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

    def _over_contents(self, spec: TSRSpec, roles: dict[str, str | None], T0_w: np.ndarray) -> np.ndarray:
        """``T0_w`` raised so that a TSR over the top of an ingredient that is a container (the action names no
        ingredient: the tool works on what lies in or on its location, the food cut on a plate) stands over the
        top of what lies there: the tool engages what it works on, not the container under it."""
        name = roles.get("ingredient")
        if spec.frame.split(":", 1)[-1] != "ingredient" or name is None:
            return T0_w
        contents = self._contents(name)
        if not contents:
            return T0_w
        top = max(p.getAABB(self.bodies.objects[c].body, physicsClientId=self.client)[1][2] for c in contents)
        rise = top - (self.pose(name)[2, 3] + self.half(name).hz)
        if rise <= 0:
            return T0_w
        T = T0_w.copy()
        T[2, 3] += rise
        return T

    def _touched(self, step: Step, roles: dict[str, str | None]) -> list[str]:
        """The objects an actuation may touch: those of its contact pairs, what lies in them (the rice in the
        pot being stirred), and what lies beside them in the same container (the onion next to the meat cut on
        a board: a knife brushes it as a person's does); every other object is an obstacle."""
        names = [name for pair in step.contacts for name in (roles.get(r) for r in pair) if name is not None]
        holders = {c for c in (self._container_of(n) for n in names) if c is not None}
        near = [*holders, *(c for h in sorted(holders) for c in self._contents(h))]
        return list(dict.fromkeys([*names, *(c for name in names for c in self._contents(name)), *near]))

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


