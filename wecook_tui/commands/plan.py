"""`wecook plan check PLAN`: is a plan fit to run, before it runs.

- ``wecook plan check PLAN``: read the plan, check it against its JSON Schema (``wecook export --schema``) and
  validate it (a malformed or inconsistent plan: one line naming the
  file and place, exit 2), then say which action's objects lie out of the reach of the arm that must work on
  them, or leave its hand no room to work (a pot beside the dough to roll, food at the end of a board a hand
  holds), and why (one line each, exit 1); exit 0 when every action can be reached. ``wecook execute`` runs the
  same check first and prints what it finds before the run.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from wecook_core.plan import Plan


def register(sub: Any) -> None:
    plan = sub.add_parser("plan", help="check a robot plan before running it",
                          description="Check a plan (wecook_plan: 1) before running it.")
    plan_sub = plan.add_subparsers(dest="plan_command", metavar="COMMAND", required=True)
    check = plan_sub.add_parser("check", help="validate a plan and say which actions the arms cannot reach",
                                description="Validate a plan (errors: exit 2), then list every action whose "
                                            "objects lie out of the reach of the arm that must work on them "
                                            "(exit 1 if any, else 0).")
    check.add_argument("plan", type=Path, help="plan file (YAML)")
    check.set_defaults(func=run_check)


def plan_findings(plan: Plan) -> list[str]:
    """What stops actions of a valid plan from being done, one line each: objects out of an arm's reach, and
    objects leaving a hand no room to work (:mod:`wecook_core.plan.room`). (The plan's form is checked when it is
    read: :func:`wecook_core.plan.schema.check_plan_file`.)"""
    from wecook_core.plan.reach import reach_problems
    from wecook_core.plan.room import room_problems

    return [str(problem) for problem in reach_problems(plan)] + [str(problem) for problem in room_problems(plan)]


def run_check(args: argparse.Namespace) -> int:
    from wecook_core.plan.schema import check_plan_file

    plan = check_plan_file(args.plan)  # the JSON Schema, then the plan's own rules: an InputError (exit 2)
    findings = plan_findings(plan)
    for line in findings:
        print(f"{args.plan}: {line}")
    arms = len(plan.agents)
    if findings:
        print(f"{len(findings)} problems: {len(plan.actions)} actions, {arms} arms")
        return 1
    print(f"{args.plan}: ok: {len(plan.actions)} actions, {arms} arms, every object within reach and room to work")
    return 0
