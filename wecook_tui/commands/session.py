"""`wecook new NAME ...` makes a session from a video, object boxes and hands; `wecook sessions` lists them.

`wecook` alone calls :func:`pick`: the list, and in a terminal a prompt to open one in the workbench.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from wecook_core.observations.importer import Imported
    from wecook_core.session.store import SessionSummary

OBJECT_FORMATS = ("cvat", "mot", "cocovid", "labelstudio", "csv")
HAND_FORMATS = ("openpose", "csv")
ROOT_HELP = "folder holding the sessions (default: $WECOOK_SESSIONS, else ./sessions)"


def register(sub: Any) -> None:
    new = sub.add_parser(
        "new", help="make a session from a video, object boxes and hand tracks",
        description="Import and check every input, then make sessions/NAME. Bad input is reported in one line "
                    "(exit 2) and leaves nothing behind.",
    )
    new.add_argument("name", help="session name: letters, digits, '.', '_', '-'")
    new.add_argument("--video", required=True, help="the video (any file OpenCV reads)")
    new.add_argument("--objects", default=None,
                     help="object boxes: CVAT video XML, MOT txt, COCO-VID JSON, Label Studio JSON or wecook CSV "
                          "(default: none; draw them in the workbench's box mode, B in `wecook open NAME`)")
    new.add_argument("--hands", default=None,
                     help="hands: an OpenPose JSON folder or wecook CSV (default: found in the video by MediaPipe "
                          "and written to ROOT/NAME.hands.csv)")
    new.add_argument("--objects-format", choices=OBJECT_FORMATS, default=None,
                     help="force the object format (default: detected from the content)")
    new.add_argument("--hands-format", choices=HAND_FORMATS, default=None,
                     help="force the hand format (default: detected)")
    new.add_argument("--labels", default=None,
                     help="MOT labels file: ID,LABEL lines, or one LABEL per class (default: labels.txt beside "
                          "the MOT file)")
    new.add_argument("--select-video", default=None, metavar="NAME_OR_ID",
                     help="COCO-VID file with several videos: the one to take (default: the one named like "
                          "--video)")
    new.add_argument("--annotation-fps", type=float, default=None, metavar="RATE",
                     help="Label Studio boxes: the frame rate the annotation counted frames at (its <Video "
                          "frameRate>; default: read from the file's framesCount, duration and times)")
    new.add_argument("--categories", default=None,
                     help="YAML file of extra object categories `objects: {label: tool|container|ingredient}`")
    new.add_argument("--max-gap", type=float, default=None, metavar="SECONDS",
                     help="refuse hand tracks missing for longer than this inside the track "
                          "(default: such gaps are interpolated and reported)")
    new.add_argument("--root", default=None, help=ROOT_HELP)
    from wecook_tui.commands.hands import add_detection_options

    add_detection_options(new)
    new.set_defaults(func=run_new)

    listing = sub.add_parser("sessions", help="list the sessions", description="List the sessions under the root.")
    listing.add_argument("--root", default=None, help=ROOT_HELP)
    listing.set_defaults(func=run_sessions)


def run_new(args: argparse.Namespace) -> int:
    from wecook_core.observations.importer import import_observations
    from wecook_core.session.store import check_name, create_session, sessions_root

    check_name(args.name)
    root = sessions_root(args.root)
    from wecook_core.errors import InputError

    if (root / args.name).exists():
        raise InputError(root / args.name, "a session of that name already exists")
    from wecook_core.files import check_writable

    check_writable(root, "sessions folder")  # before the import (and a detection of the hands)
    table = None
    if args.categories:
        from wecook_core.knowledge.categories import load_categories

        table = load_categories(extra=[Path(args.categories)])
    from wecook_core.observations.importer import InputChecks

    checks = InputChecks(gap_error_seconds=args.max_gap)
    detected = None
    if args.hands is None:  # hands from the pixels, kept beside the session (its recorded input)
        from wecook_core.formats.detect import read_objects
        from wecook_core.formats.video import probe_video
        from wecook_tui.commands.hands import detect_to_csv, summary

        detected = root / f"{args.name}.hands.csv"
        if detected.exists():
            raise InputError(detected, "exists; give it with --hands, or remove it to detect the hands again")
        # The boxes are checked before the (slow) detection; the detected hands stay if the import fails later.
        info = probe_video(args.video, fps=args.fps)
        if args.objects is not None:
            read_objects(args.objects, args.objects_format, labels=args.labels, video=info,
                         select=args.select_video, fps=args.annotation_fps)
        root.mkdir(parents=True, exist_ok=True)
        print(summary(detect_to_csv(args.video, detected, args)))
        args.hands = str(detected)
    facts = None
    if args.fps is not None:  # the container's rate is unusable: the user's stands in
        from wecook_core.formats.video import probe_video

        facts = probe_video(args.video, fps=args.fps)
    imported = import_observations(args.video, args.objects, args.hands, objects_format=args.objects_format,
                                   hands_format=args.hands_format, labels=args.labels, select=args.select_video,
                                   annotation_fps=args.annotation_fps, categories=table, checks=checks,
                                   video_facts=facts)
    path = create_session(root, args.name, args.video, args.objects, args.hands,
                          objects_format=imported.objects_format, hands_format=imported.hands_format,
                          labels=args.labels, categories=args.categories, select=args.select_video,
                          annotation_fps=args.annotation_fps, imported=imported, fps=args.fps)
    print(describe(imported, args.objects, args.hands))
    print(f"session {args.name} made in {path}; open it with: wecook open {args.name}"
          + (f" --root {args.root}" if args.root else ""))
    return 0


def describe(imported: Imported, objects: str | Path | None, hands: str | Path) -> str:
    """What an import found, for a person: video, objects with categories, hands, gaps, warnings."""
    obs = imported.observations
    video = obs.video
    frames = video.decoded_frames if video.decoded_frames is not None else video.frame_count
    lines = [f"video    {video.path}: {frames} frames at {video.fps:g} fps ({frames / video.fps:.1f} s), "
             f"{video.width}x{video.height}"]
    if objects is None:
        lines.append("objects  none yet: in the workbench's box mode (B) keep the boxes it proposes (1-9; p proposes "
                     "on another frame) or draw them (b), then name (n) and track (t) them")
    else:
        lines.append(f"objects  {objects} ({imported.objects_format}): {len(obs.objects)} tracks")
    width = max((len(t.name) for t in obs.objects), default=0)
    for track in obs.objects:
        label = f" (label {track.label!r})" if track.label != track.name else ""
        lines.append(f"  {track.name:<{width}}  {obs.categories[track.name].value:<10}  frames "
                     f"{int(track.frames[0])}-{int(track.frames[-1])}, {len(track.frames)} boxes{label}")
    lines.append(f"hands    {hands} ({imported.hands_format}): {len(obs.hands)} hands")
    for hand in obs.hands:
        missing = imported.missing.get(hand.hand, 0)
        lines.append(f"  {hand.hand}  frames {int(hand.frames[0])}-{int(hand.frames[-1])}, {len(hand.frames)} "
                     f"detections, {missing} missing inside")
    if imported.gaps:
        lines.append(f"gaps     {len(imported.gaps)} longer than the limit (interpolated):")
        lines += [f"  {g.hand}  frames {g.start}-{g.end - 1} ({g.seconds:.1f} s)" for g in imported.gaps]
    for warning in imported.warnings:
        if not any(f"{g.hand} is missing" in warning for g in imported.gaps):
            lines.append(f"warning: {warning}")
    return "\n".join(lines)


def _table(rows: list[SessionSummary]) -> str:
    header = ("#", "NAME", "CREATED", "CORRECTIONS", "VIDEO")
    cells = [(str(i), r.name, r.created, str(r.corrections) if r.problem is None else "-",
              r.video if r.problem is None else f"({r.problem})") for i, r in enumerate(rows, 1)]
    widths = [max(len(row[c]) for row in [header, *cells]) for c in range(4)]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(row[:4], widths, strict=True)) + "  " + row[4]
                     for row in [header, *cells])


def run_sessions(args: argparse.Namespace) -> int:
    from wecook_core.session.store import list_sessions, sessions_root

    root = sessions_root(args.root)
    rows = list_sessions(root)
    if not rows:
        print(f"no sessions in {root}; make one with: wecook new NAME --video V --objects F --hands H")
        return 0
    print(_table(rows))
    return 0


def pick(args: argparse.Namespace) -> int:
    """`wecook` alone: list the sessions; in a terminal, ask which one to open in the workbench."""
    from wecook_core.session.store import list_sessions, sessions_root

    root = sessions_root(getattr(args, "root", None))
    rows = list_sessions(root)
    if not rows:
        print(f"no sessions in {root}. Try `wecook demo`, or make one with "
              "`wecook new NAME --video V --objects F --hands H`; `wecook --help` lists every command.")
        return 0
    print(f"sessions in {root}:")
    print(_table(rows))
    if not (sys.stdin.isatty() and sys.stdout.isatty()):
        print("open one with: wecook open NAME")
        return 0
    try:
        answer = input("open which session (number or name, Enter to quit)? ").strip()
    except EOFError:
        return 0
    if not answer:
        return 0
    chosen = next((r for i, r in enumerate(rows, 1) if answer in (str(i), r.name)), None)
    if chosen is None:
        print(f"no session {answer!r}", file=sys.stderr)
        return 1
    from wecook_tui.commands.workbench import launch

    return launch(chosen.path)
