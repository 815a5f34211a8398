"""Placing (a primitive of the world, :mod:`wecook_core.execution.world`, written against its
:class:`~.protocols.Scene` and :class:`~.protocols.Arm`): putting the carried object down on a given pose or
region, or on the roomiest free spot of a region."""

from __future__ import annotations

import math
from collections.abc import Generator

import numpy as np

from wecook_core.execution.schedule.program import ActionFailed, Program, Tick
from wecook_core.execution.skills.tsr import TSR, xyzrpy_to_matrix
from wecook_core.execution.world.grasping import release
from wecook_core.execution.world.protocols import Cell
from wecook_core.execution.world.retry import retrying
from wecook_core.plan import PlanAction

HAND_SPAN = 0.22
"""Metres: the Panda hand's length along its finger axis (it lies across an object it takes from above)."""
HAND_CLEAR_HEIGHT = 0.04
"""Metres above the table from which an object can be in the way of a hand taking something from above."""
FREE_MARGIN = 0.1
"""Metres of clearance around an object put down on a free spot beyond which spots count as equally roomy
(room for the hand to take it again)."""
FINGERS_ALONG = 0.035
"""Metres either side of a tool's grasp point, along the tool, that the fingers taking it reach down to the table
(their width, and the grasp region's play along the handle)."""
FINGERS_OUT = 0.02
"""Metres beyond a tool's long edges that the fingers taking it reach down to the table (the opening to approach
it, and their thickness)."""


