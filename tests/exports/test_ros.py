"""The dispatch script for the paper's ROS platform: standalone, importing only rospy and wecook.msg, publishing
one latched TaskMsg whose every message has the platform's fields and types, and whose every action the platform
plans (tests/exports/platform_model.py, a model of its ActionPlanner and TaskGraph), with every object it names in
the scene; what it cannot plan is mapped where faithful, else left out and reported."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import pytest
from exports_helpers import check_message, platform_checks, run_dispatch, script_imports
from platform_model import Crash, Platform

from wecook_core.errors import InputError
from wecook_core.plan import Plan, load_plan, read_plan
from wecook_core.plan.ros import MESSAGES, ActionMsg, load_urdf_table, ros_task
from wecook_core.plan.ros_platform import PLANNERS
from wecook_core.plan.ros_script import dispatch_script
from wecook_core.workflows import demo_plan

SMALL = Path(__file__).parent / "golden" / "small.yaml"
DEMO_MOUNTS = {"p1": [-0.2, 0.15, 0.7, 0.0, 0.0, 0.7071068, 0.7071068],
               "p2": [-0.2, -0.2, 0.7, 0.0, 0.0, 0.7071068, 0.7071068]}
"""The arms of the platform's two-arm demos (demos/holdingcut0/mass_verde_2777.py, handover0, transferstir0)."""


@pytest.fixture(scope="module")
def demo() -> Plan:
    return demo_plan()


def test_the_exporter_knows_the_platform_messages_as_they_are_defined() -> None:
    import importlib.util

    spec = importlib.util.spec_from_file_location("stand_in_msg", Path(__file__).parent / "stand_in/wecook/msg.py")
    assert spec is not None and spec.loader is not None
    msg = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(msg)
    assert {name: msg.fields_of(name) for name in msg.DEFINITIONS} == MESSAGES


@pytest.mark.slow
def test_the_demo_plan_dispatches_what_the_platform_plans(demo: Plan, monkeypatch: pytest.MonkeyPatch) -> None:
    script, export = dispatch_script(demo, "demo")
    ast.parse(script)
    assert script_imports(script) == {"rospy", "wecook.msg"}
    run = run_dispatch(script, monkeypatch, connect_after=2)
    assert set(run.imported) == {"rospy", "wecook.msg"}
    assert run.rospy.publishers == [("WeCookDispatch", run.msg.TaskMsg, 1, True)]  # latched
    # published, then kept up until the platform subscribed (two polls without, one with), then a while more
    assert run.rospy.calls == ["publish", "get_num_connections", "sleep", "get_num_connections", "sleep",
                               "get_num_connections", "sleep"]
    assert run.rospy.nodes == [("wecook_demo", True)]
    task = run.task
    assert check_message(run.msg, task) == len(run.msg.built)  # every message built is in the task, and sound
    platform = platform_checks(demo, export, task)
    assert ("transfer", "jar") not in platform.reads  # a tool's transfer reads its destination, not its source
    # squeeze and peel have no planner: left out, with why; pour and sprinkle tip the held bottle (planTransfer's
    # second form); the holding while stirring has no holding planner: P1's stir goes alone
    assert set(export.left_out) == {"a2", "a3"}
    assert "squeeze" in export.left_out["a2"] and "peel" in export.left_out["a3"]
    assert set(export.mapped) == {"a10", "a11", "a12"}
    verbs = dict(zip(export.dispatched, task.actions, strict=True))
    assert (verbs["a11"].verb, verbs["a11"].location, verbs["a11"].tool) == ("transfer", ["oil", "pot"], "oil")
    assert (verbs["a10"].verb, verbs["a10"].location, verbs["a10"].tool) == ("transfer", ["salt", "pot"], "salt")
    assert (verbs["a12"].pid, verbs["a12"].verb, verbs["a12"].tool) == (["p1"], "stir", "spoon")
    assert (verbs["a4"].location, verbs["a4"].tool) == (["jar", "pot"], "spoon")  # the jar is in the scene
    for line in ("a2 left out: squeeze", "a3 left out: peel", "a11 sent as transfer", "a12 sent as p1's stir alone"):
        assert f"# - {line}" in script
    # the bottles keep names the platform's planner collides with; what tools pass through is food
    names = {o.name: o.url for o in task.scene.objects}
    assert names["oil"].endswith("objects/oil.urdf") and names["salt"].endswith("objects/salt.urdf")
    assert all("food" in n for n, url in names.items() if "/food/" in url)
    assert not [n for n, url in names.items() if "/food/" not in url and "food" in n]
    assert ["jar", "food_rice"] in [c.pair for c in task.scene.containingMap]  # the platform's order
    assert all(a in names and b in names for a, b in (c.pair for c in task.scene.containingMap))
    for obj in task.scene.objects:
        assert obj.url.startswith("package://wecook_assets/data/") and obj.url.endswith(".urdf")
        assert len(obj.pose) == 7 and abs(sum(q * q for q in obj.pose[3:]) - 1) < 1e-6
    assert {a.pid: a.pose for a in task.agents} == DEMO_MOUNTS
    assert [(t.tagId, t.objectName, t.objectPose) for t in task.scene.tags] == [(1, "None", [0.0] * 6 + [1.0])]
    # each person's objects lie on the side of the arm mounted for them (P1 at +y), on the table's top
    xs = [o.pose[0] for o in task.scene.objects[1:]]
    assert min(xs) >= 0.119 and max(xs) <= 0.881
    assert task.scene.objects[0].name == "table0"


