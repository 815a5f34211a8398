"""Where the persons stand and where the objects lie on the table (nominal 640x360 image, top-down view).

P1 sits at the left edge facing right, P2 (when there is one) at the right edge facing left; the pot and the
chopping board lie in the middle column, which both reach; every other object lies in its owner's strip.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wecook_core.synth.kitchen import KINDS, MAX_DOUGH, Kind
from wecook_core.synth.motion import rotation

WIDTH, HEIGHT = 640.0, 360.0
"""The nominal image every position is computed in (scaled to the requested size at the end)."""
HALF_SHOULDERS = 44.0
REACH = 250.0
"""How far from the nearest shoulder an object's home may lie (the body leans in for the far ones)."""
CLEARANCE = 17.0
"""Least gap between two objects' boxes at home, pixels (more than the association's 'near' distance)."""
MIDDLE_CLEARANCE = 40.0
"""Least gap between an object at home and the pot or the chopping board (hands work around those)."""


@dataclass(frozen=True)
class Body:
    """A person seen from above."""

    person: str
    neck: tuple[float, float]
    forward: tuple[float, float]
    """Unit vector: the way the person faces."""
    left: tuple[float, float]
    """Unit vector: the person's own left."""
    rests: dict[str, tuple[float, float]]
    """Hand -> where it rests when idle."""

    def hand(self, side: str) -> str:
        return f"{side}H_{self.person}"

    def shoulder(self, hand: str) -> np.ndarray:
        sign = 1.0 if hand.startswith("L") else -1.0
        return np.asarray(self.neck) + sign * HALF_SHOULDERS * np.asarray(self.left)

    def hand_towards(self, point: np.ndarray) -> str:
        """The hand on the side of ``point``."""
        side = float(np.dot(np.asarray(point) - np.asarray(self.neck), self.left))
        return self.hand("L" if side > 0 else "R")

    def outward(self, hand: str) -> np.ndarray:
        """Unit vector away from the body's midline on the side of ``hand`` (where its elbow points)."""
        sign = 1.0 if hand.startswith("L") else -1.0
        return sign * np.asarray(self.left)

    def direction_to(self, hand: str, point: np.ndarray) -> np.ndarray:
        """Unit vector from the hand's shoulder to ``point`` (how a held tool points there)."""
        d = np.asarray(point, dtype=float) - self.shoulder(hand)
        return d / max(float(np.hypot(*d)), 1e-9)


@dataclass(eq=False)
class Thing:
    """An object of the scenario while the script is being written (mutable: owner and home change)."""

    track_id: int
    kind: Kind
    name: str
    home: np.ndarray
    """Centre, pixels."""
    angle: float
    """Radians, of the local x axis at home."""
    owner: str | None
    """The person whose strip it lies in; None for the middle column."""
    homes: dict[str, np.ndarray] = field(default_factory=dict)
    """Person -> where the object goes when that person owns it (handed-over objects)."""
    inside: str | None = None
    """Name of the container it starts in."""
    offset: np.ndarray = field(default_factory=lambda: np.zeros(2))
    """For contents: centre minus the container's centre, in the container's local frame."""

    @property
    def label(self) -> str:
        return self.kind.label


def extent(size: tuple[float, float] | np.ndarray, angle: float, round_: bool) -> np.ndarray:
    """Half width and half height of the box of a ``size`` shape turned by ``angle``."""
    w, h = float(size[0]) / 2, float(size[1]) / 2
    c, s = abs(np.cos(angle)), abs(np.sin(angle))
    if round_:
        return np.array([np.hypot(w * c, h * s), np.hypot(w * s, h * c)])
    return np.array([w * c + h * s, w * s + h * c])


def box_of(centre: np.ndarray, size: tuple[float, float] | np.ndarray, angle: float, round_: bool) -> np.ndarray:
    half = extent(size, angle, round_)
    return np.concatenate([np.asarray(centre) - half, np.asarray(centre) + half])


def gap(a: np.ndarray, b: np.ndarray) -> float:
    dx = max(a[0] - b[2], b[0] - a[2], 0.0)
    dy = max(a[1] - b[3], b[1] - a[3], 0.0)
    return float(np.hypot(dx, dy))


@dataclass(eq=False)
class Layout:
    """The table at the start of a scenario."""

    bodies: tuple[Body, ...]
    things: dict[str, Thing]
    """Name -> thing, in track id order."""
    meeting: np.ndarray | None
    """Where handovers happen (two persons), pixels."""
    groups: dict[str, tuple[str, ...]]
    """Task group -> the names of its objects (ownership moves with the group)."""
    handed: str | None = None
    """The object the persons pass to each other (it has a place on both sides); None for one person."""

    def body(self, person: str) -> Body:
        return next(b for b in self.bodies if b.person == person)


