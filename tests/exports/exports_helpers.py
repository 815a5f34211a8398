"""Running exported plans off their platforms: a dispatch script against stand-ins of ``rospy`` and ``wecook.msg``
(``stand_in/``, put on sys.path), and a PDDL plan's steps on the domain and problem the ``pddl`` library parsed."""

from __future__ import annotations

import ast
import builtins
import importlib
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from platform_model import Platform

from wecook_core.plan import Plan
from wecook_core.plan.ros import RosExport

STAND_IN = Path(__file__).parent / "stand_in"


@dataclass
class Dispatched:
    rospy: ModuleType
    msg: ModuleType
    imported: list[str]
    """Every module the script imported (``import x`` -> ``x``, ``from x.y import z`` -> ``x.y``), in order."""

    @property
    def task(self) -> Any:
        assert len(self.rospy.published) == 1, self.rospy.published
        topic, message = self.rospy.published[0]
        assert topic == "WeCookDispatch"
        return message


def run_dispatch(script: str, monkeypatch: pytest.MonkeyPatch, connect_after: int = 0) -> Dispatched:
    """Execute ``script`` as ``__main__`` with the stand-ins on sys.path, recording what it imports; the
    platform's subscriber connects after ``connect_after`` polls."""
    for name in ("rospy", "wecook", "wecook.msg"):
        monkeypatch.delitem(sys.modules, name, raising=False)
    monkeypatch.syspath_prepend(str(STAND_IN))
    rospy = importlib.import_module("rospy")
    msg = importlib.import_module("wecook.msg")
    assert Path(rospy.__file__).parent == STAND_IN and Path(msg.__file__).parent == STAND_IN / "wecook"
    rospy.connect_after = connect_after
    imported: list[str] = []
    real_import = builtins.__import__

    def recording_import(name: str, globals: Any = None, locals: Any = None, fromlist: Any = (),
                         level: int = 0) -> Any:
        imported.append(name)
        return real_import(name, globals, locals, fromlist, level)

    scope = {"__name__": "__main__", "__builtins__": {**vars(builtins), "__import__": recording_import}}
    exec(compile(script, "dispatch.py", "exec"), scope)
    return Dispatched(rospy, msg, imported)


def script_imports(script: str) -> set[str]:
    """Modules the script's import statements name (anywhere in it)."""
    out: set[str] = set()
    for node in ast.walk(ast.parse(script)):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            out.add("." * node.level + (node.module or ""))
    return out


def check_message(msg: ModuleType, message: Any, where: str = "TaskMsg") -> int:
    """Assert that ``message`` and every message in it has exactly its definition's fields, each of its type;
    returns how many messages were checked."""
    kind = type(message).__name__
    fields = msg.fields_of(kind)
    assert type(message) is getattr(msg, kind), where
    assert set(vars(message)) == {f for f, _ in fields}, (where, sorted(vars(message)))
    count = 1
    for field, ros_type in fields:
        value = getattr(message, field)
        msg.check_value(ros_type, value, f"{where}.{field}")
        base = ros_type.removesuffix("[]")
        if base in msg.DEFINITIONS:
            items = value if ros_type.endswith("[]") else [value]
            for k, item in enumerate(items):
                count += check_message(msg, item, f"{where}.{field}[{k}]")
    return count


def platform_checks(plan: Plan, export: RosExport, task: Any) -> Platform:
    """The bar: the platform plans every dispatched action for every pid it names, and merges the chains; every
    object a planner reads is in the scene; every plan object is in the scene; each plan action is dispatched
    or reported left out."""
    scene = {o.name for o in task.scene.objects}
    platform = Platform(scene, {a.pid for a in task.agents})
    graphs = platform.run(task)
    for action, graph in zip(task.actions, graphs, strict=True):
        assert graph and all(graph.get(pid) for pid in action.pid), (action.verb, graph)
        named = {action.tool, *action.location, *action.ingredients} - {"hand", "air"}
        assert named <= scene, (action.verb, named - scene)
    assert {export.names[o.name] for o in plan.scene.objects} <= scene
    assert not export.missing
    assert sorted(export.dispatched + tuple(export.left_out)) == sorted(a.id for a in plan.actions)
    return platform


