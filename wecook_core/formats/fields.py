"""Reading numbers and boxes out of text fields of outside formats, with errors that name the place."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

from wecook_core.errors import InputError

Box = tuple[float, float, float, float]

Warn = Callable[[str], None]
"""Where importers send findings that are not fatal (one line each)."""


def ignore_warning(message: str) -> None:
    """The default :data:`Warn`: drop the message."""


def check_box(path: str | Path, place: str, x1: float, y1: float, x2: float, y2: float) -> Box:
    """The box if its corners are ordered, else :class:`InputError` at ``place``."""
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
    except ValueError:
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
