"""`wecook open NAME` and `wecook demo`: the review workbench (Textual, imported only when the command runs)."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from wecook_core.errors import InputError

DEMO_NAME = "demo"


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    opener = subparsers.add_parser("open", help="review and correct a session in the workbench")
    opener.add_argument("name", help="session name (in the sessions folder) or a session folder's path")
    opener.add_argument("--root", type=Path, default=None,
                        help="sessions folder (default: $WECOOK_SESSIONS or ./sessions)")
    opener.set_defaults(func=run)
    demo = subparsers.add_parser("demo", help="build the bundled demo session if missing, then open it")
    demo.add_argument("--root", type=Path, default=None, help="sessions folder (as for open)")
    demo.set_defaults(func=run_demo)


def session_path(name: str, root: Path | None) -> Path:
    """The folder of session ``name``: a path to a session folder, or a name under the sessions root."""
    from wecook_core.session import sessions_root

    given = Path(name)
    if (given / "session.yaml").is_file():
        return given
    path = sessions_root(root) / name
    if not (path / "session.yaml").is_file():
        raise InputError(path, "no such session (create one with `wecook new NAME --video V --objects F "
                         "--hands H`, or try `wecook demo`)")
    return path


def demo_session(root: Path | None) -> Path:
    """The demo session, created from ``assets/demo`` the first time."""
    from wecook_core.session import create_session, sessions_root
    from wecook_core.synth import demo_dir

    path = sessions_root(root) / DEMO_NAME
    if (path / "session.yaml").is_file():
        return path
    assets = Path(demo_dir())
    return Path(create_session(sessions_root(root), DEMO_NAME, assets / "video.mp4", assets / "objects.csv",
                               assets / "hands.csv"))


def quiet_decoders() -> None:
    """FFmpeg and OpenCV log to stderr, where the terminal UI draws: silence them before cv2 loads."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    os.environ.setdefault("OPENCV_LOG_LEVEL", "OFF")


def launch(path: Path) -> int:
    quiet_decoders()
    from wecook_tui.app import WecookApp

    WecookApp(path).run()
    return 0


def run(args: argparse.Namespace) -> int:
    quiet_decoders()
    return launch(session_path(args.name, args.root))


def run_demo(args: argparse.Namespace) -> int:
    quiet_decoders()
    return launch(demo_session(args.root))
