"""Drawing a scene with OpenCV: a top-down kitchen table, objects as simple coloured shapes, the persons'
heads, shoulders and arms reaching in from the table's edges. Frames are written with ``cv2.VideoWriter``
(mp4v).

Shapes are built as polygons in the nominal 640x360 frame and mapped to the output size, so the drawing and
the boxes agree at any size. Rendering is deterministic: the same scenario gives the same pixels.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import cv2
import numpy as np

from wecook_core.model import Category
from wecook_core.synth.layout import HEIGHT, WIDTH
from wecook_core.synth.motion import rotation
from wecook_core.synth.scene import ObjectPath, PersonPath, Scene

if TYPE_CHECKING:
    from wecook_core.synth.scenario import Scenario

SHIFT = 3
"""Sub-pixel bits for OpenCV's polygon drawing."""
SKIN = (140, 170, 215)
SHIRTS = {"P1": (150, 90, 40), "P2": (60, 60, 170)}
HAIR = (30, 40, 60)
TABLE = (125, 165, 195)
BLACK = (30, 30, 30)


class _Canvas:
    def __init__(self, size: tuple[int, int]) -> None:
        self.size = size
        self.scale = np.array([size[0] / WIDTH, size[1] / HEIGHT])
        self.image = np.zeros((size[1], size[0], 3), dtype=np.uint8)

    def _pts(self, points: np.ndarray) -> np.ndarray:
        return np.round(np.asarray(points) * self.scale * (1 << SHIFT)).astype(np.int32).reshape(-1, 1, 2)

    def poly(self, points: np.ndarray, colour: tuple[int, int, int], outline: tuple[int, int, int] | None = None
             ) -> None:
        pts = self._pts(points)
        cv2.fillPoly(self.image, [pts], colour, cv2.LINE_AA, SHIFT)
        if outline is not None:
            cv2.polylines(self.image, [pts], True, outline, 1, cv2.LINE_AA, SHIFT)

    def line(self, a: np.ndarray, b: np.ndarray, colour: tuple[int, int, int], width: float) -> None:
        pts = self._pts(np.array([a, b])).reshape(2, 2)
        thickness = max(1, round(width * float(self.scale.mean())))
        cv2.line(self.image, tuple(int(v) for v in pts[0]), tuple(int(v) for v in pts[1]), colour, thickness,
                 cv2.LINE_AA, SHIFT)

    def dot(self, centre: np.ndarray, radius: float, colour: tuple[int, int, int]) -> None:
        pts = self._pts(np.asarray(centre)).reshape(2)
        r = max(1, round(radius * float(self.scale.mean()) * (1 << SHIFT)))
        cv2.circle(self.image, (int(pts[0]), int(pts[1])), r, colour, -1, cv2.LINE_AA, SHIFT)


_CIRCLE = np.stack([np.cos(np.linspace(0, 2 * np.pi, 28, endpoint=False)),
                    np.sin(np.linspace(0, 2 * np.pi, 28, endpoint=False))], axis=1)


def _ellipse(centre: np.ndarray, w: float, h: float, angle: float, local: tuple[float, float] = (0, 0)
             ) -> np.ndarray:
    pts = _CIRCLE * (w / 2, h / 2) + local
    return centre + pts @ rotation(angle).T


def _rect(centre: np.ndarray, x0: float, x1: float, y0: float, y1: float, angle: float) -> np.ndarray:
    pts = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=float)
    return centre + pts @ rotation(angle).T


def _shade(colour: tuple[int, int, int], factor: float) -> tuple[int, int, int]:
    b, g, r = (min(255, max(0, int(c * factor))) for c in colour)
    return (b, g, r)