def _bodies(persons: int, rng: np.random.Generator) -> tuple[Body, ...]:
    def body(person: str, neck: tuple[float, float], forward: tuple[float, float], left: tuple[float, float]
             ) -> Body:
        n, f, lft = np.asarray(neck), np.asarray(forward), np.asarray(left)
        rests = {}
        for side, sign in (("L", 1.0), ("R", -1.0)):
            p = n + f * (50 + rng.uniform(-3, 3)) + lft * sign * (42 + rng.uniform(-4, 6))
            rests[f"{side}H_{person}"] = (float(p[0]), float(p[1]))
        return Body(person, (float(n[0]), float(n[1])), forward, left, rests)

    p1 = body("P1", (52.0, 180.0 + rng.uniform(-6, 6)), (1.0, 0.0), (0.0, -1.0))
    if persons == 1:
        return (p1,)
    return (p1, body("P2", (588.0, 180.0 + rng.uniform(-6, 6)), (-1.0, 0.0), (0.0, 1.0)))


def _choose_labels(rng: np.random.Generator) -> dict[str, str]:
    from wecook_core.synth.kitchen import SCOOPED, TIPPED, TRANSFER_SOURCES

    return {
        "source": str(rng.choice(TRANSFER_SOURCES)),
        "scooped": str(rng.choice(SCOOPED)),
        "tipped": str(rng.choice(TIPPED)),
    }


GROUPS: dict[str, tuple[str, ...]] = {
    "knife": ("knife",),
    "spoon": ("spoon", "source", "scooped"),
    "peeler": ("peeler", "potato"),
    "rolling_pin": ("rolling pin", "dough"),
    "lemon": ("lemon",),
    "oil": ("oil",),
    "salt": ("salt",),
    "bowl": ("bowl", "tipped"),
}
"""Objects that belong together (a tool and what it works on); the strings ``source``, ``scooped`` and
``tipped`` stand for the labels chosen by seed."""


def make_layout(persons: int, rng: np.random.Generator, attempts: int = 200) -> Layout:
    """A random table for ``persons`` (1 or 2): objects placed apart from each other, all within reach.

    Two persons share every group of objects (balanced by area); one person works with the knife and three
    or four other groups (a single strip of table holds no more)."""
    if persons not in (1, 2):
        raise ValueError("persons must be 1 or 2")
    bodies = _bodies(persons, rng)
    labels = _choose_labels(rng)
    for _ in range(attempts):
        owners = _owners(persons, labels, rng)
        layout = _try_layout(bodies, labels, owners, rng)
        if layout is not None:
            return layout
    raise RuntimeError("could not place the objects on the table")  # pragma: no cover - never seen


def _area(group: str, labels: dict[str, str]) -> float:
    total = 0.0
    for member in GROUPS[group]:
        w, h = MAX_DOUGH if member == "dough" else KINDS[labels.get(member, member)].size
        total += (w + CLEARANCE) * (h + CLEARANCE)
    return total


def _owners(persons: int, labels: dict[str, str], rng: np.random.Generator) -> dict[str, str]:
    names = list(GROUPS)
    if persons == 1:
        others = [g for g in names if g != "knife"]
        rng.shuffle(others)
        return dict.fromkeys(["knife", *others[: int(rng.integers(3, 5))]], "P1")
    areas = np.array([_area(g, labels) for g in names])
    while True:
        picks = rng.integers(0, 2, len(names))
        if abs(float(areas @ picks) - float(areas.sum()) / 2) <= 0.08 * float(areas.sum()):
            return {g: ("P1", "P2")[int(p)] for g, p in zip(names, picks, strict=True)}


