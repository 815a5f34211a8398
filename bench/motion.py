"""Motion planning and simulation speed of the executor.

- ``rrtconnect_query``: median wall time of an OMPL RRTConnect query (+ reduceVertices) between random
  collision-free Panda configurations in the demo's scene, the other arm and the objects as obstacles;
  baseline: the pure-Python BiRRT on the same queries.
- ``sim_speed_recording``: simulated seconds per wall second of the demo's plan
  (:func:`wecook_core.workflows.demo_plan`, as ``wecook export demo`` writes it) while recording MCAP (target: at
  least 5); baseline: the same run with an observer that drops everything.
- ``demo_plan_done``: share of the demo plan's actions done over the run seeds :data:`DEMO_SEEDS`.
- ``synthetic_plans_done``: share of the actions done over 10 synthetic two-arm plans
  (:func:`wecook_core.execution.plan_samples.synthetic_plan`, seeds 0-9; every verb, handovers and holdings).
- ``video_plans_done``: share of the actions done over the plans of synthetic videos :data:`VIDEO_SEEDS`, each
  through the whole pipeline (segmentation, recognition, graph, layout), as a user's own video would be.
- ``scenario_plans_done``: share of the actions done over the plans exported from every scenario of the
  independent generator (``../shared/data/scenarios/``, :func:`scenario_plans`), run seed 0.
- ``scenario_variants_done``: share of the actions done over plans of variants of those scenarios, a stand-in for
  held-out ones of the same kind: each scenario's object boxes shifted, each object by its own constant offset
  of up to :data:`VARIANT_SHIFT` of the frame (:data:`VARIANT_DRAWS` draws per scenario), then analysed and laid
  out as a user's own would be, run seed 0.
- ``scenario_sim_speed_recording``: simulated seconds per wall second over those plans while recording MCAP
  (target: at least 10); baseline: the same runs with an observer that drops everything. Every recording is
  checked by ``wecook runs check``, joint limits included (the note counts the steps over a limit).
- ``demo_plan_done_dynamics`` / ``scenario_plans_done_dynamics``: the same shares in the physics mode
  (``execute --dynamics``: position control within the URDF's effort and velocity limits, objects held by
  friction), the demo at run seeds :data:`DYNAMICS_SEEDS`; ratio: against the kinematic mode's share on the same
  runs. ``scenario_sim_speed_dynamics``: its simulated seconds per wall second, recording; ratio against the
  kinematic mode's, recording.
  For the shares the note lists the failures.
- ``all_failing_plan_wall``: wall seconds of a 40-action plan whose actions all fail (the knife out of the arm's
  reach, under its base: every grasp fails after its retries, nothing simulated); baseline: the same plan cut to
  :data:`~wecook_core.execution.schedule.executor.FAILURES_IN_A_ROW` actions (a ratio near 1: the run does not grow with
  the plan; issue 13's bar: nothing over 30 s).

Run: ``.venv/bin/python -m bench.motion``.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.recording import Discard
from bench.standins import SHIFT as VARIANT_SHIFT
from bench.standins import SHIFT_DRAWS as VARIANT_DRAWS
from wecook_core.execution.bullet.planning_scene import PlanningScene
from wecook_core.execution.bullet.robot import HOME, LOWER, UPPER
from wecook_core.execution.plan_samples import synthetic_plan
from wecook_core.execution.planning.motion import MotionProblem, plan_motion
from wecook_core.execution.run import execute_plan
from wecook_core.plan import Plan
from wecook_core.recording.writer import McapRecorder
from wecook_core.workflows import demo_plan

DEMO_SEEDS = tuple(range(20))
"""Run seeds of the demo's plan whose share of actions done is reported."""
VIDEO_SEEDS = tuple(range(10))
"""Synthetic videos (``wecook synth --seed``) whose exported plans are run."""
DYNAMICS_SEEDS = tuple(range(6))
"""Run seeds of the demo's plan run in both modes (the kinematic and the physics one)."""

