"""A plain `pip install .` (not editable) into a fresh venv gives a working wecook: its knowledge, skills and demo
are package data."""

from __future__ import annotations

import os
import shutil
import subprocess
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_pip_install_then_demo_headless(tmp_path: Path) -> None:
    source = tmp_path / "source"  # a copy, so the build leaves nothing in the repository
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, source / name)
    for package in ("wecook_core", "wecook_tui"):
        shutil.copytree(ROOT / package, source / package, ignore=shutil.ignore_patterns("__pycache__"))
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    python = env_dir / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "WECOOK_SESSIONS")}
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", str(source)], check=True, env=env,
                   cwd=tmp_path, timeout=600)
    done = subprocess.run([str(env_dir / "bin" / "wecook"), "demo", "--headless", "--root", str(tmp_path / "s")],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "against the truth: precision" in done.stdout
    assert (tmp_path / "s" / "demo" / "trees.yaml").is_file()
    where = subprocess.run([str(python), "-c", "import wecook_core; print(wecook_core.__file__)"],
                           capture_output=True, text=True, env=env, cwd=tmp_path, check=True)
    assert str(env_dir) in where.stdout and str(ROOT) not in where.stdout  # the installed copy, not the repo's
