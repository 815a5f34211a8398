"""Benchmarks (not tests): `make bench` runs every module here and prints one table.

Each module exposes ``run() -> list[dict]`` with rows ``{"benchmark", "value", "unit", "ratio_vs_baseline",
"note"}``. Speed is reported as a ratio against a baseline measured in the same run, since this machine is
shared and noisy.
"""
