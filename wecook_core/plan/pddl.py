"""A plan as PDDL (STRIPS with typing): a domain, a problem and the plan's own steps, so that task planners can
check the plan (a validator runs :attr:`PddlExport.steps` on the problem) or solve it their own way (pyperplan
does, in the tests).

The problem gives each part of a plan action (a *task*: one per ingredient moved or acted on) to the arm the plan
gives it to, with the tool and on the thing the plan says (``(task-cut task-a9 p1 knife tomato)``), and orders the
tasks as the plan's ``after`` edges do (gates: a task that waits for others is ready once each of them is done).
What a task needs is the domain's (:mod:`~wecook_core.plan.pddl_domain`): a cut, a stir, a roll... needs the arm to
hold the tool, fit for the verb (``fits-cut``: the tools the plan uses for it, the knife); a pour, a sprinkle or a
dip needs it to hold the thing poured (the oil); a transfer moves an ingredient from where it is with a fit tool, by
tipping the held container it is in, or by hand; a task the plan does by hand (a squeeze) needs a free hand; a
holding's action needs the other arm to hold the held thing meanwhile; a handover needs the giver to hold the thing
and the receiver's hand free. Grasping needs the arm to reach the thing: ``(reaches ?a ?x)`` for every place the
thing takes in the plan that lies in the arm's reach band (:mod:`wecook_core.plan.reach`). The domain holds the
forms the plan uses, and no by-hand form of a verb the plan does with a tool.

The goal: every task done and every arm free. The plan's own steps: ``grasp`` each action's tool (a holding: the
holder's grasp of the held thing first), one step per task, ``release``; a handover's receiver releases what it
got; a task that waits opens its gates first (``pass``, ``start``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from wecook_core.model import Category
from wecook_core.plan.model import Act, Plan, PlanAction
from wecook_core.plan.pddl_domain import HANDOVER, HELD_VERBS, Schema, domain_text, schema
from wecook_core.plan.reach import positions, reach_band

DOMAIN = "wecook"
TABLETOP = "tabletop"
_RESERVED = frozenset({TABLETOP, "object", "either", "and", "or", "not", "define", "domain", "problem", "arm",
                       "task", "gate", "thing", "tool", "container", "ingredient"})
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
    tasks: Mapping[str, str] = field(default_factory=dict)
    """PDDL task -> the plan action id it is part of."""

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


@dataclass(frozen=True)
class _Task:
    name: str
    action_id: str
    schema: Schema
    fact: tuple[str, ...]
    """The task fact's arguments after the task."""
    step: tuple[str, ...]
    """The schema's arguments in the plan's own step."""


