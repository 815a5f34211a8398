"""`wecook runs check|recover|show|export`: run recordings (MCAP), from the file alone.

- ``wecook runs check FILE.mcap``: exit 0 when the recording is sound, else list the problems, exit 1.
- ``wecook runs recover FILE.mcap [-o OUT.mcap]``: rewrite the file of a killed run as a complete one.
- ``wecook runs show FILE.mcap``: the run's summary: plan, result table, duration, topics.
- ``wecook runs export FILE.mcap --csv DIR``: ``DIR/joint_states.csv`` and ``DIR/events.csv`` (never overwritten).
- ``wecook runs export FILE.mcap --ros2 OUT [--storage mcap|sqlite3]``: the run as a ROS 2 bag (a new folder OUT):
  joint states, transforms, camera images and calibration, log and events as ROS 2 messages (CDR).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(sub: Any) -> None:
    runs = sub.add_parser("runs", help="check, recover, show or export run recordings (MCAP)",
                          description="Check a run's recording, recover the recording of a killed run, show a "
                                      "run's summary, or export it (joint states and events as CSV; or a ROS 2 bag).")
    runs_sub = runs.add_subparsers(dest="runs_command", metavar="COMMAND", required=True)
    check = runs_sub.add_parser("check", help="validate a recording (CRCs, summary, topics, events)")
    check.add_argument("file", type=Path, help="recording (.mcap)")
    check.set_defaults(func=run_check)
    recover = runs_sub.add_parser("recover", help="rewrite the recording of a killed run as a complete file")
    recover.add_argument("file", type=Path, help="recording (.mcap)")
    recover.add_argument("-o", "--out", type=Path, help="output (default: FILE with .recovered.mcap)")
    recover.add_argument("--force", action="store_true", help="replace the output if it exists")
    recover.set_defaults(func=run_recover)
    show = runs_sub.add_parser("show", help="print a run's summary: plan, result table, duration, topics")
    show.add_argument("file", type=Path, help="recording (.mcap)")
    show.set_defaults(func=run_show)
    export = runs_sub.add_parser("export", help="write a run's joint states and events as CSV, or the run as a "
                                               "ROS 2 bag")
    export.add_argument("file", type=Path, help="recording (.mcap)")
    to = export.add_mutually_exclusive_group(required=True)
    to.add_argument("--csv", type=Path, metavar="DIR",
                    help="folder for joint_states.csv and events.csv (made if missing; files never overwritten)")
    to.add_argument("--ros2", type=Path, metavar="OUT",
                    help="a ROS 2 bag (a new folder, never overwritten): sensor_msgs JointState per arm, tf2_msgs "
                         "TFMessage, CompressedImage and CameraInfo, rcl_interfaces Log; CDR (needs rosbags)")
    export.add_argument("--storage", choices=("mcap", "sqlite3"), default="mcap",
                        help="--ros2: the bag's storage (default: %(default)s)")
    export.set_defaults(func=run_export)


def run_check(args: argparse.Namespace) -> int:
    from wecook_core.recording.check import check_recording

    report = check_recording(args.file)
    counts = ", ".join(f"{topic} {n}" for topic, n in sorted(report.messages.items()))
    statuses = [s.split(":")[0] for s in report.actions.values()]
    actions = ", ".join(f"{statuses.count(s)} {s}" for s in ("done", "failed", "unfinished") if s in statuses)
    print(f"{report.path}: {sum(report.messages.values())} messages ({counts}); {report.duration_s:.1f} s; "
          f"actions: {actions or 'none'}")
    if report.ok:
        print("ok")
        return 0
    for problem in report.problems:
        print(f"problem: {problem}")
    return 1


def run_recover(args: argparse.Namespace) -> int:
    from wecook_core.recording.check import recover_recording

    out = args.out or args.file.with_name(args.file.stem + ".recovered.mcap")
    report = recover_recording(args.file, out, replace=getattr(args, "force", False))
    state = "the run had finished" if report.finished else "the run had not finished"
    state += "; nothing was lost" if not report.lost else f"; of its {report.bytes_total} bytes, lost:"
    print(f"wrote {report.out}: {report.total} messages, {report.attachments} attachments, "
          f"{report.metadata} metadata records; {state}")
    for line in report.lost:
        print(f"  lost: {line}")
    if report.closed_actions:
        print(f"marked as interrupted: {', '.join(report.closed_actions)}")
    return 0


def run_show(args: argparse.Namespace) -> int:
    from wecook_core.recording.report import format_summary, summarize_recording

    print(format_summary(summarize_recording(args.file)))
    return 0


def run_export(args: argparse.Namespace) -> int:
    if args.ros2 is not None:
        return run_export_ros2(args)
    from wecook_core.recording.report import export_csv

    for path in export_csv(args.file, args.csv):
        print(f"wrote {path}")
    return 0


def run_export_ros2(args: argparse.Namespace) -> int:
    from wecook_core.recording.ros2 import export_ros2

    done = export_ros2(args.file, args.ros2, storage=args.storage)
    print(f"wrote {done.out} (ROS 2 bag, {done.storage}): {sum(done.messages.values())} messages")
    for topic, n in sorted(done.messages.items()):
        print(f"  {topic:<28} {done.types[topic]:<32} {n}")
    if done.left_out:
        print("left out (no ROS 2 message): " + ", ".join(f"{t} {n}" for t, n in sorted(done.left_out.items())))
    return 0
