"""One video's stages, as pure steps on its session folder: each writes what the matching command writes.

``hands`` (detect hands when the manifest gives none) -> ``import`` (``wecook new``) -> ``analyze`` (``wecook
analyze``: trees.yaml, graph.yaml) -> ``export`` (``wecook export``: plans/plan.yaml) -> ``execute`` (``wecook
execute``: a recording in runs/). Each stage is keyed by a content hash of everything it reads (input files,
parameters, corrections, the knowledge tables, the upstream stage's key, wecook's version); its key and result
are stamped in ``<session>/batch/<stage>.json``, written atomically after the stage's own files, so a second run
skips a stage whose key is unchanged and a killed batch loses no finished stage.

The stages of one video run in one process (:mod:`wecook_core.batch.video`) and share a :class:`Carry`: the
digests of the input files (hashed once per video, not once per stage) and the analysis, which ``export``
lays out instead of analysing the session a second time.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

from wecook_core import __version__
from wecook_core.batch.manifest import BatchItem
from wecook_core.errors import InputError
from wecook_core.files import write_atomic
from wecook_core.session.paths import session_paths

STAGES: tuple[str, ...] = ("hands", "import", "analyze", "export", "execute")
"""Every stage, in the order they run for one video."""
STAMP_DIR = "batch"
"""A session's stamps: ``<session>/batch/<stage>.json``."""
EARLY_STAMPS = ".batch"
"""Stamps of the stages before the session exists (``hands``): ``ROOT/.batch/<name>/<stage>.json``."""


@dataclass(frozen=True)
class StageOptions:
    """What the stages take besides the video's inputs (part of every stage's key)."""

    seed: int = 0
    """Run seed of the execute stage."""
    force: bool = False
    """Redo stages whose key is unchanged."""
    record: bool = True
    """The execute stage records an MCAP file."""


@dataclass(frozen=True)
class StageResult:
    """What one stage did for one video."""

    video: str
    stage: str
    status: Literal["done", "cached", "failed", "skipped"]
    """``cached``: its key was unchanged, nothing ran; ``skipped``: an earlier stage of the video failed."""
    seconds: float = 0.0
    """Wall time of the stage (0 when cached or skipped)."""
    summary: Mapping[str, Any] = field(default_factory=dict)
    """Stage figures: ``trees``, ``nodes``, ``actions``, ``done``, ``path``..."""
    error: str = ""
    """The one-line error of a failed stage."""
    key: str = ""
    pid: int = 0
    """The process that ran it (a Ray worker, or this one)."""
    peak_rss_mb: float = 0.0
    """That process's peak resident memory so far, MiB."""
    started: float = 0.0
    """Wall clock when the stage began (seconds since the epoch; 0 when skipped)."""
    node: str = ""
    """The Ray node that ran it (empty in this process)."""


@dataclass
class Carry:
    """What one video's stages hand on to the next ones in the same process (never across videos)."""

    digests: dict[Path, str] = field(default_factory=dict)
    """Content hash of each input file or folder read so far."""
    analysed: Any = None
    """The :class:`~wecook_core.workflows.Analysed` of this run's ``analyze``, for ``export``."""


def stages_for(item: BatchItem, wanted: Sequence[str]) -> tuple[str, ...]:
    """The stages to run for ``item``, in order: ``hands`` only when the manifest gives no hands."""
    unknown = [s for s in wanted if s not in STAGES]
    if unknown:
        raise InputError(None, f"unknown stage {unknown[0]!r} (stages: {', '.join(STAGES)})")
    return tuple(s for s in STAGES if s in wanted and not (s == "hands" and item.hands is not None))


