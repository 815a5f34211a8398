"""Runs a plan: both arms concurrently in one simulation, each following its person's actions.

Scheduling. Each agent runs a cooperative program (a generator) over its actions in plan order (a
collaboration is in both agents' lists). Every simulation tick the scheduler advances each program once, then
steps the world; a program yields :data:`WORK` when it commanded motion (or holds on purpose) and :data:`WAIT`
when it is blocked. Before an action starts, every ``after`` action must be done (a plan's ``after`` edges come
from the objects actions share, :func:`wecook_core.plan.object_dependencies`); if one failed or was skipped, the
action is skipped, naming the failure it depends on (and so, transitively, everything depending on it), while
actions that share nothing with the failure go on. ``stop_at_first_failure`` skips everything not yet started
once one action has failed; :data:`FAILURES_IN_A_ROW` failures one after another (none done in between) skip
everything not yet started, so a plan whose actions all fail ends after a few attempts. A collaboration
starts when both agents have arrived at it; the roles then meet through a :class:`Meeting` (named signals, or
a failure that aborts the partner). The world turns an action and a role into primitives (``world.program``).
If every program waits for :data:`DEADLOCK_SECONDS` of simulated time, the waiting actions fail ("deadlock")
instead of hanging; the whole run is bounded by ``max_sim_time`` simulated seconds and by ``timeout`` wall
seconds (:func:`default_timeout` of the plan's size).

How the arms avoid each other (the PyBullet world, :mod:`wecook_core.execution.world`), in three layers: the
first kept by the roles (``world.roles``), the other two by the arms (``world.bullet_arm``, sharing one
``world.traffic.Traffic``):

1. Workspace zones. An action claims the table area around the objects it names (plus the meeting point of a
   handover), grown by a margin, before its first primitive; an action of the other arm whose zone overlaps
   waits until that action ends. Arms working on separate parts of the table run at once; arms that would
   work in the same place take turns. A collaboration's two roles share one zone.
2. Motion reservations. Every motion (planned transit, straight move, actuation) is planned or checked against
   the other arm's current configuration (it is in the planning client) and, before it starts, reserves the
   region it sweeps (AABBs of its links and carried objects along the path, padded). A motion whose region
   overlaps the other arm's active reservation waits until that motion ends, then is re-planned (a straight
   move is re-checked against where the other arm stopped). An arm at rest holds no reservation but is an
   obstacle to every plan, so a motion never enters where the other arm stands or where it is going.
3. Rest and right of way. Between actions an arm folds back over its base (``robot.REST``), leaving the table.
   When the other arm blocks every goal of a primitive, the blocked arm waits for it to come to rest, and the
   other arm, once at rest, waits until the blocked primitive ends.

During the run the world also queries contacts between the two arms every other step and reports any touch
as a failure event (``RunResult.arm_contacts``; a good run has none).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Literal

from wecook_core.execution.schedule.observer import RunEvent, RunObserver
from wecook_core.execution.schedule.program import WORK, ActionFailed, Meeting, Program, World, waiting, waits_for
from wecook_core.plan import Plan, PlanAction

DEADLOCK_SECONDS = 20.0
"""Simulated seconds of every program waiting before the waiting actions fail as deadlocked."""
TIMEOUT_BASE = 60.0
"""Wall seconds of a run's default time limit for starting up, before any action."""
TIMEOUT_PER_ACTION = 30.0
"""Wall seconds per action of a run's default time limit (a run goes at about 2 to 5 s per action)."""
WAIT_REPORTED = 0.5
"""Simulated seconds a wait lasts before it is told as an event (shorter ones, such as a motion letting the other
arm's end, are only counted in the arms' totals)."""
FAILURES_IN_A_ROW = 4
"""Actions failing one after another, none done in between, after which a run stops (the rest skipped): a plan
whose actions all fail ends after this many, not after trying every one (each costs seconds of goal search)."""


def default_timeout(plan: Plan) -> float:
    """The default wall-clock limit of a run of ``plan``: :data:`TIMEOUT_BASE` + :data:`TIMEOUT_PER_ACTION` per
    action."""
    return TIMEOUT_BASE + TIMEOUT_PER_ACTION * len(plan.actions)


@dataclass(frozen=True)
class ActionResult:
    action_id: str
    status: Literal["done", "failed", "skipped"]
    reason: str = ""
    """Why it failed or was skipped; empty when done."""
    agents: tuple[str, ...] = ()
    start: float | None = None
    """Simulated seconds when it started (None if it never did)."""
    end: float | None = None


