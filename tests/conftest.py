from __future__ import annotations

from pathlib import Path

import pytest

from wecook_core.knowledge.recognize import Knowledge, load_knowledge
from wecook_core.resources import shared_dir


@pytest.fixture(scope="session")
def shared() -> Path:
    path = shared_dir()
    assert path.is_dir(), f"the team's shared data folder is missing: {path}"
    return path


@pytest.fixture(scope="session")
def knowledge() -> Knowledge:
    """The shipped commonsense tables."""
    return load_knowledge()