def planning_queries(n: int = 15) -> tuple[list[float], list[float], int]:
    scene = PlanningScene(demo_plan())  # the demo's table: 16 objects
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
        "note": f"median of {len(ompl_times)} Panda queries in the demo's scene ({solved} solved); baseline "
                f"pure-Python BiRRT {statistics.median(py_times) * 1000:.1f} ms"}]
    plan = demo_plan()
    bare = execute_plan(plan, Discard(), seed=0)
    with tempfile.TemporaryDirectory() as tmp:
        recorder = McapRecorder(Path(tmp) / "run.mcap")
        began = time.perf_counter()
        recorded = execute_plan(plan, recorder, seed=0)
        wall = time.perf_counter() - began
    n = len(plan.actions)
    done = sum(a.status == "done" for a in recorded.actions)
    speed = recorded.sim_time / wall
    rows.append({
        "benchmark": "sim_speed_recording", "value": round(speed, 2), "unit": "sim s / wall s",
        "ratio_vs_baseline": round(speed / (bare.sim_time / bare.wall_time), 3),
        "note": f"the demo's plan ({n} actions), {done}/{n} done, {recorded.sim_time:.1f} sim s in {wall:.1f} "
                f"wall s; baseline without recording {bare.sim_time / bare.wall_time:.2f}x (target >= 5x)"})
    rows.append(_done_share("demo_plan_done", [(plan, seed) for seed in DEMO_SEEDS],
                            f"the demo's plan at run seeds {DEMO_SEEDS[0]}-{DEMO_SEEDS[-1]}"))
    kinematic = _done_share("demo_plan_done", [(plan, seed) for seed in DYNAMICS_SEEDS], "")
    rows.append(_done_share("demo_plan_done_dynamics", [(plan, seed) for seed in DYNAMICS_SEEDS],
                            f"the demo's plan at run seeds {DYNAMICS_SEEDS[0]}-{DYNAMICS_SEEDS[-1]} in the physics "
                            f"mode (kinematic on the same seeds: {kinematic['value']})", dynamics=True,
                            baseline=float(kinematic["value"])))  # type: ignore[arg-type]
    rows.append(_done_share("synthetic_plans_done", [(synthetic_plan(k), 0) for k in range(10)],
                            "10 synthetic plans (seeds 0-9), run seed 0"))
    rows.append(_done_share("video_plans_done", [(_video_plan(k), 0) for k in VIDEO_SEEDS],
                            f"plans of synthetic videos {VIDEO_SEEDS[0]}-{VIDEO_SEEDS[-1]} (analysed, laid out, "
                            "exported as a user would), run seed 0"))
    rows += _scenario_rows()
    rows.append(_done_share("scenario_variants_done", [(plan, 0) for _, plan in scenario_variants()],
                            f"plans of the shared scenarios with shifted object boxes (draws {VARIANT_DRAWS}, up to "
                            f"{VARIANT_SHIFT:.0%} of the frame), run seed 0"))
    rows.append(_all_failing_row())
    return rows


def all_failing_plan(n: int) -> Plan:
    """``n`` cuts by P1 with a knife lying almost under P1's base, where the arm cannot take it."""
    from wecook_core.model import Category
    from wecook_core.plan import DEFAULT_ROBOT, Agent, PlanAction, Scene, SceneObject, Table

    objects = (SceneObject("knife", Category.TOOL, "box", (0.2, 0.03, 0.025), -0.45, 0.2, 1.5708),
               SceneObject("tomato", Category.INGREDIENT, "sphere", (0.06, 0.06, 0.06), 0.15, -0.3, 0.0))
    return Plan(agents=(Agent("P1", DEFAULT_ROBOT, (-0.5, 0.0, 0.0), 0.0),),
                scene=Scene(table=Table(size=(1.0, 0.8)), objects=objects),
                actions=tuple(PlanAction(f"a{k + 1}", ("P1",), "cut", "knife", ("tomato",)) for k in range(n)))