def ros_action(pid: list[str], verb: str, location: list[str], tool: str, ingredients: list[str]) -> ActionMsg:
    return ActionMsg(tuple(pid), verb, tuple(location), tool, tuple(ingredients))


def test_actions_follow_the_platform_conventions(monkeypatch: pytest.MonkeyPatch) -> None:
    plan = read_plan(SMALL)
    export = ros_task(plan)
    actions = dict(zip(export.dispatched, export.task.actions, strict=True))
    assert actions["a1"] == ros_action(["p1"], "cut", ["chopping_board"], "knife", ["food_tomato"])
    assert actions["a2"] == ros_action(["p1"], "transfer", ["chopping_board", "pot"], "chopping_board",
                                       ["food_tomato"])
    assert actions["a3"] == ros_action(["p1", "p2"], "handover", ["air"], "hand", ["spoon"])
    assert actions["a4"] == ros_action(["p2"], "stir", ["pot"], "spoon", [])  # no holding_pot_stir planner
    # by hand, the source is where the onion is: its containing pair
    assert actions["a5"] == ros_action(["p2"], "transfer", ["bowl_2", "pot"], "hand", ["food_onion"])
    assert actions["a6"] == ros_action(["p2"], "stir", ["pot"], "whisk", ["food_onion", "food_tomato"])
    assert export.stand_ins["whisk"].endswith("objects/spoon.urdf")
    assert any("whisk: no URDF of its own" in w for w in export.warnings())
    pose = {o.name: o.pose for o in export.task.objects}
    # the plan's table centre at (0.4, 0) on the platform's table top, the plan's x axis along the platform's -y
    assert pose["pot"][:3] == pytest.approx((0.4 + 0.05, -0.1, 0.73), abs=1e-4)
    assert pose["knife"][2] == pytest.approx(0.78)  # the knife's URDF origin is 5 cm up, as in the demos
    run = run_dispatch(dispatch_script(plan, "small", if_sim=False)[0], monkeypatch)
    assert run.task.ifSim is False
    platform_checks(plan, export, run.task)


HOLDINGS = """wecook_plan: 1
agents: [{pid: P1}, {pid: P2}]
scene:
  objects:
  - {name: knife, category: tool, shape: box, size: [0.18, 0.03, 0.025], pose: {x: -0.1, y: -0.2}}
  - {name: spoon, category: tool, shape: box, size: [0.16, 0.03, 0.02], pose: {x: 0.1, y: -0.2}}
  - {name: board, category: container, shape: box, size: [0.22, 0.15, 0.02], pose: {x: -0.1, y: 0.1}}
  - {name: pot, category: container, shape: cylinder, size: [0.16, 0.16, 0.1], pose: {x: 0.1, y: 0.05}}
  - {name: bowl, category: container, shape: cylinder, size: [0.15, 0.15, 0.07], pose: {x: -0.05, y: -0.05}}
  - {name: food_processor, category: container, shape: box, size: [0.1, 0.1, 0.1], pose: {x: 0.0, y: 0.2}}
  - {name: ham, category: ingredient, shape: box, size: [0.05, 0.05, 0.01], pose: {x: -0.1, y: 0.1}}
  - {name: rice, category: ingredient, shape: box, size: [0.05, 0.05, 0.01], pose: {x: -0.05, y: -0.05}}
  - {name: lemon, category: ingredient, shape: sphere, size: [0.05, 0.05, 0.05], pose: {x: 0.0, y: 0.0}}
  containing: [[ham, board], [rice, bowl]]
actions:
- {id: a1, pid: [P2, P1], verb: holding, tool: board, partner: {verb: cut, tool: knife, ingredients: [ham]}}
- {id: a2, pid: [P1], verb: cut, ingredients: [lemon]}
- {id: a3, pid: [P2, P1], verb: holding, tool: pot, partner: {verb: transfer, tool: spoon, ingredients: [rice],
   source: bowl, location: pot}}
- {id: a4, pid: [P2, P1], verb: holding, tool: food_processor, partner: {verb: transfer, ingredients: [ham],
   source: board, location: food_processor}}
- {id: a5, pid: [P1], verb: squeeze, ingredients: [lemon], location: pot, after: [a2]}
- {id: a6, pid: [P1], verb: dip, tool: ham, location: bowl, after: [a5]}
- {id: a7, pid: [P1], verb: stir, tool: spoon, location: pot, after: [a5]}
"""


