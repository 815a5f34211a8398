"""Sharper frames through the terminal's graphics protocol, where it has one (textual-image).

Half-blocks (:mod:`wecook_tui.frames`) work everywhere and stay the default. A terminal that shows images
gets the picture at its own pixel size instead: Kitty's graphics protocol (kitty, Ghostty) or Sixel (WezTerm,
foot, iTerm2 3.5+, mlterm, contour), drawn by the ``textual-image`` package (the ``graphics`` extra).

The protocol is chosen from the environment only, never by querying the terminal on every start: asking
costs up to a tenth of a second per question when the terminal does not answer, and can swallow a key
typed meanwhile. ``WECOOK_GRAPHICS`` decides (``auto``, ``kitty``, ``sixel``, ``halfblocks``); ``auto`` (the
default) uses a protocol only for a terminal known to have it, and never inside tmux or screen, which do not
pass images through by default. textual-image itself is imported only when a protocol is chosen, before the
app starts (it asks the terminal for its cell size then).
"""

from __future__ import annotations

import importlib.util
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import cv2
import numpy as np

from wecook_tui.frames import Overlay, contrasting, draw

PROTOCOLS = ("kitty", "sixel")
SIXEL_TERMINALS = ("WezTerm", "iTerm.app", "mlterm", "contour")
"""``$TERM_PROGRAM`` values of terminals that show Sixel images."""


def choose(env: Mapping[str, str], *, available: bool | None = None) -> str | None:
    """The graphics protocol to draw frames with (``kitty`` or ``sixel``), None for half-blocks.

    ``available``: whether textual-image is installed (None: look)."""
    wanted = env.get("WECOOK_GRAPHICS", "auto").strip().lower() or "auto"
    protocol = wanted if wanted in PROTOCOLS else _known_terminal(env) if wanted == "auto" else None
    if protocol is None:
        return None
    if available is None:
        available = importlib.util.find_spec("textual_image") is not None
    return protocol if available else None


def _known_terminal(env: Mapping[str, str]) -> str | None:
    if env.get("TMUX") or env.get("STY") or env.get("TERM", "").startswith(("screen", "tmux")):
        return None
    term, program = env.get("TERM", ""), env.get("TERM_PROGRAM", "")
    if term in ("xterm-kitty", "xterm-ghostty") or env.get("KITTY_WINDOW_ID") or program == "ghostty":
        return "kitty"
    if program in SIXEL_TERMINALS or term.startswith(("foot", "mlterm", "contour")):
        return "sixel"
    return None


@dataclass(frozen=True)
class Graphics:
    """A chosen protocol: the textual-image widget class and the terminal's cell size in pixels."""

    protocol: str
    widget: Any
    """A ``textual_image.widget`` class (``TGPImage`` or ``SixelImage``)."""
    cell: tuple[int, int]
    """(width, height) of a cell in pixels."""

    def picture_size(self, cells: tuple[int, int], video_size: tuple[int, int]) -> tuple[int, int]:
        """(width, height) in pixels of the video fitted into ``cells`` (columns, rows) at this cell size."""
        columns, rows = cells
        vw, vh = video_size
        if vw <= 0 or vh <= 0 or columns <= 0 or rows <= 0:
            return (max(1, columns * self.cell[0]), max(1, rows * self.cell[1]))
        scale = min(columns * self.cell[0] / vw, rows * self.cell[1] / vh)
        return (max(1, int(vw * scale)), max(1, int(vh * scale)))

    def cells_of(self, size: tuple[int, int]) -> tuple[int, int]:
        """The cells (columns, rows) a picture of ``size`` pixels covers."""
        return (max(1, -(-size[0] // self.cell[0])), max(1, -(-size[1] // self.cell[1])))


def load(protocol: str) -> Graphics | None:
    """textual-image's widget for ``protocol`` (imported now, while the terminal can still be asked its cell
    size); None when it cannot be imported."""
    try:
        from textual_image._terminal import get_cell_size
        from textual_image.widget import SixelImage, TGPImage
    except (ImportError, OSError):
        return None
    try:
        size = get_cell_size()
        cell = (int(size.width) or 10, int(size.height) or 20)
    except Exception:  # a closed or odd terminal: the VT340's cells
        cell = (10, 20)
    return Graphics(protocol, TGPImage if protocol == "kitty" else SixelImage, cell)


def picture(image: np.ndarray, overlay: Overlay, video_size: tuple[int, int]) -> np.ndarray:
    """``image`` (BGR, the picture's size) with the overlay drawn and its labels written as text in pixels:
    the name above each box (below at the top edge) on the box colour, hands' names beside their markers."""
    out = draw(image, replace(overlay, labels=False), video_size).image
    if not overlay.labels:
        return out
    height, width = out.shape[:2]
    vw, vh = video_size
    sx, sy = (width / vw if vw else 1.0), (height / vh if vh else 1.0)
    scale = max(0.35, min(0.8, height / 900))
    thick = 1
    for mark in overlay.boxes:
        colour = (255, 255, 255) if mark.selected else mark.colour
        x1, y1, _, y2 = mark.box
        (tw, th), base = cv2.getTextSize(mark.name, cv2.FONT_HERSHEY_SIMPLEX, scale, thick)
        x = int(min(max(0, x1 * sx), max(0, width - tw - 2)))
        top = int(y1 * sy) - th - base - 2
        y = top if top >= 0 else int(y2 * sy) + 2
        cv2.rectangle(out, (x, y), (x + tw + 2, y + th + base + 2), colour[::-1], -1)
        cv2.putText(out, mark.name, (x + 1, y + th + 1), cv2.FONT_HERSHEY_SIMPLEX, scale,
                    contrasting(colour)[::-1], thick, cv2.LINE_AA)
    for hand in overlay.hands:
        x, y = int(hand.xy[0] * sx) + 6, int(hand.xy[1] * sy)
        cv2.putText(out, hand.hand, (x, y), cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), thick + 2, cv2.LINE_AA)
        cv2.putText(out, hand.hand, (x, y), cv2.FONT_HERSHEY_SIMPLEX, scale, hand.colour[::-1], thick, cv2.LINE_AA)
    return out


def to_pil(image: np.ndarray) -> Any:
    """The BGR picture as a ``PIL.Image`` (RGB), what textual-image draws."""
    from PIL import Image

    return Image.fromarray(np.ascontiguousarray(image[..., ::-1]))
