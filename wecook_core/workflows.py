"""The use cases, each written once: analyse a session, export its plan, the demo.

The command line (``wecook analyze``, ``export``, ``demo``) and the workbench all call these, so the segments a
person reviews are the ones exported: GGS always runs with :func:`segmentation_params` (``k_max`` raised to
the video's length), and the journal's corrections are folded against the segmentation they apply to (span
corrections cover every segment of their action).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from wecook_core.errors import InputError
from wecook_core.plan import DEFAULT_ROBOT, DEFAULT_TABLE, Plan, Table, plan_from_graph, validate, write_plan

if TYPE_CHECKING:
    from wecook_core.knowledge.categories import CategoryTable
    from wecook_core.knowledge.recognize import Knowledge
    from wecook_core.model import Observations, Scores, Segmentation
    from wecook_core.perception.params import Params
    from wecook_core.perception.pipeline import Analysis
    from wecook_core.session.corrections import Correction
    from wecook_core.session.store import Session


# ------------------------------------------------------------------------------------------ analysis


def segment(obs: Observations, params: Params) -> Segmentation:
    """GGS's own segmentation of ``obs`` (before any split or merge), as every path computes it."""
    from wecook_core.perception.pipeline import segmentation_params
    from wecook_core.perception.segmentation import segment_hands

    return segment_hands(obs, segmentation_params(obs, params))


def analyse(obs: Observations, knowledge: Knowledge, params: Params, corrections: Sequence[Correction] = (), *,
            segmentation: Segmentation | None = None, shots: Sequence[int] = (),
            categories: CategoryTable | None = None) -> Analysis:
    """Every stage with the typed ``corrections`` applied: the boxes drawn in the box mode join the observations
    and the categories the user gave apply (:func:`wecook_core.session.boxes.with_drawn`, drawn labels
    categorised with ``categories``, default the shipped table), splits and merges cut GGS's segmentation
    (``segmentation``, computed by :func:`segment` when not given; corrections never change it, nor do boxes:
    GGS reads the hands), then the other corrections are folded against the final segments
    (:func:`~wecook_core.perception.pipeline.final_segments`: every cut, shot cuts and unseen holds' edges included)."""
    from wecook_core.perception.pipeline import analyze, final_segments, repaired
    from wecook_core.session.boxes import with_drawn
    from wecook_core.session.corrections import fold

    obs = with_drawn(obs, corrections, categories).observations
    if segmentation is None:
        segmentation = segment(obs, params)
    repairs = repaired(obs, params, shots)
    cut = final_segments(segmentation, repairs.shots, repairs.unseen, params, obs.video.fps, fold(corrections))
    folded = fold(corrections, cut.segments)
    return analyze(obs, knowledge, params, folded, segmentation=segmentation, repairs=repairs)


@dataclass
class Review:
    """A session opened for review: what the workbench holds (observations None when they cannot be read)."""

    session: Session
    observations: Observations | None
    knowledge: Knowledge | None
    warnings: list[str] = field(default_factory=list)
    video_problem: str | None = None
    """What is wrong with the video when the boxes and hands are shown against the recorded facts."""
    segmentation: Segmentation | None = None
    """GGS's segmentation, computed by the first analysis and reused by the next ones."""
    shots: tuple[int, ...] | None = None
    """The video's shot cuts, found (or read from the session's cache) by the first analysis and reused."""

    def analyse(self, corrections: Sequence[Correction] | None = None) -> Analysis:
        """The analysis with ``corrections`` (default: the journal's, in effect now)."""
        from wecook_core.knowledge.recognize import load_knowledge

        if self.observations is None:
            raise InputError(self.session.path, "the session's inputs cannot be read")
        if self.segmentation is None:
            self.segmentation = segment(self.observations, self.session.params)
        knowledge = self.knowledge if self.knowledge is not None else load_knowledge()
        applied = self.session.applied_corrections if corrections is None else corrections
        if self.shots is None:
            self.shots = cached_shot_cuts(self.session.path, self.observations.video.path)
        return analyse(self.observations, knowledge, self.session.params, applied, segmentation=self.segmentation,
                       shots=self.shots, categories=self.session.category_table())