def test_holdings_map_to_the_platform_holding_planners_or_the_actor_alone(monkeypatch: pytest.MonkeyPatch) -> None:
    plan = load_plan(HOLDINGS)
    export = ros_task(plan)
    actions = dict(zip(export.dispatched, export.task.actions, strict=True))
    assert actions["a1"] == ros_action(["p2", "p1"], "holding_board_cut", ["board"], "knife", ["food_ham"])
    assert actions["a3"] == ros_action(["p2", "p1"], "holding_pot_transfer", ["bowl", "pot"], "spoon", ["food_rice"])
    # by hand, planHolding would read six nodes of the actor's two: P1's transfer goes alone
    assert actions["a4"] == ros_action(["p1"], "transfer", ["board", "fd_processor"], "hand", ["food_ham"])
    assert "p2's hold of fd_processor is left out" in export.mapped["a4"]
    assert set(export.left_out) == {"a2", "a5", "a6"}
    assert "cut by hand" in export.left_out["a2"]
    assert export.waiting == {"a5": ("a7",)}  # dispatched, though it waits for a squeeze no arm will do
    warnings = export.warnings()
    assert "a5 left out: squeeze: no squeezing motion (ActionPlanner's planSqueeze is commented out) (a7 waits " \
           "for it in the plan)" in warnings
    assert "fd_processor" in export.names.values()  # a container is not food: its name loses "food"
    run = run_dispatch(dispatch_script(plan, "holdings")[0], monkeypatch)
    platform_checks(plan, export, run.task)


def test_the_model_of_the_platform_catches_what_would_crash_it() -> None:
    def task(*actions: ActionMsg) -> object:
        from types import SimpleNamespace

        return SimpleNamespace(actions=[SimpleNamespace(pid=list(a.pid), verb=a.verb, location=list(a.location),
                                                        tool=a.tool, ingredients=list(a.ingredients))
                                        for a in actions])

    platform = Platform({"table0", "knife", "pot", "spoon", "food_x", "bowl"}, {"p1", "p2"})
    cut = ros_action(["p1"], "cut", [], "knife", ["food_x"])
    assert platform.run(task(cut, cut)) == [{"p1": 4}, {"p1": 4}]
    with pytest.raises(Crash, match="merge"):  # the old export's squeeze between two cuts
        platform.run(task(cut, ros_action(["p1"], "squeeze", [], "hand", ["food_x"]), cut))
    with pytest.raises(Crash, match="merge"):
        platform.run(task(cut, ros_action(["p2", "p1"], "holding_pot_stir", ["pot"], "spoon", []), cut))
    with pytest.raises(Crash, match=r"reads \[0\] to \[5\]"):
        platform.run(task(ros_action(["p2", "p1"], "holding_pot_transfer", ["bowl", "pot"], "hand", ["food_x"])))
    with pytest.raises(Crash, match="not in the scene"):
        platform.run(task(ros_action(["p1"], "transfer", ["jar", "pot"], "spoon", ["food_rice"])))
    with pytest.raises(Crash, match="null"):
        platform.run(task(ros_action(["p1", "p3"], "handover", ["air"], "hand", ["food_x"])))
    assert set(PLANNERS) >= {"cut", "stir", "handover", "transfer", "roll", "heat", "feeding"}


