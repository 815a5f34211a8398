"""`wecook synth OUT_DIR --seed N [--persons 1|2] [--duration S] [--no-video] [--no-openpose]`: write a
synthetic cooking scenario with its true trees (video.mp4, objects.csv, hands.csv, openpose/, truth.yaml)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(sub: Any) -> None:
    parser = sub.add_parser(
        "synth", help="write a synthetic cooking scenario with known answers",
        description="A top-down kitchen table, one or two persons cutting, stirring, pouring, passing and "
                    "holding things; writes the video, object boxes, hand tracks, OpenPose keypoints and the "
                    "true action trees. The same seed gives the same files.")
    parser.add_argument("out_dir", type=Path, help="folder to write (created)")
    parser.add_argument("--force", action="store_true", help="replace a scenario already in the folder")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--persons", type=int, choices=(1, 2), default=2, help="1 or 2 persons (default 2)")
    parser.add_argument("--duration", type=float, default=None, metavar="S",
                        help="seconds of video (default: as long as one pass over every action takes)")
    parser.add_argument("--fps", type=float, default=30.0, help="frames per second (default 30)")
    parser.add_argument("--size", default="640x360", metavar="WxH", help="image size (default 640x360)")
    parser.add_argument("--no-video", action="store_true", help="skip video.mp4 (fast)")
    parser.add_argument("--no-openpose", action="store_true", help="skip the openpose/ folder")
    parser.set_defaults(func=run)


def _size(text: str) -> tuple[int, int]:
    from wecook_core.errors import InputError

    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise InputError(None, f"--size must be WIDTHxHEIGHT like 640x360, found {text!r}") from None
    if width < 64 or height < 36:
        raise InputError(None, f"--size must be at least 64x36, found {text!r}")
    return width, height


def run(args: argparse.Namespace) -> int:
    import time

    from wecook_core.errors import InputError
    from wecook_core.synth import synthesize, write_scenario
    from wecook_core.synth.files import check_scenario_folder
    from wecook_core.trees.notation import has_action

    if args.duration is not None and args.duration <= 0:
        raise InputError(None, f"--duration must be positive, found {args.duration:g}")
    if args.fps <= 0:
        raise InputError(None, f"--fps must be positive, found {args.fps:g}")
    check_scenario_folder(args.out_dir, replace=getattr(args, "force", False))  # before the slow part
    started = time.perf_counter()
    scenario = synthesize(args.seed, args.persons, duration_s=args.duration, fps=args.fps, size=_size(args.size))
    out = write_scenario(scenario, args.out_dir, video=not args.no_video, openpose=not args.no_openpose)
    counted = sum(has_action(span.tree) for span in scenario.truth)
    print(f"{out}: {scenario.frames} frames ({scenario.frames / scenario.fps:.1f} s), {args.persons} person(s), "
          f"{len(scenario.observations.objects)} objects, {len(scenario.truth)} true trees ({counted} with an "
          f"action) in {time.perf_counter() - started:.1f} s")
    return 0