def _fingers(half: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """The corners (4, 2), in the tool's frame, of where the fingers taking a tool of half extents ``half`` at
    ``centre`` reach down to the table."""
    return np.array([[centre[0] + sx * FINGERS_ALONG, sy * (half[1] + FINGERS_OUT)] for sx in (-1, 1)
                     for sy in (-1, 1)])


def _handle(half: np.ndarray) -> np.ndarray:
    """Where a hand takes a tool lying on the table, in the tool's frame (x, y): its handle, at the -x end."""
    return np.array([-HANDLE_AT * half[0], 0.0])


HANDLE_AT = 0.55
"""Where along a tool's half length, from its centre towards its -x end, its handle is taken (a fraction)."""
HAND_DEPTH = 0.06
"""Metres: the Panda hand's depth along the object's axis (across its finger axis)."""
GRID_STEP = 0.02
"""Metres between the free spots tried, along x and y of the region."""
YAWS = np.radians([-90, -45, 0, 45, 90])
"""The turns about z tried at each spot (those within the region's bounds), radians."""
YAW_COST = 0.01
"""Metres of distance from the region's centre one radian of turn counts as, when room is equal."""
ALONE = 1.0
"""Metres: the clearance of a footprint when nothing is there to be clear of."""
OVERLAPS = -1.0
"""The clearance of footprints that overlap (any negative value: no room)."""
ROUNDING = 1e-9
"""Slack on the region's bounds so that a bound on the grid is tried (metres, radians)."""


def _clearance(pts: np.ndarray, against: np.ndarray) -> float:
    """Metres between the bounding box of ``pts`` (n, 2) and the nearest of the boxes ``against`` (m, 2, 2:
    min and max corner); :data:`OVERLAPS` when it meets one, :data:`ALONE` when there are none."""
    if not len(against):
        return ALONE
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    sep = np.maximum(against[:, 0] - hi, lo - against[:, 1])
    overlap = np.all(sep < 0, axis=1)
    gap = np.maximum(sep, 0.0)
    return float(np.min(np.where(overlap, OVERLAPS, np.hypot(gap[:, 0], gap[:, 1]))))


def _grip(cell: Cell, name: str, half: np.ndarray, is_tool: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where the hand holds ``name``, in the object's frame: the grip's centre, the finger axis (across) and
    the axis along the object; the hand's own grip when it carries it, else a tool's handle or the centre."""
    hands = [cell.scene.hand(pid) for pid in cell.arms]
    holder = next((h for h in hands if h.carried == name), None)
    if holder is not None and holder.riding:
        T_obj_ee = np.linalg.inv(holder.riding[0].T_ee_obj)
        return T_obj_ee[:2, 3], T_obj_ee[:2, 1], T_obj_ee[:2, 0]
    return (_handle(half) if is_tool else np.zeros(2)), np.array([0.0, 1.0]), np.array([1.0, 0.0])


def _boxes_2d(boxes: list[np.ndarray]) -> np.ndarray:
    """World boxes (each 2 x 3) as their footprints, (n, 2, 2)."""
    return np.array([box[:, :2] for box in boxes]).reshape(-1, 2, 2)


def _their_fingers(cell: Cell, names: list[str]) -> np.ndarray:
    """Where the fingers taking each other tool lying on the table reach down, world footprints (n, 2, 2)."""
    scene = cell.scene
    in_hand = {r.name for pid in cell.arms for r in scene.hand(pid).riding}
    found = []
    for n in names:
        if scene.kind(n) == "tool" and n not in in_hand and scene.container_of(n) is None:
            h = np.array(scene.size(n)) / 2
            T = scene.pose(n)
            pts = _fingers(h, _handle(h)) @ T[:2, :2].T + T[:2, 3]
            found.append([pts.min(axis=0), pts.max(axis=0)])
    return np.array(found).reshape(-1, 2, 2)


def _spots(region: TSR) -> list[tuple[float, float, float, np.ndarray]]:
    """Every spot tried in ``region``: (x, y, yaw) on its grid, and the object pose there."""
    B = region.Bw
    xs = np.arange(B[0, 0], B[0, 1] + ROUNDING, GRID_STEP)
    ys = np.arange(B[1, 0], B[1, 1] + ROUNDING, GRID_STEP)
    yaws = [y for y in YAWS if B[5, 0] - ROUNDING <= y <= B[5, 1] + ROUNDING] or [0.0]
    z = (B[2, 0] + B[2, 1]) / 2
    return [(x, y, yaw, region.T0_w @ xyzrpy_to_matrix([x, y, z, 0, 0, yaw]) @ region.Tw_e)
            for yaw in yaws for x in xs for y in ys]


def free_poses(cell: Cell, name: str, region: TSR) -> list[np.ndarray]:
    """Object poses of ``region`` on a :data:`GRID_STEP` grid (turned by each of :data:`YAWS` within the bounds),
    the roomiest first. Room is the smaller of two clearances: the object's footprint to every other object, and
    the footprint of a hand taking it again (:data:`HAND_SPAN` across the object at its grasp point) to every
    object taller than :data:`HAND_CLEAR_HEIGHT`. Spots where a tool's fingers would meet something come only
    after the others, as spots without room do: where the fingers taking the object (a tool) reach down beside
    it, no other object may lie, and the object may not lie where the fingers taking another tool on the table
    reach down (a spoon put down across the whisk's handle leaves neither to be taken). Clearances beyond
    :data:`FREE_MARGIN` count as equally roomy; then the spot nearest the region's centre wins."""
    scene = cell.scene
    own = {r.name for pid in cell.arms for r in scene.hand(pid).riding if scene.hand(pid).carried == name}
    half = np.array(scene.size(name)) / 2
    corners = np.array([[sx * half[0], sy * half[1]] for sx in (-1, 1) for sy in (-1, 1)])
    is_tool = scene.kind(name) == "tool"
    centre, across, along = _grip(cell, name, half, is_tool)
    hand = np.array([centre + sy * HAND_SPAN / 2 * across + sx * HAND_DEPTH / 2 * along
                     for sx in (-1, 1) for sy in (-1, 1)])
    fingers = _fingers(half, centre) if is_tool else np.zeros((0, 2))
    names = [n for n in scene.names() if n not in own and n != name]
    others = scene.boxes(names)
    boxes = _boxes_2d(others)
    tall = _boxes_2d([box for box in others if box[1, 2] - scene.table_height > HAND_CLEAR_HEIGHT])
    fingered = _their_fingers(cell, names)
    scored = []
    for x, y, yaw, T in _spots(region):
        R, t = T[:2, :2], T[:2, 3]
        footprint = corners @ R.T + t
        own_room = _clearance(footprint, boxes)
        if own_room <= 0.0:
            continue
        room = min(own_room, _clearance(hand @ R.T + t, tall))
        # where the hand has no room, or the fingers meet something, only after every roomy spot
        free_fingers = _clearance(footprint, fingered) > 0.0 and (
            not len(fingers) or _clearance(fingers @ R.T + t, boxes) > 0.0)
        tier = 0 if room > 0.0 and free_fingers else 1
        scored.append((tier, -min(max(room, own_room * tier), FREE_MARGIN), math.hypot(x, y) + YAW_COST * abs(yaw),
                       T))
    scored.sort(key=lambda item: item[:3])
    return [item[3] for item in scored]


def place(cell: Cell, action: PlanAction | None, pid: str, target: np.ndarray | list[TSR], free: bool = False
          ) -> Program:
    """Put the carried object down at ``target`` (object pose, or TSRs of object poses): planned move above,
    straight down, release. ``free``: only where it stands clear of the other objects."""
    scene, arm = cell.scene, cell.arms[pid]
    hand = scene.hand(pid)
    name = hand.carried
    if name is None:
        return
    scene.event("primitive_start", action, pid, name, "place")
    T_obj_ee = np.linalg.inv(hand.riding[0].T_ee_obj)
    regions = target if isinstance(target, list) else [TSR(target, np.eye(4), np.array(
        [[-0.01, 0.01], [-0.01, 0.01], [0.002, 0.006], [0, 0], [0, 0], [-0.1, 0.1]]))]

    def attempt(k: int) -> Generator[Tick, None, str | None]:
        if free:
            spots = free_poses(cell, name, regions[0])
            goals = [T @ T_obj_ee for T in spots[k * cell.samples:(k + 1) * cell.samples]]
        else:
            goals = arm.goal_samples(regions, T_obj_ee, cell.samples)
        chosen = None
        blocked = None
        for G in goals:
            found = arm.ik_goal([G], [], check=False)
            if found is None:
                continue
            above = G.copy()
            above[2, 3] += cell.skills.lift
            found_above = arm.ik_goal([above], [])
            if found_above is None:
                continue
            try:  # the straight way down must be feasible too
                arm.cartesian_path(found_above[0], [G], [], f"put down {name}")
            except ActionFailed as error:
                blocked = str(error)
                continue
            chosen = (found_above[0], G)
            break
        if chosen is None:
            return blocked or arm.no_goal(f"place pose for {name}", len(goals))
        try:
            yield from arm.transit(chosen[0], what=f"place {name}")
            yield from arm.linear([chosen[1]], ignore=[], what=f"put down {name}")
        except ActionFailed as error:
            return str(error)
        yield from release(cell, pid)
        return None

    yield from retrying(scene, arm, cell.attempts, action, "place", f"place {name}", name, attempt,
                        "no reachable place pose")
