"""A model of how the paper's ROS platform (icaros-usc/wecook at a293374) takes a TaskMsg, written for the tests
from its C++ sources (independently of the exporter's table in wecook_core/plan/ros_platform.py), so that a
dispatched task can be checked as the platform would run it:

- ``src/wecook/TaskGraph/ActionPlanner.cpp``, ``ActionPlanner::plan``: the verb picks the planner in this order:
  ``== "cut"``, ``== "stir"``, ``== "handover"``, ``== "transfer"``, ``find('_') != npos`` (planHolding),
  ``== "roll"``, ``== "heat"``, ``== "feeding"``; anything else gets no primitive task graph. Each planner's
  primitive nodes per pid, and the fields and objects it reads (``get_ingredients()[0]``, ``get_locations()[1]``:
  unchecked vector indexing; ``ObjectMgr::getObjTransform``: ``m_objects.at``, which throws), are modelled below.
  planHolding's transfer case takes the actor's ``planTransfer`` nodes ``[0]`` to ``[5]`` by index (only the
  third form, with a tool, has six) and handles only ``<object>`` == ``location[1]`` or ``location[0]``.
- ``src/wecook/TaskGraph/TaskGraph.cpp``: ``addNode`` chains each pid's actions in message order; ``merge`` walks
  each pid's chain from its head and dereferences ``getHeadNode(pid)`` of every next action and
  ``getTailNode(pid)`` of the one before it (``m_headMap[pid]``: null when that action has no node of the pid).
- ``src/wecook/World.cpp``, ``setupFollowingTask``: one agent per AgentMsg; ``agents[pid]`` of another pid is null.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any


class Crash(AssertionError):
    """What would crash the platform's node (a throw, an out-of-range read, a null dereference)."""


@dataclass
class Platform:
    objects: set[str]
    agents: set[str]
    reads: list[tuple[str, str]] = field(default_factory=list)
    """(verb, object name) for every object a planner read."""

    def obj(self, verb: str, name: str) -> str:
        if name not in self.objects:
            raise Crash(f"{verb}: getObjTransform({name!r}) throws: not in the scene")
        self.reads.append((verb, name))
        return name

    def agent(self, verb: str, pid: str) -> str:
        if pid not in self.agents:
            raise Crash(f"{verb}: agents[{pid!r}] is null")
        return pid

    @staticmethod
    def at(values: Any, k: int, what: str) -> Any:
        if k >= len(values):
            raise Crash(f"{what}[{k}] read past the end of {list(values)}")
        return values[k]

    # ---------------------------------------------------------------------------------------- the planners

    def plan(self, a: Any) -> dict[str, int]:
        """Primitive nodes per pid of the action's graph ({}: none)."""
        verb = a.verb
        if verb == "cut":
            return self.plan_cut(a, verb)
        if verb == "stir":
            self.obj(verb, a.tool)
            self.obj(verb, self.at(a.location, 0, "location"))
            return {self.at(a.pid, 0, "pid"): 4}
        if verb == "handover":
            self.obj(verb, self.at(a.ingredients, 0, "ingredients"))
            giver, receiver = self.at(a.pid, 0, "pid"), self.at(a.pid, 1, "pid")
            self.agent(verb, giver)
            self.agent(verb, receiver)
            return {giver: 3, receiver: 1}
        if verb == "transfer":
            return self.plan_transfer(a, a.pid[0] if a.pid else "")
        if "_" in verb:
            return self.plan_holding(a)
        if verb in ("roll", "heat"):
            self.obj(verb, a.tool)
            self.obj(verb, self.at(a.ingredients, 0, "ingredients"))
            return {self.at(a.pid, 0, "pid"): 4}
        if verb == "feeding":
            self.obj(verb, a.tool)
            self.obj(verb, self.at(a.ingredients, 0, "ingredients"))
            self.obj(verb, self.at(a.location, 1, "location"))
            return {self.at(a.pid, 0, "pid"): 6}
        return {}

    def plan_cut(self, a: Any, verb: str, pid: str | None = None) -> dict[str, int]:
        self.obj(verb, a.tool)
        self.obj(verb, self.at(a.ingredients, 0, "ingredients"))
        return {pid or self.at(a.pid, 0, "pid"): 4}

    def plan_transfer(self, a: Any, pid: str) -> dict[str, int]:
        if a.tool == "hand":
            self.obj("transfer", self.at(a.ingredients, 0, "ingredients"))
            self.obj("transfer", self.at(a.location, 1, "location"))
            return {pid: 2}
        if a.tool == self.at(a.location, 0, "location"):
            self.obj("transfer", a.location[0])
            self.obj("transfer", self.at(a.location, 1, "location"))
            return {pid: 4}
        self.obj("transfer", a.tool)
        self.obj("transfer", self.at(a.ingredients, 0, "ingredients"))
        self.obj("transfer", self.at(a.location, 1, "location"))
        return {pid: 6}

    def plan_holding(self, a: Any) -> dict[str, int]:
        verb = a.verb
        first, last = verb.index("_"), verb.rindex("_")
        held, inner = verb[first + 1:last], verb[last + 1:]
        holder, actor = self.at(a.pid, 0, "pid"), self.at(a.pid, 1, "pid")
        if inner == "transfer":
            if held not in (self.at(a.location, 1, "location"), self.at(a.location, 0, "location")):
                return {}
            self.obj(verb, held)
            self.agent(verb, holder)
            self.agent(verb, actor)
            nodes = self.plan_transfer(a, actor)[actor]
            if nodes != 6:
                raise Crash(f"{verb}: the actor's planTransfer has {nodes} nodes, planHolding reads [0] to [5]")
            return {holder: 3, actor: 6}
        if inner == "cut":
            self.obj(verb, held)
            self.agent(verb, holder)
            return {holder: 2, **self.plan_cut(a, verb, actor)}
        return {}

    # ---------------------------------------------------------------------------------------- the task

    def run(self, task: Any) -> list[dict[str, int]]:
        """Plan every action and merge the chains as the platform does; the nodes per pid of each action."""
        graphs = [self.plan(a) for a in task.actions]
        chains: dict[str, list[int]] = {}
        for k, a in enumerate(task.actions):
            for pid in a.pid:
                chains.setdefault(pid, []).append(k)
        for pid, chain in chains.items():
            for last, current in itertools.pairwise(chain):
                for k in (last, current):
                    if not graphs[k].get(pid):
                        raise Crash(f"TaskGraph::merge: action {k} ({task.actions[k].verb}) has no primitive node "
                                    f"of {pid} in {pid}'s chain")
        return graphs