def open_review(path: str | Path) -> Review:
    """Open the session for review. Never fails on bad inputs (they are warnings): a video that does not open
    gives the boxes and hands against its recorded facts; only a folder that is not a session is an InputError."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.session.store import open_session

    session = open_session(path, lock=True)  # one writer per session, held while it is open
    review = Review(session, None, None, [str(w) for w in session.warnings])
    try:
        imported = session.import_observations(video_optional=True)
        review.observations = imported.observations
        if imported.video_problem:
            review.video_problem = imported.video_problem
            review.warnings.append(f"{imported.video_problem}: boxes and hands shown against the video facts "
                                   "recorded in the session")
    except (InputError, OSError) as error:
        review.warnings.append(f"inputs cannot be read: {error}")
    try:
        review.knowledge = load_knowledge()
    except InputError as error:
        review.warnings.append(f"commonsense tables cannot be read ({error}); action picker unranked")
    return review


def write_results(session: Session, analysis: Analysis) -> None:
    """Write the analysis' ``trees.yaml`` and ``graph.yaml`` into the session."""
    from wecook_core.trees.graph import write_graph_file
    from wecook_core.trees.treefile import write_tree_file

    write_tree_file(session.trees_path, analysis.trees)
    write_graph_file(session.graph_path, analysis.graph)


SHOTS_FILE = "shots.json"
"""The session's cache of its video's shot cuts (finding them decodes the whole video)."""


def cached_shot_cuts(session: str | Path, video: str) -> tuple[int, ...]:
    """The video's shot cuts, from ``session/shots.json`` when it was made from this very file (path, size
    and modification time) by this version of the detection (``shots.DETECTOR``), else found
    (:func:`wecook_core.perception.segmentation.shots.shot_cuts`) and written there.
    A video that cannot be read has none."""
    import contextlib
    import json

    from wecook_core.perception.segmentation.shots import DETECTOR, shot_cuts

    source = Path(video)
    if not source.is_file():
        return ()
    stat = source.stat()
    key = {"video": str(source.resolve()), "size": stat.st_size, "mtime_ns": stat.st_mtime_ns, "detector": DETECTOR}
    cache = Path(session) / SHOTS_FILE
    try:
        data = json.loads(cache.read_text(encoding="utf-8"))
        if {k: data.get(k) for k in key} == key and isinstance(data.get("cuts"), list):
            return tuple(int(c) for c in data["cuts"])
    except (OSError, ValueError, TypeError):
        pass
    cuts = shot_cuts(source)
    from wecook_core.files import write_atomic

    with contextlib.suppress(OSError, InputError):  # a read-only session still analyses
        write_atomic(cache, json.dumps({**key, "cuts": list(cuts)}) + "\n", replace=True, what="shot cache")
    return cuts


@dataclass(frozen=True)
class Analysed:
    """A session analysed by :func:`analyse_session`."""

    session: Session
    observations: Observations
    """The imported observations with the boxes drawn in the box mode (what the plan is laid out from)."""
    analysis: Analysis


def analyse_session(path: str | Path, knowledge: Knowledge | None = None, *, write: bool = True) -> Analysed:
    """Open the session at ``path``, import its inputs, analyse them with its corrections and (``write``) write
    its trees and graph. Unreadable inputs raise :class:`InputError`."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.session.boxes import with_drawn
    from wecook_core.session.store import open_session

    session = open_session(path)
    if write:  # a trees.yaml that cannot be written is said before the analysis
        from wecook_core.files import check_output, check_writable

        check_output(session.trees_path, replace=True, what="tree file")
        check_output(session.graph_path, replace=True, what="graph file")
        check_writable(session.path, "session folder")
    obs = session.load_observations()
    corrections, table = session.applied_corrections, session.category_table()
    analysis = analyse(obs, knowledge if knowledge is not None else load_knowledge(), session.params,
                       corrections, shots=cached_shot_cuts(session.path, obs.video.path), categories=table)
    if write:
        write_results(session, analysis)
    return Analysed(session, with_drawn(obs, corrections, table).observations, analysis)


# ---------------------------------------------------------------------------------------------- plans


@dataclass(frozen=True)
class Exported:
    plan: Plan
    path: Path
    """Where the plan was written."""
    warnings: tuple[str, ...] = ()
    """The session's warnings (changed inputs, torn journal lines), to show the user."""


def plan_of(analysis: Analysis, obs: Observations, *, table: Table = DEFAULT_TABLE,
            robot: str = DEFAULT_ROBOT) -> Plan:
    """The robot plan of an analysis: its graph laid out on ``table``."""
    return plan_from_graph(analysis.graph, obs, table=table, robot=robot)


