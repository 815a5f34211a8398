"""A session on disk: the inputs (by path and content hash), the parameters, and the journal of corrections.

Layout of ``sessions/NAME/``::

    session.yaml     inputs (path, sha256, size, mtime, format), video facts, Params, created time, version
    journal.jsonl    corrections, one JSON line each, append-only (see :mod:`wecook_core.session.journal`)
    trees.yaml       graph.yaml     plans/plan.yaml     runs/          (written by later stages)

The names are spelled once, in :class:`SessionPaths`.

Opening a session never fails on what a crash or a later change can do: a torn journal line, an input file
that changed (its sha256 differs) or went missing are :attr:`Session.warnings`, for the workbench to show.
Creating one imports every input first, and builds the folder under a temporary name, so bad input leaves
nothing behind.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import os
import shutil
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from wecook_core import __version__
from wecook_core.errors import InputError, yaml_error
from wecook_core.files import fsync_dir, read_text, write_atomic
from wecook_core.formats.detect import HAND_FORMATS, OBJECT_FORMATS
from wecook_core.formats.video import probe_video, usable_frames
from wecook_core.model import Corrections, Observations, VideoInfo
from wecook_core.observations.importer import Imported, import_observations
from wecook_core.perception.params import Params, params_from_dict
from wecook_core.session.corrections import Correction
from wecook_core.session.inputs import InputFile, content_hash, input_problem, record_input
from wecook_core.session.journal import Journal, JournalEntry, read_journal, replay
from wecook_core.session.paths import (
    ENV_ROOT,
    JOURNAL_FILE,
    SESSION_FILE,
    SessionPaths,
    check_name,
    find_session,
    session_paths,
    sessions_root,
)

if TYPE_CHECKING:
    from wecook_core.knowledge.categories import CategoryTable

SESSION_FORMAT = 1
MAX_SESSION_BYTES = 1 << 20
"""The largest session.yaml read (1 MiB; wecook writes about 2 KB)."""

# ---------------------------------------------------------------------------------------- session


class Session:
    """An open session. Corrections go through :meth:`record`, :meth:`undo` and :meth:`redo`."""

    def __init__(self, path: Path, meta: Mapping[str, Any], warnings: list[str], *, lock: bool = False) -> None:
        self.path = path
        self.paths = SessionPaths(path)
        self.name = path.name
        self.meta = dict(meta)
        self.warnings: list[str] = warnings
        """Problems found on opening (changed or missing inputs, torn or unreadable journal lines)."""
        self.created: str = str(meta.get("created", ""))
        self.version: str = str(meta.get("wecook_version", ""))
        self.inputs: dict[str, InputFile] = _inputs(meta.get("inputs"), warnings)
        self.params: Params = _params(meta.get("params"), warnings, path / SESSION_FILE)
        self.video: VideoInfo | None = _video(meta.get("video"))
        """The video's facts when the session was made (without opening the video)."""
        rate = meta.get("video_fps")
        self.video_fps: float | None = float(rate) if isinstance(rate, int | float) and rate > 0 else None
        """The frame rate given with ``--fps`` when the session was made (its container's is unusable)."""
        self.journal = Journal(self.paths.journal, lock=lock)
        """Its writer lock is taken at open with ``lock`` (the workbench), else at the first correction."""
        self.warnings.extend(self.journal.warnings)
        self._imported: Imported | None = None

    def close(self) -> None:
        """Let go of the session's writer lock (:meth:`Journal.close`)."""
        self.journal.close()

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # paths
    @property
    def journal_path(self) -> Path:
        return self.journal.path

    @property
    def trees_path(self) -> Path:
        return self.paths.trees

    @property
    def graph_path(self) -> Path:
        return self.paths.graph

    @property
    def plans_dir(self) -> Path:
        return self.paths.plans

    @property
    def runs_dir(self) -> Path:
        return self.paths.runs

    # journal
    @property
    def entries(self) -> tuple[JournalEntry, ...]:
        return self.journal.entries

    @property
    def corrections(self) -> Corrections:
        """The journal folded: what the pipeline applies on top of its own results."""
        return self.journal.corrections

    @property
    def applied_corrections(self) -> tuple[Correction, ...]:
        """The typed corrections in effect, oldest first (fold them against a segmentation for span ones)."""
        return self.journal.applied_corrections

    @property
    def can_undo(self) -> bool:
        return self.journal.can_undo

    @property
    def can_redo(self) -> bool:
        return self.journal.can_redo

    def record(self, correction: Correction | Mapping[str, Any]) -> JournalEntry:
        """Append a correction (typed, or ``{"op": ..., fields}``: :mod:`wecook_core.session.corrections`);
        durable (fsynced) on return.

        ValueError for a malformed correction, OSError when the disk refuses (nothing changes then),
        :class:`JournalChangedError` when another process wrote the journal meanwhile.
        """
        return self.journal.record(correction)

    def undo(self) -> Correction | None:
        """Take back the latest correction in effect (durable on return): the correction taken back, None when
        there is none."""
        taken = self.journal.applied[-1] if self.journal.can_undo else None
        return taken.correction if taken is not None and self.journal.undo() is not None else None

    def redo(self) -> Correction | None:
        """Re-apply the latest undone correction (durable on return): that correction, None when there is none."""
        entry = self.journal.redo()
        return self.journal.applied[-1].correction if entry is not None else None

    # inputs
    def import_observations(self, *, video_optional: bool = False) -> Imported:
        """Import the inputs (kept in memory, and on disk in ``cache/`` while the inputs and the import code stay
        the same): InputError when one is missing or no longer reads.

        ``video_optional``: a video that is missing, does not open, or no longer holds the frames of the boxes
        and hands (cut short since) is no error when the session recorded its facts: those stand in, and
        :attr:`Imported.video_problem` says what is wrong with the video (the boxes and hands are checked
        against the recorded facts as usual). That import is not cached.
        """
        if self._imported is not None:
            return self._imported
        from wecook_core.session.cache import cache_key, load_cached, save_cached

        key = cache_key(self.inputs)
        video = self._input("video")
        self._imported = load_cached(self.paths.cache, key)
        if self._imported is not None:  # its video by the recorded path (a cache may hold a relative one)
            self._imported = _with_video_path(self._imported, video.path)
            return self._imported
        try:
            facts = probe_video(video.path, fps=self.video_fps)
        except InputError as error:
            if not video_optional or self.video is None:
                raise
            return self._with_recorded_video(video.path, self.video, str(error))
        try:
            self._imported = self._import(video.path, facts)
        except InputError as error:
            # The video opens, but may have been cut short since: then the recorded facts may still fit.
            if not video_optional or self.video is None or _same_video(facts, self.video):
                raise
            return self._with_recorded_video(video.path, self.video, str(error))
        save_cached(self.paths.cache, key, self._imported)
        return self._imported

    def _with_recorded_video(self, video: str, recorded: VideoInfo, problem: str) -> Imported:
        return replace(self._import(video, recorded), video_problem=problem)

    def _import(self, video: str, facts: VideoInfo) -> Imported:
        objects, hands = self.inputs.get("objects"), self._input("hands")  # no objects: a video alone
        for item, formats in ((objects, OBJECT_FORMATS), (hands, HAND_FORMATS)):
            if item is not None and item.format is not None and item.format not in formats:
                raise InputError(self.path / SESSION_FILE, f"unknown {item.role} format {item.format!r:.40}; "
                                 f"expected one of {', '.join(formats)}", place=f"inputs.{item.role}.format")
        labels = self.inputs.get("labels")
        return import_observations(
            video, objects.path if objects else None, hands.path,
            objects_format=objects.format if objects else None, hands_format=hands.format,
            labels=labels.path if labels else None, select=objects.select if objects else None,
            annotation_fps=objects.fps if objects else None, categories=self.category_table(), video_facts=facts,
        )

    def category_table(self) -> CategoryTable | None:
        """The category table with the session's extra categories file on top; None: the default table."""
        extra = self.inputs.get("categories")
        return _category_table(Path(extra.path) if extra else None)

    def load_observations(self, *, video_optional: bool = False) -> Observations:
        """The observations of :meth:`import_observations`."""
        return self.import_observations(video_optional=video_optional).observations

    def _input(self, role: str) -> InputFile:
        item = self.inputs.get(role)
        if item is None:
            raise InputError(self.path / SESSION_FILE, f"no {role} input recorded", place="inputs")
        return item

    @property
    def uncategorised(self) -> tuple[str, ...]:
        """Imported labels nothing categorised (taken as ingredients) that the user has not categorised yet."""
        from wecook_core.session.boxes import categories_given

        listed = self.meta.get("uncategorised")
        given = categories_given(self.applied_corrections)
        return tuple(str(label) for label in listed if str(label) not in given) if isinstance(listed, list) else ()

    def set_params(self, params: Params) -> None:
        """Record new parameters in ``session.yaml`` (atomically)."""
        self.meta["params"] = dataclasses.asdict(params)
        _write_yaml(self.path / SESSION_FILE, self.meta)
        self.params = params