def draw_object(canvas: _Canvas, path: ObjectPath, frame: int) -> None:
    c, a = path.centre[frame], float(path.angle[frame])
    w, h = (float(v) for v in path.size[frame])
    colour = path.kind.colour
    style = path.kind.style
    dark = _shade(colour, 0.6)
    if style == "knife":
        canvas.poly(_rect(c, -w / 2, -w / 2 + 0.36 * w, -h / 2, h / 2, a), (40, 60, 95), BLACK)
        blade = np.array([(-w / 2 + 0.36 * w, -0.4 * h), (w / 2 - 0.12 * w, -0.4 * h), (w / 2, 0.4 * h),
                          (-w / 2 + 0.36 * w, 0.4 * h)])
        canvas.poly(c + blade @ rotation(a).T, colour, dark)
    elif style == "spoon":
        canvas.poly(_rect(c, -w / 2, 0.1 * w, -0.2 * h, 0.2 * h, a), colour, dark)
        canvas.poly(_ellipse(c, 0.4 * w, h, a, (0.3 * w, 0)), colour, dark)
    elif style == "peeler":
        canvas.poly(_rect(c, -w / 2, 0.05 * w, -0.35 * h, 0.35 * h, a), colour, dark)
        canvas.poly(_rect(c, 0.05 * w, w / 2, -h / 2, h / 2, a), (190, 190, 195), BLACK)
    elif style == "rolling_pin":
        canvas.poly(_rect(c, -w / 2, -0.3 * w, -0.28 * h, 0.28 * h, a), dark, BLACK)
        canvas.poly(_rect(c, 0.3 * w, w / 2, -0.28 * h, 0.28 * h, a), dark, BLACK)
        canvas.poly(_rect(c, -0.3 * w, 0.3 * w, -h / 2, h / 2, a), colour, dark)
    elif style == "board":
        canvas.poly(_rect(c, -w / 2, w / 2, -h / 2, h / 2, a), colour, dark)
        canvas.poly(_rect(c, -w / 2 + 5, w / 2 - 5, -h / 2 + 5, h / 2 - 5, a), _shade(colour, 1.06))
    elif style == "pot":
        r = min(w / 2, h / 2 - 12)
        for sign in (-1, 1):
            canvas.poly(_rect(c, -9, 9, sign * (h / 2 - 14), sign * h / 2, a), BLACK)
        canvas.poly(_ellipse(c, 2 * r, 2 * r, a), colour, BLACK)
        canvas.poly(_ellipse(c, 2 * r - 8, 2 * r - 8, a), _shade(colour, 1.6))
    elif style in ("bowl", "jar"):
        canvas.poly(_ellipse(c, w, h, a), colour, dark)
        canvas.poly(_ellipse(c, 0.78 * w, 0.78 * h, a), _shade(colour, 1.12))
    elif style == "tomato":
        canvas.poly(_ellipse(c, w, h, a), colour, dark)
        cuts = min(int(path.worked[frame]), 3)
        for k in range(cuts):  # slices
            x = (k + 1) / (cuts + 1) * w - w / 2
            canvas.line(c + rotation(a) @ np.array([x, -0.45 * h]), c + rotation(a) @ np.array([x, 0.45 * h]),
                        (120, 150, 235), 1.5)
        if not cuts:
            canvas.dot(c, 2.5, (40, 140, 40))
    elif style == "potato":
        peeled = path.worked[frame] > 0
        canvas.poly(_ellipse(c, w, h, a), (150, 210, 235) if peeled else colour, dark)
        for dx, dy in ((-0.2, -0.1), (0.15, 0.2), (0.25, -0.15)):
            canvas.dot(c + rotation(a) @ np.array([dx * w, dy * h]), 1.2, dark)
    elif style in ("lemon", "dough", "heap"):
        canvas.poly(_ellipse(c, w, h, a), colour, dark)
    elif style == "peas":
        for dx, dy in ((-0.25, -0.2), (0.2, -0.25), (0.0, 0.15), (-0.3, 0.25), (0.3, 0.2), (0.05, -0.05)):
            canvas.dot(c + rotation(a) @ np.array([dx * w, dy * h]), 0.2 * h, colour)
    elif style == "cheese":
        canvas.poly(_rect(c, -w / 2, w / 2, -h / 2, h / 2, a), colour, dark)
        canvas.dot(c + rotation(a) @ np.array([-0.2 * w, 0.1 * h]), 1.5, dark)
    elif style == "carrot":
        canvas.poly(c + np.array([(-w / 2, -h / 2), (w / 2, 0), (-w / 2, h / 2)]) @ rotation(a).T, colour, dark)
        canvas.poly(_rect(c, -w / 2 - 1, -w / 2 + 3, -h / 3, h / 3, a), (40, 150, 40))
    elif style == "bottle":
        canvas.poly(_rect(c, -w / 2, w / 2, -0.25 * h, h / 2, a), colour, dark)
        canvas.poly(_rect(c, -0.22 * w, 0.22 * w, -h / 2, -0.25 * h, a), (40, 40, 180), BLACK)
    elif style == "shaker":
        canvas.poly(_rect(c, -w / 2, w / 2, -0.15 * h, h / 2, a), colour, (150, 150, 150))
        canvas.poly(_rect(c, -w / 2, w / 2, -h / 2, -0.15 * h, a), (150, 150, 155), BLACK)
    else:  # pragma: no cover - every kind has a style
        canvas.poly(_rect(c, -w / 2, w / 2, -h / 2, h / 2, a), colour, dark)


def draw_person(canvas: _Canvas, person: PersonPath, frame: int) -> None:
    neck = person.neck[frame]
    forward, left = np.asarray(person.forward), np.asarray(person.left)
    shirt = SHIRTS.get(person.person, (90, 90, 90))
    torso = neck - 20 * forward
    canvas.poly(torso + (_CIRCLE * (26, 56)) @ np.stack([forward, left]), shirt, _shade(shirt, 0.6))
    for arm in person.arms:
        shoulder, elbow, wrist, hand = (arm.shoulder[frame], arm.elbow[frame], arm.wrist[frame],
                                        arm.centre[frame])
        canvas.line(shoulder, elbow, shirt, 15)
        canvas.line(elbow, wrist, SKIN, 11)
        direction = hand - elbow
        angle = float(np.arctan2(direction[1], direction[0]))
        canvas.poly(_ellipse(hand, 26, 20, angle), SKIN, _shade(SKIN, 0.7))
    canvas.dot(neck - 6 * forward, 17, HAIR)