def write_checked_plan(plan: Plan, path: str | Path, *, replace: bool = True) -> Path:
    """Check ``plan`` (InputError naming ``path`` when invalid) and write it there atomically (its folder made if
    missing; an existing file only when ``replace``)."""
    path = Path(path)
    validate(plan, path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return Path(write_plan(plan, path, replace=replace))


def session_plan(session_path: str | Path, *, table: Table = DEFAULT_TABLE,
                 robot: str = DEFAULT_ROBOT) -> tuple[Plan, Path, tuple[str, ...]]:
    """The plan of the session at ``session_path``, analysed with its corrections (not validated), its
    ``plans/`` folder and its warnings. Unreadable inputs raise :class:`InputError`."""
    done = analyse_session(session_path, write=False)
    plan = plan_of(done.analysis, done.observations, table=table, robot=robot)
    return plan, done.session.paths.plan.parent, tuple(done.session.warnings)


def export_session_plan(session_path: str | Path, out: str | Path | None = None, *,
                        table: Table = DEFAULT_TABLE, robot: str = DEFAULT_ROBOT, force: bool = False) -> Exported:
    """Analyse the session at ``session_path`` and write its plan to ``out`` (default
    ``<session>/plans/plan.yaml``, wecook's own file, replaced whole on every export); ``robot`` is the arms'
    URDF (relative to ``pybullet_data`` unless absolute). Unreadable inputs, an invalid plan, or an ``out`` that
    is a folder or exists (unless ``force``) raise :class:`InputError`."""
    from wecook_core.files import check_output, check_writable

    replace = force or out is None
    if out is not None:
        check_output(out, replace=replace, what="plan")  # before the analysis, not after
    check_writable(Path(out).parent if out is not None else Path(session_path) / "plans", "plan")
    plan, plans_dir, warnings = session_plan(session_path, table=table, robot=robot)
    path = write_checked_plan(plan, Path(out) if out is not None else plans_dir / "plan.yaml", replace=replace)
    return Exported(plan, path, warnings)


def inputs_plan(video: str | Path, objects: str | Path, hands: str | Path, *, table: Table = DEFAULT_TABLE,
                robot: str = DEFAULT_ROBOT) -> Plan:
    """The plan ``wecook new``, ``analyze`` and ``export`` give for these input files, without a session: the
    observations imported, analysed with the default parameters, no corrections and the video's shot cuts, and
    laid out on ``table``."""
    from wecook_core.knowledge.recognize import load_knowledge
    from wecook_core.observations.importer import load_observations
    from wecook_core.perception.params import Params
    from wecook_core.perception.segmentation.shots import shot_cuts

    obs = load_observations(video, objects, hands)
    analysis = analyse(obs, load_knowledge(), Params(), shots=shot_cuts(video))
    return plan_of(analysis, obs, table=table, robot=robot)


def demo_plan(table: Table = DEFAULT_TABLE, robot: str = DEFAULT_ROBOT) -> Plan:
    """The plan of the bundled demo (``wecook_core/assets/demo``) as ``wecook export demo`` writes it for a new demo
    session: its observations analysed with the default parameters and no corrections, laid out on ``table``."""
    from wecook_core.synth import demo_dir

    folder = demo_dir()
    return inputs_plan(folder / "video.mp4", folder / "objects.csv", folder / "hands.csv", table=table, robot=robot)


# ----------------------------------------------------------------------------------------------- demo

DEMO_NAME = "demo"


def demo_session(root: str | Path | None = None) -> Path:
    """The demo session under ``root`` (as :func:`sessions_root`), created from the bundled demo the first time."""
    from wecook_core.session.store import SESSION_FILE, create_session, sessions_root
    from wecook_core.synth import demo_dir

    path = sessions_root(root) / DEMO_NAME
    if (path / SESSION_FILE).is_file():
        return path
    assets = Path(demo_dir())
    return Path(create_session(sessions_root(root), DEMO_NAME, assets / "video.mp4", assets / "objects.csv",
                               assets / "hands.csv"))


@dataclass(frozen=True)
class DemoReport:
    analysed: Analysed
    scores: Scores
    """The trees scored against the demo's truth."""


def run_demo(root: str | Path | None = None) -> DemoReport:
    """Make the demo session if missing, analyse it (writing its trees and graph) and score it against the truth."""
    from wecook_core.perception.evaluation import evaluate
    from wecook_core.synth import demo_dir
    from wecook_core.trees.treefile import read_tree_file

    analysed = analyse_session(demo_session(root))
    scores = evaluate(analysed.analysis.trees, read_tree_file(Path(demo_dir()) / "truth.yaml"))
    return DemoReport(analysed, scores)
