from __future__ import annotations

from pathlib import Path

import pytest
from tui_scenario import write_inputs


@pytest.fixture(scope="session")
def scenario_inputs(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, Path]:
    """The small kitchen scenario's video and CSVs, written once per test run."""
    return write_inputs(tmp_path_factory.mktemp("scenario"))


@pytest.fixture(params=["kitchen", pytest.param("demo", marks=pytest.mark.slow)])
def session_path(request: pytest.FixtureRequest, tmp_path: Path, scenario_inputs: tuple[Path, Path, Path]) -> Path:
    """A fresh session (real `create_session`): the small kitchen scenario, or the bundled demo
    (`wecook demo`'s own code path, two persons, 1459 frames, every tree case)."""
    from wecook_core.session.store import create_session
    from wecook_core.workflows import demo_session

    if request.param == "demo":
        return demo_session(tmp_path / "sessions")
    video, objects, hands = scenario_inputs
    return Path(create_session(tmp_path / "sessions", "kitchen", video, objects, hands))


@pytest.fixture(autouse=True)
def no_user_keys(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Tests never read the developer's own key file."""
    monkeypatch.setenv("WECOOK_KEYS", str(tmp_path / "no-keys.toml"))