def _try_layout(
    bodies: tuple[Body, ...], labels: dict[str, str], owners: dict[str, str], rng: np.random.Generator
) -> Layout | None:
    persons = len(bodies)
    things: dict[str, Thing] = {}
    boxes: dict[str, np.ndarray] = {}
    track = 1

    def add(label: str, centre: np.ndarray, angle: float, owner: str | None) -> Thing:
        nonlocal track
        kind = KINDS[label]
        name = label.replace(" ", "_")
        thing = Thing(track, kind, name, np.asarray(centre, dtype=float), angle, owner)
        track += 1
        things[name] = thing
        size = MAX_DOUGH if label == "dough" else kind.size
        boxes[name] = box_of(centre, size, angle, kind.round)
        return thing

    # the middle: pot and chopping board (and, for two persons, the handover place between them)
    knife_owner = owners["knife"]
    x = 320.0 + rng.uniform(-6, 6)
    order = ["pot", "chopping board"]
    rng.shuffle(order)
    top, bottom = order
    ht, hb = KINDS[top].size[1] / 2, KINDS[bottom].size[1] / 2
    yt, yb = 16 + ht + rng.uniform(0, 10), 344 - hb - rng.uniform(0, 10)
    add(top, np.array([x, yt]), 0.0, None)
    add(bottom, np.array([x, yb]), 0.0, None)
    meeting = np.array([x, (yt + ht + yb - hb) / 2 + rng.uniform(-4, 4)]) if persons == 2 else None
    board = things["chopping_board"]
    cutter = next(b for b in bodies if b.person == knife_owner)
    to_cutter = np.asarray(cutter.neck) - board.home
    to_cutter /= np.hypot(*to_cutter)
    tomato = add("tomato", board.home + 16 * to_cutter, 0.0, None)
    tomato.inside = "chopping_board"
    middle_boxes = list(boxes.values())
    keep: list[np.ndarray] = []
    for body in bodies:  # where hands work around the pot and the board: no object at home there
        side = float(np.sign(body.forward[0]))
        for name in ("pot", "chopping_board"):
            b = boxes[name]
            edge = b[0] if side > 0 else b[2]
            keep.append(np.array([min(edge, edge - side * 60), b[1] - 10, max(edge, edge - side * 60), b[3] + 10]))

    # everything else: each group in its owner's area, the biggest first
    order_labels: list[tuple[str, str]] = []
    for group, members in GROUPS.items():
        if group not in owners:
            continue
        for member in members:
            label = labels.get(member, member)
            if KINDS[label].style in ("heap", "peas", "cheese", "carrot"):
                continue  # contents are placed in their container below
            order_labels.append((label, owners[group]))
    order_labels.sort(key=lambda item: -float(np.prod(KINDS[item[0]].size)))
    for label, owner in order_labels:
        body = next(b for b in bodies if b.person == owner)
        placed = _place(label, body, persons, boxes, middle_boxes, keep, bodies, rng)
        if placed is None:
            return None
        centre, angle, kept = placed
        keep.extend(kept)
        if KINDS[label].style in ("bowl", "jar"):  # the rim a hand takes faces the person
            hand = body.hand_towards(centre)
            d = centre - body.shoulder(hand)
            angle = float(np.arctan2(d[1], d[0]))
        add(label, centre, angle, owner)
    # contents: in their container, a little off centre, away from the hand that grips the container
    for container, content in ((labels["source"], labels["scooped"]), ("bowl", labels["tipped"])):
        if container.replace(" ", "_") not in things:
            continue
        holder = things[container]
        offset = np.array([rng.uniform(3, 6), rng.uniform(-4, 4)])
        centre = holder.home + rotation(holder.angle) @ offset
        inner = add(content, centre, float(rng.uniform(-0.4, 0.4)), holder.owner)
        inner.inside = holder.name
        inner.offset = offset
    # where the object passed between the persons goes on the other person's side
    handed = str(rng.choice(["lemon", "salt", "oil"])) if persons == 2 else None
    if handed is not None:
        for label in (handed,):
            thing = things[label]
            thing.homes[thing.owner or "P1"] = thing.home
            other = next(b for b in bodies if b.person != thing.owner)
            placed = _place(label, other, persons, boxes, middle_boxes, keep, bodies, rng)
            if placed is None:
                return None
            thing.homes[other.person] = placed[0]
            keep.extend(placed[2])
            boxes[f"{label}@{other.person}"] = box_of(placed[0], thing.kind.size, placed[1], thing.kind.round)
    ordered = dict(sorted(things.items(), key=lambda item: item[1].track_id))
    groups = {g: tuple(labels.get(m, m).replace(" ", "_") for m in members)
              for g, members in GROUPS.items() if g in owners}
    return Layout(bodies, ordered, meeting, groups, handed)