def _with_video_path(imported: Imported, path: str) -> Imported:
    """``imported`` with its video's path set to ``path``."""
    obs = imported.observations
    if obs.video.path == path:
        return imported
    return replace(imported, observations=replace(obs, video=replace(obs.video, path=path)))


def _same_video(a: VideoInfo, b: VideoInfo) -> bool:
    """Whether two probes of a video found the same size, rate and usable frames."""
    return (a.width, a.height, a.fps, usable_frames(a)) == (b.width, b.height, b.fps, usable_frames(b))


def _category_table(extra: Path | None) -> CategoryTable | None:
    """The category table with the session's extra file on top (None: the default table)."""
    if extra is None:
        return None
    from wecook_core.knowledge.categories import load_categories

    return load_categories(extra=[extra])


def _inputs(value: Any, warnings: list[str]) -> dict[str, InputFile]:
    inputs: dict[str, InputFile] = {}
    names = {f.name for f in dataclasses.fields(InputFile)}
    if not isinstance(value, dict):
        warnings.append("session.yaml: inputs is not a mapping of role -> file; no inputs")
        return inputs
    for role, item in value.items():
        if not isinstance(item, dict) or not {"path", "sha256", "size", "mtime_ns"} <= set(item) \
                or not all(isinstance(item.get(k), str) for k in ("path", "sha256")) \
                or not all(isinstance(item.get(k), str | None) for k in ("format", "select")) \
                or isinstance(item.get("fps"), bool) or not isinstance(item.get("fps"), int | float | None) \
                or not all(isinstance(item.get(k), int) for k in ("size", "mtime_ns")):
            warnings.append(f"session.yaml: input {role!r} is incomplete; ignored")
            continue
        inputs[role] = InputFile(role=role, **{k: v for k, v in item.items() if k in names and k != "role"})
        problem = input_problem(inputs[role])
        if problem:
            warnings.append(problem)
    return inputs


