"""Synthetic two-arm plans with known content, for tests and benchmarks of the executor.

:func:`synthetic_plan` lays a random kitchen out on the table the way :func:`wecook_core.plan.layout_scene`
does (inside the reach region where it can, tools lying across the table, ingredients in their containers) and
writes ``n`` actions, with one handover and one holding, every action after the previous action of each agent it
involves. As in a video, a person works on the things on their side of the table (P1 on ``-x``): an action goes to
the person nearer its place (its location, else its ingredient or tool), alternating when it is in the middle;
the giver of a handover is the one nearer the object, the holder of a holding the one nearer the container.
Every verb of the vocabulary appears across a few seeds.
"""

from __future__ import annotations

import math

import numpy as np

from wecook_core.model import Category
from wecook_core.plan import Act, Plan, PlanAction, Scene, SceneObject, agents_for

ONE_ARM_CUTS = """\
wecook_plan: 1
agents:
- {pid: P1, robot: franka_panda/panda.urdf, base: {position: [-0.5, 0.0, 0.0], yaw: 0.0}}
scene:
  table: {size: [1.0, 0.8], height: 0.0}
  objects:
  - {name: knife, category: tool, shape: box, size: [0.2, 0.03, 0.025], pose: {x: -0.1, y: 0.15, yaw: 1.5708}}
  - {name: tomato, category: ingredient, shape: sphere, size: [0.05, 0.05, 0.05], pose: {x: 0.0, y: 0.0}}
  - {name: chopping_board, category: container, shape: box, size: [0.25, 0.18, 0.02], pose: {x: 0.0, y: 0.0}}
  containing: [[tomato, chopping_board]]
actions:
- {id: a1, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], location: chopping_board, after: []}
- {id: a2, pid: [P1], verb: cut, tool: knife, ingredients: [tomato], location: chopping_board, after: [a1]}
"""
"""Plan YAML: one arm cuts a tomato on a board twice (about 20 s simulated): the smallest real run, for CLI
tests and the recording benchmark."""


_SLOTS = [(x, y) for y in (-0.3, -0.1, 0.1, 0.3) for x in (-0.19, 0.0, 0.19)]
"""Footprint centres (metres) objects are dealt to: 19 cm apart across the table and 20 cm along it, so that a
tool lies at least 3 cm from its neighbours (room for the fingers, as :func:`wecook_core.plan.layout_scene`
leaves), on the table and inside both arms' reach."""


def _objects(rng: np.random.Generator) -> tuple[list[SceneObject], list[tuple[str, str]]]:
    slots = [_SLOTS[i] for i in rng.permutation(len(_SLOTS))]
    half_pi = math.pi / 2
    specs = [
        ("chopping_board", Category.CONTAINER, "box", (0.22, 0.15, 0.02), 0.0),
        ("bowl", Category.CONTAINER, "cylinder", (0.15, 0.15, 0.07), 0.0),
        ("pot", Category.CONTAINER, "cylinder", (0.16, 0.16, 0.1), 0.0),
        ("knife", Category.TOOL, "box", (0.18, 0.03, 0.025), half_pi),
        ("spoon", Category.TOOL, "box", (0.16, 0.03, 0.02), half_pi),
        ("rolling_pin", Category.TOOL, "box", (0.18, 0.035, 0.035), half_pi),
        ("oil", Category.INGREDIENT, "cylinder", (0.05, 0.05, 0.14), 0.0),
        ("lemon", Category.INGREDIENT, "sphere", (0.05, 0.05, 0.05), 0.0),
    ]
    objects = [SceneObject(name, cat, shape, size, slots[k][0], slots[k][1], yaw)
               for k, (name, cat, shape, size, yaw) in enumerate(specs)]
    board, bowl = objects[0], objects[1]
    objects.append(SceneObject("tomato", Category.INGREDIENT, "sphere", (0.05, 0.05, 0.05), board.x, board.y))
    objects.append(SceneObject("cheese", Category.INGREDIENT, "box", (0.04, 0.04, 0.03), bowl.x, bowl.y))
    return objects, [("tomato", "chopping_board"), ("cheese", "bowl")]


_INDIVIDUAL = [
    ("cut", "knife", ("tomato",), "chopping_board", None),
    ("peel", "knife", ("tomato",), "chopping_board", None),
    ("spread", "knife", ("tomato",), "chopping_board", None),
    ("roll", "rolling_pin", ("tomato",), "chopping_board", None),
    ("stir", "spoon", (), "pot", None),
    ("dip", "spoon", (), "bowl", None),
    ("pour", "oil", (), "pot", None),
    ("sprinkle", "oil", (), "bowl", None),
    ("squeeze", None, ("lemon",), "pot", None),
    ("wrap", "knife", ("tomato",), "chopping_board", None),
    ("transfer", "spoon", ("cheese",), "pot", "bowl"),
]


def synthetic_plan(seed: int, n: int = 10) -> Plan:
    """A plan of ``n`` actions (``n >= 3``) by P1 and P2 on a random layout; the same seed gives the same plan."""
    rng = np.random.default_rng(seed)
    objects, containing = _objects(rng)
    order = [_INDIVIDUAL[i] for i in rng.permutation(len(_INDIVIDUAL))]
    if any(verb == "transfer" for verb, *_ in order[: n - 2]):  # the cheese leaves the bowl: no dip after it
        order = [o for o in order if o[0] != "transfer"] + [o for o in order if o[0] == "transfer"]
    handover_at, holding_at = sorted(rng.choice(np.arange(1, n), size=2, replace=False).tolist())
    actions: list[PlanAction] = []
    last: dict[str, str] = {}
    k = 0
    where = {o.name: o.x for o in objects}

    def nearer(name: str | None, i: int) -> str:
        x = where.get(name or "", 0.0)
        return "P1" if x < -1e-9 else "P2" if x > 1e-9 else ("P1", "P2")[i % 2]

    def pair(first: str) -> tuple[str, str]:
        return (first, "P2" if first == "P1" else "P1")

    for i in range(n):
        aid = f"a{i + 1}"
        if i == handover_at:
            thing = str(rng.choice(["knife", "lemon", "spoon"]))
            action = PlanAction(aid, pair(nearer(thing, i)), "handover", thing)
        elif i == holding_at:
            action = PlanAction(aid, pair(nearer("bowl", i)), "holding", "bowl",
                                partner=Act("stir", "spoon", (), "bowl"))
        else:
            verb, tool, ingredients, location, source = order[k % len(order)]
            k += 1
            person = nearer(location or (ingredients[0] if ingredients else tool), i)
            action = PlanAction(aid, (person,), verb, tool, ingredients, location, source)
        after = tuple(dict.fromkeys(last[p] for p in action.pids if p in last))
        actions.append(PlanAction(action.id, action.pids, action.verb, action.tool, action.ingredients,
                                  action.location, action.source, action.partner, after))
        for p in action.pids:
            last[p] = aid
    return Plan(agents=agents_for(["P1", "P2"]), scene=Scene(objects=tuple(objects), containing=tuple(containing)),
                actions=tuple(actions))
