"""A plan acted out: the scheduler (:mod:`.schedule`) over the PyBullet world (:mod:`.bullet`), reported to an
observer (a recorder of :mod:`wecook_core.recording`, a progress display, or both)."""

from __future__ import annotations

import time
from collections.abc import Mapping

import yaml

from wecook_core.execution.bullet.world import BulletWorld
from wecook_core.execution.schedule.executor import FAILURES_IN_A_ROW, RunResult, default_timeout, run_schedule
from wecook_core.execution.schedule.observer import RunEvent, RunObserver
from wecook_core.plan import Plan, plan_to_dict


def execute_plan(plan: Plan, observer: RunObserver, *, seed: int = 0, realtime: bool = False,
                 planner: str = "rrtconnect", planning_time: float = 1.0, images: bool = True,
                 metadata: Mapping[str, str] | None = None, timeout: float | None = None,
                 stop_at_first_failure: bool = False, failures_in_a_row: int | None = FAILURES_IN_A_ROW,
                 dynamics: bool = False) -> RunResult:
    """Execute ``plan`` in PyBullet (DIRECT, headless) with two Panda arms; report through ``observer``. The
    world (:class:`~wecook_core.execution.bullet.world.BulletWorld`) is a scene, an arm per person, the primitives over
    them and the roles calling those.

    The same plan and seed give the same run. ``realtime`` paces the simulation to the wall clock.
    ``planning_time`` bounds every motion-planning query (seconds). ``images``: camera images at action
    boundaries (``observer.on_image``). The observer sees ``on_start`` first and ``on_end`` last. ``timeout``:
    wall seconds for the whole run (default :func:`default_timeout`); ``stop_at_first_failure``: skip every
    action not yet started once one has failed (else only those depending on it, see :func:`run_schedule`);
    ``failures_in_a_row``: stop after that many actions failed one after another (None: never).
    ``dynamics``: the physics mode (:class:`~wecook_core.execution.bullet.scene.BulletScene`): joints driven by
    position control within the URDF's effort and velocity limits, objects held by friction; else kinematic.
    """
    began = time.perf_counter()
    world = BulletWorld(plan, observer, seed=seed, realtime=realtime, planner=planner,
                        planning_time=planning_time, images=images, dynamics=dynamics)
    try:
        meta = {"seed": str(seed), "planner": planner, "mode": "dynamics" if dynamics else "kinematic",
                **(metadata or {})}
        observer.on_start(world.frames(), yaml.safe_dump(plan_to_dict(plan), sort_keys=False), seed, meta)
        world.publish_state()
        limit = default_timeout(plan) if timeout is None else timeout
        waited: dict[str, float] = {}
        results = run_schedule(plan, world, observer, timeout=max(limit - (time.perf_counter() - began), 1.0),
                               stop_at_first_failure=stop_at_first_failure, failures_in_a_row=failures_in_a_row,
                               waited=waited)
        done = sum(r.status == "done" for r in results)
        waits = {pid: round(s, 3) for pid, s in sorted(waited.items())}
        observer.on_event(world.time, RunEvent("run_end", detail=f"{done}/{len(results)} actions done",
                                               data={"done": done, "total": len(results),
                                                     "arm_contacts": world.arm_contacts, "waited_s": waits}))
        observer.on_end(world.time)
        return RunResult(results, world.time, time.perf_counter() - began, seed, world.arm_contacts, waits)
    finally:
        world.close()
