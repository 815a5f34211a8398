"""What a batch must give back: the shared scenarios made, analysed and exported one session at a time."""

from __future__ import annotations

from pathlib import Path

from wecook_core.resources import shared_dir
from wecook_tui.cli import main

SCENARIOS = shared_dir() / "data" / "scenarios"


def one_session_at_a_time(root: Path, names: list[str]) -> Path:
    """The shared scenarios ``names`` made, analysed and exported one by one with the CLI, into ``root``."""
    for name in names:
        folder = SCENARIOS / name
        assert main(["new", name, "--root", str(root), "--video", str(folder / "video.mp4"),
                     "--objects", str(folder / "objects.xml"), "--hands", str(folder / "openpose")]) == 0
        assert main(["analyze", name, "--root", str(root)]) == 0
        assert main(["export", name, "--root", str(root)]) == 0
    return root