def _keep_out(label: str, centres: np.ndarray, angle: float, body: Body) -> np.ndarray:
    """``(k, j, 4)``: for objects at ``centres`` ``(k, 2)``, the boxes where a hand will work on them at
    home, which no other object may touch: behind a jar or a potato (the spoon's, the peeler's hand), beside
    the dough (the rolling pin's ends), at a tool's handle and at a bowl's near rim."""
    kind = KINDS[label]
    shoulder = (body.shoulder(body.hand("L")) + body.shoulder(body.hand("R"))) / 2
    back = shoulder - centres
    back /= np.maximum(np.linalg.norm(back, axis=1), 1e-9)[:, None]

    def square(points: np.ndarray, half: float) -> np.ndarray:
        return np.concatenate([points - half, points + half], axis=1)[:, None, :]

    if kind.style in ("jar", "potato"):
        return square(centres + 38 * back, 24)
    if kind.style == "bowl":
        return square(centres + 28 * back, 19)
    if kind.style == "dough":
        half = extent(MAX_DOUGH, angle, True)
        lateral = np.abs(np.asarray(body.left)) * 44
        return np.concatenate([centres - half - lateral, centres + half + lateral], axis=1)[:, None, :]
    if kind.grip:
        axis = rotation(angle) @ np.array([kind.grip, 0.0])
        ends = [square(centres + axis, 18)]
        if kind.style == "rolling_pin":
            ends.append(square(centres - axis, 18))
        return np.concatenate(ends, axis=1)
    return np.zeros((len(centres), 0, 4))


def _gaps(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Gaps between boxes ``a[..., 4]`` and ``b[..., 4]`` (broadcast), 0 where they overlap."""
    dx = np.maximum(np.maximum(a[..., 0] - b[..., 2], b[..., 0] - a[..., 2]), 0.0)
    dy = np.maximum(np.maximum(a[..., 1] - b[..., 3], b[..., 1] - a[..., 3]), 0.0)
    return np.hypot(dx, dy)


def _clear(candidates: np.ndarray, others: list[np.ndarray], least: float) -> np.ndarray:
    if not others:
        return np.ones(candidates.shape[0], dtype=bool)
    gaps = _gaps(candidates[:, None, :], np.asarray(others)[None, :, :])
    return np.all(gaps >= least, axis=1)


def _place(
    label: str, body: Body, persons: int, boxes: dict[str, np.ndarray], middle: list[np.ndarray],
    keep: list[np.ndarray], bodies: tuple[Body, ...], rng: np.random.Generator, step: float = 3.0,
) -> tuple[np.ndarray, float, list[np.ndarray]] | None:
    """A random free spot for ``label`` in ``body``'s strip (every spot on a 3-pixel grid is checked), its
    angle and its keep-out boxes; None when the strip is full."""
    kind = KINDS[label]
    size = MAX_DOUGH if label == "dough" else kind.size
    forward = np.asarray(body.forward)
    angle = float(np.arctan2(forward[1], forward[0])) + rng.uniform(-0.12, 0.12)
    if kind.style == "rolling_pin":
        angle += np.pi / 2
    if kind.round and kind.style in ("bowl", "jar"):
        angle = 0.0  # turned towards the hand that takes it once placed
    x_lo, x_hi = (116.0, 234.0) if body.person == "P1" else (406.0, 524.0)
    y_lo, y_hi = 10.0, 350.0
    half = extent(size, angle, kind.round)
    xs = np.arange(x_lo + half[0], x_hi - half[0] + 1e-9, step)
    ys = np.arange(y_lo + half[1], y_hi - half[1] + 1e-9, step)
    if not len(xs) or not len(ys):
        return None
    centres = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2) + rng.uniform(0, step, 2)
    candidates = np.concatenate([centres - half, centres + half], axis=1)
    shoulders = np.array([body.shoulder(body.hand("L")), body.shoulder(body.hand("R"))])
    reach = np.min(np.linalg.norm(centres[:, None, :] - shoulders[None], axis=2), axis=1)
    hands = [np.array([*np.asarray(r) - 18, *np.asarray(r) + 18]) for b in bodies for r in b.rests.values()]
    ok = ((reach <= REACH - 10) & _clear(candidates, list(boxes.values()), CLEARANCE)
          & _clear(candidates, middle, MIDDLE_CLEARANCE) & _clear(candidates, hands, CLEARANCE)
          & _clear(candidates, keep, 2.0))
    kept = _keep_out(label, centres, angle, body)
    if kept.shape[1] and boxes:
        gaps = _gaps(kept[:, :, None, :], np.asarray(list(boxes.values()))[None, None, :, :])
        ok &= np.all(gaps >= 2.0, axis=(1, 2))
    choices = np.flatnonzero(ok)
    if not len(choices):
        return None
    pick = int(rng.choice(choices))
    return centres[pick], angle, list(kept[pick])
