"""A plan as PDDL (STRIPS with typing): a domain, a problem and the plan's own steps, so that task planners can
check the plan (a validator runs :attr:`PddlExport.steps` on the problem) or re-plan it (a planner solves the
problem its own way).

The domain ``wecook``: arms (``agent``) and things (``tool``, ``container``, ``ingredient``; the constant
``tabletop`` is where an ingredient in no container is). Facts: ``(free ?a)`` the arm holds nothing,
``(holding ?a ?x)`` which arm holds what, ``(loose ?x)`` no arm holds it, ``(in ?x ?c)`` containment,
``(done-<verb> ?x)`` the verb was done to ``x``, ``(received ?a ?x)`` a handover gave ``x`` to ``a``,
``(steadied ?x)`` an arm held ``x`` still for the other. Actions: ``grasp`` and ``release``; one per verb with a
tool the arm holds (``cut ?a ?tool ?x``) and one by the hand itself (``cut-by-hand ?a ?x``); ``transfer`` and
``transfer-by-hand`` move an ingredient from one place to another; ``handover`` from a holding arm to a free
one; ``hold-steady``.

The problem: the plan's objects, every arm free and every thing loose, its containing pairs (other ingredients
on the ``tabletop``); the goal is what the plan's steps achieve: each verb done to each thing it names, where
the ingredients end up, what was handed over and held steady, and every arm free at the end.

The steps of a plan action: ``grasp`` its tool, the verb on each ingredient (else on its location, else on the
tool), ``release``; a handover is ``grasp``, ``handover``, the receiver's ``release``; a holding is the holder's
``grasp`` and ``hold-steady``, the actor's steps, the holder's ``release``. Actions go in the order of ``after``
(ties in plan order).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from wecook_core.model import VERBS, Category
from wecook_core.plan.model import Act, Plan, PlanAction

DOMAIN = "wecook"
TABLETOP = "tabletop"
ACTION_VERBS: tuple[str, ...] = tuple(v for v in VERBS if v != "transfer")
"""Verbs with a ``<verb>`` and a ``<verb>-by-hand`` action in the domain."""
_RESERVED = frozenset({TABLETOP, "object", "either", "and", "or", "not", "define", "domain", "problem", "agent",
                       "thing", "tool", "container", "ingredient"})
_TYPE = {Category.TOOL: "tool", Category.CONTAINER: "container", Category.INGREDIENT: "ingredient"}


def pddl_name(name: str, taken: Iterable[str] = ()) -> str:
    """A PDDL name for a plan name: lower case, letters, digits, ``-`` and ``_``, starting with a letter, not a
    keyword or type of the domain, and not in ``taken`` (``-2``, ``-3``... appended)."""
    base = re.sub(r"[^a-z0-9_-]", "-", name.lower())
    if not base or not base[0].isalpha():
        base = "o-" + base
    if base in _RESERVED:
        base += "-1"
    used = set(taken)
    out, k = base, 2
    while out in used:
        out, k = f"{base}-{k}", k + 1
    return out


def domain_text() -> str:
    """The ``wecook`` domain (the same for every plan)."""
    lines = [f"(define (domain {DOMAIN})",
             "  (:requirements :strips :typing)",
             "  (:types agent thing - object",
             "          tool container ingredient - thing)",
             f"  (:constants {TABLETOP} - container)",
             "  (:predicates",
             "    (free ?a - agent)",
             "    (holding ?a - agent ?x - thing)",
             "    (loose ?x - thing)",
             "    (in ?x - thing ?c - thing)",
             "    (received ?a - agent ?x - thing)",
             "    (steadied ?x - thing)",
             *(f"    (done-{verb} ?x - thing)" for verb in (*ACTION_VERBS, "transfer")),
             "  )",
             "  (:action grasp",
             "    :parameters (?a - agent ?x - thing)",
             "    :precondition (and (free ?a) (loose ?x))",
             "    :effect (and (holding ?a ?x) (not (free ?a)) (not (loose ?x))))",
             "  (:action release",
             "    :parameters (?a - agent ?x - thing)",
             "    :precondition (holding ?a ?x)",
             "    :effect (and (free ?a) (loose ?x) (not (holding ?a ?x))))"]
    for verb in ACTION_VERBS:
        lines += [f"  (:action {verb}",
                  "    :parameters (?a - agent ?t - thing ?x - thing)",
                  "    :precondition (holding ?a ?t)",
                  f"    :effect (done-{verb} ?x))",
                  f"  (:action {verb}-by-hand",
                  "    :parameters (?a - agent ?x - thing)",
                  "    :precondition (free ?a)",
                  f"    :effect (done-{verb} ?x))"]
    lines += ["  (:action transfer",
              "    :parameters (?a - agent ?t - thing ?x - thing ?from - thing ?to - thing)",
              "    :precondition (and (holding ?a ?t) (in ?x ?from))",
              "    :effect (and (not (in ?x ?from)) (in ?x ?to) (done-transfer ?x)))",
              "  (:action transfer-by-hand",
              "    :parameters (?a - agent ?x - thing ?from - thing ?to - thing)",
              "    :precondition (and (free ?a) (loose ?x) (in ?x ?from))",
              "    :effect (and (not (in ?x ?from)) (in ?x ?to) (done-transfer ?x)))",
              "  (:action handover",
              "    :parameters (?g - agent ?r - agent ?x - thing)",
              "    :precondition (and (holding ?g ?x) (free ?r))",
              "    :effect (and (holding ?r ?x) (free ?g) (received ?r ?x) (not (holding ?g ?x)) (not (free ?r))))",
              "  (:action hold-steady",
              "    :parameters (?a - agent ?x - thing)",
              "    :precondition (holding ?a ?x)",
              "    :effect (steadied ?x))",
              ")", ""]
    return "\n".join(lines)


@dataclass(frozen=True)
class PddlExport:
    domain: str
    problem: str
    steps: tuple[tuple[str, ...], ...]
    """The plan's steps, each ``(action, arg, ...)`` in PDDL names."""
    step_actions: tuple[str, ...]
    """The plan action id each step comes from."""
    names: Mapping[str, str]
    """Plan object or pid -> its PDDL name."""

    def plan_text(self) -> str:
        """The steps in the plan format validators read (``(grasp p1 knife)``, a comment per plan action)."""
        lines, last = [], None
        for step, action_id in zip(self.steps, self.step_actions, strict=True):
            if action_id != last:
                lines.append(f"; {action_id}")
                last = action_id
            lines.append("(" + " ".join(step) + ")")
        return "\n".join(lines) + "\n"