def run_stage(item: BatchItem, stage: str, root: Path, options: StageOptions,
              carry: Carry | None = None) -> StageResult:
    """Run ``stage`` for ``item`` under the sessions ``root`` unless its stamp says it is done; never raises
    for the video's own problems (they are the result's ``error``). ``carry``: what the video's earlier
    stages in this process left (see :class:`Carry`)."""
    started, began = time.time(), time.perf_counter()
    result = _run(item, stage, root, options, began, carry if carry is not None else Carry())
    return replace(result, pid=os.getpid(), peak_rss_mb=_peak_rss_mb(), started=started)


def _peak_rss_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux


def _run(item: BatchItem, stage: str, root: Path, options: StageOptions, began: float,
         carry: Carry) -> StageResult:
    try:
        key = _key(item, stage, root, options, carry)
        stamp = _read_stamp(_stamp_path(root, item.name, stage))
        if not options.force and stamp is not None and stamp.get("key") == key:
            return StageResult(item.name, stage, "cached", 0.0, stamp.get("summary", {}), key=key)
        summary = _RUN[stage](item, root, options, carry)
        result = StageResult(item.name, stage, "done", time.perf_counter() - began, summary, key=key)
        _write_stamp(_stamp_path(root, item.name, stage),
                     {"key": key, "summary": summary, "seconds": result.seconds})
        return result
    except InputError as error:
        return StageResult(item.name, stage, "failed", time.perf_counter() - began, error=str(error))
    except Exception as error:  # one video's failure never stops the batch
        return StageResult(item.name, stage, "failed", time.perf_counter() - began,
                           error=f"{type(error).__name__}: {error}")


# ------------------------------------------------------------------------------------------------ keys


def _file_hash(path: Path, digest: Any) -> None:
    if path.is_dir():
        for child in sorted(path.rglob("*")):
            if child.is_file():
                digest.update(str(child.relative_to(path)).encode())
                _file_hash(child, digest)
        return
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)


def _hands_path(item: BatchItem, root: Path) -> Path:
    """The hands of ``item``: the manifest's, else ``ROOT/NAME.hands.csv``, where ``wecook new`` without
    ``--hands`` writes the hands it detects."""
    return item.hands if item.hands is not None else root / f"{item.name}.hands.csv"


def _digest(path: Path, carry: Carry) -> str:
    """Content hash of the file or folder ``path``, once per video (inputs do not change under a batch)."""
    known = carry.digests.get(path)
    if known is None:
        digest = hashlib.sha256()
        _file_hash(path, digest)
        known = carry.digests[path] = digest.hexdigest()
    return known


def _key(item: BatchItem, stage: str, root: Path, options: StageOptions, carry: Carry) -> str:
    """Content hash of everything ``stage`` reads for ``item``."""
    digest = hashlib.sha256(f"wecook {__version__} {stage}".encode())
    inputs = [item.video, item.objects, _hands_path(item, root), item.categories]
    if stage == "hands":
        inputs = [item.video]
    for path in inputs:
        if path is not None and path.exists():
            digest.update(str(path.name).encode())
            digest.update(_digest(path, carry).encode())
    session = root / item.name
    if stage in ("analyze", "export", "execute"):
        from wecook_core.knowledge.recognize import KNOWLEDGE_PATH

        for path in (session_paths(session).session_file, session_paths(session).journal):
            if path.exists():
                _file_hash(path, digest)
        digest.update(_digest(KNOWLEDGE_PATH, carry).encode())
    if stage == "execute":
        digest.update(json.dumps({"seed": options.seed, "record": options.record}).encode())
        plan = session_paths(session).plan
        if plan.exists():
            _file_hash(plan, digest)
    return digest.hexdigest()[:32]


def _stamp_path(root: Path, name: str, stage: str) -> Path:
    """Where ``stage``'s stamp of video ``name`` lies: in its session, or beside it before the session exists."""
    if stage == "hands":
        return root / EARLY_STAMPS / name / f"{stage}.json"
    return root / name / STAMP_DIR / f"{stage}.json"


def _read_stamp(path: Path) -> dict[str, Any] | None:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _write_stamp(path: Path, data: Mapping[str, Any]) -> None:
    write_atomic(path, json.dumps(data, indent=1, default=str), replace=True, what="batch stamp")