@dataclass(frozen=True)
class RunResult:
    actions: tuple[ActionResult, ...]
    """One per plan action, in plan order."""
    sim_time: float
    """Simulated seconds."""
    wall_time: float
    """Seconds."""
    seed: int = 0
    arm_contacts: int = 0
    """Times the two arms (or what they carry) were found touching during the run (0 in a good run)."""
    waited: Mapping[str, float] = field(default_factory=dict)
    """Agent -> simulated seconds it waited (for actions, the other arm, a partner)."""

    @property
    def ok(self) -> bool:
        return all(a.status == "done" for a in self.actions) and self.arm_contacts == 0

    def result(self, action_id: str) -> ActionResult:
        return next(a for a in self.actions if a.action_id == action_id)


def run_schedule(plan: Plan, world: World, observer: RunObserver | None = None, *,
                 max_sim_time: float = 1800.0, timeout: float | None = None,
                 stop_at_first_failure: bool = False,
                 failures_in_a_row: int | None = FAILURES_IN_A_ROW,
                 waited: dict[str, float] | None = None) -> tuple[ActionResult, ...]:
    """Run every agent's program to the end; one result per plan action, in plan order. ``timeout``: wall
    seconds after which what is running fails and the rest is skipped (None: no limit); ``failures_in_a_row``:
    that many actions failing one after another (none done in between) skip every action not yet started
    (None: no limit); ``waited``, when given, gets the seconds each agent waited."""
    waited = {} if waited is None else waited
    began = time.perf_counter()
    results: dict[str, ActionResult] = {}
    cause: dict[str, str] = {}
    """Skipped action -> the failed action it depends on."""
    first_failure: list[str] = []
    streak: list[str] = []
    """The actions that failed since the last one done."""
    started: dict[str, float] = {}
    meetings: dict[str, Meeting] = {}
    pids = sorted({a.pid for a in plan.agents} | {pid for a in plan.actions for pid in a.pids})
    by_id = {a.id: a for a in plan.actions}

    def emit(kind: str, action: PlanAction | None, pid: str | None = None, detail: str = "",
             data: Mapping[str, object] | None = None) -> None:
        if observer is not None:
            observer.on_event(world.time, RunEvent(kind, action.id if action else None, None, pid, detail,  # type: ignore[arg-type]
                                                   data or {}))

    def finish(action: PlanAction, status: Literal["done", "failed", "skipped"], reason: str = "") -> None:
        if action.id in results:
            return
        results[action.id] = ActionResult(action.id, status, reason, tuple(action.pids), started.get(action.id),
                                          world.time if action.id in started else None)
        if status == "failed" and not first_failure:
            first_failure.append(action.id)
        if status == "failed":
            streak.append(action.id)
        elif status == "done":
            streak.clear()
        if status == "done":
            world.action_boundary(action, "end")
            emit("action_end", action)
        else:
            if action.id in started:
                world.action_boundary(action, "end")
            emit("action_failed", action, detail=f"{status}: {reason}")
            if observer is not None:
                observer.on_log(world.time, "warning" if status == "skipped" else "error",
                                f"{action.id} ({action.verb}) {status}: {reason}")

    current: dict[str, PlanAction] = {}
    """Agent -> the action it works at or waits for."""
    waits = _Waits(emit, world)

    def agent_program(pid: str) -> Program:
        for action in (a for a in plan.actions if pid in a.pids):
            current[pid] = action
            while action.id not in results:
                blocked = [d for d in action.after if d in results and results[d].status != "done"]
                if blocked:
                    d = blocked[0]
                    root = cause.get(d)
                    if root is not None:
                        cause[action.id] = root
                        why = f"needs {d} ({by_id[d].verb}), which depends on {root} ({by_id[root].verb}), which failed"
                    else:
                        cause[action.id] = d
                        why = f"needs {d} ({by_id[d].verb}), which {results[d].status}"
                    finish(action, "skipped", why)
                    break
                if stop_at_first_failure and first_failure:
                    f = first_failure[0]
                    finish(action, "skipped", f"stopped at the first failure, {f} ({by_id[f].verb})")
                    break
                if failures_in_a_row is not None and len(streak) >= failures_in_a_row:
                    finish(action, "skipped", f"stopped after {len(streak)} actions failed in a row "
                           f"({', '.join(streak[:failures_in_a_row])}): see `wecook plan check`")
                    break
                if all(d in results for d in action.after):
                    break
                d = next(d for d in action.after if d not in results)
                yield waiting(f"{d} ({by_id[d].verb}) to end")
            if action.id in results:
                continue
            meeting = meetings.setdefault(action.id, Meeting(frozenset(action.pids)))
            meeting.arrived.add(pid)
            current[pid] = action
            while not meeting.needed <= meeting.arrived and meeting.failure is None:
                yield waiting(f"the collaboration partner {'+'.join(sorted(meeting.needed - meeting.arrived))} to "
                              f"come to {action.id} ({action.verb})")
            if action.id not in started:
                started[action.id] = world.time
                emit("action_start", action, detail=f"{action.verb} by {'+'.join(action.pids)}")
                world.action_boundary(action, "start")
            failed = meeting.failure is not None
            if not failed:
                try:
                    yield from world.program(action, pid, meeting)
                except ActionFailed as error:
                    meeting.fail(str(error))
                    failed = True
            if failed:
                yield from world.recover(pid)
            meeting.finished.add(pid)
            while not meeting.needed <= meeting.finished:
                yield waiting(f"the collaboration partner {'+'.join(sorted(meeting.needed - meeting.finished))} to "
                              f"finish {action.id} ({action.verb})")
            if meeting.failure is None:
                finish(action, "done")
            else:
                finish(action, "failed", meeting.failure)

    programs: dict[str, Program] = {pid: agent_program(pid) for pid in pids}
    idle = 0.0
    while programs:
        worked = False
        for pid in list(programs):
            try:
                tick = next(programs[pid])
            except StopIteration:
                del programs[pid]
                waits.tick(pid, None, None)
                continue
            worked |= tick == WORK
            waits.tick(pid, None if tick == WORK else waits_for(tick) or "something it does not name",
                       current.get(pid))
        if not programs:
            break
        idle = 0.0 if worked else idle + world.dt
        late = timeout is not None and time.perf_counter() - began > timeout
        if idle > DEADLOCK_SECONDS or world.time > max_sim_time or late:
            why = "deadlock: every arm is waiting" if idle > DEADLOCK_SECONDS else \
                f"the run exceeded its wall-clock limit of {timeout:.0f} s" if late else \
                f"the run exceeded its limit of {max_sim_time:.0f} s simulated"
            for meeting_id, meeting in meetings.items():
                if meeting_id not in results:
                    meeting.fail(why)
            pending = [a for a in plan.actions if a.id not in results and a.id not in meetings]
            for action in pending:
                finish(action, "skipped", why)
            for action in plan.actions:
                if action.id in meetings and action.id not in results:
                    finish(action, "failed", why)
            break
        world.step()
    for pid in pids:
        waits.tick(pid, None, None)
    for action in plan.actions:
        if action.id not in results:
            finish(action, "skipped", "never reached")
    waited.update(waits.total)
    return tuple(results[a.id] for a in plan.actions)