def ordered(actions: Sequence[PlanAction]) -> list[PlanAction]:
    """The actions in an order that keeps ``after`` (each ready action in plan order; unknown ids ignored)."""
    ids = {a.id for a in actions}
    done: set[str] = set()
    left = list(actions)
    out: list[PlanAction] = []
    while left:
        ready = next((a for a in left if all(d in done or d not in ids for d in a.after)), left[0])
        out.append(ready)
        done.add(ready.id)
        left.remove(ready)
    return out


class _Steps:
    """Grounds plan actions into domain steps, following where each ingredient is."""

    def __init__(self, plan: Plan, names: Mapping[str, str]) -> None:
        self.n = names
        self.inside: dict[str, str | None] = {i: c for i, c in plan.scene.containing}
        """Ingredient -> the object it is in (None: the tabletop)."""
        self.steps: list[tuple[str, ...]] = []
        self.ids: list[str] = []
        self.goal: list[tuple[str, ...]] = []
        self.moved: set[str] = set()

    def add(self, action_id: str, *step: str) -> None:
        self.steps.append(step)
        self.ids.append(action_id)

    def fact(self, *fact: str) -> None:
        if fact not in self.goal:
            self.goal.append(fact)

    def act(self, action_id: str, pid: str, act: PlanAction | Act, busy: str | None = None) -> None:
        """The steps of one arm's action (``busy``: an object the other arm holds meanwhile)."""
        a = self.n[pid]
        hand = act.tool is None or act.tool in act.ingredients or act.tool == busy
        tool = None if hand or act.tool is None else self.n[act.tool]
        if tool:
            self.add(action_id, "grasp", a, tool)
        if act.verb == "transfer":
            for ingredient in act.ingredients:
                source = act.source or self.inside.get(ingredient)
                destination = act.location
                frm = self.n[source] if source else TABLETOP
                to = self.n[destination] if destination else TABLETOP
                x = self.n[ingredient]
                self.add(action_id, *(("transfer", a, tool, x, frm, to) if tool
                                      else ("transfer-by-hand", a, x, frm, to)))
                self.inside[ingredient] = destination
                self.moved.add(ingredient)
                self.fact("done-transfer", x)
        else:
            targets = list(act.ingredients) or ([act.location] if act.location else []) or (
                [act.tool] if act.tool else [])
            for target in targets:
                x = self.n[target]
                self.add(action_id, *((act.verb, a, tool, x) if tool else (f"{act.verb}-by-hand", a, x)))
                self.fact(f"done-{act.verb}", x)
        if tool:
            self.add(action_id, "release", a, tool)

    def action(self, action: PlanAction) -> None:
        if action.verb == "handover" and action.tool is not None:
            g, r, x = self.n[action.pids[0]], self.n[action.pids[1]], self.n[action.tool]
            self.add(action.id, "grasp", g, x)
            self.add(action.id, "handover", g, r, x)
            self.add(action.id, "release", r, x)
            self.fact("received", r, x)
        elif action.verb == "holding" and action.partner is not None and action.tool is not None:
            h, x = self.n[action.pids[0]], self.n[action.tool]
            self.add(action.id, "grasp", h, x)
            self.add(action.id, "hold-steady", h, x)
            self.act(action.id, action.pids[1], action.partner, busy=action.tool)
            self.add(action.id, "release", h, x)
            self.fact("steadied", x)
        elif action.verb not in ("handover", "holding"):
            self.act(action.id, action.pids[0], action)


