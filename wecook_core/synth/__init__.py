"""Synthetic cooking scenarios with known answers: the demo, the tests and the benchmarks run on them.

>>> scenario = synthesize(7)                      # pure: same seed, same scenario
>>> write_scenario(scenario, "out/")               # video.mp4, objects.csv, hands.csv, openpose/, truth.yaml
"""

from __future__ import annotations

from wecook_core.synth.scenario import Scenario, synthesize, write_scenario

__all__ = ["Scenario", "synthesize", "write_scenario"]