class _Tasks:
    """Plan actions -> tasks and the plan's own steps, following where each ingredient is."""

    def __init__(self, plan: Plan, names: Mapping[str, str]) -> None:
        self.n = names
        self.inside: dict[str, str | None] = {i: c for i, c in plan.scene.containing}
        self.tasks: list[_Task] = []
        self.fits: set[tuple[str, str]] = set()
        self.steps: list[tuple[tuple[str, ...], str]] = []
        self.taken = set(names.values())

    def task(self, action_id: str, s: Schema, fact: tuple[str, ...], step: tuple[str, ...]) -> _Task:
        name = pddl_name(f"task-{action_id}", self.taken)
        self.taken.add(name)
        out = _Task(name, action_id, s, fact, (name, *step))
        self.tasks.append(out)
        return out

    def act(self, action_id: str, pid: str, act: PlanAction | Act,
            held: tuple[str, str] | None = None) -> tuple[str | None, list[_Task]]:
        """The tool one arm grasps for ``act`` (None: none) and its tasks; ``held``: (holder, thing) held meanwhile."""
        a, n = self.n[pid], self.n
        busy = held[1] if held else None
        hand = act.tool is None or act.tool in act.ingredients or (busy is not None and n[act.tool] == busy)
        tool = None if hand or act.tool is None else n[act.tool]
        extra = held or ()
        tasks: list[_Task] = []

        def add(s: Schema, fact: tuple[str, ...], step: tuple[str, ...]) -> None:
            s = s.held() if held else s
            tasks.append(self.task(action_id, s, (*fact, *extra), (*step, *extra)))

        if act.verb == "transfer":
            for ingredient in act.ingredients:
                source, destination = act.source or self.inside.get(ingredient), act.location
                x = n[ingredient]
                frm, to = (n[source] if source else TABLETOP), (n[destination] if destination else TABLETOP)
                if tool is None:
                    add(schema("transfer", "hand"), (a, x, to), (a, x, frm, to))
                elif tool == frm:
                    add(schema("transfer", "tipping"), (a, tool, x, to), (a, tool, x, to))
                else:
                    self.fits.add(("transfer", tool))
                    add(schema("transfer", "tool"), (a, tool, x, to), (a, tool, x, frm, to))
                self.inside[ingredient] = destination
        elif act.verb in HELD_VERBS and tool is not None:
            into = act.location or next((self.inside[i] for i in act.ingredients if self.inside.get(i)), None)
            x = n[into] if into else TABLETOP
            add(schema(act.verb, "held"), (a, tool, x), (a, tool, x))
        else:
            targets = list(act.ingredients) or ([act.location] if act.location else []) or (
                [act.tool] if act.tool else [])
            for target in targets:
                if tool is None:
                    add(schema(act.verb, "hand"), (a, n[target]), (a, n[target]))
                else:
                    self.fits.add((act.verb, tool))
                    add(schema(act.verb, "tool"), (a, tool, n[target]), (a, tool, n[target]))
        return tool, tasks

    def action(self, action: PlanAction) -> list[tuple[str, ...]]:
        """The action's steps (its tasks' steps between grasps and releases)."""
        if action.verb == "handover" and action.tool is not None:
            g, r, x = self.n[action.pids[0]], self.n[action.pids[1]], self.n[action.tool]
            t = self.task(action.id, HANDOVER, (g, r, x), (g, r, x))
            return [("grasp", g, x), (HANDOVER.name, *t.step), ("release", r, x)]
        if action.verb == "holding" and action.partner is not None and action.tool is not None:
            h, x = self.n[action.pids[0]], self.n[action.tool]
            tool, tasks = self.act(action.id, action.pids[-1], action.partner, (h, x))
            a = self.n[action.pids[-1]]
            inner = [(t.schema.name, *t.step) for t in tasks]
            if tool:
                inner = [("grasp", a, tool), *inner, ("release", a, tool)]
            return [("grasp", h, x), *inner, ("release", h, x)]
        if action.verb in ("handover", "holding"):
            return []
        tool, tasks = self.act(action.id, action.pids[0], action)
        a = self.n[action.pids[0]]
        inner = [(t.schema.name, *t.step) for t in tasks]
        return [("grasp", a, tool), *inner, ("release", a, tool)] if tool else inner


def _reaches(plan: Plan, names: Mapping[str, str]) -> list[tuple[str, str]]:
    """(arm, thing) for every thing an arm reaches at a place it takes in the plan (robots not checked reach
    everything), and the tabletop for every arm."""
    category = {o.name: o.category for o in plan.scene.objects}
    places: dict[str, set[tuple[float, float]]] = {o.name: {(o.x, o.y)} for o in plan.scene.objects}
    for _action, where in positions(plan):
        for name, xy in where.items():
            places.setdefault(name, set()).add(xy)
    out = []
    for agent in plan.agents:
        bx, by = agent.base_position[0], agent.base_position[1]
        for obj in plan.scene.objects:
            band = reach_band(agent, category[obj.name])
            if band is None or any(band[0] <= math.hypot(x - bx, y - by) <= band[1] for x, y in places[obj.name]):
                out.append((names[agent.pid], names[obj.name]))
        out.append((names[agent.pid], TABLETOP))
    return out


def _fact(fact: Sequence[str]) -> str:
    return "(" + " ".join(fact) + ")"


