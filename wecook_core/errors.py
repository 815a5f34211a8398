"""Errors about the user's input: each names the file and the place, and reads as one line."""

from __future__ import annotations

import json
from pathlib import Path

MAX_MESSAGE_CHARS = 2000
"""An error's line is cut to this many characters (it quotes the input, which may be huge)."""


class InputError(Exception):
    """Bad input from the user: a file, a place in it (line, frame, field) and what was expected.

    ``str(error)`` is the one line the command line prints (exit code 2) and the workbench shows.
    """

    def __init__(self, path: str | Path | None, message: str, *, place: str | None = None) -> None:
        self.path = str(path) if path is not None else None
        self.place = place
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        where = ""
        if self.path:
            where = self.path + (f":{self.place}" if self.place else "") + ": "
        elif self.place:
            where = f"{self.place}: "
        text = (where + self.message).replace("\r", "\\r").replace("\n", "\\n")  # always one line
        return text if len(text) <= MAX_MESSAGE_CHARS else text[: MAX_MESSAGE_CHARS - 3] + "..."


def yaml_error(path: str | Path | None, error: Exception, what: str = "malformed YAML") -> InputError:
    """The :class:`InputError` of a YAML parser's error: ``what``, then the parser's problem in brackets, placed
    at the line the parser points at (when it points at one)."""
    mark = getattr(error, "problem_mark", None)
    place = f"line {mark.line + 1}" if mark is not None else None
    return InputError(path, f"{what} ({getattr(error, 'problem', None) or error})", place=place)


def json_error(path: str | Path | None, error: json.JSONDecodeError, what: str = "malformed JSON") -> InputError:
    """The :class:`InputError` of a JSON parser's error: ``what`` and its message, at its line and column."""
    return InputError(path, f"{what} ({error.msg})", place=f"line {error.lineno}, column {error.colno}")


def read_input_text(path: str | Path, missing: str = "file not found") -> str:
    """The UTF-8 text of the user's file ``path``: an :class:`InputError` saying ``missing`` when there is no
    such file, ``cannot read: ...`` when it does not read (a folder, no permission, not UTF-8, a FIFO)."""
    import stat

    try:
        if Path(path).exists() and not stat.S_ISREG(Path(path).stat().st_mode) and not Path(path).is_dir():
            raise InputError(path, "cannot read: not a regular file (a FIFO or a device)")
        return Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(path, missing) from None
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(path, f"cannot read: {error}") from None


def load_json(path: str | Path | None, text: str | bytes, what: str = "malformed JSON") -> object:
    """``json.loads(text)``, every failure an :class:`InputError` naming ``path``: malformed JSON at its line
    and column; nesting deeper than the interpreter's recursion limit (about 1000 levels); an integer of more
    than 4300 digits (Python's limit on converting text to int)."""
    try:
        return json.loads(text)
    except json.JSONDecodeError as error:
        raise json_error(path, error, what) from None
    except RecursionError:
        raise InputError(path, f"{what} (nested too deeply: more than about 1000 levels)") from None
    except (ValueError, UnicodeDecodeError) as error:
        raise InputError(path, f"{what} ({error})") from None
