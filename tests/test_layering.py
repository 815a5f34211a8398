"""The core never imports the UI: every module of wecook_core imports without textual or wecook_tui."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import wecook_core

SCRIPT = """
import importlib, pkgutil, sys
import wecook_core
for module in pkgutil.walk_packages(wecook_core.__path__, "wecook_core."):
    importlib.import_module(module.name)
bad = sorted(m for m in sys.modules if m.split(".")[0] in ("textual", "wecook_tui"))
print(" ".join(bad))
"""


@pytest.mark.slow
def test_core_never_imports_the_ui() -> None:
    result = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=120,
                            cwd=Path(wecook_core.__file__).parents[1])
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == ""


def test_no_textual_import_statement_in_core() -> None:
    root = Path(wecook_core.__file__).parent
    offenders = [
        str(path) for path in root.rglob("*.py")
        if any(line.lstrip().startswith(("import textual", "from textual", "from wecook_tui", "import wecook_tui"))
               for line in path.read_text().splitlines())
    ]
    assert offenders == []


WORLD_SCRIPT = """
import importlib, pkgutil, sys
import wecook_core.execution.world as world
for module in pkgutil.walk_packages(world.__path__, "wecook_core.execution.world."):
    importlib.import_module(module.name)
importlib.import_module("wecook_core.execution.schedule.executor")
importlib.import_module("wecook_core.execution.skills.library")
bad = sorted(m for m in sys.modules if m.split(".")[0] in ("pybullet", "pybullet_data", "ompl")
             or m.startswith("wecook_core.execution.bullet") or m.startswith("wecook_core.recording"))
print(" ".join(bad))
"""


@pytest.mark.slow
def test_the_world_its_skills_and_the_scheduler_import_no_simulator() -> None:
    """The primitives and roles are written against protocols (world/protocols.py): loading them, the skills and
    the scheduler loads neither pybullet nor the adapter, so they run against the tests' plain-Python fake."""
    result = subprocess.run([sys.executable, "-c", WORLD_SCRIPT], capture_output=True, text=True, timeout=120,
                            cwd=Path(wecook_core.__file__).parents[1])
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == ""
