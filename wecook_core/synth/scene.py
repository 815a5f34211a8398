"""The true state of every frame: where each hand, arm, body and object is, resolved from a script.

Positions are pixels of the nominal 640x360 image (the renderer and the detector scale them to the requested
size); arrays have one row per frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from wecook_core.model import Category
from wecook_core.synth.events import Appear, Effect, Glide, Resize, Ride, Turn
from wecook_core.synth.kitchen import Kind, category_of
from wecook_core.synth.layout import HALF_SHOULDERS, Body, box_of, extent
from wecook_core.synth.motion import elbows, hand_path, minimum_jerk, rotation
from wecook_core.synth.writer import Script


@dataclass(frozen=True, eq=False)
class ObjectPath:
    """One object over the whole scenario."""

    track_id: int
    name: str
    kind: Kind
    category: Category
    centre: np.ndarray
    """float64 ``(frames, 2)``, pixels."""
    angle: np.ndarray
    """float64 ``(frames,)``, radians of the local x axis."""
    size: np.ndarray
    """float64 ``(frames, 2)``: ``w, h`` along the local axes, pixels."""
    visible: np.ndarray
    """bool ``(frames,)``: the object is on the table (stirred-in ingredients vanish)."""
    held: np.ndarray
    """bool ``(frames,)``: riding on a hand (drawn above the others)."""
    worked: np.ndarray
    """int ``(frames,)``: how often it has been worked so far (cuts of the tomato, peels of the potato)."""

    @property
    def label(self) -> str:
        return self.kind.label

    def boxes(self) -> np.ndarray:
        """float64 ``(frames, 4)``: the true boxes, ``x1 y1 x2 y2``."""
        w, h = self.size[:, 0] / 2, self.size[:, 1] / 2
        c, s = np.abs(np.cos(self.angle)), np.abs(np.sin(self.angle))
        if self.kind.round:
            hx, hy = np.hypot(w * c, h * s), np.hypot(w * s, h * c)
        else:
            hx, hy = w * c + h * s, w * s + h * c
        half = np.stack([hx, hy], axis=1)
        return np.concatenate([self.centre - half, self.centre + half], axis=1)


@dataclass(frozen=True, eq=False)
class ArmPath:
    """One arm: shoulder, elbow, wrist and the hand's centre, ``(frames, 2)`` each."""

    hand: str
    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray
    centre: np.ndarray


@dataclass(frozen=True, eq=False)
class PersonPath:
    person: str
    neck: np.ndarray
    """float64 ``(frames, 2)``: the body leans towards the table when a hand reaches far."""
    forward: tuple[float, float]
    left: tuple[float, float]
    arms: tuple[ArmPath, ArmPath]
    """Left arm, right arm."""


@dataclass(frozen=True, eq=False)
class Scene:
    fps: float
    frames: int
    objects: tuple[ObjectPath, ...]
    persons: tuple[PersonPath, ...]
    effects: tuple[Effect, ...]


def _wrap(angle: float) -> float:
    return float((angle + np.pi) % (2 * np.pi) - np.pi)


def _angles(frames: int, home: float, turns: list[Turn], fps: float) -> np.ndarray:
    angle = np.full(frames, home)
    current, cursor = home, 0
    for turn in turns:
        a, b = min(turn.start, frames), min(turn.end, frames)
        angle[cursor:a] = current
        target = current + _wrap(turn.angle - current)
        s = minimum_jerk(np.arange(b - a) / max(turn.end - turn.start, 1))
        angle[a:b] = current + s * (target - current)
        current, cursor = target, b
    angle[cursor:] = current
    return angle


def _sizes(frames: int, base: tuple[float, float], resizes: list[Resize], fps: float) -> np.ndarray:
    scale = np.ones((frames, 2))
    current: np.ndarray = np.ones(2)
    cursor = 0
    for resize in resizes:
        a, b = min(resize.start, frames), min(resize.end, frames)
        scale[cursor:a] = current
        target = np.asarray(resize.scale)
        t = np.arange(b - a)
        if resize.pulses > 0:
            s = (1 - np.cos(2 * np.pi * resize.pulses * t / fps)) / 2
            scale[a:b] = current + s[:, None] * (target - current)
        else:
            s = minimum_jerk(t / max(resize.end - resize.start, 1))
            scale[a:b] = current + s[:, None] * (target - current)
            current = target
        cursor = b
    scale[cursor:] = current
    return scale * np.asarray(base)


