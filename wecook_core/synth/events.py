"""What happens to an object in a synthetic scenario, frame span by frame span: it rides on a hand, glides,
appears or vanishes, turns, changes size; and what is drawn between two objects (a stream of oil, falling salt).
The script (:mod:`wecook_core.synth.script`) writes them; the scene (:mod:`wecook_core.synth.scene`) plays them."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Ride:
    """The object's centre is ``hand + R(angle of ref) @ vector`` on frames ``[start, end)``; afterwards it
    stays where it was left."""

    start: int
    end: int
    hand: str
    ref: str
    """The object whose angle turns ``vector`` (the object itself, or the container / spoon it rides in)."""
    vector: tuple[float, float]


@dataclass(frozen=True)
class Glide:
    """The object slides from where it is to ``to`` on frames ``[start, end)`` (tipped into the pot)."""

    start: int
    end: int
    to: tuple[float, float]


@dataclass(frozen=True)
class Appear:
    """From ``frame`` on the object is (``visible``) or is not there; when it appears it lies at ``at``."""

    frame: int
    visible: bool
    at: tuple[float, float] | None = None


@dataclass(frozen=True)
class Turn:
    """The object's angle goes to ``angle`` (radians) over ``[start, end)``."""

    start: int
    end: int
    angle: float


@dataclass(frozen=True)
class Resize:
    """The object's size goes to ``scale`` times its kind's size over ``[start, end)``; with ``pulse`` it
    springs back afterwards (``pulses`` squeezes per second)."""

    start: int
    end: int
    scale: tuple[float, float]
    pulses: float = 0.0


PositionEvent = Ride | Glide | Appear


@dataclass(frozen=True)
class Effect:
    """Something drawn between two objects: a stream of oil, falling salt."""

    kind: str
    """``pour`` or ``sprinkle``."""
    start: int
    end: int
    source: str
    target: str
