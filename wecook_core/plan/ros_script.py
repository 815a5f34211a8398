"""The standalone ROS 1 script that publishes a plan's ``TaskMsg`` (see :mod:`wecook_core.plan.ros`).

The script is in the shape of the platform's demos: it imports only ``rospy`` and ``wecook.msg`` and builds the
messages positionally in their fields' order. Unlike the demos, which publish once a second after start-up and
exit (a TaskManager that subscribes later never gets the task), its publisher is latched: it publishes once,
waits until a subscriber (the platform's TaskManager) has connected, which gets the latched task on connecting,
and stays a few seconds more before it exits. It runs under Python 2 (ROS Melodic) and 3 (ROS Noetic): no
f-strings, no annotations.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Sequence
from typing import TYPE_CHECKING

from wecook_core.plan.model import Plan
from wecook_core.plan.ros import ros_task
from wecook_core.plan.ros_messages import TOPIC, ActionMsg, AgentMsg, ObjectMsg, TagMsg
from wecook_core.plan.ros_table import UrdfTable

if TYPE_CHECKING:
    from wecook_core.plan.ros import RosExport

INDENT = " " * 4


def _s(value: str) -> str:
    return repr(str(value))


def _strings(values: Sequence[str]) -> str:
    return "[" + ", ".join(_s(v) for v in values) + "]"


def _floats(values: Sequence[float]) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def _object(o: ObjectMsg) -> str:
    return f"ObjectMsg({_s(o.name)}, {_s(o.url)}, {_floats(o.pose)})"


def _action(a: ActionMsg) -> str:
    fields = [_strings(a.pid), _s(a.verb), _strings(a.location), _s(a.tool), _strings(a.ingredients)]
    return f"ActionMsg({', '.join(fields)})"


def _tag(t: TagMsg) -> str:
    return f"TagMsg({int(t.tag_id)}, {_s(t.object_name)}, {_floats(t.object_pose)})"


def _agent(a: AgentMsg) -> str:
    return f"AgentMsg({_s(a.pid)}, {_s(a.type)}, {_floats(a.pose)}, {a.if_float!r})"


def _items(items: Sequence[str], indent: str) -> str:
    """A list literal, one item a line, aligned under its opening bracket."""
    if not items:
        return "[]"
    return "[" + (",\n" + indent + " ").join(items) + "]"


def _comment_lines(text: str) -> list[str]:
    """``text`` as comment lines of at most 118 characters (a wrapped line of a ``- `` item is indented)."""
    out = []
    for line in text.splitlines():
        indent = "  " if line.startswith("- ") else ""
        wrapped = textwrap.wrap(line, 116, subsequent_indent=indent, break_on_hyphens=False) or [""]
        out += [("# " + w).rstrip() for w in wrapped]
    return out


def node_name(title: str) -> str:
    """A ROS node name for the script: ``wecook_`` and the title's letters, digits and underscores."""
    return "wecook_" + (re.sub(r"[^A-Za-z0-9_]", "_", title).strip("_") or "plan")


def render_script(export: RosExport, title: str, source: str | None = None) -> str:
    """The script publishing ``export.task``; ``title`` names the plan (and the node), ``source`` says where the
    plan came from (for the header)."""
    task = export.task
    header = [f"{title}: a wecook plan for the WeCook ROS platform (icaros-usc/wecook).",
              "",
              "Written by `wecook export --format wecook-ros`" + (f" from {source}" if source else "") + ".",
              f"Publishes the plan as one TaskMsg on the topic {TOPIC}, latched, and exits once the platform (its "
              "TaskManager) has subscribed and had time to take it; the platform runs it.",
              f"{len(task.actions)} actions, {len(task.agents)} arms, {len(task.objects)} objects."]
    if export.names and any(k != v for k, v in export.names.items()):
        header += ["", "Renamed for the platform: " + ", ".join(f"{k} -> {v}" for k, v in export.names.items()
                                                               if k != v) + "."]
    warnings = export.warnings()
    if warnings:
        header += ["", "Check before running:"] + [f"- {w}" for w in warnings]
    lines = ["#!/usr/bin/env python", "", *_comment_lines("\n".join(header)), "", "import rospy",
             "from wecook.msg import ActionMsg, AgentMsg, ContainingMsg, ObjectMsg, SceneMsg, TagMsg, TaskMsg", "", "",
             "def talker():",
             f"{INDENT}pub = rospy.Publisher({_s(TOPIC)}, TaskMsg, queue_size=1, latch=True)",
             f"{INDENT}rospy.init_node({_s(node_name(title))}, anonymous=True)", ""]
    scene = f"{INDENT}scene_msg = SceneMsg("
    pad = " " * len(scene)
    objects = _items([_object(o) for o in task.objects], pad)
    containing = _items([f"ContainingMsg({_strings(c.pair)})" for c in task.containing], pad)
    tags = _items([_tag(t) for t in task.tags], pad)
    lines.append(f"{scene}{objects},\n{pad}{tags},\n{pad}{containing})")
    lines.append("")
    head = f"{INDENT}task_msg = TaskMsg("
    pad = " " * len(head)
    actions = _items([_action(a) for a in task.actions], pad)
    agents = _items([_agent(a) for a in task.agents], pad)
    tail = (f"{pad}'',\n{pad}'',\n{pad}{_s(task.type)},\n{pad}{_s(task.motion_planner)},\n"
            f"{pad}{task.if_sim!r})")
    lines.append(f"{head}scene_msg,\n{pad}{actions},\n{pad}{agents},\n{tail}")
    lines += ["", f"{INDENT}pub.publish(task_msg)  # latched: a subscriber that connects later gets it too",
              f"{INDENT}while pub.get_num_connections() == 0 and not rospy.is_shutdown():",
              f"{INDENT * 2}rospy.sleep(0.5)  # waiting for the platform's TaskManager to subscribe",
              f"{INDENT}rospy.sleep(3.0)  # time for the latched task to reach it before this node goes", "", "",
              "if __name__ == '__main__':", f"{INDENT}try:", f"{INDENT * 2}talker()",
              f"{INDENT}except rospy.ROSInterruptException:", f"{INDENT * 2}pass", ""]
    return "\n".join(lines)


def dispatch_script(plan: Plan, title: str, table: UrdfTable | None = None, *, if_sim: bool = True,
                    source: str | None = None) -> tuple[str, RosExport]:
    """The dispatch script of ``plan`` and the export it publishes (its :meth:`RosExport.warnings` to report)."""
    export = ros_task(plan, table, if_sim=if_sim)
    return render_script(export, title, source), export
