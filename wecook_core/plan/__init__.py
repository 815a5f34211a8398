"""The robot plan: what two arms must do, built from an action graph, in and out of YAML (``wecook_plan: 1``).

World frame of a plan (the executor and the recording use the same one): metres, z up, the table top is the
rectangle ``|x| <= size_x / 2, |y| <= size_y / 2`` at ``z = table.height``. Arm P1 stands at the ``-x`` end of
the table facing ``+x``, arm P2 at the ``+x`` end facing ``-x``. Seen from the camera of the video, P1 (the
left person) is on the left: image x grows with world x, and the image's top (far from the camera) is ``+y``.

A plan file::

    wecook_plan: 1
    agents:
    - {pid: P1, robot: franka_panda/panda.urdf, base: {position: [-0.5, 0.0, 0.0], yaw: 0.0}}
    scene:
      table: {size: [1.0, 0.8], height: 0.0}
      objects:
      - {name: knife, category: tool, shape: box, size: [0.2, 0.03, 0.025], pose: {x: 0.1, y: 0.0, yaw: 0.0}}
      containing:
      - [tomato, chopping_board]
    actions:
    - {id: a1, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], location: chopping_board,
       after: [], frames: [10, 52], tree: "(HP ...)"}

The package: :mod:`.model` (the dataclasses and constants), :mod:`.checks` (``plan_problems``, ``validate``),
:mod:`.yaml_file` (``read_plan``, ``write_plan`` and friends), :mod:`.from_graph` (``plan_from_graph``).
Import the names from here.
"""

from __future__ import annotations

from wecook_core.plan.checks import plan_problems, validate
from wecook_core.plan.from_graph import action_objects, agents_for, object_dependencies, plan_actions, plan_from_graph
from wecook_core.plan.model import (
    ARM_REACH,
    DEFAULT_ROBOT,
    DEFAULT_TABLE,
    PLAN_VERBS,
    PLAN_VERSION,
    SHAPES,
    Act,
    Agent,
    Plan,
    PlanAction,
    Scene,
    SceneObject,
    Table,
    Vec3,
)
from wecook_core.plan.yaml_file import dump_plan, load_plan, plan_from_dict, plan_to_dict, read_plan, write_plan

__all__ = [
    "ARM_REACH",
    "DEFAULT_ROBOT",
    "DEFAULT_TABLE",
    "PLAN_VERBS",
    "PLAN_VERSION",
    "SHAPES",
    "Act",
    "Agent",
    "Plan",
    "PlanAction",
    "Scene",
    "SceneObject",
    "Table",
    "Vec3",
    "action_objects",
    "agents_for",
    "dump_plan",
    "load_plan",
    "object_dependencies",
    "plan_actions",
    "plan_from_dict",
    "plan_from_graph",
    "plan_problems",
    "plan_to_dict",
    "read_plan",
    "validate",
    "write_plan",
]