def resolve(script: Script, rng: np.random.Generator) -> Scene:
    """Per-frame positions of everything in ``script`` (noise drawn from ``rng``)."""
    frames, fps = script.frames, script.fps
    layout = script.layout
    hands: dict[str, np.ndarray] = {}
    for body in layout.bodies:
        for hand, rest in body.rests.items():
            hands[hand] = hand_path(script.phases.get(hand, []), np.asarray(rest), frames, fps, rng)
    persons = tuple(_person(body, hands, frames, fps, rng) for body in layout.bodies)

    angles: dict[str, np.ndarray] = {}
    for name in layout.things:
        angles[name] = _angles(frames, _initial_angle(script, name), script.turns.get(name, []), fps)
    objects = []
    for name, thing in layout.things.items():
        centre = np.empty((frames, 2))
        visible = np.ones(frames, dtype=bool)
        held = np.zeros(frames, dtype=bool)
        current, cursor = _initial_home(script, name), 0
        for event in script.moves.get(name, []):
            if isinstance(event, Appear):
                a = min(event.frame, frames)
                centre[cursor:a] = current
                visible[a:] = event.visible
                if event.at is not None:
                    current = np.asarray(event.at)
                cursor = a
                continue
            a, b = min(event.start, frames), min(event.end, frames)
            centre[cursor:a] = current
            if isinstance(event, Ride):
                turn = rotation(angles[event.ref][a:b])
                centre[a:b] = hands[event.hand][a:b] + turn @ np.asarray(event.vector)
                held[a:b] = True
            elif isinstance(event, Glide):
                s = minimum_jerk(np.arange(b - a) / max(event.end - event.start, 1))
                centre[a:b] = current + s[:, None] * (np.asarray(event.to) - current)
            if b > a:
                current = centre[b - 1].copy()
            if isinstance(event, Glide) and b == event.end:
                current = np.asarray(event.to, dtype=float)
            cursor = b
        centre[cursor:] = current
        size = _sizes(frames, thing.kind.size, script.sizes.get(name, []), fps)
        worked = np.zeros(frames, dtype=np.int64)
        for mark in script.marks.get(name, []):
            worked[min(mark, frames):] += 1
        objects.append(ObjectPath(thing.track_id, name, thing.kind, category_of(thing.label), centre,
                                  angles[name], size, visible, held, worked))
    return Scene(fps, frames, tuple(objects), persons, tuple(script.effects))


def _initial_home(script: Script, name: str) -> np.ndarray:
    """Where the object lay at the start (handovers moved ``home`` while scheduling)."""
    return np.asarray(script.initial_homes[name], dtype=float)


def _initial_angle(script: Script, name: str) -> float:
    return float(script.layout.things[name].angle)


def _person(body: Body, hands: dict[str, np.ndarray], frames: int, fps: float, rng: np.random.Generator
            ) -> PersonPath:
    neck0 = np.asarray(body.neck)
    forward = np.asarray(body.forward)
    left = np.asarray(body.left)
    far = np.max([(hands[body.hand(s)] - neck0) @ forward for s in ("L", "R")], axis=0)
    lean = gaussian_filter1d(np.clip(far - 150.0, 0.0, 50.0), sigma=0.25 * fps, mode="nearest")
    sway = gaussian_filter1d(rng.normal(0.0, 1.0, (frames, 2)), sigma=1.5 * fps, axis=0, mode="nearest")
    sway *= 1.5 / max(float(np.std(sway)), 1e-9)
    neck = neck0 + lean[:, None] * forward + sway
    arms = []
    for side, sign in (("L", 1.0), ("R", -1.0)):
        hand = body.hand(side)
        shoulder = neck + sign * HALF_SHOULDERS * left
        elbow, wrist = elbows(shoulder, hands[hand], sign * left)
        arms.append(ArmPath(hand, shoulder, elbow, wrist, hands[hand]))
    return PersonPath(body.person, neck, body.forward, body.left, (arms[0], arms[1]))


__all__ = ["ArmPath", "ObjectPath", "PersonPath", "Scene", "box_of", "extent", "resolve"]