# ------------------------------------------------------------------------------------------------ PDDL


def _atoms(formula: Any) -> tuple[list[tuple[str, ...]], list[tuple[str, ...]]]:
    """(positive, negative) atoms of a conjunction of literals, as (predicate, term names...)."""
    from pddl.logic.base import And, Not
    from pddl.logic.predicates import Predicate

    if isinstance(formula, And):
        pos: list[tuple[str, ...]] = []
        neg: list[tuple[str, ...]] = []
        for operand in formula.operands:
            p, n = _atoms(operand)
            pos += p
            neg += n
        return pos, neg
    if isinstance(formula, Not):
        p, n = _atoms(formula.argument)
        return n, p
    assert isinstance(formula, Predicate), f"not a literal: {formula!r}"
    return [(str(formula.name), *(str(t.name) for t in formula.terms))], []


def _ground(atoms: list[tuple[str, ...]], binding: dict[str, str]) -> list[tuple[str, ...]]:
    return [(atom[0], *(binding.get(t, t) for t in atom[1:])) for atom in atoms]


def simulate(domain_file: Path, problem_file: Path, steps: list[tuple[str, ...]]) -> set[tuple[str, ...]]:
    """Parse domain and problem with ``pddl``, run ``steps`` from the initial state (asserting each step's
    action exists, its arguments are objects of the parameters' types and its precondition holds) and assert
    the goal holds at the end; returns the final state."""
    from pddl import parse_domain, parse_problem

    domain = parse_domain(domain_file)
    problem = parse_problem(problem_file)
    assert problem.domain_name == domain.name
    actions = {str(a.name): a for a in domain.actions}
    parents = {str(k): str(v) for k, v in domain.types.items() if v is not None}
    types = {str(o.name): {str(t) for t in o.type_tags} for o in (*problem.objects, *domain.constants)}

    def is_a(obj: str, wanted: str) -> bool:
        todo = list(types[obj])
        while todo:
            t = todo.pop()
            if t == wanted:
                return True
            if t in parents:
                todo.append(parents[t])
        return wanted == "object"

    state = {atom for fact in problem.init for atom in _atoms(fact)[0]}
    for k, (name, *args) in enumerate(steps):
        action = actions[name]
        assert len(action.parameters) == len(args), (k, name, args)
        binding = {}
        for param, arg in zip(action.parameters, args, strict=True):
            assert arg in types, f"step {k} {name}: {arg} is not an object"
            assert all(is_a(arg, str(t)) for t in param.type_tags), (k, name, arg, param.type_tags)
            binding[str(param.name)] = arg
        pos, neg = (_ground(atoms, binding) for atoms in _atoms(action.precondition))
        missing = [a for a in pos if a not in state] + [a for a in neg if a in state]
        assert not missing, f"step {k} ({name} {' '.join(args)}): precondition fails on {missing}"
        add, delete = (_ground(atoms, binding) for atoms in _atoms(action.effect))
        state = (state - set(delete)) | set(add)
    pos, neg = _atoms(problem.goal)
    assert not [g for g in pos if g not in state] and not [g for g in neg if g in state], (pos, state)
    return state


# ------------------------------------------------------------------------------------------------ a planner

HELD = ("pour", "sprinkle", "dip")
Key = tuple[object, ...]


def solve(domain_file: Path, problem_file: Path) -> list[tuple[str, ...]]:
    """pyperplan's plan (greedy best-first search with hFF, as on its command line's defaults for GBF), as
    ``(action, arg, ...)`` steps; asserts that it finds one."""
    from pyperplan.heuristics.relaxation import hFFHeuristic
    from pyperplan.planner import search_plan
    from pyperplan.search import greedy_best_first_search

    solution = search_plan(str(domain_file), str(problem_file), greedy_best_first_search, hFFHeuristic)
    assert solution is not None, f"pyperplan found no plan for {problem_file}"
    return [tuple(op.name.strip("()").split()) for op in solution]


