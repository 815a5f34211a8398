from __future__ import annotations

import pytest

from wecook_core.knowledge.recognize import Knowledge, load_knowledge


@pytest.fixture(scope="session")
def knowledge() -> Knowledge:
    """The shipped commonsense tables."""
    return load_knowledge()
