"""Laying a video's objects out on the table of a plan: where each object goes, its shape and size.

Image -> table: each object's position is the centre of its median box over its first :data:`FIRST_FRAMES`
sightings; the bounding rectangle of those boxes (at least a fifth of the image on each axis) is scaled, each
axis on its own, onto the table's reach region (``Table.reach``): image left -> ``-x`` (P1's side), image top ->
``+y`` (see :mod:`wecook_core.plan` for the world frame); when P1 works right of P2 in the video, the image is
turned half round first, so that each person's things lie at their arm's end. Then nothing may overlap, and a
hand keeps room where it works: push-apart inside the reach region, else each object to the nearest free spot.
What starts in a container, and where on it: :mod:`wecook_core.plan.contents`.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from wecook_core.knowledge.nouns import match
from wecook_core.model import PERSONS, ActionGraph, Category, Observations, person_of
from wecook_core.plan.contents import containing as containing_of
from wecook_core.plan.contents import fit_board, holders, spread, taken_from_by_hand, worked
from wecook_core.plan.model import DEFAULT_ROBOT, DEFAULT_TABLE, Scene, SceneObject, Table, Vec3
from wecook_core.plan.reach import MIN_REACH, WORK_REACH, min_reach
from wecook_core.trees.notation import action_of

_FLAT_CONTAINERS = ("board", "tray", "mat", "sheet")
_ROUND_INGREDIENTS = {name: True for name in ("tomato", "lemon", "lime", "orange", "apple", "onion", "potato", "egg",
                                              "peach", "ball", "bell_pepper")}
_BOTTLES = {**{name: True for name in ("oil", "bottle", "salt", "pepper", "sauce", "vinegar", "milk", "jar", "shaker",
                                       "syrup")},
            **{name: False for name in ("bell_pepper", "red_pepper", "green_pepper", "yellow_pepper", "sweet_pepper",
                                        "chili_pepper", "chilli_pepper")}}
"""Ingredients kept in a bottle, matched by head noun (:func:`wecook_core.knowledge.nouns.match`, whole words):
olive_oil is one, foil and boiled_egg are not; pepper (the spice) is, bell_pepper (the vegetable) is not."""
_CONTAINER_HEIGHTS = (("plate", 0.03), ("pan", 0.05), ("bowl", 0.07), ("pot", 0.12), ("cup", 0.09),
                      ("glass", 0.1), ("mug", 0.09))
FIRST_FRAMES = 5
"""How many of an object's first sightings are combined (median box) to place it."""
GAP = 0.06
"""Metres left free between neighbouring objects (room for the gripper's fingers)."""
HAND_ROOM = 0.1
"""Metres from a tool's long edge to any object taller than :data:`LOW`: a gripper taking the tool from above
lies across it, its palm reaching about 11 cm either side of the tool's axis at the height of a pot's rim."""
LOW = 0.04
"""Metres: objects at most this tall (boards, tools, small ingredients) pass under a gripper's palm."""
HAND_DEPTH = 0.07
"""Metres: the deepest a container may be for a hand to take something out of it (a gripper's fingers reach
about 5 cm below its palm)."""
REACH_SLACK = 0.05
"""Metres kept inside an arm's reach band when placing what it must reach (the object's own size, poses
around it)."""
ARM_CLEARANCE = 0.28
"""Metres kept free at each end of the table: the arm's base stands there, and a Panda reaches down to the
table badly closer than about 0.3 m from its base."""


