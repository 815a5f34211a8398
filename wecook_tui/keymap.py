"""User key bindings: a TOML file mapping binding ids to keys, applied with ``App.set_keymap``.

The file is ``$WECOOK_KEYS`` if set, else ``~/.config/wecook/keys.toml``. Either a ``[keys]`` table or
top-level entries; a value is a key or a comma-separated list of keys (Textual key names)::

    [keys]
    next-frame = "right,l"
    accept = "enter"

Unknown ids and bad values are reported (never fatal): the defaults stay for those bindings.
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path


@dataclass(frozen=True)
class LoadedKeymap:
    keymap: dict[str, str] = field(default_factory=dict)
    """Binding id -> comma-separated keys."""
    path: Path | None = None
    """The file read, if any."""
    problems: tuple[str, ...] = ()
    """One line each: the file and what is wrong."""


def keymap_path() -> Path:
    override = os.environ.get("WECOOK_KEYS")
    if override:
        return Path(override).expanduser()
    return Path("~/.config/wecook/keys.toml").expanduser()


def load_keymap(path: Path | None = None, known_ids: set[str] | None = None) -> LoadedKeymap:
    """Read the key file; a missing file gives an empty keymap, a broken one a problem line."""
    path = path or keymap_path()
    if not path.is_file():
        return LoadedKeymap()
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as error:
        return LoadedKeymap(path=path, problems=(f"{path}: not a key file ({error}); default keys used",))
    table = data.get("keys", data)
    if not isinstance(table, dict):
        return LoadedKeymap(path=path, problems=(f"{path}: [keys] must be a table of id = \"keys\"",))
    keymap: dict[str, str] = {}
    problems: list[str] = []
    for binding_id, value in table.items():
        if isinstance(value, list) and all(isinstance(v, str) for v in value):
            value = ",".join(value)
        if not isinstance(value, str) or not value.strip():
            problems.append(f"{path}: {binding_id}: expected a key string like \"ctrl+s\" or \"a,b\"")
            continue
        if known_ids is not None and binding_id not in known_ids:
            problems.append(f"{path}: {binding_id}: no such binding (see the help screen for ids)")
            continue
        keymap[binding_id] = ",".join(key.strip() for key in value.split(",") if key.strip())
    return LoadedKeymap(keymap=keymap, path=path, problems=tuple(problems))