def _params(value: Any, warnings: list[str], path: Path) -> Params:
    """The session's parameters; a value of the wrong type or out of range is an InputError at its place."""
    unknown: list[str] = []
    params = params_from_dict(value, path, unknown=unknown)
    if unknown:
        warnings.append(f"session.yaml: unknown parameters {', '.join(sorted(unknown))} ignored")
    return params


def _video(value: Any) -> VideoInfo | None:
    if not isinstance(value, dict):
        return None
    try:
        return VideoInfo(**value)
    except TypeError:
        return None


def _write_yaml(path: Path, data: Mapping[str, Any]) -> None:
    """Write ``path`` atomically (:func:`~wecook_core.files.write_atomic`)."""
    write_atomic(path, yaml.safe_dump(dict(data), sort_keys=False, allow_unicode=True), replace=True,
                 what="session file")

# ----------------------------------------------------------------------------------- create / open


def create_session(
    root: str | Path,
    name: str,
    video: str | Path,
    objects: str | Path | None,
    hands: str | Path,
    *,
    objects_format: str | None = None,
    hands_format: str | None = None,
    labels: str | Path | None = None,
    categories: str | Path | None = None,
    select: str | None = None,
    annotation_fps: float | None = None,
    params: Params | None = None,
    imported: Imported | None = None,
    fps: float | None = None,
) -> Path:
    """Make ``root/name`` from the inputs, after importing them all; return its path.

    Bad input raises :class:`InputError` and leaves nothing behind (the folder is built under a temporary
    name and renamed into place). ``objects`` None makes a session of a video alone (boxes drawn later in the
    workbench's box mode). ``labels`` is MOT's labels file and ``categories`` a file of extra object
    categories (both recorded as inputs); ``select`` the video of a COCO-VID file holding several;
    ``annotation_fps`` the frame rate a Label Studio annotation was made at (None: read from the file).
    ``imported`` skips the import when the caller already did it with the same arguments. ``fps``: the video's
    frame rate given by the user (its container's is unusable), recorded and used whenever the video is read.
    """
    check_name(name)
    root = Path(root)
    target = root / name
    if target.exists():
        raise InputError(target, "a session of that name already exists")
    if imported is None:
        imported = import_observations(video, objects, hands, objects_format=objects_format,
                                       hands_format=hands_format, labels=labels, select=select,
                                       annotation_fps=annotation_fps,
                                       categories=_category_table(Path(categories) if categories else None),
                                       video_facts=probe_video(video, fps=fps) if fps is not None else None)
    inputs = {"video": record_input("video", video)}
    imported = _with_video_path(imported, inputs["video"].path)  # absolute: found from any folder
    if objects is not None:  # else a video alone: its boxes are drawn in the workbench
        inputs["objects"] = record_input("objects", objects, imported.objects_format, select, annotation_fps)
    inputs["hands"] = record_input("hands", hands, imported.hands_format)
    if labels is not None:
        inputs["labels"] = record_input("labels", labels)
    if categories is not None:
        inputs["categories"] = record_input("categories", categories)
    meta = {
        "wecook_session": SESSION_FORMAT,
        "name": name,
        "created": dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "wecook_version": __version__,
        "inputs": {role: {k: v for k, v in dataclasses.asdict(item).items() if k != "role"}
                   for role, item in inputs.items()},
        "video": dataclasses.asdict(imported.observations.video),
        "params": dataclasses.asdict(params or Params()),
        "uncategorised": list(imported.uncategorised),  # labels taken as ingredients until the user says
        **({"video_fps": fps} if fps is not None else {}),
    }
    root.mkdir(parents=True, exist_ok=True)
    building = Path(tempfile.mkdtemp(prefix=f".{name}.creating-", dir=root))
    try:
        paths = SessionPaths(building)
        _write_yaml(paths.session_file, meta)
        paths.journal.touch()
        paths.plans.mkdir()
        paths.runs.mkdir()
        fsync_dir(building)
        if target.exists():
            raise InputError(target, "a session of that name already exists")
        os.rename(building, target)
        fsync_dir(root)
    except BaseException:
        shutil.rmtree(building, ignore_errors=True)
        raise
    from wecook_core.session.cache import cache_key, save_cached

    save_cached(SessionPaths(target).cache, cache_key(inputs), imported)  # the first open need not import again
    return target


