"""Synthetic hand trajectories with known breakpoints, for tests and benchmarks.

A hand rests at a home position, reaches a work spot, works there (small noisy motion: stirring, cutting),
pauses, returns home, and so on. Every phase change is a true breakpoint.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class SyntheticTrajectory:
    xy: np.ndarray
    """float64 ``(frames, 2)``, hand centre in pixels (top-left origin)."""
    breakpoints: tuple[int, ...]
    """Frames where a new phase starts (interior: never 0)."""
    phases: tuple[str, ...]
    """Phase names, one per segment: ``rest reach work pause return``."""


def hand_trajectory(
    rng: np.random.Generator,
    frames: int,
    *,
    width: float = 1280.0,
    height: float = 720.0,
    cycle: tuple[int, int, int, int, int] = (90, 24, 150, 45, 24),
    jitter: float = 1.0,
    work_spread: float = 12.0,
) -> SyntheticTrajectory:
    """Repeat rest / reach / work / pause / return cycles until ``frames`` frames are filled.

    ``cycle`` gives each phase's mean length in frames (each drawn within ±30 %); ``jitter`` is the tracker's
    noise in pixels (every phase), ``work_spread`` the extra motion while working, in pixels.
    """
    home = np.array([width * rng.uniform(0.1, 0.3), height * rng.uniform(0.6, 0.9)])
    pieces: list[np.ndarray] = []
    names: list[str] = []
    breaks: list[int] = []
    done = 0
    where = home
    while done < frames:
        spot = np.array([width * rng.uniform(0.35, 0.9), height * rng.uniform(0.2, 0.7)])
        for name, mean_len in zip(("rest", "reach", "work", "pause", "return"), cycle, strict=True):
            length = max(4, round(mean_len * rng.uniform(0.7, 1.3)))
            t = (np.arange(length) + 1) / length
            if name in ("reach", "return"):
                goal = spot if name == "reach" else home
                ease = 0.5 - 0.5 * np.cos(np.pi * t)  # smooth start and stop, like a real reach
                piece = where + ease[:, None] * (goal - where)
                where = goal
            elif name == "work":
                angle = 2 * np.pi * t * length / 20 + rng.uniform(0, 2 * np.pi)
                circle = np.stack([np.cos(angle), np.sin(angle)], axis=1) * work_spread
                piece = where + circle + rng.normal(0, work_spread / 3, (length, 2))
            else:
                piece = np.repeat(where[None], length, axis=0)
            pieces.append(piece + rng.normal(0, jitter, (length, 2)))
            names.append(name)
            if done > 0:
                breaks.append(done)
            done += length
    xy = np.concatenate(pieces)[:frames]
    kept = [b for b in breaks if b < frames]
    return SyntheticTrajectory(xy=xy, breakpoints=tuple(kept), phases=tuple(names[: len(kept) + 1]))
