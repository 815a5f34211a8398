"""The `wecook` command line. Subcommands live in `wecook_tui.commands`, imported lazily by name."""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

from wecook_core.errors import InputError

COMMAND_MODULES: tuple[str, ...] = (
    "session",  # new, sessions
    "hands",
    "boxes",
    "workbench",  # open, demo
    "analyze",
    "plan",  # plan check
    "export",
    "execute",
    "runs",  # runs check, recover, show, export
    "evaluate",
    "synth",
    "segment",
    "knowledge",  # knowledge, recognize
    "batch",
)
"""Modules of `wecook_tui.commands`, in the order their commands are listed by `wecook --help`."""


INTERACTIVE = frozenset({"open", "demo", "boxes", "batch"})
"""Commands that handle SIGTERM themselves (the workbench's event loop, the batch's workers)."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program is, so that it stops as on Ctrl-C: every ``finally`` and
    ``except BaseException`` runs and removes its temporary files. A subclass of KeyboardInterrupt so that what
    handles Ctrl-C handles it too."""


def stop_on_sigterm() -> None:
    """Make SIGTERM raise :class:`Terminated` in the main thread (once: a second one is ignored while the first
    one's clean-up runs)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return

    def terminate(signum: int, frame: object) -> None:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        raise Terminated

    signal.signal(signal.SIGTERM, terminate)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="wecook",
        description="Turn cooking videos into robot plans: analyse, review, export, execute.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        module = importlib.import_module(f"wecook_tui.commands.{name}")
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    func = getattr(args, "func", None)
    if func is None:
        if "session" in COMMAND_MODULES:  # `wecook` alone lists the sessions to pick from
            from wecook_tui.commands import session

            return int(session.pick(args))
        parser.print_help()
        return 0
    if args.command not in INTERACTIVE:
        stop_on_sigterm()
    try:
        return int(func(args) or 0)
    except InputError as error:
        print(f"wecook: error: {error}", file=sys.stderr)
        return 2
    except Terminated:
        print("wecook: terminated", file=sys.stderr)
        return 143
    except KeyboardInterrupt:
        print("wecook: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # `wecook ... | head`: the reader left; say nothing more
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141
    except OSError as error:  # a full disk, a read-only folder, a missing permission: one line, exit 2
        from wecook_core.files import os_error_line

        print(f"wecook: error: {os_error_line(error, _subject(args))}", file=sys.stderr)
        return 2
    except MemoryError:
        subject = _subject(args)
        print(f"wecook: error: {subject + ': ' if subject else ''}out of memory (a memory limit: `ulimit -v`?)",
              file=sys.stderr)
        return 2


def _subject(args: argparse.Namespace) -> str | None:
    """The file a command works on, for an error that names none: its video, recording, plan, session or output."""
    for name in ("video", "record", "plan", "name", "output", "out", "manifest"):
        value = getattr(args, name, None)
        if value is not None and not callable(value):
            return str(value)
    return None


if __name__ == "__main__":
    sys.exit(main())
