"""Where a session's files live: the sessions folder, session names, and each file of a session folder.

Every name of the session layout (:mod:`wecook_core.session.store`) is spelled here and nowhere else.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from wecook_core.errors import InputError

SESSION_FILE = "session.yaml"
JOURNAL_FILE = "journal.jsonl"
TREES_FILE = "trees.yaml"
GRAPH_FILE = "graph.yaml"
PLANS_DIR = "plans"
PLAN_FILE = "plan.yaml"
RUNS_DIR = "runs"
VIEW_FILE = "workbench.json"
CACHE_FILE = "cache/observations.npz"
ENV_ROOT = "WECOOK_SESSIONS"

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")

# ---------------------------------------------------------------------------------------- names, root


def sessions_root(root: str | Path | None = None) -> Path:
    """Where sessions live: ``root`` when given, else ``$WECOOK_SESSIONS``, else ``./sessions``."""
    if root is not None:
        path = Path(root)
    else:
        env = os.environ.get(ENV_ROOT)
        path = Path(env) if env else Path.cwd() / "sessions"
    for folder in (path, *path.parents):
        if folder.exists():
            if not folder.is_dir():
                raise InputError(folder, "is not a folder: sessions live in a folder (--root DIR or "
                                 "$WECOOK_SESSIONS)")
            break
    return path


def check_name(name: str) -> str:
    """``name`` if it can name a session folder: letters, digits, ``. _ -``, not starting with a dot."""
    if not _NAME.match(name) or ".." in name:
        raise InputError(None, f"bad session name {name!r}: use 1-64 letters, digits, '.', '_' or '-', starting "
                         "with a letter or digit")
    return name


@dataclass(frozen=True)
class SessionPaths:
    """Where each file of the session folder ``folder`` lives: the one place these names are spelled."""

    folder: Path

    @property
    def session_file(self) -> Path:
        return self.folder / SESSION_FILE

    @property
    def journal(self) -> Path:
        return self.folder / JOURNAL_FILE

    @property
    def trees(self) -> Path:
        return self.folder / TREES_FILE

    @property
    def graph(self) -> Path:
        return self.folder / GRAPH_FILE

    @property
    def plans(self) -> Path:
        return self.folder / PLANS_DIR

    @property
    def plan(self) -> Path:
        """The plan ``wecook export`` and the workbench write by default."""
        return self.plans / PLAN_FILE

    @property
    def runs(self) -> Path:
        return self.folder / RUNS_DIR

    @property
    def cache(self) -> Path:
        """The imported observations, kept so that opening does not import the inputs again."""
        return self.folder / CACHE_FILE

    @property
    def view(self) -> Path:
        """Where the workbench left off (its cursor), so reopening resumes there."""
        return self.folder / VIEW_FILE


def session_paths(folder: str | Path) -> SessionPaths:
    return SessionPaths(Path(folder))


def find_session(name: str | Path, root: str | Path | None = None) -> Path:
    """The folder of session ``name``: ``name`` itself when it is a session folder, else ``ROOT/NAME`` (root as
    :func:`sessions_root`). InputError when there is no such session."""
    given = Path(name)
    if (given / SESSION_FILE).is_file():
        return given
    path = sessions_root(root) / check_name(str(name))
    if not (path / SESSION_FILE).is_file():
        raise InputError(path, "no such session (create one with `wecook new NAME --video V --objects F "
                         "--hands H`, or try `wecook demo`)")
    return path


