"""A batch's manifest: which videos, with which boxes and hands, under which session names.

Three shapes are read, each into the same tuple of :class:`BatchItem`:

- YAML: ``videos:`` (or a top-level list) of mappings ``{name, video, objects, hands, truth, categories}``;
- CSV with a header naming the same columns (``hands``, ``truth`` and ``categories`` may be empty);
- a folder of scenario folders, each holding ``video.mp4``, object boxes (``objects.xml``, ``objects.csv``,
  ``objects.json`` or ``objects.txt``), hands (an ``openpose/`` folder or ``hands.csv``; none is allowed) and
  optionally ``truth.yaml`` and ``categories.yaml``; the session is named after the folder.

Relative paths are taken from the manifest's own folder (and made absolute). A row that cannot be used is an
:class:`InputError` naming the manifest and the row, before anything runs.
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from wecook_core.errors import InputError, read_input_text, yaml_error
from wecook_core.session.store import check_name

COLUMNS = ("name", "video", "objects", "hands", "truth", "categories")
OBJECT_FILES = ("objects.xml", "objects.csv", "objects.json", "objects.txt")
MAX_VIDEOS = 100_000
"""Most rows a manifest may hold."""


@dataclass(frozen=True)
class BatchItem:
    """One video of a batch and the inputs its session is made from."""

    name: str
    """Session name (a folder under the sessions root)."""
    video: Path
    objects: Path
    """Object boxes in any format ``wecook new`` reads."""
    hands: Path | None = None
    """Hands (OpenPose folder or CSV); None: detected from the video by the ``hands`` stage."""
    truth: Path | None = None
    """True trees, for the batch's precision and recall."""
    categories: Path | None = None
    """Extra object categories (``wecook new --categories``)."""


def read_manifest(path: str | Path) -> tuple[BatchItem, ...]:
    """The items of the manifest file or scenario folder at ``path``, in its order; names are unique. Every
    path in them is absolute, so Ray workers, whatever their working folder or node, read the same files."""
    path = Path(os.path.abspath(path))
    if path.is_dir():
        items = _folder(path)
    elif not path.exists():
        raise InputError(path, "no such manifest file or folder")
    elif path.suffix.lower() == ".csv":
        items = _csv(path)
    else:
        items = _yaml(path)
    if not items:
        raise InputError(path, "the manifest lists no videos")
    if len(items) > MAX_VIDEOS:
        raise InputError(path, f"{len(items)} videos: at most {MAX_VIDEOS} in one manifest")
    seen: dict[str, int] = {}
    for i, item in enumerate(items, 1):
        if item.name in seen:
            raise InputError(path, f"video {i}: name {item.name!r} is also video {seen[item.name]}")
        seen[item.name] = i
    return tuple(items)


def _folder(path: Path) -> list[BatchItem]:
    items = []
    for folder in sorted(p for p in path.iterdir() if p.is_dir() and not p.name.startswith(".")):
        video = folder / "video.mp4"
        objects = next((folder / f for f in OBJECT_FILES if (folder / f).is_file()), None)
        if not video.is_file() or objects is None:
            continue
        hands = folder / "openpose" if (folder / "openpose").is_dir() else folder / "hands.csv"
        truth, categories = folder / "truth.yaml", folder / "categories.yaml"
        items.append(BatchItem(_name(path, folder.name, folder.name), video, objects,
                               hands if hands.exists() else None, truth if truth.is_file() else None,
                               categories if categories.is_file() else None))
    return items


def _yaml(path: Path) -> list[BatchItem]:
    try:
        data = yaml.safe_load(read_input_text(path))
    except yaml.YAMLError as error:
        raise yaml_error(path, error) from None
    rows = data.get("videos") if isinstance(data, dict) else data
    if not isinstance(rows, list):
        raise InputError(path, "expected a list of videos (or a mapping with `videos:`)")
    return [_item(path, f"video {i}", row) for i, row in enumerate(rows, 1)]


def _csv(path: Path) -> list[BatchItem]:
    reader = csv.DictReader(io.StringIO(read_input_text(path).lstrip("\ufeff")))
    missing = [c for c in ("name", "video", "objects") if c not in (reader.fieldnames or ())]
    if missing:
        raise InputError(path, f"line 1: the header lacks {', '.join(missing)} (columns: {', '.join(COLUMNS)})")
    return [_item(path, f"line {i}", row) for i, row in enumerate(reader, 2)]


def _item(manifest: Path, where: str, row: Any) -> BatchItem:
    if not isinstance(row, dict):
        raise InputError(manifest, f"{where}: expected a mapping with {', '.join(COLUMNS)}")
    unknown = sorted(set(map(str, row)) - set(COLUMNS))
    if unknown:
        raise InputError(manifest, f"{where}: unknown field {unknown[0]!r} (fields: {', '.join(COLUMNS)})")

    def file(key: str, required: bool) -> Path | None:
        value = row.get(key)
        if value is None or str(value).strip() == "":
            if required:
                raise InputError(manifest, f"{where}: `{key}` is missing")
            return None
        p = Path(str(value).strip()).expanduser()
        return p if p.is_absolute() else manifest.parent / p

    video = file("video", True)
    assert video is not None
    objects = file("objects", True)
    assert objects is not None
    name = str(row.get("name") or video.parent.name if row.get("name") is None else row["name"]).strip()
    return BatchItem(_name(manifest, where, name), video, objects, file("hands", False), file("truth", False),
                     file("categories", False))


def _name(manifest: Path, where: str, name: str) -> str:
    try:
        return check_name(name)
    except InputError as error:
        raise InputError(manifest, f"{where}: {error.message}") from None
