"""Motion planning and simulation speed of the executor.

- ``rrtconnect_query``: median wall time of an OMPL RRTConnect query (+ reduceVertices) between random
  collision-free Panda configurations in the demo-sized scene, the other arm and the objects as obstacles;
  baseline: the pure-Python BiRRT on the same queries.
- ``sim_speed_recording``: simulated seconds per wall second of a 10-action two-arm plan while recording MCAP
  (target: at least 5); baseline: the same run with an observer that drops everything.
- ``synthetic_plans_done``: share of the actions done over 10 synthetic two-arm plans
  (:func:`wecook_core.execution.plan_samples.synthetic_plan`, seeds 0-9; every verb, handovers and holdings);
  baseline: the number of actions; the note lists the failures.

Run: ``.venv/bin/python -m bench.motion``.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from wecook_core.execution.executor import execute_plan
from wecook_core.execution.motion import MotionProblem, plan_motion
from wecook_core.execution.plan_samples import synthetic_plan
from wecook_core.execution.planning_scene import PlanningScene
from wecook_core.execution.robot import HOME, LOWER, UPPER
from wecook_core.model import Category
from wecook_core.plan import Plan, PlanAction, Scene, SceneObject, agents_for

OBJECTS = (
    SceneObject("knife", Category.TOOL, "box", (0.2, 0.03, 0.025), -0.1, 0.18),
    SceneObject("chopping_board", Category.CONTAINER, "box", (0.26, 0.18, 0.02), -0.05, -0.05),
    SceneObject("tomato", Category.INGREDIENT, "sphere", (0.05, 0.05, 0.05), -0.05, -0.05),
    SceneObject("bowl", Category.CONTAINER, "cylinder", (0.16, 0.16, 0.07), 0.12, 0.12),
    SceneObject("spoon", Category.TOOL, "box", (0.18, 0.03, 0.02), 0.12, -0.22),
    SceneObject("lemon", Category.INGREDIENT, "sphere", (0.05, 0.05, 0.05), 0.14, -0.06),
)


def demo_plan() -> Plan:
    actions = (
        PlanAction("a1", ("P1",), "cut", "knife", ("tomato",), "chopping_board"),
        PlanAction("a2", ("P2",), "stir", "spoon", (), "bowl"),
        PlanAction("a3", ("P2", "P1"), "handover", "lemon", after=("a1", "a2")),
        PlanAction("a4", ("P1",), "squeeze", None, ("lemon",), "bowl", after=("a3",)),
        PlanAction("a5", ("P2",), "stir", "spoon", (), "bowl", after=("a3",)),
        PlanAction("a6", ("P1",), "cut", "knife", ("tomato",), "chopping_board", after=("a4",)),
        PlanAction("a7", ("P1", "P2"), "handover", "knife", after=("a6", "a5")),
        PlanAction("a8", ("P2",), "cut", "knife", ("tomato",), "chopping_board", after=("a7",)),
        PlanAction("a9", ("P1",), "dip", "spoon", (), "bowl", after=("a7",)),
        PlanAction("a10", ("P2",), "peel", "knife", ("tomato",), "chopping_board", after=("a8",)),
    )
    scene = Scene(objects=OBJECTS, containing=(("tomato", "chopping_board"),))
    return Plan(agents=agents_for(["P1", "P2"]), scene=scene,
                actions=actions)


class Discard:
    def on_start(self, *args: object) -> None: ...
    def on_state(self, *args: object) -> None: ...
    def on_event(self, *args: object) -> None: ...
    def on_log(self, *args: object) -> None: ...
    def on_image(self, *args: object) -> None: ...
    def on_end(self, *args: object) -> None: ...


def planning_queries(n: int = 15) -> tuple[list[float], list[float], int]:
    scene = PlanningScene(demo_plan())
    try:
        rng = np.random.default_rng(0)
        collides = scene.collision_fn("P1")
        configs = []
        while len(configs) < 2 * n:
            q = np.clip(HOME + rng.normal(0, 0.8, 7), LOWER, UPPER)
            if not collides(q):
                configs.append(q)
        ompl_times, py_times, solved = [], [], 0
        for k in range(n):
            problem = MotionProblem(configs[2 * k], configs[2 * k + 1], LOWER, UPPER, collides, resolution=0.03)
            a = plan_motion(problem, planner="rrtconnect", time_limit=2.0, seed=k)
            b = plan_motion(problem, planner="birrt", time_limit=2.0, seed=k)
            solved += a.ok
            ompl_times.append(a.seconds)
            py_times.append(b.seconds)
        return ompl_times, py_times, solved
    finally:
        scene.close()


def run() -> list[dict[str, object]]:
    ompl_times, py_times, solved = planning_queries()
    rows: list[dict[str, object]] = [{
        "benchmark": "rrtconnect_query", "value": round(statistics.median(ompl_times) * 1000, 2), "unit": "ms",
        "ratio_vs_baseline": round(statistics.median(ompl_times) / statistics.median(py_times), 3),
        "note": f"median of {len(ompl_times)} Panda queries ({solved} solved); baseline pure-Python BiRRT "
                f"{statistics.median(py_times) * 1000:.1f} ms"}]
    plan = demo_plan()
    from wecook_core.execution.recorder import McapRecorder

    bare = execute_plan(plan, Discard(), seed=0)
    with tempfile.TemporaryDirectory() as tmp:
        recorder = McapRecorder(Path(tmp) / "run.mcap")
        began = time.perf_counter()
        recorded = execute_plan(plan, recorder, seed=0)
        wall = time.perf_counter() - began
    done = sum(a.status == "done" for a in recorded.actions)
    speed = recorded.sim_time / wall
    rows.append({
        "benchmark": "sim_speed_recording", "value": round(speed, 2), "unit": "sim s / wall s",
        "ratio_vs_baseline": round(speed / (bare.sim_time / bare.wall_time), 3),
        "note": f"10-action plan, {done}/10 done, {recorded.sim_time:.1f} sim s in {wall:.1f} wall s; "
                f"baseline without recording {bare.sim_time / bare.wall_time:.2f}x (target >= 5x)"})
    done_total, total, failures, sim, wall = 0, 0, [], 0.0, 0.0
    for seed in range(10):
        result = execute_plan(synthetic_plan(seed), Discard(), seed=0, images=False)
        done_total += sum(a.status == "done" for a in result.actions)
        total += len(result.actions)
        sim += result.sim_time
        wall += result.wall_time
        failures += [f"plan {seed} {a.action_id}: {a.reason[:80]}" for a in result.actions if a.status == "failed"]
    rows.append({
        "benchmark": "synthetic_plans_done", "value": round(done_total / total, 3), "unit": "share of actions",
        "ratio_vs_baseline": round(done_total / total, 3),
        "note": f"{done_total}/{total} actions done, {sim:.0f} sim s in {wall:.0f} wall s; "
                + ("; ".join(failures) if failures else "no failures")})
    return rows


if __name__ == "__main__":
    for row in run():
        print(row)
