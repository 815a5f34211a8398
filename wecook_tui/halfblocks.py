"""Half-block rendering: a picture as terminal cells, two pixels per cell.

A terminal cell shows two pixels stacked: the upper-half-block character ``▀`` with the top pixel as its
foreground colour and the bottom pixel as its background. That works in every terminal with true colour (and
degrades gracefully in 256-colour ones), so the frame view never depends on a graphics protocol.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from rich.color import Color
from rich.segment import Segment
from rich.style import Style
from textual.strip import Strip

HALF_BLOCK = "▀"


@dataclass(frozen=True)
class Label:
    """Text placed on the half-block image, in cells."""

    x: int
    y: int
    text: str
    colour: tuple[int, int, int]
    background: tuple[int, int, int] | None = None
    """The cells' background; None: the image under the label."""


@dataclass
class Canvas:
    """An image the size of the view (2 pixels per cell row) with the labels to print over it."""

    image: np.ndarray
    labels: list[Label] = field(default_factory=list)


# ----------------------------------------------------------------------------------- half blocks

_COLOURS: dict[int, Color] = {}
_QUANT = 0xF8
"""Colours are quantised to 5 bits per channel: fewer distinct styles, same look at this resolution."""


def _colour(packed: int) -> Color:
    colour = _COLOURS.get(packed)
    if colour is None:
        colour = Color.from_rgb(packed >> 16, (packed >> 8) & 255, packed & 255)
        _COLOURS[packed] = colour
    return colour


_PAIR_STYLES: dict[int, Style] = {}


def _pair_style(key: int) -> Style:
    """The style of a cell whose (top, bottom) colours are packed as ``top << 24 | bottom``."""
    style = _PAIR_STYLES.get(key)
    if style is None:
        if len(_PAIR_STYLES) > 200_000:
            _PAIR_STYLES.clear()
        style = Style.from_color(_colour(key >> 24), _colour(key & 0xFFFFFF))
        _PAIR_STYLES[key] = style
    return style


def _label_cells(labels: list[Label], bottom: list[int], width: int) -> dict[int, Segment]:
    cells: dict[int, Segment] = {}
    for label in labels:
        fg = _colour(_pack(label.colour))
        bg = _colour(_pack(label.background)) if label.background is not None else None
        for offset, char in enumerate(label.text[: max(0, width - label.x)]):
            x = label.x + offset
            cells[x] = Segment(char, Style.from_color(fg, bg or _colour(bottom[x])) + _BOLD)
    return cells


_BOLD = Style(bold=True)


def _pack(rgb: tuple[int, int, int]) -> int:
    return ((rgb[0] & _QUANT) << 16) | ((rgb[1] & _QUANT) << 8) | (rgb[2] & _QUANT)


_RUNS: dict[int, Segment] = {}
"""Half-block runs by ``(top << 24 | bottom) << 10 | length``: a frame step reuses most of them."""


def to_strips(canvas: Canvas) -> list[Strip]:
    """One :class:`Strip` per pair of pixel rows; labels overwrite cells with text on the bottom colour.

    Runs of equal cells are found with numpy over the whole picture at once; Python only looks each run's
    segment up (built once, reused by later frames). Rows with labels are spliced cell by cell.
    """
    image = canvas.image
    if image.shape[0] % 2:
        image = np.vstack([image, image[-1:]])
    rgb = (image[..., ::-1] & _QUANT).astype(np.uint64)
    packed = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
    keys = (packed[0::2] << 24) | packed[1::2]
    rows, width = keys.shape
    labels_by_row: dict[int, list[Label]] = {}
    for label in canvas.labels:
        labels_by_row.setdefault(label.y, []).append(label)
    change = np.ones((rows, width), dtype=bool)
    change[:, 1:] = keys[:, 1:] != keys[:, :-1]
    if width >= 1024:  # too wide to pack a run's length in 10 bits: cell by cell
        return [_row_strip(keys[row], change[row], packed[2 * row + 1], labels_by_row.get(row), width)
                for row in range(rows)]
    cells_by_row: dict[int, dict[int, Segment]] = {}
    for row, labels in labels_by_row.items():
        if 0 <= row < rows:
            cells = cells_by_row[row] = _label_cells(labels, packed[2 * row + 1].tolist(), width)
            for x in cells:  # a label's cell starts a run of its own, and the cell after it another
                change[row, x] = True
                if x + 1 < width:
                    change[row, x + 1] = True
    flat_keys = keys.ravel()
    starts = np.flatnonzero(change.ravel())
    lengths = np.diff(np.append(starts, rows * width)).astype(np.uint64)  # every row starts a run
    runs = ((flat_keys[starts] << np.uint64(10)) | lengths).tolist()  # a run's key and length in one int
    row_starts = np.searchsorted(starts, np.arange(rows + 1) * width).tolist()
    if len(_RUNS) > 300_000:
        _RUNS.clear()
    strips: list[Strip] = []
    for row in range(rows):
        segments: list[Segment] = []
        append = segments.append
        row_cells = cells_by_row.get(row)
        x = 0
        for run in runs[row_starts[row]:row_starts[row + 1]]:
            if row_cells is not None and x in row_cells:
                append(row_cells[x])  # a label's cell: the run (one cell long) is the label's character
                x += 1
                continue
            segment = _RUNS.get(run)
            if segment is None:
                segment = _RUNS[run] = Segment(HALF_BLOCK * (run & 1023), _pair_style(run >> 10))
            append(segment)
            x += run & 1023
        strips.append(Strip(segments, width))
    return strips


def _row_strip(row_keys: np.ndarray, change: np.ndarray, bottom: np.ndarray, labels: list[Label] | None,
               width: int) -> Strip:
    """One row's strip, with its labels' cells."""
    starts = np.flatnonzero(change).tolist()
    cells = _label_cells(labels, bottom.tolist(), width) if labels else None
    if cells:
        starts = sorted(set(starts) | set(cells) | {x + 1 for x in cells if x + 1 < width})
    run_keys = row_keys[starts].tolist()
    ends = [*starts[1:], width]
    segments: list[Segment] = []
    for start, end, key in zip(starts, ends, run_keys, strict=True):
        if cells is not None and start in cells:
            segments.append(cells[start])
            if end - start > 1:
                segments.append(Segment(HALF_BLOCK * (end - start - 1), _pair_style(key)))
        else:
            segments.append(Segment(HALF_BLOCK * (end - start), _pair_style(key)))
    return Strip(segments, width)
