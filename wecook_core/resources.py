"""Where shipped data lives: ``wecook_core/assets/`` (package data), and the team's ``../shared`` (read in place)."""

from __future__ import annotations

import os
from pathlib import Path

REPO_DIR = Path(__file__).resolve().parents[1]
"""The checkout (or, once installed, the folder holding the package)."""
ASSETS_DIR = Path(__file__).resolve().parent / "assets"
"""Shipped data: knowledge tables, object categories, skills, the demo scenario."""


def shared_dir() -> Path:
    """`$WECOOK_SHARED`, else the `shared/` folder beside the checkout."""
    return Path(os.environ.get("WECOOK_SHARED", REPO_DIR.parent / "shared"))