def export_pddl(plan: Plan, problem_name: str = "plan") -> PddlExport:
    """The plan's domain, problem and steps (see the module's docstring)."""
    pids = sorted({a.pid for a in plan.agents} | {p for a in plan.actions for p in a.pids})
    names: dict[str, str] = {}
    for pid in pids:
        names[pid] = pddl_name(pid, names.values())
    for obj in plan.scene.objects:
        names[obj.name] = pddl_name(obj.name, names.values())
    tasks = _Tasks(plan, names)
    by_action: dict[str, list[_Task]] = {}
    steps: list[tuple[str, ...]] = []
    step_ids: list[str] = []
    gates: list[str] = []
    init: list[tuple[str, ...]] = []
    for action in ordered(plan.actions):
        first = len(tasks.tasks)
        action_steps = tasks.action(action)
        mine = by_action[action.id] = tasks.tasks[first:]
        waits = [t.name for d in action.after for t in by_action.get(d, ())]
        opening: list[tuple[str, ...]] = []
        for task in mine:
            if not waits:
                init.append(("ready", task.name))
                continue
            chain = [pddl_name(f"gate-{task.name}-{k}", tasks.taken) for k in range(len(waits) + 1)]
            tasks.taken.update(chain)
            gates += chain
            init.append(("open", chain[0]))
            for k, wait in enumerate(waits):
                init.append(("needs", chain[k], wait, chain[k + 1]))
                opening.append(("pass", chain[k], wait, chain[k + 1]))
            init.append(("unlocks", chain[-1], task.name))
            opening.append(("start", chain[-1], task.name))
        for step in (*opening, *action_steps):
            steps.append(step)
            step_ids.append(action.id)
    arms = [names[p] for p in pids]
    inside = {i: c for i, c in plan.scene.containing}
    init = [*(("free", a) for a in arms), *(("loose", names[o.name]) for o in plan.scene.objects),
            *(("in", names[o.name], names[inside[o.name]] if o.name in inside else TABLETOP)
              for o in plan.scene.objects if o.category is Category.INGREDIENT),
            *(("reaches", a, x) for a, x in _reaches(plan, names)),
            *(("fits-" + verb, tool) for verb, tool in sorted(tasks.fits)),
            *((f"task-{t.schema.name}", t.name, *t.fact) for t in tasks.tasks), *init]
    goal = [*(("done", t.name) for t in tasks.tasks), *(("free", a) for a in arms)]
    by_type: dict[str, list[str]] = {"container": [TABLETOP]}
    for obj in plan.scene.objects:
        by_type.setdefault(_TYPE[obj.category], []).append(names[obj.name])
    objects = [f"    {' '.join(arms)} - arm", *(f"    {' '.join(v)} - {t}" for t, v in by_type.items())]
    if tasks.tasks:
        objects.append(f"    {' '.join(t.name for t in tasks.tasks)} - task")
    if gates:
        objects.append(f"    {' '.join(gates)} - gate")
    problem = "\n".join([f"(define (problem {pddl_name(problem_name)})", f"  (:domain {DOMAIN})",
                         "  (:objects", *objects, "  )",
                         "  (:init", *(f"    {_fact(f)}" for f in init), "  )",
                         "  (:goal (and", *(f"    {_fact(f)}" for f in goal), "  ))", ")", ""])
    schemas = tuple(sorted({t.schema for t in tasks.tasks}, key=lambda s: s.name))
    domain = domain_text(schemas, tuple(sorted({verb for verb, _ in tasks.fits})), DOMAIN)
    return PddlExport(domain, problem, tuple(steps), tuple(step_ids), names,
                      {t.name: t.action_id for t in tasks.tasks})


def write_pddl(export: PddlExport, folder: str | Path) -> tuple[Path, Path, Path]:
    """Write ``domain.pddl``, ``problem.pddl`` and ``plan.pddl`` (the steps) into ``folder`` (made if needed)."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths = (out / "domain.pddl", out / "problem.pddl", out / "plan.pddl")
    from wecook_core.files import write_atomic

    for path, text in zip(paths, (export.domain, export.problem, export.plan_text()), strict=True):
        write_atomic(path, text, replace=True, what="PDDL file")
    return paths