def _first_box(frames: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    return np.median(boxes[: min(FIRST_FRAMES, len(frames))], axis=0)


def _clip(value: float, low: float, high: float) -> float:
    return float(min(max(value, low), high))


def _shape_for(name: str, category: Category, width_m: float, depth_m: float) -> tuple[str, Vec3, float]:
    """Shape, size (metres) and yaw of an object from its category, its name and its box size on the table."""
    long_side, short_side = max(width_m, depth_m), min(width_m, depth_m)
    yaw = 0.0 if width_m >= depth_m else math.pi / 2
    if category is Category.TOOL:  # lying across the table (along y): graspable by either arm, even near its base
        return "box", (round(_clip(long_side, 0.14, 0.24), 3), 0.03, 0.025), math.pi / 2
    if category is Category.CONTAINER:
        if any(word in name for word in _FLAT_CONTAINERS):
            return "box", (round(_clip(long_side, 0.2, 0.3), 3), round(_clip(short_side, 0.14, 0.22), 3), 0.02), yaw
        height = next((h for word, h in _CONTAINER_HEIGHTS if word in name), 0.08)
        d = round(_clip(long_side, 0.1, 0.22), 3)
        return "cylinder", (d, d, height), 0.0
    if match(name, _BOTTLES):
        return "cylinder", (0.05, 0.05, 0.14), 0.0
    d = round(_clip(short_side, 0.04, 0.07), 3)
    if match(name, _ROUND_INGREDIENTS):
        return "sphere", (d, d, d), 0.0
    return "box", (round(_clip(long_side, 0.04, 0.08), 3), d, 0.03), yaw


def _gaps(objects: Sequence[SceneObject], worked: Collection[str] = ()) -> np.ndarray:
    """``(n, n, 2)`` metres to keep free between footprints i and j along x and y: :data:`GAP`; :data:`HAND_ROOM`
    across a tool (perpendicular to its long axis) from an object taller than :data:`LOW`, and on both axes
    around an object a held tool works on where it lies (``worked``: the hand carrying the tool comes down over
    it, turned whichever way the tool needs) from an object taller than :data:`LOW`."""
    n = len(objects)
    gaps = np.full((n, n, 2), GAP)
    for i, tool in enumerate(objects):
        if tool.category is not Category.TOOL and tool.name not in worked:
            continue
        hx, hy = tool.half_extents()
        axes = [0, 1] if tool.name in worked else [0 if hy >= hx else 1]  # a tool along y: the hand spans x
        for j, other in enumerate(objects):
            if j != i and other.size[2] > LOW:
                for across in axes:
                    gaps[i, j, across] = gaps[j, i, across] = max(gaps[i, j, across], HAND_ROOM)
    return gaps


def _push_apart(centres: np.ndarray, halves: np.ndarray, bound: tuple[float, float], gaps: np.ndarray,
                sides: np.ndarray, iterations: int = 150) -> tuple[np.ndarray, bool]:
    """Move axis-aligned footprints apart until none overlap (``gaps[i, j]`` apart, see :func:`_gaps`), keeping
    each inside ``|x| <= bound[0], |y| <= bound[1]`` (an object too big for that keeps its centre within half the
    bound and sticks out) and on its arm's half (``sides``: -1 ``x <= 0``, +1 ``x >= 0``, 0 anywhere). Each
    overlapping pair is pushed apart, half each, along the axis where they overlap least (so left stays left of
    right, top above bottom), then everything is clamped into the bound. Centres first get a deterministic
    sub-millimetre spiral offset so coincident or aligned objects spread in 2-D. Returns the centres and whether
    every overlap was resolved."""
    n = len(centres)
    k = np.arange(n)
    angle = k * 2.399963  # golden angle
    c = centres.astype(float) + 1e-4 * np.stack([np.cos(angle), np.sin(angle)], axis=1) * (k[:, None] + 1)
    limit = np.maximum(np.array(bound)[None, :] - halves, np.array(bound)[None, :] / 2)  # big ones stick out
    low, high = -limit.copy(), limit.copy()
    high[sides < 0, 0] = np.minimum(high[sides < 0, 0], 0.0)
    low[sides > 0, 0] = np.maximum(low[sides > 0, 0], 0.0)
    for _ in range(iterations):
        moved = False
        for i in range(n - 1):  # pairs in turn (Gauss-Seidel): keeps the layout's order better than all at once
            d = c[i + 1:] - c[i]
            pen = halves[i] + halves[i + 1:] + gaps[i, i + 1:] - np.abs(d)
            for m in np.nonzero((pen > 1e-9).all(axis=1))[0]:
                j = i + 1 + int(m)
                dj = c[j] - c[i]
                pj = halves[i] + halves[j] + gaps[i, j] - np.abs(dj)
                if (pj <= 1e-9).any():
                    continue
                axis = int(np.argmin(pj))
                step = (float(pj[axis]) / 2 + 1e-4) * (1.0 if dj[axis] >= 0 else -1.0)
                c[i, axis] -= step
                c[j, axis] += step
                moved = True
        c = np.clip(c, low, high)
        if not moved:
            return c, True
    return c, False


def _settle(centres: np.ndarray, halves: np.ndarray, bounds: Sequence[tuple[float, float]], gaps: np.ndarray,
            sides: np.ndarray, step: float = 0.01, reach: Reach | None = None) -> np.ndarray:
    """Place objects one by one, biggest first: each stays at its centre if it keeps its gaps (:func:`_gaps`)
    from those already placed inside ``bounds[0]`` and on its arm's half (``sides``), else goes to the nearest
    point of a ``step`` grid that does. On a crowded table the rules loosen in this order: half the gaps in
    ``bounds[0]``, the gaps then half of them in ``bounds[1]`` (say, the whole table), then either half of the
    table, then 5 mm in each bound. With ``reach`` (object index, points -> which points every arm using the
    object reaches), every rule first asks for reach too, and objects that some arm must reach are placed before
    the others. Always terminates; positions stay near the input."""
    # objects both arms must reach first (the region both reach is small), then those of one arm, then the rest
    arms = np.zeros(len(centres), int) if reach is None else np.array([len(reach.arms[i]) for i in range(len(centres))])
    order = np.lexsort((-(halves[:, 0] * halves[:, 1]), -arms))
    out = centres.copy()
    settled: list[int] = []
    # (bound, share of the gaps, fixed gap, keep the arm's half, within reach)
    base_rules = [*((k, share, 0.0, True) for k in range(len(bounds)) for share in (1.0, 0.5)),
                  *((k, 0.5, 0.0, False) for k in range(len(bounds))),
                  *((k, 0.0, 0.005, False) for k in range(len(bounds)))]
    rules = [*((*r, True) for r in base_rules if reach is not None), *((*r, False) for r in base_rules)]
    for i in order:
        def free(points: np.ndarray, share: float, fixed: float, i: int = i) -> np.ndarray:
            if not settled:
                return np.ones(len(points), bool)
            others = out[settled]
            reach = halves[settled] + halves[i] + share * gaps[i, settled] + fixed - 1e-9
            apart = np.abs(points[:, None, :] - others[None, :, :]) >= reach[None, :, :]
            return np.all(apart.any(axis=2), axis=1)

        def on_side(points: np.ndarray, i: int = i) -> np.ndarray:
            return points[:, 0] * sides[i] >= -1e-9

        def reached(points: np.ndarray, i: int = i) -> np.ndarray:
            return reach(int(i), points) if reach is not None else np.ones(len(points), bool)

        first = np.maximum(np.array(bounds[0]) - halves[i], 0.0)
        here = out[i][None, :]
        if free(here, 1.0, 0.0)[0] and on_side(here)[0] and np.all(np.abs(out[i]) <= first + 1e-9) \
                and reached(here)[0]:
            settled.append(int(i))
            continue
        for k, share, fixed, keep_side, within in rules:
            limit = np.maximum(np.array(bounds[k]) - halves[i], 0.0)
            xs = np.arange(-limit[0], limit[0] + 1e-9, step)
            ys = np.arange(-limit[1], limit[1] + 1e-9, step)
            grid: np.ndarray = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
            grid = grid[np.argsort(np.hypot(*(grid - out[i]).T), kind="stable")]
            ok = free(grid, share, fixed) & (on_side(grid) if keep_side else True) & (reached(grid) if within else True)
            if ok.any():
                out[i] = grid[int(np.argmax(ok))]
                break
        settled.append(int(i))
    return out


def _users(graph: ActionGraph) -> dict[str, set[str]]:
    """Object name -> the persons whose actions use it (held or acted on)."""
    users: dict[str, set[str]] = {}
    for node in graph.nodes:
        actions = [action_of(node.span.tree, node.span.start, node.span.end)]
        if actions[0].partner is not None:
            actions.append(actions[0].partner)
        for action in actions:
            person = action.hand.split("_", 1)[-1]
            for name in (action.held, *action.targets):
                if name is not None:
                    users.setdefault(name, set()).add(person)
    return users


@dataclass(frozen=True)
class Reach:
    """Where each object may lie so that every arm using it (or what starts in it) reaches it: between its
    nearest reach (:func:`~wecook_core.plan.reach.min_reach`, at least :data:`REACH_SLACK` beyond
    :data:`~wecook_core.plan.reach.MIN_REACH`) and the robot's work reach less :data:`REACH_SLACK`, from each
    such arm's base."""

    arms: tuple[tuple[np.ndarray, ...], ...]
    """Per object (by index): the bases (x, y) of the arms that must reach it."""
    lows: tuple[float, ...]
    """Per object (by index): metres, the nearest to a base it may lie."""
    high: float | None
    """Metres; None: the robot is not checked."""

    def __call__(self, i: int, points: np.ndarray) -> np.ndarray:
        """Which of the ``(n, 2)`` table points every arm of object ``i`` reaches."""
        ok = np.ones(len(points), bool)
        if self.high is None:
            return ok
        for base in self.arms[i]:
            d = np.hypot(*(points - base).T)
            ok &= (d >= self.lows[i]) & (d <= self.high)
        return ok


def _reach_rule(free: Sequence[str], users: Mapping[str, set[str]], containing: Mapping[str, str], table: Table,
                robot: str, categories: Mapping[str, Category]) -> Reach:
    """The :class:`Reach` of the objects ``free`` (P1 at the ``-x`` end of the table, P2 at the ``+x`` end)."""
    high = WORK_REACH.get(robot)
    bases = {"P1": np.array([-table.size[0] / 2, 0.0]), "P2": np.array([table.size[0] / 2, 0.0])}
    arms = []
    for name in free:
        persons = set(users.get(name, ()))
        for content, container in containing.items():
            if container == name:
                persons |= users.get(content, set())
        arms.append(tuple(bases[p] for p in sorted(persons) if p in bases))
    lows = tuple(max(min_reach(categories.get(name, Category.INGREDIENT)), MIN_REACH + REACH_SLACK) for name in free)
    return Reach(tuple(arms), lows, None if high is None else high - REACH_SLACK)


def p1_on_the_right(obs: Observations) -> bool:
    """Whether P1 works right of P2 in the video: the median x of P1's hands over every frame they are seen,
    against P2's (False when either is never seen)."""
    xs = {p: [h.xy[:, 0] for h in obs.hands if person_of(h.hand) == p and len(h.frames)] for p in PERSONS}
    if not xs["P1"] or not xs["P2"]:
        return False
    return float(np.median(np.concatenate(xs["P1"]))) > float(np.median(np.concatenate(xs["P2"])))


MIN_IMAGE_PARTS = 5
"""The image's table area spans at least 1/this of the image on each axis (a few objects close together are
not blown up to the whole table)."""
ARM_BASE = 0.12
"""Metres kept free at each end of the table when even :data:`ARM_CLEARANCE` leaves no room: the arm's base."""
EDGE = 0.01
"""Metres kept free along the table's long edges when the objects need the whole table."""
DECIMALS = 4
"""Positions on the table are rounded to 0.1 mm."""
ARM_HALF = {frozenset({"P1"}): -1, frozenset({"P2"}): 1}
"""The half of the table an object used by one person only stays on: -1 ``x <= 0`` (P1), +1 ``x >= 0`` (P2)."""


def _to_table(boxes: np.ndarray, obs: Observations, table: Table) -> tuple[np.ndarray, float]:
    """The table positions (n, 2) of the centres of the image boxes (n, 4), and the mean metres per pixel."""
    width, height = float(obs.video.width or 1), float(obs.video.height or 1)
    lo = boxes[:, :2].min(axis=0)
    hi = boxes[:, 2:].max(axis=0)
    minimum = np.array([width, height]) / MIN_IMAGE_PARTS
    mid = (lo + hi) / 2
    span = np.maximum(hi - lo, minimum)
    lo = mid - span / 2
    reach = np.array(table.reach)
    scale = 2 * reach / span  # metres per pixel, per axis
    centres_px = (boxes[:, :2] + boxes[:, 2:]) / 2
    xy = (centres_px - lo) * scale - reach
    xy[:, 1] = -xy[:, 1]  # image y grows downwards; world +y is the image's top
    if p1_on_the_right(obs):  # P1's arm stands at -x: the video turned half round
        xy = -xy
    return xy, float(scale.mean())


def _side(users: Mapping[str, set[str]], name: str) -> int:
    """The half of the table ``name`` stays on (:data:`ARM_HALF`), 0: either."""
    return ARM_HALF.get(frozenset(users.get(name, ())), 0)


def _sized(names: Sequence[str], boxes: np.ndarray, xy: np.ndarray, m_per_px: float,
           obs: Observations) -> dict[str, SceneObject]:
    """Each object at its table position with its category's shape, sized from its box."""
    objects: dict[str, SceneObject] = {}
    for k, name in enumerate(names):
        category = obs.categories.get(name, Category.INGREDIENT)
        w = float(boxes[k, 2] - boxes[k, 0]) * m_per_px
        d = float(boxes[k, 3] - boxes[k, 1]) * m_per_px
        shape, size, yaw = _shape_for(name, category, w, d)
        objects[name] = SceneObject(name, category, shape, size, float(xy[k, 0]), float(xy[k, 1]), yaw)
    return objects


def _fit_containers(objects: dict[str, SceneObject], graph: ActionGraph, containing: Mapping[str, str],
                    held: Mapping[str, set[str]]) -> None:
    """Containers a hand reaches into made no deeper than the fingers reach (:data:`HAND_DEPTH`); a board long
    enough for what starts on it and the hands holding it, held along x (:func:`~.contents.fit_board`)."""
    for container in taken_from_by_hand(graph):
        o = objects.get(container)
        if o is not None and o.category is Category.CONTAINER and o.size[2] > HAND_DEPTH:
            objects[container] = SceneObject(o.name, o.category, o.shape, (o.size[0], o.size[1], HAND_DEPTH),
                                             o.x, o.y, o.yaw)
    for container in set(containing.values()) | set(held):
        o = objects.get(container)
        if o is not None and o.shape == "box" and o.category is Category.CONTAINER:
            items = [objects[n] for n, c in sorted(containing.items()) if c == container]
            objects[container] = fit_board(o, items, held.get(container, set()))


def _place(objects: Mapping[str, SceneObject], free: Sequence[str], graph: ActionGraph, obs: Observations,
           users: Mapping[str, set[str]], containing: Mapping[str, str], table: Table, robot: str) -> np.ndarray:
    """Where the objects ``free`` (those not in a container) lie once apart: pushed apart in the reach region;
    if they do not fit there, or something is out of an arm's reach, settled one by one (:func:`_settle`)."""
    centres = np.array([[objects[n].x, objects[n].y] for n in free])
    halves = np.array([objects[n].half_extents() for n in free])
    gaps = _gaps([objects[n] for n in free], worked(graph, obs.categories))
    sides = np.array([_side(users, n) for n in free])
    inner = (table.size[0] / 2 - ARM_CLEARANCE, table.size[1] / 2 - GAP)
    whole = (table.size[0] / 2 - ARM_BASE, table.size[1] / 2 - EDGE)  # all but the arms' bases
    placed, ok = _push_apart(centres, halves, table.reach, gaps, sides)
    reaches = _reach_rule(free, users, containing, table, robot, obs.categories)
    if not ok:  # too crowded for the reach region: each object, biggest first, to the free spot nearest its place
        placed = _settle(centres, halves, (inner, whole), gaps, sides)
    if not all(reaches(k, placed[[k]])[0] for k in range(len(free))):  # something is out of an arm's reach: each
        # object (those both arms must reach first, then the biggest first) to the free spot nearest its place
        # that its arms reach
        placed = _settle(centres, halves, (inner, whole), gaps, sides, reach=reaches)
    return placed


def layout_scene(graph: ActionGraph, obs: Observations, table: Table = DEFAULT_TABLE,
                 robot: str = DEFAULT_ROBOT) -> Scene:
    """Objects of the video laid out on the table.

    Mapping image -> table: each object's position is the centre of its median box over its first
    :data:`FIRST_FRAMES` sightings. The image's table area is the bounding rectangle of those boxes (at least a
    fifth of the image on each axis, :data:`MIN_IMAGE_PARTS`); it is scaled, each axis on its own, onto the reach region
    ``[-reach_x, reach_x] x [-reach_y, reach_y]``: image left -> ``-x`` (P1's side), image top -> ``+y``;
    turned half round (image right -> ``-x``, image top -> ``-y``) when P1's hands work right of P2's
    (:func:`p1_on_the_right`): the table's ``-x`` end is P1's arm's.
    An object that only one person's actions use is kept on that arm's half (``x <= 0`` for P1, ``x >= 0`` for
    P2): a robot arm does not reach across the table as a person does.
    Sizes come from the category (containers wide, tools long and thin, ingredients small), scaled from the
    box by the mean of the two axis scales and clipped to sane limits. Objects on the table are then pushed
    apart until no footprints overlap, :data:`GAP` apart (:data:`HAND_ROOM` across a tool, and all round what a
    held tool works on where it lies, from anything tall enough to meet the gripper's palm), inside the reach
    region and each on its arm's half; when they do not fit there, each object, biggest first, goes to the free
    spot nearest its mapped place on the table (less :data:`ARM_CLEARANCE` at the arms' ends, then less
    :data:`ARM_BASE` and :data:`EDGE`), the rules
    loosening only as far as the table needs (see :func:`_settle`); ingredients that start in a container sit
    inside it, a board held still lies along x with its food clear of the end the holder presses
    (:mod:`wecook_core.plan.contents`).
    """
    first = {t.name: _first_box(t.frames, t.boxes) for t in obs.objects if len(t.frames)}
    if not first:
        return Scene(table=table)
    names = sorted(first, key=lambda n: (float(first[n][0]), n))
    boxes = np.array([first[n] for n in names])
    xy, m_per_px = _to_table(boxes, obs, table)
    users = _users(graph)
    for k, name in enumerate(names):  # an object only one arm uses goes to that arm's half of the table
        side = _side(users, name)
        if side < 0:
            xy[k, 0] = min(xy[k, 0], 0.0)
        elif side > 0:
            xy[k, 0] = max(xy[k, 0], 0.0)
    containing = containing_of(graph, obs, first)
    objects = _sized(names, boxes, xy, m_per_px, obs)
    held = holders(graph, containing)
    _fit_containers(objects, graph, containing, held)
    free = [n for n in names if n not in containing]
    placed = _place(objects, free, graph, obs, users, containing, table, robot)
    for n, (x, y) in zip(free, placed, strict=True):
        o = objects[n]
        objects[n] = SceneObject(o.name, o.category, o.shape, o.size, round(float(x), DECIMALS),
                                 round(float(y), DECIMALS), o.yaw)
    by_container: dict[str, list[str]] = {}
    for ingredient, container in sorted(containing.items()):
        by_container.setdefault(container, []).append(ingredient)
    for container, ingredients in by_container.items():  # spread along the container's longer axis
        for o in spread(objects[container], [objects[n] for n in ingredients], held.get(container, set())):
            objects[o.name] = o
    return Scene(table=table, objects=tuple(objects[n] for n in names),
                 containing=tuple(sorted(containing.items())))
