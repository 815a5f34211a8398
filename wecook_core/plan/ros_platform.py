"""What the paper's ROS platform (icaros-usc/wecook) can plan, read from its sources, and how wecook's verbs map
onto it.

Sources (icaros-usc/wecook at a293374, 2023-06-06):

- ``src/wecook/TaskGraph/ActionPlanner.cpp``, ``ActionPlanner::plan``: the verb picks the planner, tested in
  this order: ``cut`` (planCut), ``stir`` (planStir), ``handover`` (planHandover), ``transfer`` (planTransfer), any
  verb containing ``_`` (planHolding), ``roll`` (planRoll), ``heat`` (planHeat), ``feeding`` (planFeeding). Any
  other verb (``wrap``, ``dip``, ``sprinkle``, ``squeeze`` are commented out; ``peel``, ``pour``, ``spread`` never
  existed) gets no primitive task graph at all.
- ``planHolding``: the verb is ``holding_<object>_<action>``; it handles ``cut`` (the holder grasps ``<object>``,
  the actor is planned by planCut) and ``transfer`` when ``<object>`` is the transfer's ``location[1]`` or
  ``location[0]`` (the actor is planned by planTransfer and its six primitive nodes are taken by index: only the
  transfer with a tool, neither ``hand`` nor the source container, has six). Anything else: no graph.
- ``src/wecook/TaskGraph/TaskGraph.cpp``, ``TaskGraph::merge``: for each pid, it walks that pid's chain of action
  nodes (the actions naming the pid, in message order) and dereferences every node's head and tail primitive
  node for the pid: one action without a graph for one of its pids crashes the node. Hence nothing is sent that
  does not plan, for every pid it names.
- ``src/wecook/ObjectMgr.cpp``: ``getObjTransform`` of a name not in the scene throws; every name a planner
  reads (below) must be an object of the scene (``air`` and ``hand`` are read by none).
- ``src/wecook/World.cpp``, ``setupFollowingTask``: an agent per ``AgentMsg``; a pid without one is a null agent.

:data:`PLANNERS` is the table of supported verbs and what each planner reads; :func:`planner_problem` says why a
message would not plan (None: it plans).
"""

from __future__ import annotations

from collections.abc import Set

from wecook_core.plan.ros_messages import ActionMsg

HAND, AIR = "hand", "air"
HOLDING = "holding"

PLANNERS: dict[str, str] = {
    "cut": "planCut: grasps `tool`, engages `ingredients[0]`, cuts, puts the tool back",
    "stir": "planStir: grasps `tool`, engages `location[0]`, stirs, puts the tool back",
    "handover": "planHandover: pid[0] grasps `ingredients[0]` and holds it out, pid[1] grasps it",
    "transfer": "planTransfer: tool `hand`: grasps `ingredients[0]`, places it on `location[1]`; tool == "
                "`location[0]`: grasps that container, tips it over `location[1]`, puts it back; else grasps "
                "`tool`, scoops `ingredients[0]`, tips it over `location[1]`, puts the tool back",
    "roll": "planRoll: grasps `tool`, engages `ingredients[0]`, rolls, puts the tool back",
    "heat": "planHeat: grasps `tool`, engages `ingredients[0]`",
    "feeding": "planFeeding: grasps `tool`, scoops `ingredients[0]`, brings it to `location[1]`",
    "holding_<object>_cut": "planHolding: pid[0] grasps and holds <object>, pid[1] cuts as planCut",
    "holding_<object>_transfer": "planHolding: pid[0] grasps and holds <object> (location[0] or location[1]), "
                                 "pid[1] transfers with a tool as planTransfer's third form",
}
"""The platform's planners by verb (``ActionPlanner.cpp``), and what each reads of the ``ActionMsg``."""

FOLLOWS: dict[str, str] = {
    "pour": "transfer",
    "sprinkle": "transfer",
}
"""wecook verbs the platform has no planner for, sent as the nearest one that does the same thing: pouring from
or sprinkling out of a held container is planTransfer's second form (grasp the container, tip it over the
destination, put it back: ``PrimitiveActuateNode`` ``transfer1`` is that tilt)."""

NO_PLANNER: dict[str, str] = {
    "peel": "no peeling motion on the platform",
    "squeeze": "no squeezing motion (ActionPlanner's planSqueeze is commented out)",
    "spread": "no spreading motion on the platform",
    "wrap": "no wrapping motion (planWrap is commented out)",
    "dip": "no dipping motion (planDip is commented out); a transfer would leave the food in the container",
}
"""wecook verbs left out of the dispatch, and why (no planner does anything like them)."""


def _objects(msg: ActionMsg) -> dict[str, list[str]]:
    """Field -> the names a planner reads from it (by the planner's rules), or raises IndexError/KeyError for
    a field it reads that is empty."""
    verb, tool, location, ingredients = msg.verb, msg.tool, msg.location, msg.ingredients
    if "_" in verb and verb not in PLANNERS:
        held = verb[verb.index("_") + 1: verb.rindex("_")]
        inner = verb[verb.rindex("_") + 1:]
        if inner == "cut":
            return {"held": [held], "tool": [tool], "ingredients": [ingredients[0]]}
        if inner == "transfer":
            if held not in location[:2] or tool in (HAND, location[0]):
                raise KeyError("transfer")
            return {"held": [held], "tool": [tool], "ingredients": [ingredients[0]], "location": [location[1]]}
        raise KeyError(inner)
    if verb in ("cut", "roll", "heat"):
        return {"tool": [tool], "ingredients": [ingredients[0]]}
    if verb == "stir":
        return {"tool": [tool], "location": [location[0]]}
    if verb == "handover":
        return {"ingredients": [ingredients[0]]}
    if verb == "transfer":
        if tool == HAND:
            return {"ingredients": [ingredients[0]], "location": [location[1]]}
        if tool == location[0]:
            return {"location": [location[0], location[1]]}
        return {"tool": [tool], "ingredients": [ingredients[0]], "location": [location[1]]}
    if verb == "feeding":
        return {"tool": [tool], "ingredients": [ingredients[0]], "location": [location[0], location[1]]}
    raise KeyError(verb)


def planner_problem(msg: ActionMsg, objects: Set[str], agents: Set[str]) -> str | None:
    """Why the platform would not plan ``msg`` in a scene of ``objects`` with ``agents`` (pids), or None."""
    two = msg.verb == "handover" or "_" in msg.verb
    if len(msg.pid) != (2 if two else 1):
        return f"{msg.verb} takes {2 if two else 1} pid(s), got {len(msg.pid)}"
    missing = [p for p in msg.pid if p not in agents]
    if missing:
        return f"no agent {', '.join(missing)}"
    try:
        read = _objects(msg)
    except KeyError as error:
        if "_" in msg.verb:
            return (f"the holding planner does only holding_<object>_cut and holding_<object>_transfer with a "
                    f"tool and <object> its source or destination, not {msg.verb}")
        return f"no planner for {error.args[0]}"
    except IndexError:
        return f"a field {msg.verb}'s planner reads is empty"
    for field, names in read.items():
        for name in names:
            if name not in objects:
                return f"{field} {name} is not in the scene"
    named = [n for n in (msg.tool, *msg.location, *msg.ingredients) if n not in objects and n not in (HAND, AIR)]
    if named:  # read by no planner, but the platform keeps the action (MetaActuateInfo): names must be real
        return f"{named[0]} is not in the scene"
    return None
