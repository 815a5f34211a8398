"""Synthetic cooking scenarios with known answers: the demo, the tests and the benchmarks run on them.

A top-down kitchen table with one or two persons (P1 at the left edge, P2 at the right) who cut, peel, roll,
squeeze, stir, pour, sprinkle, transfer with a spoon or by tipping a bowl, hold the pot (or the chopping
board) for each other and pass things over. Every tree case of DESIGN.md's table appears in a two-person
scenario; the true trees run from the grasp that starts each action to the release that ends it.

>>> scenario = synthesize(7)                  # pure: the same seed gives the same scenario
>>> write_scenario(scenario, "out/")           # video.mp4, objects.csv, hands.csv, openpose/, truth.yaml

Modules: :mod:`.kitchen` (what objects look like), :mod:`.layout` (where they lie), :mod:`.script` (who does
what when: the scheduler), :mod:`.tasks` (each task kind), :mod:`.writer` (what tasks share), :mod:`.motion` (how
hands move), :mod:`.scene` (every frame's true state), :mod:`.detect` (what
detectors report: jitter, dropouts, keypoints), :mod:`.render` (OpenCV drawing), :mod:`.openpose` (the
OpenPose JSON folder), :mod:`.scenario` (the public functions), :mod:`.files`
(writing a scenario to disk).
"""

from __future__ import annotations

from pathlib import Path

from wecook_core.resources import ASSETS_DIR
from wecook_core.synth.files import write_scenario
from wecook_core.synth.scenario import Scenario, synthesize

DEMO_SEED = 2074
"""The seed of the bundled demo (``wecook_core/assets/demo``): two persons, every case, 48.6 s at 30 fps, 640x360."""
DEMO_DIR = ASSETS_DIR / "demo"


def demo_dir() -> Path:
    """The bundled demo scenario: ``video.mp4``, ``objects.csv``, ``hands.csv``, ``truth.yaml`` (no
    ``openpose/``: :func:`write_demo_openpose` writes it)."""
    return DEMO_DIR


def demo_scenario() -> Scenario:
    """The scenario of the bundled demo, in memory (same as the files of :func:`demo_dir`)."""
    return synthesize(DEMO_SEED)


def write_demo(out_dir: str | Path = DEMO_DIR, *, openpose: bool = False) -> Path:
    """Regenerate the demo's files (``wecook synth assets/demo --seed 2074 --no-openpose`` does the same)."""
    return write_scenario(demo_scenario(), out_dir, openpose=openpose)


def write_demo_openpose(out_dir: str | Path) -> Path:
    """The demo's OpenPose folder (about 6 MB of small JSON files, so not shipped), written to ``out_dir``."""
    from wecook_core.synth.openpose import write_openpose

    return write_openpose(demo_scenario(), out_dir)


__all__ = [
    "DEMO_SEED", "Scenario", "demo_dir", "demo_scenario", "synthesize", "write_demo", "write_demo_openpose",
    "write_scenario",
]
