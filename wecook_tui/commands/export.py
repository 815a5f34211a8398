"""`wecook export`: a session's corrected plan, for wecook's executor, the paper's ROS platform or task planners.

- ``wecook export NAME [-o plan.yaml] [--root DIR] [--robot URDF]``: analyse session NAME (with its corrections)
  and write its plan (``wecook_plan: 1``), by default to ``sessions/NAME/plans/plan.yaml``.
- ``--format wecook-ros [-o dispatch.py] [--urdfs FILE ...] [--real]``: a standalone ROS 1 script that publishes
  the plan as a ``TaskMsg`` on ``WeCookDispatch`` for the platform of icaros-usc/wecook (default
  ``plans/dispatch.py``); objects without a URDF there are reported.
- ``--format pddl [-o DIR]``: ``domain.pddl``, ``problem.pddl`` and the plan's steps ``plan.pddl`` (default
  ``plans/pddl/``).
- ``--plan FILE`` instead of NAME: export a plan file (checked against the schema first).
- ``wecook export --schema``: print the JSON Schema of plan files.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from wecook_core.plan import Plan

FORMATS = ("wecook", "wecook-ros", "pddl")


def register(sub: Any) -> None:
    export = sub.add_parser("export", help="write a session's robot plan (YAML, ROS dispatch script or PDDL)",
                            description="Analyse a session with its corrections and write its plan: wecook's "
                                        "YAML (wecook_plan: 1), a ROS 1 script for the WeCook platform, or PDDL.")
    export.add_argument("name", nargs="?", help="session name")
    export.add_argument("--plan", type=Path, metavar="FILE", help="export this plan file instead of a session's")
    export.add_argument("--format", choices=FORMATS, default="wecook",
                        help="wecook: the plan's YAML; wecook-ros: a script publishing it as a TaskMsg on "
                             "WeCookDispatch; pddl: domain, problem and steps (default: %(default)s)")
    export.add_argument("-o", "--out", type=Path,
                        help="output file (a folder for pddl; default: in sessions/NAME/plans/, or beside --plan)")
    export.add_argument("--root", type=Path, help="where sessions live (default: $WECOOK_SESSIONS or ./sessions)")
    export.add_argument("--robot", default="franka_panda/panda.urdf", metavar="URDF",
                        help="the arms' URDF, relative to pybullet_data unless absolute (default: %(default)s)")
    export.add_argument("--urdfs", type=Path, action="append", default=[], metavar="FILE",
                        help="wecook-ros: a URDF table laid over the shipped one (wecook_ros_objects: 1), repeatable")
    export.add_argument("--real", action="store_true", help="wecook-ros: for the real arms (ifSim false)")
    export.add_argument("--force", action="store_true", help="replace what -o names if it exists")
    export.add_argument("--schema", action="store_true", help="print the JSON Schema of plan files and stop")
    export.set_defaults(func=run_export, parser=export)


def _default(args: argparse.Namespace, folder: Path) -> Path:
    stem = args.plan.stem if args.plan is not None else "plan"
    return {"wecook": folder / f"{stem}.yaml", "wecook-ros": folder / ("dispatch.py" if stem == "plan" else
                                                                         f"{stem}-dispatch.py"),
            "pddl": folder / ("pddl" if stem == "plan" else f"{stem}-pddl")}[args.format]


def run_export(args: argparse.Namespace) -> int:
    if args.schema:
        from wecook_core.plan.schema import schema_text

        sys.stdout.write(schema_text())
        return 0
    if (args.name is None) == (args.plan is None):
        args.parser.error("give a session NAME or --plan FILE (or --schema)")
    if args.format == "wecook" and args.plan is None:
        return _export_yaml(args)
    if args.plan is not None:
        from wecook_core.plan.schema import check_plan_file

        plan, folder, title = check_plan_file(args.plan), args.plan.resolve().parent, args.plan.stem
        source = str(args.plan)
    else:
        from wecook_core.session.store import check_name, sessions_root
        from wecook_core.workflows import session_plan

        session = sessions_root(args.root) / check_name(args.name)
        plan, folder, warnings = session_plan(session, robot=args.robot)
        for warning in warnings:
            print(f"wecook: warning: {warning}", file=sys.stderr)
        title, source = args.name, f"session {args.name}"
    out = args.out if args.out is not None else _default(args, folder)
    from wecook_core.errors import InputError
    from wecook_core.plan import validate

    validate(plan, source)
    if args.format == "wecook":
        from wecook_core.plan import write_plan

        if args.plan is not None and out.resolve() == args.plan.resolve():
            raise InputError(out, "is the plan being exported: give another file with -o")

        write_plan(plan, out, replace=args.force)
        print(f"wrote {out}: {_counts(plan)}")
    elif args.format == "wecook-ros":
        _export_ros(args, plan, out, title, source)
    else:
        _export_pddl(plan, out, title, replace=args.force or args.out is None)
    return 0


def _counts(plan: Plan) -> str:
    return f"{len(plan.actions)} actions, {len(plan.agents)} arms, {len(plan.scene.objects)} objects"


def _export_yaml(args: argparse.Namespace) -> int:
    from wecook_core.session.store import check_name, sessions_root
    from wecook_core.workflows import export_session_plan

    session = sessions_root(args.root) / check_name(args.name)
    exported = export_session_plan(session, args.out, robot=args.robot, force=args.force)
    for warning in exported.warnings:
        print(f"wecook: warning: {warning}", file=sys.stderr)
    print(f"wrote {exported.path}: {_counts(exported.plan)}")
    return 0


def _export_ros(args: argparse.Namespace, plan: Plan, out: Path, title: str, source: str) -> None:
    from wecook_core.errors import InputError
    from wecook_core.plan.ros import load_urdf_table
    from wecook_core.plan.ros_script import dispatch_script

    script, export = dispatch_script(plan, title, load_urdf_table(args.urdfs), if_sim=not args.real, source=source)
    from wecook_core.files import check_output, write_atomic

    if out.is_dir():
        raise InputError(out, "is a folder: give the script's file name with -o")
    check_output(out, replace=args.force or args.out is None, what="dispatch script")
    write_atomic(out, script, replace=True, what="dispatch script")
    out.chmod(out.stat().st_mode | 0o111)
    for warning in export.warnings():
        print(f"wecook: warning: {warning}", file=sys.stderr)
    task = export.task
    print(f"wrote {out}: a TaskMsg of {len(task.actions)} actions, {len(task.agents)} arms, {len(task.objects)} "
          f"objects for WeCookDispatch ({'simulation' if task.if_sim else 'real arms'})")


def _export_pddl(plan: Plan, out: Path, title: str, *, replace: bool) -> None:
    from wecook_core.errors import InputError
    from wecook_core.plan.pddl import export_pddl, write_pddl

    if out.exists() and not out.is_dir():
        raise InputError(out, "is a file: pddl writes a folder (domain.pddl, problem.pddl, plan.pddl)")
    taken = [name for name in ("domain.pddl", "problem.pddl", "plan.pddl") if (out / name).exists()]
    if taken and not replace:
        raise InputError(out / taken[0], "exists; not overwritten (pass --force to replace the PDDL files)")
    export = export_pddl(plan, title)
    paths = write_pddl(export, out)
    print(f"wrote {', '.join(str(p) for p in paths)}: {len(export.steps)} steps for {len(plan.actions)} actions")
