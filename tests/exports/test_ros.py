"""The dispatch script for the paper's ROS platform: standalone, importing only rospy and wecook.msg, publishing
one TaskMsg whose every message has the platform's fields and types, and the plan's actions verb for verb."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from exports_helpers import check_message, expected_verbs, run_dispatch, script_imports

from wecook_core.errors import InputError
from wecook_core.plan import Plan, read_plan
from wecook_core.plan.ros import MESSAGES, load_urdf_table, ros_task
from wecook_core.plan.ros_script import dispatch_script
from wecook_core.workflows import demo_plan

SMALL = Path(__file__).parent / "golden" / "small.yaml"


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
def test_the_demo_plan_dispatches_as_one_task_with_its_actions(demo: Plan, monkeypatch: pytest.MonkeyPatch) -> None:
    script, export = dispatch_script(demo, "demo")
    ast.parse(script)
    assert script_imports(script) == {"rospy", "wecook.msg"}
    run = run_dispatch(script, monkeypatch)
    assert set(run.imported) == {"rospy", "wecook.msg"}
    assert run.rospy.publishers == [("WeCookDispatch", run.msg.TaskMsg, 10)]
    assert run.rospy.nodes == [("wecook_demo", True)]
    task = run.task
    assert check_message(run.msg, task) == len(run.msg.built)  # every message built is in the task, and sound
    assert [a.verb for a in task.actions] == expected_verbs(demo)
    assert [a.pid for a in task.actions] == [[p.lower() for p in a.pids] for a in demo.actions]
    assert sorted(a.pid for a in task.agents) == ["p1", "p2"]
    assert (task.type, task.motionPlannerType, task.ifSim) == ("follow", "RRTConnect", True)
    names = export.names
    in_scene = [o.name for o in task.scene.objects]
    assert in_scene[0] == "table0"
    # every object is in the scene or reported missing, never dropped in silence
    assert sorted(in_scene[1:] + [names[m] for m in export.missing]) == sorted(names[o.name]
                                                                               for o in demo.scene.objects)
    assert set(export.missing) == {"jar", "peeler"}
    for name in export.missing:
        assert f"# - {name}: no URDF on the platform" in script
    for obj in task.scene.objects:
        assert obj.url.startswith("package://wecook_assets/data/") and obj.url.endswith(".urdf")
        assert len(obj.pose) == 7 and abs(sum(q * q for q in obj.pose[3:]) - 1) < 1e-6
    pairs = [c.pair for c in task.scene.containingMap]
    assert ["bowl", names["onion"]] in pairs  # the platform's order: container first
    assert all(a in in_scene and b in in_scene for a, b in pairs)


def test_actions_follow_the_platform_conventions(monkeypatch: pytest.MonkeyPatch) -> None:
    plan = read_plan(SMALL)
    export = ros_task(plan)
    actions = {a.id: m for a, m in zip(plan.actions, export.task.actions, strict=True)}
    assert actions["a1"] == ros_action(["p1"], "cut", ["chopping_board"], "knife", ["food_tomato"])
    assert actions["a2"] == ros_action(["p1"], "transfer", ["chopping_board", "pot"], "chopping_board",
                                       ["food_tomato"])
    assert actions["a3"] == ros_action(["p1", "p2"], "handover", ["air"], "hand", ["spoon"])
    assert actions["a4"] == ros_action(["p1", "p2"], "holding_pot_stir", ["pot"], "spoon", [])
    # by hand, the source is where the onion is: its containing pair
    assert actions["a5"] == ros_action(["p2"], "transfer", ["bowl_2", "pot"], "hand", ["food_onion"])
    assert actions["a6"] == ros_action(["p2"], "stir", ["pot"], "whisk", ["food_onion", "food_tomato"])
    assert export.missing == {"whisk": ("a6",)}
    assert any("whisk: no URDF on the platform" in w for w in export.warnings())
    pose = {o.name: o.pose for o in export.task.objects}
    # the plan's table centre sits on the platform's table top, its x axis along the table's long side (y)
    assert pose["pot"][:3] == pytest.approx((0.5 - 0.05, 0.1, 0.73), abs=1e-4)
    assert pose["knife"][2] == pytest.approx(0.78)  # the knife's URDF origin is 5 cm up, as in the demos
    agents = {a.pid: a.pose for a in export.task.agents}
    assert agents["p1"][:3] == pytest.approx((0.5, -0.5, 0.73))
    assert agents["p2"][:3] == pytest.approx((0.5, 0.5, 0.73))
    run = run_dispatch(dispatch_script(plan, "small", if_sim=False)[0], monkeypatch)
    assert run.task.ifSim is False
    assert [a.verb for a in run.task.actions] == expected_verbs(plan)


def ros_action(pid: list[str], verb: str, location: list[str], tool: str, ingredients: list[str]) -> object:
    from wecook_core.plan.ros import ActionMsg

    return ActionMsg(tuple(pid), verb, tuple(location), tool, tuple(ingredients))


def test_users_extend_the_urdf_table(tmp_path: Path) -> None:
    plan = read_plan(SMALL)
    extra = tmp_path / "mine.yaml"
    extra.write_text("wecook_ros_objects: 1\nobjects:\n  whisk: {url: objects/whisk.urdf, z: 0.04}\n"
                     "  tomato: file:///home/me/tomato.urdf\nfood_prefix: ''\n")
    export = ros_task(plan, load_urdf_table([extra]))
    assert export.missing == {}
    urls = {o.name: o.url for o in export.task.objects}
    assert urls["whisk"] == "package://wecook_assets/data/objects/whisk.urdf"
    assert urls["tomato"] == "file:///home/me/tomato.urdf"  # no prefix now, its own URDF
    assert urls["bowl_2"] == "package://wecook_assets/data/objects/bowl.urdf"  # the kind of a numbered name
    assert "onion" in export.stand_ins


@pytest.mark.parametrize(("text", "place"), [
    ("objects: {}\n", "top level"),
    ("wecook_ros_objects: 1\nobjects: {whisk: {z: 1}}\n", "objects.whisk"),
    ("wecook_ros_objects: 1\nobjects: {whisk: {url: a.urdf, z: high}}\n", "objects.whisk.z"),
    ("wecook_ros_objects: 1\norigin: {position: [0, 0], yaw: 0}\n", "origin.position"),
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
])
def test_the_stand_in_rejects_what_the_platform_would(monkeypatch: pytest.MonkeyPatch, before: str, after: str,
                                                      complaint: str) -> None:
    script, _ = dispatch_script(read_plan(SMALL), "small")
    assert before in script
    with pytest.raises(TypeError, match=complaint):
        run_dispatch(script.replace(before, after, 1), monkeypatch)
