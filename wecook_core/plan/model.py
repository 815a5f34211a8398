"""The plan's dataclasses and constants (world frame: see :mod:`wecook_core.plan`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from wecook_core.model import COLLABORATIONS, VERBS, Category

PLAN_VERSION = 1
DEFAULT_ROBOT = "franka_panda/panda.urdf"
"""URDF of an arm, relative to ``pybullet_data`` unless absolute."""
SHAPES: tuple[str, ...] = ("box", "cylinder", "sphere")
ARM_REACH: dict[str, float] = {DEFAULT_ROBOT: 0.85}
"""Metres: how far from its base (horizontally) an arm reaches an object on the table, by robot URDF (the
Franka Panda reaches 0.855 m from its shoulder). Objects an action uses must lie within the reach of one of its
agents; robots not listed are not checked."""
PLAN_VERBS: tuple[str, ...] = (*VERBS, *COLLABORATIONS)
"""Verbs a plan action may have: the vocabulary, ``handover`` and ``holding``."""

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class Table:
    """The table top, centred on the world origin."""

    size: tuple[float, float] = (1.0, 0.8)
    """Metres: extent along x (between the arms) and along y."""
    height: float = 0.0
    """Metres: z of the table top (the arms' bases stand on it)."""
    reach: tuple[float, float] = (0.1, 0.3)
    """Metres: half extents of the region, centred on the origin, that both arms reach comfortably; objects
    laid out from a video are placed inside it (see :func:`plan_from_graph`)."""

    def holds(self, x: float, y: float, half_x: float = 0.0, half_y: float = 0.0) -> bool:
        """True when a footprint of the given half extents centred at (x, y) lies on the table top."""
        return abs(x) + half_x <= self.size[0] / 2 + 1e-9 and abs(y) + half_y <= self.size[1] / 2 + 1e-9


DEFAULT_TABLE = Table()


@dataclass(frozen=True)
class Agent:
    """One robot arm; person ``pid`` of the video."""

    pid: str
    """``P1`` or ``P2``."""
    robot: str = DEFAULT_ROBOT
    """URDF path, relative to ``pybullet_data`` unless absolute."""
    base_position: Vec3 = (0.0, 0.0, 0.0)
    """Metres, world frame."""
    base_yaw: float = 0.0
    """Radians about z; 0 faces +x."""


@dataclass(frozen=True)
class SceneObject:
    """An object on the table, drawn and simulated as one primitive shape."""

    name: str
    """As in the trees (``chopping_board``, ``bowl_2``)."""
    category: Category
    shape: str
    """``box``, ``cylinder`` or ``sphere``. Containers are built open on top by the simulation."""
    size: Vec3
    """Metres: box full extents (x, y, z before yaw); cylinder (diameter, diameter, height); sphere (d, d, d)."""
    x: float
    y: float
    """Metres: centre of the footprint on the table, world frame. For an ingredient inside a container: where
    it sits inside it."""
    yaw: float = 0.0
    """Radians about z."""

    def half_extents(self) -> tuple[float, float]:
        """Half extents of the footprint along world x and y (yaw taken into account)."""
        hx, hy = self.size[0] / 2, self.size[1] / 2
        c, s = abs(math.cos(self.yaw)), abs(math.sin(self.yaw))
        return hx * c + hy * s, hx * s + hy * c


@dataclass(frozen=True)
class Scene:
    table: Table = field(default_factory=Table)
    objects: tuple[SceneObject, ...] = ()
    containing: tuple[tuple[str, str], ...] = ()
    """``(ingredient, container)`` pairs: the ingredient starts inside the container."""

    def object(self, name: str) -> SceneObject:
        for obj in self.objects:
            if obj.name == name:
                return obj
        raise KeyError(name)

    def names(self) -> frozenset[str]:
        return frozenset(obj.name for obj in self.objects)


@dataclass(frozen=True)
class Act:
    """What the other arm does during a ``holding`` action."""

    verb: str
    tool: str | None = None
    ingredients: tuple[str, ...] = ()
    location: str | None = None
    source: str | None = None


@dataclass(frozen=True)
class PlanAction:
    """One action of the plan.

    Fields by verb:

    - vocabulary verbs (``cut``, ``pour``, ...): ``pids == (p,)``; ``tool`` is the object the arm grasps to act
      (a tool such as ``knife``, or the held ingredient / container for pour, sprinkle, dip and tipping
      transfers; None for an action by the hand itself such as squeeze); ``ingredients`` are the ingredients
      acted on; ``location`` the container or target acted on / into.
    - ``transfer``: ``ingredients`` move from ``source`` to ``location``, carried by ``tool``.
    - ``handover``: ``pids == (giver, receiver)``; ``tool`` is the object handed over.
    - ``holding``: ``pids == (holder, actor)``; ``tool`` is the object the holder keeps still while the actor
      does ``partner`` on it.
    """

    id: str
    pids: tuple[str, ...]
    verb: str
    tool: str | None = None
    ingredients: tuple[str, ...] = ()
    location: str | None = None
    source: str | None = None
    """Transfer only: the container the ingredients leave."""
    partner: Act | None = None
    """Holding only: the actor's action."""
    after: tuple[str, ...] = ()
    """Ids of actions that must end before this one starts."""
    frames: tuple[int, int] | None = None
    """Source video frames ``[start, end)``."""
    tree: str | None = None
    """The action tree it came from, bracket notation."""


@dataclass(frozen=True)
class Plan:
    agents: tuple[Agent, ...]
    scene: Scene
    actions: tuple[PlanAction, ...]
    version: int = PLAN_VERSION

    def action(self, action_id: str) -> PlanAction:
        for action in self.actions:
            if action.id == action_id:
                return action
        raise KeyError(action_id)