def _all_failing_row() -> dict[str, object]:
    from wecook_core.execution.schedule.executor import FAILURES_IN_A_ROW

    full = execute_plan(all_failing_plan(40), Discard(), seed=0, images=False)
    cut = execute_plan(all_failing_plan(FAILURES_IN_A_ROW), Discard(), seed=0, images=False)
    statuses = {s: sum(a.status == s for a in full.actions) for s in ("done", "failed", "skipped")}
    return {"benchmark": "all_failing_plan_wall", "value": round(full.wall_time, 2), "unit": "s",
            "ratio_vs_baseline": round(full.wall_time / cut.wall_time, 3),
            "note": f"40 failing actions: {statuses}, {full.sim_time:.1f} s simulated; baseline the first "
                    f"{FAILURES_IN_A_ROW} alone {cut.wall_time:.1f} s (bar: nothing over 30 s)"}


def scenario_plans() -> list[tuple[str, Plan]]:
    """(name, plan) of every scenario in ``../shared/data/scenarios/``: its observations imported (CVAT boxes,
    OpenPose hands), analysed with the default parameters and laid out, as ``wecook new``, ``analyze`` and
    ``export`` would."""
    from wecook_core.resources import shared_dir
    from wecook_core.workflows import inputs_plan

    root = shared_dir() / "data" / "scenarios"
    out = []
    for folder in sorted(p for p in root.iterdir() if (p / "objects.xml").is_file()):
        out.append((folder.name, inputs_plan(folder / "video.mp4", folder / "objects.xml", folder / "openpose")))
    return out


def scenario_variants() -> list[tuple[str, Plan]]:
    """(name, plan) of variants of every shared scenario: each object's boxes shifted by its own constant offset,
    up to :data:`VARIANT_SHIFT` of the frame on each axis (draws :data:`VARIANT_DRAWS`), the hands as they are;
    analysed with the default parameters and laid out as :func:`scenario_plans` does (the ``shifted`` class of
    :mod:`bench.standins`)."""
    from bench.standins import standin_plans

    return [(name, plan) for _, name, plan in standin_plans(["shifted"])]


def _recorded(plans: list[tuple[str, Plan]], dynamics: bool) -> dict[str, object]:
    """Each plan run at seed 0, recorded and checked: done, total, failures, sim and wall seconds, arm contacts,
    the recordings failing the check and the recorded steps over a joint limit."""
    from wecook_core.recording.check import check_recording

    out: dict = {"done": 0, "total": 0, "failures": [], "sim": 0.0, "wall": 0.0, "contacts": 0, "bad": [],
                 "over": 0}
    with tempfile.TemporaryDirectory() as tmp:
        for name, plan in plans:
            path = Path(tmp) / f"{name}.mcap"
            recorder = McapRecorder(path)
            began = time.perf_counter()
            result = execute_plan(plan, recorder, seed=0, dynamics=dynamics)
            out["wall"] += time.perf_counter() - began
            out["sim"] += result.sim_time
            out["contacts"] += result.arm_contacts
            out["done"] += sum(a.status == "done" for a in result.actions)
            out["total"] += len(result.actions)
            out["failures"] += [f"{name} {a.action_id} {a.status}: {a.reason[:70]}" for a in result.actions
                                if a.status == "failed"]
            report = check_recording(path)
            out["over"] += sum(" over its limit " in p for p in report.problems)
            if not report.ok:
                out["bad"].append(name)
    return out