def plan_work(plan: Plan, names: dict[str, str]) -> list[tuple[str, list[Key]]]:
    """What wecook's plan has each person do, per action (in an order that keeps ``after``): (action id, keys), a
    key ``(person, verb, tool or None, what it acts on, holder or None)`` in PDDL names; a handover is
    ``(person, 'handover', thing)`` for giver and receiver, a hold ``(holder, 'holding', thing)``."""
    from wecook_core.plan.pddl import TABLETOP, ordered

    def n(name: str | None) -> str:
        return names[name] if name is not None else TABLETOP

    def act_keys(pid: str, act: Any, holder: str | None = None, held: str | None = None) -> list[Key]:
        hand = act.tool is None or act.tool in act.ingredients or act.tool == held
        tool = None if hand else names[act.tool]
        if act.verb == "transfer":
            return [(names[pid], "transfer", tool, (names[i], n(act.location)), holder) for i in act.ingredients]
        if act.verb in HELD and tool is not None:
            return [(names[pid], act.verb, tool, n(act.location), holder)]
        targets = list(act.ingredients) or ([act.location] if act.location else []) or [act.tool]
        return [(names[pid], act.verb, tool, names[t], holder) for t in targets]

    out = []
    for a in ordered(plan.actions):
        if a.verb == "handover":
            keys: list[Key] = [(names[p], "handover", names[a.tool]) for p in a.pids]
        elif a.verb == "holding":
            h = names[a.pids[0]]
            keys = [(h, "holding", names[a.tool]), *act_keys(a.pids[-1], a.partner, h, a.tool)]
        else:
            keys = act_keys(a.pids[0], a)
        out.append((a.id, keys))
    return out


def step_work(domain_file: Path, steps: list[tuple[str, ...]]) -> list[list[Key]]:
    """The keys (as :func:`plan_work`'s) of each step, read by the domain's parameter roles (``?a`` acts, ``?t`` is
    held to act, ``?x`` is acted on, ``?to`` where a transfer puts it, ``?h`` holds ``?held``, ``?r`` receives)."""
    from pddl import parse_domain

    params = {str(a.name): [f"?{p.name}" for p in a.parameters] for a in parse_domain(domain_file).actions}
    out = []
    for name, *args in steps:
        b = dict(zip(params[name], args, strict=True))
        verb = name.removesuffix("-held").split("-")[0]
        if verb in ("grasp", "release", "pass", "start"):
            out.append([])
        elif verb == "handover":
            out.append([(b["?a"], "handover", b["?x"]), (b["?r"], "handover", b["?x"])])
        else:
            target = (b["?x"], b["?to"]) if verb == "transfer" else b["?x"]
            keys: list[Key] = [(b["?a"], verb, b.get("?t"), target, b.get("?h"))]
            if "?h" in b:
                keys.append((b["?h"], "holding", b["?held"]))
            out.append(keys)
    return out


def check_same_work(plan: Plan, names: dict[str, str], domain_file: Path, steps: list[tuple[str, ...]]) -> None:
    """Assert that ``steps`` give each person the same verbs with the same tools on the same things as wecook's
    plan, and that every action's steps come after those of the actions it waits for."""
    from collections import Counter

    wanted = plan_work(plan, names)
    got = step_work(domain_file, steps)
    assert Counter(k for _, keys in wanted for k in keys) == Counter(k for keys in got for k in keys)
    owners: dict[Key, list[str]] = {}
    for action_id, keys in wanted:
        for key in keys:
            owners.setdefault(key, []).append(action_id)
    where: dict[str, list[int]] = {}
    for index, keys in enumerate(got):
        for key in keys:
            where.setdefault(owners[key].pop(0), []).append(index)
    for a in plan.actions:
        for before in a.after:
            if before in where and a.id in where:
                assert max(where[before]) < min(where[a.id]), f"{a.id} done before {before}, which it waits for"
