"""Exporting a session's plan: analyse the session (with its corrections) and lay the graph out as a plan."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from wecook_core.perception.pipeline import Analysis
from wecook_core.plan import DEFAULT_ROBOT, DEFAULT_TABLE, Plan, Table, plan_from_graph, validate, write_plan


@dataclass(frozen=True)
class Exported:
    plan: Plan
    path: Path
    """Where the plan was written."""
    warnings: tuple[str, ...] = ()
    """The session's warnings (changed inputs, torn journal lines), to show the user."""


@dataclass(frozen=True)
class Analysed:
    analysis: Analysis
    trees_path: Path
    graph_path: Path


def analyze_session(session_path: str | Path) -> Analysed:
    """Analyse the session at ``session_path`` with its corrections; write its trees and graph."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.perception.pipeline import analyze
    from wecook_core.session.store import open_session
    from wecook_core.trees.graph import write_graph_file
    from wecook_core.trees.treefile import write_tree_file

    session = open_session(session_path)
    analysis = analyze(session.load_observations(), load_knowledge(), session.params, session.corrections)
    write_tree_file(session.trees_path, analysis.trees)
    write_graph_file(session.graph_path, analysis.graph)
    return Analysed(analysis, session.trees_path, session.graph_path)


def session_plan(session_path: str | Path, *, table: Table = DEFAULT_TABLE,
                 robot: str = DEFAULT_ROBOT) -> tuple[Plan, Path, tuple[str, ...]]:
    """The plan of the session at ``session_path``, analysed with its corrections (not validated), its
    ``plans/`` folder and its warnings. Unreadable inputs raise :class:`InputError`."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.perception.pipeline import analyze
    from wecook_core.session.store import open_session

    session = open_session(session_path)
    obs = session.load_observations()
    analysis = analyze(obs, load_knowledge(), session.params, session.corrections)
    plan = plan_from_graph(analysis.graph, obs, table=table, robot=robot)
    return plan, session.plans_dir, tuple(session.warnings)


def export_session_plan(session_path: str | Path, out: str | Path | None = None, *,
                        table: Table = DEFAULT_TABLE, robot: str = DEFAULT_ROBOT, force: bool = False) -> Exported:
    """Analyse the session at ``session_path`` and write its plan to ``out`` (default
    ``<session>/plans/plan.yaml``, wecook's own file, replaced whole on every export); ``robot`` is the arms'
    URDF (relative to ``pybullet_data`` unless absolute). Unreadable inputs, an invalid plan, or an ``out`` that
    is a folder or exists (unless ``force``) raise :class:`InputError`."""
    from wecook_core.files import check_output

    replace = force or out is None
    if out is not None:
        check_output(out, replace=replace, what="plan")  # before the analysis, not after
    plan, plans_dir, warnings = session_plan(session_path, table=table, robot=robot)
    path = Path(out) if out is not None else plans_dir / "plan.yaml"
    validate(plan, path)
    write_plan(plan, path, replace=replace)
    return Exported(plan, path, warnings)


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
