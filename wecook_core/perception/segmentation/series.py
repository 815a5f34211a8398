"""Reading a numeric series from a text file: one sample per line, whitespace- or comma-separated numbers."""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from wecook_core.errors import InputError, read_input_text

_SEPARATORS = re.compile(r"[,\s]+")


def load_series(path: str | Path, columns: Sequence[int] | None = None) -> np.ndarray:
    """float64 ``(samples, features)``: one row per non-blank line (``#`` starts a comment).

    Cells are separated by commas and/or whitespace. ``columns`` (0-based) selects and orders features;
    default all. Raises :class:`InputError` naming the file and line for a missing or empty file, a cell
    that is not a finite number, a row whose length differs from the first row's, or a column out of range.
    """
    path = Path(path)
    text = read_input_text(path, "no such file")
    rows: list[list[float]] = []
    width = 0
    for number, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip().strip(",")
        if not content:
            continue
        cells = _SEPARATORS.split(content)
        if not rows:
            width = len(cells)
            for column in columns or ():
                if not 0 <= column < width:
                    raise InputError(path, f"column {column} out of range: rows have {width} columns "
                                     f"(0..{width - 1})", place=f"line {number}")
        elif len(cells) != width:
            raise InputError(path, f"{len(cells)} columns, expected {width} like the first row",
                             place=f"line {number}")
        row = []
        for index, cell in enumerate(cells):
            try:
                value = float(cell)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise InputError(path, f"column {index}: {cell!r} is not a finite number", place=f"line {number}")
            row.append(value)
        rows.append(row)
    if not rows:
        raise InputError(path, "no samples: the file is empty (expected one row of numbers per line)")
    data = np.array(rows, dtype=np.float64)
    if columns is not None:
        data = data[:, list(columns)]
    return data