def _draw_effect(canvas: _Canvas, scene: Scene, index: dict[str, ObjectPath], frame: int) -> None:
    for effect in scene.effects:
        if not effect.start <= frame < effect.end:
            continue
        source, target = index[effect.source], index[effect.target]
        s, t = source.centre[frame], target.centre[frame]
        towards = (t - s) / max(float(np.hypot(*(t - s))), 1e-6)
        spout = s + towards * 0.5 * float(max(source.size[frame]))
        inside = t - towards * 10
        if effect.kind == "pour":
            canvas.line(spout, inside, (70, 210, 235), 3)
        else:
            rng = np.random.default_rng(frame)
            for k in rng.uniform(0, 1, 6):
                p = spout + k * (inside - spout) + rng.normal(0, 3, 2)
                canvas.dot(p, 1.3, (250, 250, 250))


def _background(size: tuple[int, int]) -> np.ndarray:
    """The table: flat wood colour with a few wide, soft planks (fine texture costs video bytes)."""
    canvas = _Canvas(size)
    canvas.image[:] = TABLE
    for y in (90.0, 180.0, 270.0):
        canvas.line(np.array([0.0, y]), np.array([WIDTH, y]), _shade(TABLE, 0.9), 1.5)
    return canvas.image


_LAYER = {Category.CONTAINER: 0, Category.INGREDIENT: 1, Category.TOOL: 2}


def _order(scene: Scene, frame: int) -> list[ObjectPath]:
    visible = [p for p in scene.objects if p.visible[frame]]
    visible.sort(key=lambda p: (_LAYER[p.category] + 3 * bool(p.held[frame]), p.track_id))
    return visible


def _draw(canvas: _Canvas, scene: Scene, index: dict[str, ObjectPath], frame: int,
          skip: frozenset[str] = frozenset()) -> None:
    for path in _order(scene, frame):
        if path.name not in skip:
            draw_object(canvas, path, frame)
    _draw_effect(canvas, scene, index, frame)
    for person in scene.persons:
        draw_person(canvas, person, frame)


def _resting(path: ObjectPath, frame: int) -> tuple[float, ...] | None:
    """The object's drawn state when it lies still (same as on the frame before), else None."""
    if not path.visible[frame] or path.held[frame] or frame == 0:
        return None
    now = (*path.centre[frame], path.angle[frame], *path.size[frame], float(path.worked[frame]))
    before = (*path.centre[frame - 1], path.angle[frame - 1], *path.size[frame - 1], float(path.worked[frame - 1]))
    return tuple(float(v) for v in now) if now == before else None


def _camera(image: np.ndarray) -> np.ndarray:
    """A slight lens blur: softer edges look like a camera and halve the mp4v file."""
    return cv2.GaussianBlur(image, (5, 5), 0)


def frames(scenario: Scenario) -> Iterator[np.ndarray]:
    """Every frame of the scenario's video, BGR ``(height, width, 3)`` uint8 (the same buffer each time:
    copy it to keep it). Objects lying still are drawn once into a cached layer until one of them moves."""
    scene = scenario.scene
    background = _background(scenario.size)
    index = {path.name: path for path in scene.objects}
    canvas = _Canvas(scenario.size)
    layer = _Canvas(scenario.size)
    layer_key: tuple[tuple[str, tuple[float, ...]], ...] | None = None
    for frame in range(scene.frames):
        resting = {p.name: state for p in scene.objects if (state := _resting(p, frame)) is not None}
        key = tuple(sorted(resting.items()))
        if key != layer_key:
            np.copyto(layer.image, background)
            for path in _order(scene, frame):
                if path.name in resting:
                    draw_object(layer, path, frame)
            layer_key = key
        np.copyto(canvas.image, layer.image)
        _draw(canvas, scene, index, frame, skip=frozenset(resting))
        yield _camera(canvas.image)


def render_frame(scenario: Scenario, frame: int) -> np.ndarray:
    """One frame, BGR uint8 (for previews and tests)."""
    if not 0 <= frame < scenario.scene.frames:
        raise IndexError(frame)
    canvas = _Canvas(scenario.size)
    canvas.image = _background(scenario.size)
    _draw(canvas, scenario.scene, {p.name: p for p in scenario.scene.objects}, frame)
    return _camera(canvas.image)


def write_video(scenario: Scenario, path: str | Path) -> Path:
    """Write the scenario's video with ``cv2.VideoWriter`` (mp4v)."""
    path = Path(path)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter.fourcc(*"mp4v"), scenario.fps, scenario.size)
    if not writer.isOpened():
        raise OSError(f"{path}: OpenCV cannot write an mp4v video here")
    try:
        for image in frames(scenario):
            writer.write(image)
    finally:
        writer.release()
    return path
