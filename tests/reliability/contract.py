"""The contract every reader of the user's files keeps, and malformed variants of good files to test it with."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from hypothesis import strategies as st

from wecook_core.errors import InputError

NASTY = ["", "-1", "0", "1e400", "-1e400", "nan", "inf", "1e308", "1" + "0" * 25, "9" * 5000, "1.5", "x", "\ufeff",
         "\x00", "'", '"', ",", "[", "{", "]]]", "<", "&amp;", "\u00e9", "\n", "true", "null", "*a", "&a",
         "!!python/none"]
"""Tokens that break parsers: huge, non-finite, negative, quoting, nesting, encoding."""


def keeps_contract(read: Callable[[], Any], named: str | Path) -> Any:
    """Call ``read``: it returns, or raises an :class:`InputError` whose one line names ``named``; anything else
    (another exception, a message of several lines) fails the test."""
    try:
        return read()
    except InputError as error:
        line = str(error)
        assert "\n" not in line and len(line) <= 2000, line[:300]
        assert str(named) in line, f"{line!r} does not name {named}"
        return error


@st.composite
def mutated(draw: st.DrawFn, good: bytes) -> bytes:
    """``good`` with a few edits: bytes replaced, tokens inserted, a piece cut out or repeated, a tail torn."""
    data = bytearray(good)
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["byte", "token", "cut", "repeat", "tear"]))
        at = draw(st.integers(0, max(len(data) - 1, 0)))
        if kind == "byte" and data:
            data[at] = draw(st.integers(0, 255))
        elif kind == "token":
            data[at:at] = draw(st.sampled_from(NASTY)).encode("utf-8")
        elif kind == "cut":
            del data[at: at + draw(st.integers(1, 40))]
        elif kind == "repeat":
            data[at:at] = data[at: at + draw(st.integers(1, 40))] * draw(st.integers(2, 5))
        else:
            del data[at:]
    return bytes(data)


@st.composite
def field_swapped(draw: st.DrawFn, good: str, separators: str = ",\n") -> str:
    """``good`` text with a few of its fields (runs between ``separators``) replaced by :data:`NASTY` tokens."""
    pieces: list[str] = []
    current = ""
    for char in good:
        if char in separators:
            pieces += [current, char]
            current = ""
        else:
            current += char
    pieces.append(current)
    fields = [k for k in range(0, len(pieces), 2)]
    for _ in range(draw(st.integers(1, 3))):
        pieces[draw(st.sampled_from(fields))] = draw(st.sampled_from(NASTY))
    return "".join(pieces)