# ---------------------------------------------------------------------------------------------- stages


_HAND_DETECTORS: dict[Any, Any] = {}
"""This process's hand detectors by their parameters: loaded by the first video, reset for each next one."""


def hand_detector(params: Any) -> Any:
    """This process's :class:`~wecook_core.observations.hands_detect.HandDetector` for ``params``."""
    from wecook_core.observations.hands_detect import HandDetector

    found = _HAND_DETECTORS.get(params)
    if found is None:
        found = _HAND_DETECTORS[params] = HandDetector(params)
    return found


def _hands(item: BatchItem, root: Path, options: StageOptions, carry: Carry) -> dict[str, Any]:
    from wecook_core.observations.hands_detect import DetectParams, detect_hands, write_hands

    params = DetectParams()
    found = detect_hands(item.video, params, detector=hand_detector(params))
    out = _hands_path(item, root)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_hands(found, item.video, out)
    return {"path": str(out), "hands": [t.hand for t in found.tracks], "frames": found.frames_read,
            "frames_with_hands": found.frames_with_hands}


def _import(item: BatchItem, root: Path, options: StageOptions, carry: Carry) -> dict[str, Any]:
    from wecook_core.session.store import create_session

    target = root / item.name
    if target.exists():
        if not options.force and not (target / STAMP_DIR / "import.json").exists():
            raise InputError(target, "a session of that name exists and was not made by a batch (use --force "
                                     "to replace it; the old one is kept beside it)")
        target.rename(target.with_name(f".{item.name}.replaced-{time.strftime('%Y%m%dT%H%M%S')}-{os.getpid()}"))
    path = create_session(root, item.name, item.video, item.objects, _hands_path(item, root),
                          categories=item.categories)
    return {"path": str(path)}


def _analyze(item: BatchItem, root: Path, options: StageOptions, carry: Carry) -> dict[str, Any]:
    from wecook_core.workflows import analyse_session

    carry.analysed = analyse_session(root / item.name)
    analysis = carry.analysed.analysis
    return {"trees": len(analysis.trees), "nodes": len(analysis.graph.nodes),
            "segments": len(analysis.segmentation.segments)}


def _export(item: BatchItem, root: Path, options: StageOptions, carry: Carry) -> dict[str, Any]:
    from wecook_core.workflows import export_session_plan, plan_of, write_checked_plan

    if carry.analysed is not None:  # analysed a moment ago in this process: lay that out, as export would
        done = carry.analysed
        plan = plan_of(done.analysis, done.observations)
        path = write_checked_plan(plan, done.session.paths.plan, replace=True)
        return {"actions": len(plan.actions), "path": str(path)}
    exported = export_session_plan(root / item.name)
    return {"actions": len(exported.plan.actions), "path": str(exported.path)}


def _execute(item: BatchItem, root: Path, options: StageOptions, carry: Carry) -> dict[str, Any]:
    from wecook_core.plan import read_plan
    from wecook_core.recording.run import recorded_run

    paths = session_paths(root / item.name)
    plan = read_plan(paths.plan)
    record = paths.runs / f"batch-seed{options.seed}.mcap"
    if options.record and record.exists():  # an earlier batch's recording is kept aside, under its time
        shutil.move(record, record.with_suffix(f".{time.strftime('%Y%m%dT%H%M%S')}.mcap"))
    result = recorded_run(plan, record if options.record else None, seed=options.seed).result
    done = sum(a.status == "done" for a in result.actions)
    return {"actions": len(result.actions), "done": done, "arm_contacts": result.arm_contacts,
            "sim_time": round(result.sim_time, 3), "recording": str(record) if options.record else None,
            "results": [asdict(a) for a in result.actions]}


_RUN = {"hands": _hands, "import": _import, "analyze": _analyze, "export": _export, "execute": _execute}
