"""The paper's ROS platform's messages (icaros-usc/wecook, ``msg/*.msg``) as frozen dataclasses, fields named and
ordered as there (:data:`MESSAGES`), and the topic it listens on."""

from __future__ import annotations

from dataclasses import dataclass

TOPIC = "WeCookDispatch"
"""The topic the platform's TaskManager subscribes to (``src/wecook/TaskManager.cpp``)."""

MESSAGES: dict[str, tuple[tuple[str, str], ...]] = {
    "ObjectMsg": (("name", "string"), ("url", "string"), ("pose", "float64[]")),
    "TagMsg": (("tagId", "uint32"), ("objectName", "string"), ("objectPose", "float64[]")),
    "ContainingMsg": (("pair", "string[]"),),
    "SceneMsg": (("objects", "ObjectMsg[]"), ("tags", "TagMsg[]"), ("containingMap", "ContainingMsg[]")),
    "ActionMsg": (("pid", "string[]"), ("verb", "string"), ("location", "string[]"), ("tool", "string"),
                  ("ingredients", "string[]")),
    "AgentMsg": (("pid", "string"), ("type", "string"), ("pose", "float64[]"), ("if_float", "bool")),
    "TaskMsg": (("scene", "SceneMsg"), ("actions", "ActionMsg[]"), ("agents", "AgentMsg[]"), ("PDDLDomain", "string"),
                ("PDDLProblem", "string"), ("type", "string"), ("motionPlannerType", "string"), ("ifSim", "bool")),
}
"""The platform's messages (its ``msg/*.msg``): name -> ((field, ROS type), ...) in declaration order."""


@dataclass(frozen=True)
class ObjectMsg:
    name: str
    url: str
    pose: tuple[float, ...]


@dataclass(frozen=True)
class TagMsg:
    tag_id: int
    object_name: str
    object_pose: tuple[float, ...]


@dataclass(frozen=True)
class ContainingMsg:
    pair: tuple[str, str]
    """``(container, contained)``."""


@dataclass(frozen=True)
class ActionMsg:
    pid: tuple[str, ...]
    verb: str
    location: tuple[str, ...]
    tool: str
    ingredients: tuple[str, ...]


@dataclass(frozen=True)
class AgentMsg:
    pid: str
    type: str
    pose: tuple[float, ...]
    if_float: bool


@dataclass(frozen=True)
class TaskMsg:
    """The ``TaskMsg`` (its ``SceneMsg`` flattened into the first three fields)."""

    objects: tuple[ObjectMsg, ...]
    containing: tuple[ContainingMsg, ...]
    actions: tuple[ActionMsg, ...]
    agents: tuple[AgentMsg, ...]
    tags: tuple[TagMsg, ...] = ()
    type: str = "follow"
    """``follow``: the platform follows the actions as given (``plan`` would have it plan from PDDL)."""
    motion_planner: str = "RRTConnect"
    if_sim: bool = True
