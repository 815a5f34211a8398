"""A batch's report: per video its stages, times, tree counts, actions done and errors; the batch's precision
and recall over the videos that have truth files. Written as ``batch.json`` in the sessions folder, atomically
(temporary file, fsync, rename) each time a video finishes (:class:`ReportWriter`), so a reader always finds a
whole file: the videos finished so far, the others ``pending``."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from wecook_core.batch.engine import BatchRun
from wecook_core.batch.manifest import BatchItem
from wecook_core.batch.stages import StageResult
from wecook_core.files import write_atomic

REPORT_FILE = "batch.json"


@dataclass(frozen=True)
class VideoReport:
    name: str
    status: str
    """``done`` (every stage done or cached), ``failed``, ``partial`` or ``pending`` (not finished yet)."""
    stages: tuple[StageResult, ...]
    trees: int | None = None
    actions: int | None = None
    """Actions in the exported plan."""
    done: int | None = None
    """Actions done by the execute stage."""
    precision: float | None = None
    recall: float | None = None
    error: str = ""
    counts: tuple[int, int, int] | None = None
    """Scored videos: (correct, predicted, true) trees with an action, for the batch's pooled scores."""

    @property
    def seconds(self) -> float:
        return sum(s.seconds for s in self.stages)


@dataclass(frozen=True)
class BatchReport:
    videos: tuple[VideoReport, ...]
    seconds: float
    engine: str
    workers: int
    precision: float | None = None
    """Over every video with a truth file: correct trees / predicted trees (pooled)."""
    recall: float | None = None

    @property
    def failed(self) -> int:
        return sum(v.status == "failed" for v in self.videos)


def build_report(run: BatchRun, root: str | Path) -> BatchReport:
    """The report of ``run``; scores the trees of every video that has a truth file and an analysis."""
    return _report(run, [video_report(item, run.results.get(item.name, ()), root) for item in run.items])


def video_report(item: BatchItem, results: Sequence[StageResult], root: str | Path) -> VideoReport:
    """One video's line of the report (its trees scored against its truth file, if any)."""
    from wecook_core.perception.evaluation import match
    from wecook_core.trees.notation import has_action
    from wecook_core.trees.treefile import read_tree_file

    results = tuple(results)
    by_stage = {r.stage: r for r in results}
    failed = next((r for r in results if r.status == "failed"), None)
    ok = all(r.status in ("done", "cached") for r in results)
    status = "pending" if not results else "failed" if failed else "done" if ok else "partial"
    analyze, export, execute = (by_stage.get(s) for s in ("analyze", "export", "execute"))
    precision = recall = None
    counts = None
    trees_file = Path(root) / item.name / "trees.yaml"
    if item.truth is not None and analyze is not None and analyze.status in ("done", "cached") \
            and trees_file.exists():
        pred = [t for t in read_tree_file(trees_file) if has_action(t.tree)]
        truth = [t for t in read_tree_file(item.truth) if has_action(t.tree)]
        hits = len(match(pred, truth))
        precision = hits / len(pred) if pred else 0.0
        recall = hits / len(truth) if truth else 0.0
        counts = (hits, len(pred), len(truth))
    return VideoReport(item.name, status, results, trees=_get(analyze, "trees"), actions=_get(export, "actions"),
                       done=_get(execute, "done"), precision=precision, recall=recall,
                       error=failed.error if failed else "", counts=counts)


def _report(run: BatchRun, videos: Sequence[VideoReport]) -> BatchReport:
    correct = sum(v.counts[0] for v in videos if v.counts)
    predicted = sum(v.counts[1] for v in videos if v.counts)
    true = sum(v.counts[2] for v in videos if v.counts)
    return BatchReport(tuple(videos), run.seconds, run.engine, run.workers,
                       correct / predicted if predicted else (0.0 if true else None),
                       correct / true if true else None)


class ReportWriter:
    """``batch.json`` kept up to date as videos finish: call it with the run so far (``run_batch``'s
    ``on_video``); each finished video is scored once, and the whole file is rewritten atomically."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        self._done: dict[str, VideoReport] = {}
        self.report: BatchReport | None = None

    def __call__(self, run: BatchRun) -> None:
        videos = []
        for item in run.items:
            results = run.results.get(item.name, ())
            known = self._done.get(item.name)
            if known is None or known.stages != tuple(results):
                known = video_report(item, results, self.root)
                if results:
                    self._done[item.name] = known
            videos.append(known)
        self.report = _report(run, videos)
        write_report(self.report, self.root)


def _get(result: StageResult | None, key: str) -> int | None:
    if result is None or result.status not in ("done", "cached"):
        return None
    value = result.summary.get(key)
    return int(value) if isinstance(value, int | float) else None


def report_dict(report: BatchReport) -> dict[str, Any]:
    return {
        "engine": report.engine, "workers": report.workers, "seconds": round(report.seconds, 3),
        "precision": report.precision, "recall": report.recall, "failed": report.failed,
        "videos": [{
            "name": v.name, "status": v.status, "seconds": round(v.seconds, 3), "trees": v.trees,
            "actions": v.actions, "done": v.done, "precision": v.precision, "recall": v.recall, "error": v.error,
            "stages": [{"stage": s.stage, "status": s.status, "seconds": round(s.seconds, 3), "error": s.error,
                        "node": s.node or None, "pid": s.pid or None,
                        "summary": {k: val for k, val in s.summary.items() if k != "results"}}
                       for s in v.stages],
        } for v in report.videos],
    }


def write_report(report: BatchReport, root: str | Path) -> Path:
    """Write ``batch.json`` into ``root`` atomically (the last report is replaced whole); returns its path."""
    return write_atomic(Path(root) / REPORT_FILE, json.dumps(report_dict(report), indent=1), replace=True,
                        what="batch report")