def _fact(fact: Sequence[str]) -> str:
    return "(" + " ".join(fact) + ")"


def export_pddl(plan: Plan, problem_name: str = "plan") -> PddlExport:
    """The plan's domain, problem and steps (see the module's docstring)."""
    names: dict[str, str] = {}
    for pid in sorted({a.pid for a in plan.agents} | {p for a in plan.actions for p in a.pids}):
        names[pid] = pddl_name(pid, names.values())
    for obj in plan.scene.objects:
        names[obj.name] = pddl_name(obj.name, names.values())
    steps = _Steps(plan, names)
    for action in ordered(plan.actions):
        steps.action(action)
    agents = [names[p] for p in sorted({a.pid for a in plan.agents} | {p for a in plan.actions for p in a.pids})]
    by_type: dict[str, list[str]] = {}
    for obj in plan.scene.objects:
        by_type.setdefault(_TYPE[obj.category], []).append(names[obj.name])
    inside = {i: c for i, c in plan.scene.containing}
    init: list[tuple[str, ...]] = [("free", a) for a in agents]
    init += [("loose", names[o.name]) for o in plan.scene.objects]
    init += [("in", names[o.name], names[inside[o.name]] if o.name in inside else TABLETOP)
             for o in plan.scene.objects if o.category is Category.INGREDIENT]
    goal = list(steps.goal)
    goal += [("in", names[i], names[c] if c is not None else TABLETOP) for i, c in steps.inside.items()
             if i in steps.moved]
    goal += [("free", a) for a in agents]
    objects = [f"    {' '.join(agents)} - agent"] + [f"    {' '.join(v)} - {t}" for t, v in by_type.items()]
    problem = "\n".join([f"(define (problem {pddl_name(problem_name)})", f"  (:domain {DOMAIN})",
                         "  (:objects", *objects, "  )",
                         "  (:init", *(f"    {_fact(f)}" for f in init), "  )",
                         "  (:goal (and", *(f"    {_fact(f)}" for f in goal), "  ))", ")", ""])
    return PddlExport(domain_text(), problem, tuple(steps.steps), tuple(steps.ids), names)


def write_pddl(export: PddlExport, folder: str | Path) -> tuple[Path, Path, Path]:
    """Write ``domain.pddl``, ``problem.pddl`` and ``plan.pddl`` (the steps) into ``folder`` (made if needed)."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths = (out / "domain.pddl", out / "problem.pddl", out / "plan.pddl")
    from wecook_core.files import write_atomic

    for path, text in zip(paths, (export.domain, export.problem, export.plan_text()), strict=True):
        write_atomic(path, text, replace=True, what="PDDL file")
    return paths
