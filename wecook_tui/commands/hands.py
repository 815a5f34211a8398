"""`wecook hands VIDEO -o hands.csv`: hands found in the video by MediaPipe, named by tracking and position.

Writes wecook's hands CSV (``frame,hand,x,y,x1,y1,x2,y2``, hands ``LH_P1 RH_P1 LH_P2 RH_P2``, persons from
left to right); ``--detections`` also writes every detection with MediaPipe's own label and its confidence.
A progress bar with the time left shows on stderr. Never overwrites a file unless ``--force``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from wecook_core.errors import InputError

if TYPE_CHECKING:
    from wecook_core.observations.hands_detect import DetectedHands

MODELS = ("full", "lite")


def register(sub: Any) -> None:
    parser = sub.add_parser(
        "hands", help="find the hands in a video (MediaPipe) and write them as wecook's hands CSV",
        description="Run MediaPipe's hand landmarker over every frame of VIDEO, name the hands LH_P1 RH_P1 LH_P2 "
                    "RH_P2 by tracking them (persons from left to right) and write wecook's hands CSV.",
    )
    parser.add_argument("video", metavar="VIDEO", help="the video (any file OpenCV reads)")
    parser.add_argument("-o", "--output", required=True, help="the hands CSV to write")
    add_detection_options(parser)
    parser.add_argument("--detections", default=None, metavar="CSV",
                        help="also write every detection with MediaPipe's label and confidence")
    parser.add_argument("--force", action="store_true", help="overwrite the output files")
    parser.set_defaults(func=run_hands)


def add_detection_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--hand-model", choices=MODELS, default="full",
                        help="MediaPipe's hand model: full (more accurate) or lite (faster); default full")
    parser.add_argument("--persons", type=int, choices=(1, 2), default=None,
                        help="persons in the video (default: two when more than two hands show at once often)")
    parser.add_argument("--no-pose", dest="pose", action="store_false",
                        help="do not run MediaPipe's pose model: name hands by tracking, position and handedness only "
                             "(faster; by default each hand is named by the arm it ends)")
    parser.add_argument("--mirrored", action="store_true",
                        help="the video is mirrored (a selfie camera): take MediaPipe's handedness as it is")
    parser.add_argument("--fps", type=float, default=None, metavar="HZ",
                        help="the video's frame rate, when its container gives none that is usable (0, say); its "
                             "frames are then counted by decoding")


def _refuse_overwrite(path: Path, force: bool) -> None:
    """Refuse an output that cannot or may not be written, before the (long) detection."""
    from wecook_core.files import check_writable

    if path.is_dir():
        raise InputError(path, "is a folder; give the name of the CSV file to write")
    if not path.parent.is_dir():
        raise InputError(path, f"the folder {path.parent} does not exist")
    if path.exists() and not force:
        raise InputError(path, "exists; not overwritten (give --force to replace it)")
    check_writable(path.parent)


def detect_to_csv(video: str | Path, output: Path, args: argparse.Namespace) -> DetectedHands:
    """Detect the hands of ``video`` with a progress bar and write them to ``output`` (written whole or not
    at all)."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    from wecook_core.observations.hand_assign import AssignParams
    from wecook_core.observations.hands_detect import DetectParams, detect_hands, native_stderr_silenced, write_hands

    params = DetectParams(model=args.hand_model, pose=getattr(args, "pose", True))
    assign = AssignParams(mirrored=args.mirrored)
    with native_stderr_silenced() as stderr:
        console = Console(file=stderr)
        columns = (TextColumn("hands"), BarColumn(), MofNCompleteColumn(), TextColumn("frames"),
                   TimeElapsedColumn(), TextColumn("left"), TimeRemainingColumn())
        with Progress(*columns, console=console, transient=False, disable=not console.is_terminal) as bar:
            task = bar.add_task("hands", total=None)

            def progress(done: int, total: int) -> None:
                bar.update(task, completed=done, total=total)

            found = detect_hands(video, params, assign, persons=args.persons, progress=progress,
                                 fps=getattr(args, "fps", None))
    write_hands(found, video, output)
    return found


def summary(found: DetectedHands, fps: float | None = None) -> str:
    share = found.frames_with_hands / max(found.frames_read, 1)
    parts = [f"{t.hand} {len(t.frames)} frames" for t in found.tracks]
    return (f"hands    found in {found.frames_with_hands} of {found.frames_read} frames ({share:.0%}): "
            + ", ".join(parts))


def run_hands(args: argparse.Namespace) -> int:
    from wecook_core.formats.video import probe_video
    from wecook_core.observations.hands_detect import write_detections_csv

    output = Path(args.output)
    _refuse_overwrite(output, args.force)
    detections = Path(args.detections) if args.detections else None
    if detections is not None:
        _refuse_overwrite(detections, args.force)
    probe_video(args.video, fps=args.fps)  # an unreadable video, a rate to give, too many pixels: said first
    found = detect_to_csv(args.video, output, args)
    if detections is not None:
        write_detections_csv(detections, found.assigned)
    print(summary(found))
    print(f"wrote {output}" + (f" and {detections}" if detections else ""))
    return 0
