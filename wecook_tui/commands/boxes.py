"""`wecook boxes VIDEO --out DIR`: the box mode on a video alone (no session yet): draw boxes, track them, export
``DIR/boxes.xml`` (CVAT for video) and ``DIR/boxes.csv`` (wecook CSV), which `wecook new --objects` imports.
In the workbench the same mode opens with B on the session's video, where every box is journaled."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(sub: Any) -> None:
    parser = sub.add_parser(
        "boxes", help="draw object boxes on a video and track them (box mode), export CVAT XML and CSV",
        description="Open the box mode on VIDEO (it proposes boxes on the first frame; p proposes on the frame "
                    "shown, 1-9 keeps a proposal, K keeps them all): b draws a box, wasd/WASD move and resize it (or "
                    "drag with the mouse), n names it, t tracks it with OpenCV until it is lost, a change at another "
                    "frame is a keyframe, z undoes, y redoes, e exports DIR/boxes.xml and DIR/boxes.csv, q quits.",
    )
    parser.add_argument("video", metavar="VIDEO", help="the video (any file OpenCV reads)")
    parser.add_argument("--out", required=True, metavar="DIR", help="folder for boxes.xml and boxes.csv")
    parser.set_defaults(func=run_boxes)


def run_boxes(args: argparse.Namespace) -> int:
    from textual.app import App

    from wecook_core.errors import InputError
    from wecook_core.formats.video import probe_video, usable_frames
    from wecook_tui.screens.boxes import BoxScreen, BoxVideo

    info = probe_video(args.video)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(out, "is a file; --out names a folder")
    video = BoxVideo(str(info.path), (info.width, info.height), info.fps, usable_frames(info))
    screen = BoxScreen(video, out, exit_on_back=True, propose=True)

    class BoxApp(App[None]):
        TITLE = "wecook boxes"
        CSS_PATH = str(Path(__file__).resolve().parents[1] / "workbench.tcss")

        def on_mount(self) -> None:
            self.push_screen(screen)

    BoxApp().run()
    exported = [p for p in (out / "boxes.xml", out / "boxes.csv") if p.exists()]
    if exported:
        print("wrote " + " and ".join(str(p) for p in exported))
    return 0