def test_users_extend_the_urdf_table(tmp_path: Path) -> None:
    plan = read_plan(SMALL)
    extra = tmp_path / "mine.yaml"
    extra.write_text("wecook_ros_objects: 1\nobjects:\n  whisk: {url: objects/whisk.urdf, z: 0.04}\n"
                     "  tomato: file:///home/me/tomato.urdf\n  onion: {url: /me/onion.urdf, food: true}\n"
                     "agents: {type: r, if_float: false, mounts: {P2: [0, 0, 0.7, 0, 0, 0, 1]}}\ntags: []\n")
    export = ros_task(plan, load_urdf_table([extra]))
    assert export.stand_ins == {}
    urls = {o.name: o.url for o in export.task.objects}
    assert urls["whisk"] == "package://wecook_assets/data/objects/whisk.urdf"
    assert urls["tomato"] == "file:///home/me/tomato.urdf"  # its own URDF, not food: no prefix
    assert urls["food_onion"] == "/me/onion.urdf"  # said to be food: the prefix
    assert urls["bowl_2"] == "package://wecook_assets/data/objects/bowl.urdf"  # the kind of a numbered name
    agents = {a.pid: a for a in export.task.agents}
    assert agents["p2"].pose == (0.0, 0.0, 0.7, 0.0, 0.0, 0.0, 1.0) and agents["p2"].if_float is False
    assert agents["p1"].pose[:3] == pytest.approx((0.4, 0.5, 0.73))  # not mounted: where the plan puts it
    assert export.task.tags == ()
    # without stand-ins, an object with no URDF is left out of the scene, and so is every action naming it
    strict = ros_task(plan, dataclasses.replace(load_urdf_table(), stand_ins={}))
    assert strict.missing == {"whisk": ("a6",), "onion": ("a5", "a6"), "tomato": ("a1", "a2", "a6")}
    assert set(strict.left_out) == {"a1", "a2", "a5", "a6"}
    assert "not in the scene" in strict.left_out["a6"]


@pytest.mark.parametrize(("text", "place"), [
    ("objects: {}\n", "top level"),
    ("wecook_ros_objects: 1\nobjects: {whisk: {z: 1}}\n", "objects.whisk"),
    ("wecook_ros_objects: 1\nobjects: {whisk: {url: a.urdf, z: high}}\n", "objects.whisk.z"),
    ("wecook_ros_objects: 1\nobjects: {whisk: {url: a.urdf, food: maybe}}\n", "objects.whisk.food"),
    ("wecook_ros_objects: 1\norigin: {position: [0, 0], yaw: 0}\n", "origin.position"),
    ("wecook_ros_objects: 1\nagents: {type: r, if_float: true, mounts: {P1: [0, 0, 0, 0, 0, 0, 2]}}\n",
     "agents.mounts.P1"),
    ("wecook_ros_objects: 1\ntags: [{id: -1, pose: [0, 0, 0, 0, 0, 0, 1]}]\n", "tags[0].id"),
    ("wecook_ros_objects: 1\ntags: [{id: 1, pose: [0, 0, 0, 0, 0, 0]}]\n", "tags[0].pose"),
    ("wecook_ros_objects: 1\nfood_prefix: ''\n", "food_prefix"),
    ("wecook_ros_objects: 1\nobjects: [\n", "line 3"),
])
def test_a_bad_urdf_table_is_one_line_naming_its_place(tmp_path: Path, text: str, place: str) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    with pytest.raises(InputError) as error:
        load_urdf_table([bad])
    assert error.value.path == str(bad) and error.value.place == place
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(("before", "after", "complaint"), [
    ("[0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]", "[0.5, 0, 0.0, 0.0, 0.0, 0.0, 1.0]", "expected a float"),
    ("'follow',", "'follow', 'extra',", "TaskMsg takes 8 fields"),
    ("'RRTConnect',\n                       True)", "'RRTConnect', 1)", "expected a bool"),
    ("TagMsg(1,", "TagMsg(-1,", "expected a uint32"),
    ("latch=True", "latched=True", "unexpected keyword"),
])
def test_the_stand_in_rejects_what_the_platform_would(monkeypatch: pytest.MonkeyPatch, before: str, after: str,
                                                      complaint: str) -> None:
    script, _ = dispatch_script(read_plan(SMALL), "small")
    assert before in script
    with pytest.raises(TypeError, match=complaint):
        run_dispatch(script.replace(before, after, 1), monkeypatch)
