"""The plan's scene as PyBullet bodies: a table, the arms, and one simple body per object.

World frame as in :mod:`wecook_core.plan`: metres, z up, table top at ``z = table.height``. Every object's body
frame sits at the centre of its bounding box, x along its footprint's first size (a tool's long axis), rotated
by the plan's yaw about z. Bodies by category:

- tool: a long thin box (its plan size), light;
- container: open on top (a floor and walls; cylinders get a ring of wall boxes), or a flat slab when it is at
  most :data:`FLAT_HEIGHT` tall (boards, plates);
- ingredient: its plan shape (box, cylinder, sphere), small; with rolling friction so spheres stay put.

An ingredient of a containing pair rests on its container's floor. :func:`build_scene` is deterministic: called
on two clients with the same plan it creates the same body ids in the same order, which the planning client
relies on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as p
import pybullet_data

from wecook_core.errors import InputError
from wecook_core.execution.schedule.observer import FrameInfo, Shape
from wecook_core.model import Category
from wecook_core.plan import Agent, Plan, SceneObject

FLAT_HEIGHT = 0.03
"""Metres: containers at most this tall are slabs (boards, plates), taller ones are open boxes / rings."""
WALL = 0.008
"""Metres: wall and floor thickness of open containers."""
TABLE_THICKNESS = 0.04
SIM_HZ = 120
"""Simulation steps per simulated second (arms are driven kinematically, so 120 Hz is plenty)."""
SOLVER_ITERATIONS = 10
"""Constraint solver iterations per step (PyBullet's default 50 costs 2.5x the step time; objects mostly rest or
ride on a hand, and 10 keeps them as still)."""
RING_SEGMENTS = 12
"""Wall boxes around a cylindrical container."""
MASS = {Category.TOOL: 0.15, Category.CONTAINER: 0.6, Category.INGREDIENT: 0.1}
"""Kilograms by category (tall ingredients, bottles, weigh four times as much: they stay up)."""
COLORS = {Category.TOOL: (0.55, 0.55, 0.6, 1.0), Category.CONTAINER: (0.85, 0.75, 0.55, 1.0),
          Category.INGREDIENT: (0.85, 0.3, 0.2, 1.0)}


@dataclass
class Body:
    """A simulated object: its body id and what the executor needs to know about it."""

    name: str
    body: int
    category: Category
    size: tuple[float, float, float]
    """Metres, full extents in the body frame."""
    shapes: tuple[Shape, ...]
    """Drawn shapes in the body frame (also the collision shapes)."""
    open_top: bool = False
    """An open container (floor + walls); False for slabs and every non-container."""
    floor_top: float = 0.0
    """Metres above the body origin of the surface things rest on (containers: floor top; others: top)."""
    home: np.ndarray = field(default_factory=lambda: np.eye(4))
    """4x4 world pose where the plan puts it."""


@dataclass
class Arm:
    pid: str
    body: int
    urdf: str
    base: np.ndarray
    """4x4 world pose of the base."""
    links: tuple[str, ...] = ()
    """Link names: ``links[0]`` the base, ``links[i + 1]`` the child link of joint ``i``."""


@dataclass
class SceneBodies:
    """Everything :func:`build_scene` created in one client."""

    client: int
    table: int
    arms: dict[str, Arm]
    objects: dict[str, Body]
    table_height: float
    table_size: tuple[float, float]

    def object_names(self) -> dict[int, str]:
        return {b.body: name for name, b in self.objects.items()}


def robot_path(urdf: str) -> str:
    path = Path(urdf)
    return str(path if path.is_absolute() else Path(pybullet_data.getDataPath()) / path)


def _yaw_matrix(x: float, y: float, z: float, yaw: float) -> np.ndarray:
    T = np.eye(4)
    c, s = math.cos(yaw), math.sin(yaw)
    T[:3, :3] = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    T[:3, 3] = (x, y, z)
    return T


def object_shapes(obj: SceneObject) -> tuple[tuple[Shape, ...], bool, float]:
    """Shapes in the body frame, whether the body is an open container, and the height of its resting surface
    above the body origin (metres)."""
    sx, sy, sz = obj.size
    color = COLORS[obj.category]
    if obj.category is Category.CONTAINER and sz > FLAT_HEIGHT:
        floor_z = -sz / 2 + WALL / 2
        shapes = [Shape("box", (sx, sy, WALL), ((0.0, 0.0, floor_z), (0, 0, 0, 1)), color)]
        wall_h = sz - WALL
        wz = -sz / 2 + WALL + wall_h / 2
        if obj.shape == "box":
            for sign in (-1, 1):
                pose = ((sign * (sx - WALL) / 2, 0.0, wz), (0.0, 0.0, 0.0, 1.0))
                shapes.append(Shape("box", (WALL, sy, wall_h), pose, color))
                shapes.append(Shape("box", (sx - 2 * WALL, WALL, wall_h),
                                    ((0.0, sign * (sy - WALL) / 2, wz), (0, 0, 0, 1)), color))
        else:  # ring of wall boxes approximating a cylinder of diameter sx
            r = sx / 2 - WALL / 2
            chord = 2 * (sx / 2) * math.tan(math.pi / RING_SEGMENTS) + WALL
            for k in range(RING_SEGMENTS):
                a = 2 * math.pi * k / RING_SEGMENTS
                quat = (0.0, 0.0, math.sin(a / 2), math.cos(a / 2))
                pose = ((r * math.cos(a), r * math.sin(a), wz), quat)
                shapes.append(Shape("box", (WALL, chord, wall_h), pose, color))
        return tuple(shapes), True, -sz / 2 + WALL
    kind = obj.shape if obj.shape in ("box", "cylinder", "sphere") else "box"
    return (Shape(kind, (sx, sy, sz), color=color),), False, sz / 2  # type: ignore[arg-type]


def _collision_and_visual(client: int, shapes: tuple[Shape, ...]) -> tuple[int, int]:
    kinds = {"box": p.GEOM_BOX, "cylinder": p.GEOM_CYLINDER, "sphere": p.GEOM_SPHERE}
    types, radii, halves, lengths, positions, orns, colors = [], [], [], [], [], [], []
    for s in shapes:
        types.append(kinds[s.kind])
        radii.append(s.size[0] / 2)
        halves.append([v / 2 for v in s.size])
        lengths.append(s.size[2])
        positions.append(list(s.pose[0]))
        orns.append(list(s.pose[1]))
        colors.append(list(s.color))
    if len(shapes) == 1:
        s = shapes[0]
        kw: dict[str, Any] = {"radius": radii[0]} if s.kind != "box" else {"halfExtents": halves[0]}
        if s.kind == "cylinder":
            kw["height"] = lengths[0]
        col = p.createCollisionShape(types[0], physicsClientId=client, **kw)
        vkw = dict(kw)
        if s.kind == "cylinder":
            vkw = {"radius": radii[0], "length": lengths[0]}
        vis = p.createVisualShape(types[0], rgbaColor=colors[0], physicsClientId=client, **vkw)
        return col, vis
    col = p.createCollisionShapeArray(types, radii=radii, halfExtents=halves, lengths=lengths,
                                      collisionFramePositions=positions, collisionFrameOrientations=orns,
                                      physicsClientId=client)
    vis = p.createVisualShapeArray(types, radii=radii, halfExtents=halves, lengths=lengths,
                                   visualFramePositions=positions, visualFrameOrientations=orns,
                                   rgbaColors=colors, physicsClientId=client)
    return col, vis


def build_scene(client: int, plan: Plan, *, self_collision: bool = False) -> SceneBodies:
    """Create the table, the arms and the objects of ``plan`` in ``client`` (gravity on, :data:`SIM_HZ`)."""
    scene = plan.scene
    table_h = scene.table.height
    p.setGravity(0, 0, -9.81, physicsClientId=client)
    p.setTimeStep(1 / SIM_HZ, physicsClientId=client)
    p.setPhysicsEngineParameter(numSolverIterations=SOLVER_ITERATIONS, physicsClientId=client)
    half = [scene.table.size[0] / 2, scene.table.size[1] / 2, TABLE_THICKNESS / 2]
    tcol = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
    tvis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=[0.6, 0.45, 0.3, 1], physicsClientId=client)
    table = p.createMultiBody(0, tcol, tvis, [0, 0, table_h - TABLE_THICKNESS / 2], physicsClientId=client)
    p.changeDynamics(table, -1, lateralFriction=1.0, physicsClientId=client)
    arms: dict[str, Arm] = {}
    for agent in sorted(plan.agents, key=lambda a: a.pid):
        arms[agent.pid] = _load_arm(client, agent, self_collision)
    inside = dict(scene.containing)
    objects: dict[str, Body] = {}
    # containers first, so their contents can be placed on their floors
    order = sorted(scene.objects, key=lambda o: (o.name in inside, o.name))
    for obj in order:
        shapes, open_top, floor_top = object_shapes(obj)
        z = table_h + obj.size[2] / 2
        if obj.name in inside and inside[obj.name] in objects:
            container = objects[inside[obj.name]]
            z = container.home[2, 3] + container.floor_top + obj.size[2] / 2 + 0.001
        home = _yaw_matrix(obj.x, obj.y, z, obj.yaw)
        col, vis = _collision_and_visual(client, shapes)
        quat = p.getQuaternionFromEuler([0, 0, obj.yaw])
        mass = MASS[obj.category] * (4.0 if obj.size[2] > 0.08 and obj.category is Category.INGREDIENT else 1.0)
        body = p.createMultiBody(mass, col, vis, home[:3, 3].tolist(), quat, physicsClientId=client)
        # objects at rest sleep (the solver skips them: 2.3x faster steps on a laid-out table) until touched,
        # moved by a hand or let go
        p.changeDynamics(body, -1, lateralFriction=1.0, rollingFriction=0.01, spinningFriction=0.01,
                         linearDamping=0.4, angularDamping=0.4,
                         activationState=p.ACTIVATION_STATE_ENABLE_SLEEPING, physicsClientId=client)
        objects[obj.name] = Body(obj.name, body, obj.category, tuple(obj.size), shapes, open_top,  # type: ignore[arg-type]
                                 floor_top, home)
    return SceneBodies(client, table, arms, objects, table_h, scene.table.size)


def _load_arm(client: int, agent: Agent, self_collision: bool) -> Arm:
    urdf = robot_path(agent.robot)
    if not Path(urdf).is_file():
        raise InputError(None, f"robot URDF {agent.robot!r} not found (looked at {urdf})",
                         place=f"agents ({agent.pid})")
    quat = p.getQuaternionFromEuler([0, 0, agent.base_yaw])
    flags = p.URDF_USE_SELF_COLLISION if self_collision else 0
    try:
        body = p.loadURDF(urdf, list(agent.base_position), quat, useFixedBase=True, flags=flags,
                          physicsClientId=client)
    except p.error as error:  # a URDF PyBullet cannot load (its meshes, its joints): one line, not a traceback
        raise InputError(None, f"PyBullet cannot load the robot URDF {urdf} ({error})",
                         place=f"agents ({agent.pid}).robot") from None
    base = _yaw_matrix(*agent.base_position, agent.base_yaw)
    links = [p.getBodyInfo(body, physicsClientId=client)[0].decode()]
    links += [p.getJointInfo(body, j, physicsClientId=client)[12].decode()
              for j in range(p.getNumJoints(body, physicsClientId=client))]
    return Arm(agent.pid, body, agent.robot, base, tuple(links))


# ------------------------------------------------------------------------------------------- drawing


def _obj_bounds(path: str) -> tuple[np.ndarray, np.ndarray] | None:
    return _obj_bounds_cached(path)


@cache
def _obj_bounds_cached(path: str) -> tuple[np.ndarray, np.ndarray] | None:
    try:
        vertices = [line.split()[1:4] for line in Path(path).read_text().splitlines() if line.startswith("v ")]
    except OSError:
        return None
    if not vertices:
        return None
    v = np.array(vertices, dtype=float)
    return v.min(axis=0), v.max(axis=0)


def link_frames(bodies: SceneBodies) -> list[FrameInfo]:
    """Frames for the recorder: ``table``, ``object/<name>``, ``<pid>/<link>`` with box shapes drawn in them
    (arm links as the bounding boxes of their collision meshes, in the link frame)."""
    c = bodies.client
    tx, ty = bodies.table_size
    frames = [FrameInfo("table", (Shape("box", (tx, ty, TABLE_THICKNESS), ((0, 0, -TABLE_THICKNESS / 2), (0, 0, 0, 1)),
                                        (0.6, 0.45, 0.3, 1.0)),))]
    for name, body in bodies.objects.items():
        frames.append(FrameInfo(f"object/{name}", body.shapes))
    for pid, arm in bodies.arms.items():
        for link in range(-1, p.getNumJoints(arm.body, physicsClientId=c)):
            shapes = []
            inertial = inertial_frame(c, arm.body, link)
            for data in p.getCollisionShapeData(arm.body, link, physicsClientId=c):
                # PyBullet gives a collision shape's frame in the link's inertial (centre of mass) frame
                geom, dims, mesh = data[2], data[3], data[4]
                pos, orn = p.multiplyTransforms(*inertial, data[5], data[6])
                if geom == p.GEOM_MESH:
                    bounds = _obj_bounds(mesh.decode() if isinstance(mesh, bytes) else str(mesh))
                    if bounds is None:
                        continue
                    lo, hi = bounds[0] * np.array(dims), bounds[1] * np.array(dims)
                    centre = p.multiplyTransforms(pos, orn, ((lo + hi) / 2).tolist(), [0, 0, 0, 1])[0]
                    shapes.append(Shape("box", tuple(float(v) for v in hi - lo),  # type: ignore[arg-type]
                                        (tuple(centre), tuple(orn)), (0.9, 0.9, 0.92, 1.0)))
                elif geom == p.GEOM_BOX:
                    shapes.append(Shape("box", tuple(float(v) for v in dims), (tuple(pos), tuple(orn))))  # type: ignore[arg-type]
            frames.append(FrameInfo(f"{pid}/{arm.links[link + 1]}", tuple(shapes)))
    return frames


def inertial_frame(client: int, body: int, link: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The link's inertial (centre of mass) frame in its URDF link frame: the ``<inertial><origin>``."""
    info = p.getDynamicsInfo(body, link, physicsClientId=client)
    return tuple(info[3]), tuple(info[4])


