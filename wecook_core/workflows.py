"""Exporting a session's plan: analyse the session (with its corrections) and lay the graph out as a plan."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from wecook_core.plan import DEFAULT_ROBOT, DEFAULT_TABLE, Plan, Table, plan_from_graph, validate, write_plan


@dataclass(frozen=True)
class Exported:
    plan: Plan
    path: Path
    """Where the plan was written."""
    warnings: tuple[str, ...] = ()
    """The session's warnings (changed inputs, torn journal lines), to show the user."""


def export_session_plan(session_path: str | Path, out: str | Path | None = None, *,
                        table: Table = DEFAULT_TABLE, robot: str = DEFAULT_ROBOT, force: bool = False) -> Exported:
    """Analyse the session at ``session_path`` and write its plan to ``out`` (default
    ``<session>/plans/plan.yaml``, wecook's own file, replaced whole on every export); ``robot`` is the arms'
    URDF (relative to ``pybullet_data`` unless absolute). Unreadable inputs, an invalid plan, or an ``out`` that
    is a folder or exists (unless ``force``) raise :class:`InputError`."""
    from wecook_core.files import check_output
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.perception.pipeline import analyze
    from wecook_core.session.store import open_session

    replace = force or out is None
    if out is not None:
        check_output(out, replace=replace, what="plan")  # before the analysis, not after
    session = open_session(session_path)
    obs = session.load_observations()
    analysis = analyze(obs, load_knowledge(), session.params, session.corrections)
    plan = plan_from_graph(analysis.graph, obs, table=table, robot=robot)
    path = Path(out) if out is not None else session.plans_dir / "plan.yaml"
    validate(plan, path)
    write_plan(plan, path, replace=replace)
    return Exported(plan, path, tuple(session.warnings))


def demo_plan(table: Table = DEFAULT_TABLE, robot: str = DEFAULT_ROBOT) -> Plan:
    """The plan of the bundled demo (``wecook_core/assets/demo``) as ``wecook export demo`` writes it for a new demo
    session: its observations analysed with the default parameters and no corrections, laid out on ``table``."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.observations.importer import load_observations
    from wecook_core.perception.pipeline import analyze
    from wecook_core.synth import demo_dir

    folder = demo_dir()
    obs = load_observations(folder / "video.mp4", folder / "objects.csv", folder / "hands.csv")
    analysis = analyze(obs, load_knowledge())
    return plan_from_graph(analysis.graph, obs, table=table, robot=robot)