def _scenario_rows() -> list[dict[str, object]]:
    plans = scenario_plans()
    bare_sim, bare_wall = 0.0, 0.0
    for _, plan in plans:
        bare = execute_plan(plan, Discard(), seed=0)
        bare_sim += bare.sim_time
        bare_wall += bare.wall_time
    kin = _recorded(plans, dynamics=False)
    dyn = _recorded(plans, dynamics=True)
    done, total, failures, sim, wall = kin["done"], kin["total"], kin["failures"], kin["sim"], kin["wall"]
    contacts, bad = kin["contacts"], kin["bad"]
    names = ", ".join(n for n, _ in plans)
    speed, bare_speed = sim / wall, bare_sim / bare_wall  # type: ignore[operator]
    dyn_share, dyn_speed = dyn["done"] / dyn["total"], dyn["sim"] / dyn["wall"]  # type: ignore[operator]
    return [
        {"benchmark": "scenario_plans_done", "value": round(done / total, 3), "unit": "share of actions",
         "ratio_vs_baseline": round(done / total, 3),
         "note": f"plans of scenarios {names} (imported, analysed, laid out, exported), run seed 0, recorded: "
                 f"{done}/{total} actions done, arm contacts {contacts}, recorded steps over a joint limit "
                 f"{kin['over']}, recordings failing `runs check`: {', '.join(bad) or 'none'}; "  # type: ignore[arg-type]
                 + ("; ".join(failures) if failures else "no failures")},  # type: ignore[arg-type]
        {"benchmark": "scenario_plans_done_dynamics", "value": round(dyn_share, 3), "unit": "share of actions",
         "ratio_vs_baseline": round(dyn_share / (done / total), 3),  # type: ignore[operator]
         "note": f"the same plans in the physics mode (execute --dynamics), recorded: {dyn['done']}/{dyn['total']} "
                 f"done (kinematic {done}/{total}), arm contacts {dyn['contacts']}, recorded steps over a joint "
                 f"limit {dyn['over']}; " + "; ".join(dyn["failures"][:8])},  # type: ignore[index]
        {"benchmark": "scenario_sim_speed_dynamics", "value": round(dyn_speed, 2), "unit": "sim s / wall s",
         "ratio_vs_baseline": round(dyn_speed / speed, 3),
         "note": f"the physics mode recording: {dyn['sim']:.0f} sim s in {dyn['wall']:.0f} wall s; baseline the "
                 f"kinematic mode recording {speed:.2f}x"},
        {"benchmark": "scenario_sim_speed_recording", "value": round(speed, 2), "unit": "sim s / wall s",
         "ratio_vs_baseline": round(speed / bare_speed, 3),
         "note": f"the same runs: {sim:.0f} sim s in {wall:.0f} wall s recording; baseline without recording "
                 f"{bare_speed:.2f}x (target >= 10x with recording)"},
    ]


def _video_plan(seed: int) -> Plan:
    """The plan ``wecook synth``, ``new``, ``analyze`` and ``export`` give for the synthetic video of ``seed``."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.perception.pipeline import analyze
    from wecook_core.plan import plan_from_graph
    from wecook_core.synth import synthesize

    scenario = synthesize(seed)
    return plan_from_graph(analyze(scenario.observations, load_knowledge()).graph, scenario.observations)


def _done_share(name: str, runs: list[tuple[Plan, int]], what: str, dynamics: bool = False,
                baseline: float | None = None) -> dict[str, object]:
    """Share of the actions done over ``runs`` (plan, run seed); the note lists the failures. ``baseline``: the
    share the ratio is against (default: the share itself)."""
    done, total, failures, sim, wall = 0, 0, [], 0.0, 0.0
    for k, (plan, seed) in enumerate(runs):
        result = execute_plan(plan, Discard(), seed=seed, images=False, dynamics=dynamics)
        done += sum(a.status == "done" for a in result.actions)
        total += len(result.actions)
        sim += result.sim_time
        wall += result.wall_time
        failures += [f"run {k} {a.action_id}: {a.reason[:80]}" for a in result.actions if a.status == "failed"]
    return {"benchmark": name, "value": round(done / total, 3), "unit": "share of actions",
            "ratio_vs_baseline": round(done / total / (baseline or 1.0), 3) if baseline != 0 else 0.0,
            "note": f"{what}: {done}/{total} actions done, {sim:.0f} sim s in {wall:.0f} wall s; "
                    + ("; ".join(failures) if failures else "no failures")}


if __name__ == "__main__":
    for row in run():
        print(row)
