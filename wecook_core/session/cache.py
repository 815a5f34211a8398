"""The session's imported observations kept on disk, so opening a session does not import its inputs again.

``cache/observations.npz`` holds every track's arrays and, as JSON, the rest of :class:`Imported` and the key
it was made for: the inputs as they are now (path, size, mtime, recorded sha256, format) and the code that
imports them (the version and the modification times of the import modules). Any difference, or any problem
reading the file, is a miss: the inputs are imported as before. Plain arrays and JSON, no pickle, so a cache
file from elsewhere cannot run code.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Mapping
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from wecook_core import __version__
from wecook_core.model import Category, HandTrack, ObjectTrack, Observations, VideoInfo
from wecook_core.observations.importer import HandGap, Imported
from wecook_core.session.inputs import InputFile, folder_files

CACHE_FORMAT = 1
_CODE = ("formats", "observations", "knowledge", "assets")
"""Folders of wecook_core whose files decide what an import gives."""


def cache_key(inputs: Mapping[str, InputFile]) -> str | None:
    """The key of a cache valid for ``inputs`` as they are now; None when an input cannot be seen."""
    items = []
    try:
        for role, item in sorted(inputs.items()):
            path = Path(item.path)
            if path.is_dir():
                files = sorted(folder_files(path), key=lambda f: f[0])  # the order of sorted Paths
                stats = [(str(path.joinpath(*parts)), stat.st_size, stat.st_mtime_ns) for parts, stat in files]
            else:
                stat = path.stat()
                stats = [(str(path), stat.st_size, stat.st_mtime_ns)]
            items.append([role, item.sha256, item.format, item.select, item.fps, stats])
    except OSError:
        return None
    return json.dumps({"format": CACHE_FORMAT, "version": __version__, "code": _code_stamp(), "inputs": items})


def _code_stamp() -> list[tuple[str, int]]:
    root = Path(__file__).resolve().parents[1]
    stamp = []
    for folder in _CODE:
        for path in sorted((root / folder).rglob("*")):
            if path.is_file() and "__pycache__" not in path.parts:
                stamp.append((path.relative_to(root).as_posix(), path.stat().st_mtime_ns))
    return stamp


def load_cached(path: Path, key: str | None) -> Imported | None:
    """The cached import at ``path`` if it was made for ``key``; None otherwise (never an error)."""
    if key is None or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            if meta.get("key") != key:
                return None
            objects = tuple(ObjectTrack(o["track_id"], o["label"], o["name"], data[f"o{i}_frames"],
                                        data[f"o{i}_boxes"]) for i, o in enumerate(meta["objects"]))
            hands = tuple(HandTrack(h, data[f"h{i}_frames"], data[f"h{i}_xy"], data[f"h{i}_boxes"])
                          for i, h in enumerate(meta["hands"]))
        obs = Observations(VideoInfo(**meta["video"]), objects, hands,
                           {name: Category(c) for name, c in meta["categories"].items()})
        return Imported(obs, meta["objects_format"], meta["hands_format"], tuple(meta["warnings"]),
                        tuple(HandGap(**g) for g in meta["gaps"]), dict(meta["missing"]))
    except (OSError, ValueError, KeyError, TypeError):
        return None


def save_cached(path: Path, key: str | None, imported: Imported) -> None:
    """Keep ``imported`` at ``path`` for ``key`` (atomically; a failure only means no cache)."""
    if key is None:
        return
    obs = imported.observations
    arrays: dict[str, Any] = {}
    for i, o in enumerate(obs.objects):
        arrays[f"o{i}_frames"], arrays[f"o{i}_boxes"] = o.frames, o.boxes
    for i, h in enumerate(obs.hands):
        arrays[f"h{i}_frames"], arrays[f"h{i}_xy"], arrays[f"h{i}_boxes"] = h.frames, h.xy, h.boxes
    meta = {
        "key": key, "video": asdict(obs.video), "categories": {k: str(v) for k, v in obs.categories.items()},
        "objects": [{"track_id": int(o.track_id), "label": o.label, "name": o.name} for o in obs.objects],
        "hands": [h.hand for h in obs.hands], "objects_format": imported.objects_format,
        "hands_format": imported.hands_format, "warnings": list(imported.warnings),
        "gaps": [asdict(g) for g in imported.gaps], "missing": dict(imported.missing),
    }
    arrays["meta"] = np.array(json.dumps(meta))
    with contextlib.suppress(OSError):
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".npz", dir=path.parent)
        try:
            with os.fdopen(fd, "wb") as handle:
                np.savez(handle, **arrays)
            os.replace(tmp, path)
        except BaseException:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
            raise