class _Waits:
    """Each arm's waits, told as ``wait`` events: one when a wait has lasted :data:`WAIT_REPORTED` seconds
    ("P2 waits for a3 (cut) to end"), one when it ends (``data``: ``seconds``, ``for``, ``since``); ``total``:
    seconds each arm waited, every wait counted."""

    def __init__(self, emit: Callable[..., None], world: World):
        self.emit = emit
        self.world = world
        self.open: dict[str, tuple[str, float, PlanAction | None, bool]] = {}
        """Agent -> (what it waits for, since, the action, told)."""
        self.total: dict[str, float] = {}

    def tick(self, pid: str, what: str | None, action: PlanAction | None) -> None:
        now = self.world.time
        wait = self.open.get(pid)
        if wait is not None and wait[0] != what:
            self._close(pid, wait, now)
            wait = None
        if what is None:
            return
        if wait is None:
            wait = (what, now, action, False)
            self.open[pid] = wait
        if not wait[3] and now - wait[1] >= WAIT_REPORTED:
            self.emit("wait", wait[2], pid, f"waits for {what}", {"for": what, "since": round(wait[1], 3)})
            self.open[pid] = (*wait[:3], True)

    def _close(self, pid: str, wait: tuple[str, float, PlanAction | None, bool], now: float) -> None:
        del self.open[pid]
        seconds = now - wait[1]
        self.total[pid] = self.total.get(pid, 0.0) + seconds
        if wait[3]:
            self.emit("wait", wait[2], pid, f"waited {seconds:.1f} s for {wait[0]}",
                      {"for": wait[0], "since": round(wait[1], 3), "seconds": round(seconds, 3)})