def open_session(path: str | Path, *, lock: bool = False) -> Session:
    """Open the session folder ``path``. Missing or changed inputs, torn or unreadable journal lines are
    :attr:`Session.warnings`; only a folder that is not a session (no readable ``session.yaml``) is an
    InputError, as is, with ``lock`` (the session held for writing while open), a session another process
    holds."""
    path = Path(path)
    meta_path = path / SESSION_FILE
    if not path.is_dir():
        raise InputError(path, "no such session")
    if not meta_path.exists() and not meta_path.is_symlink():
        raise InputError(path, f"not a session: no {SESSION_FILE}")
    try:
        meta = yaml.safe_load(read_text(meta_path, "session file", MAX_SESSION_BYTES))
    except yaml.YAMLError as error:
        raise yaml_error(meta_path, error) from None
    except RecursionError:
        raise InputError(meta_path, "malformed YAML (nested too deeply)") from None
    except (ValueError, OverflowError) as error:  # an integer of more than 4300 digits, a bad date
        raise InputError(meta_path, f"malformed YAML ({str(error)[:100]})") from None
    if not isinstance(meta, dict) or "inputs" not in meta:
        raise InputError(meta_path, "not a wecook session file (no inputs)")
    warnings: list[str] = []
    version = meta.get("wecook_session", SESSION_FORMAT)
    if not isinstance(version, int) or version > SESSION_FORMAT:
        warnings.append(f"{meta_path}: made by a newer wecook (session format {meta.get('wecook_session')})")
    return Session(path, meta, warnings, lock=lock)


@dataclass(frozen=True)
class SessionSummary:
    """One line of ``wecook sessions``."""

    name: str
    path: Path
    video: str
    created: str
    corrections: int
    """Corrections in effect (after undo / redo)."""
    problem: str | None = None
    """Why the session could not be read, when it could not."""


def list_sessions(root: str | Path) -> list[SessionSummary]:
    """Every session under ``root``, by name; unreadable ones are listed with their problem."""
    root = Path(root)
    if not root.is_dir():
        return []
    summaries = []
    for folder in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")):
        if not (folder / SESSION_FILE).exists():
            continue
        try:
            meta = yaml.safe_load(read_text(folder / SESSION_FILE, "session file", MAX_SESSION_BYTES))
            video = str(meta["inputs"]["video"]["path"])
            created = str(meta.get("created", ""))
            entries, _, _ = read_journal(folder / JOURNAL_FILE)
        except (InputError, RecursionError, yaml.YAMLError, KeyError, TypeError) as error:
            summaries.append(SessionSummary(folder.name, folder, "", "", 0, f"unreadable session ({error})"))
            continue
        summaries.append(SessionSummary(folder.name, folder, video, created, len(replay(entries).applied)))
    return summaries


__all__ = [
    "ENV_ROOT",
    "JOURNAL_FILE",
    "SESSION_FILE",
    "SESSION_FORMAT",
    "InputFile",
    "Session",
    "SessionPaths",
    "SessionSummary",
    "check_name",
    "content_hash",
    "create_session",
    "find_session",
    "list_sessions",
    "open_session",
    "session_paths",
    "sessions_root",
]
