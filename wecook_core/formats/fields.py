"""Reading numbers and boxes out of text fields of outside formats, with errors that name the place."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from pathlib import Path

from wecook_core.errors import InputError

Box = tuple[float, float, float, float]

MAX_FRAME = 10**7
"""The largest frame index an importer accepts: 10 million frames, 92 hours at 30 fps. Frames past the video
are refused later anyway; this bound comes first, so no importer ever sizes an array by a frame number it
was given (``10**25`` overflows a 64-bit index; ``10**9`` would fill memory)."""

MAX_ID = 2**31 - 1
"""The largest track (or image, category) id an importer accepts."""

MAX_COORDINATE = 1e6
"""Pixels: the largest magnitude of a coordinate an importer accepts (a frame is at most some thousands of
pixels; ``1e308`` would overflow every sum taken of it)."""

Warn = Callable[[str], None]
"""Where importers send findings that are not fatal (one line each)."""


def ignore_warning(message: str) -> None:
    """The default :data:`Warn`: drop the message."""


def check_box(path: str | Path, place: str, x1: float, y1: float, x2: float, y2: float) -> Box:
    """The box if its corners are ordered and within :data:`MAX_COORDINATE`, else :class:`InputError` at
    ``place``."""
    check_coordinates(path, place, "box", (x1, y1, x2, y2))
    if x2 < x1 or y2 < y1:
        raise InputError(path, f"box ({x1:g}, {y1:g}, {x2:g}, {y2:g}) has negative width or height", place=place)
    return (x1, y1, x2, y2)


def parse_float(path: str | Path, place: str, field: str, value: object) -> float:
    """A finite number from ``value`` (text or a JSON number) or :class:`InputError` naming ``field``."""
    if value is None:
        raise InputError(path, f"missing {field}", place=place)
    if isinstance(value, bool) or not isinstance(value, str | int | float):
        raise InputError(path, f"{field} must be a number, got {value!r}", place=place)
    try:
        number = float(value)
    except (ValueError, OverflowError):
        raise InputError(path, f"{field} must be a number, got {value!r}", place=place) from None
    if not math.isfinite(number):
        raise InputError(path, f"{field} must be a finite number, got {value!r}", place=place)
    return number


def parse_int(path: str | Path, place: str, field: str, value: object) -> int:
    """A whole number from ``value`` (``"12"``, ``"12.0"`` or ``12``) or :class:`InputError` naming ``field``."""
    number = parse_float(path, place, field, value)
    if number != int(number):
        raise InputError(path, f"{field} must be a whole number, got {value!r}", place=place)
    return int(number)


def check_coordinates(path: str | Path, place: str, field: str, values: Iterable[float]) -> None:
    """:class:`InputError` naming ``field`` when a value is not finite or beyond :data:`MAX_COORDINATE`."""
    for value in values:
        if not math.isfinite(value) or abs(value) > MAX_COORDINATE:
            raise InputError(path, f"{field} coordinate {value:g} is not a pixel position (beyond "
                             f"{MAX_COORDINATE:g})", place=place)


def check_frame(path: str | Path, place: str, frame: int, field: str = "frame") -> int:
    """``frame`` when ``0 <= frame <= MAX_FRAME``, else :class:`InputError` naming ``field``."""
    if frame < 0:
        raise InputError(path, f"{field} {frame} is negative", place=place)
    if frame > MAX_FRAME:
        raise InputError(path, f"{field} {frame} is beyond {MAX_FRAME}, the largest frame index wecook reads",
                         place=place)
    return frame


def check_id(path: str | Path, place: str, value: int, field: str = "id") -> int:
    """``value`` when ``|value| <= MAX_ID``, else :class:`InputError` naming ``field``."""
    if abs(value) > MAX_ID:
        raise InputError(path, f"{field} {value} is beyond {MAX_ID}, the largest id wecook reads", place=place)
    return value