def world_poses(bodies: SceneBodies) -> dict[str, tuple[tuple[float, float, float], tuple[float, float, float, float]]]:
    """Every frame of :func:`link_frames` -> its world pose now: arm links at their URDF link frames (the
    frames their URDF visuals are placed in), not at their centres of mass."""
    c = bodies.client
    out: dict[str, tuple] = {"table": ((0.0, 0.0, bodies.table_height), (0.0, 0.0, 0.0, 1.0))}
    for name, body in bodies.objects.items():
        pos, orn = p.getBasePositionAndOrientation(body.body, physicsClientId=c)
        out[f"object/{name}"] = (tuple(pos), tuple(orn))
    for pid, arm in bodies.arms.items():
        # PyBullet's base pose is its centre of mass; the URDF's base link frame is that less the inertial offset
        com = p.getBasePositionAndOrientation(arm.body, physicsClientId=c)
        pos, orn = p.multiplyTransforms(*com, *p.invertTransform(*inertial_frame(c, arm.body, -1)))
        out[f"{pid}/{arm.links[0]}"] = (tuple(pos), tuple(orn))
        n = len(arm.links) - 1
        for link, state in enumerate(p.getLinkStates(arm.body, list(range(n)), computeForwardKinematics=True,
                                                     physicsClientId=c)):
            out[f"{pid}/{arm.links[link + 1]}"] = (tuple(state[4]), tuple(state[5]))
    return out
