"""The real `wecook open` in a real terminal (tmux gives it one, also in CI): open, step, correct, export; and a
SIGKILL in the middle of a session loses nothing that was shown."""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from tui_driving import journal, pilot_test, settle

from wecook_core.model import SegmentStatus
from wecook_tui.app import WecookApp

REPO = Path(__file__).resolve().parents[2]
WECOOK = Path(sys.executable).with_name("wecook")


class Terminal:
    """A detached tmux session on a private server socket, 160x50, running one command."""

    def __init__(self, socket: str, name: str) -> None:
        self.socket = socket
        self.name = name

    def tmux(self, *args: str) -> str:
        done = subprocess.run(["tmux", "-L", self.socket, *args], capture_output=True, text=True, timeout=20)
        return done.stdout

    def start(self, command: str) -> None:
        """Start ``command`` in the session; again if the session did not come up (a new-session sent while the
        server of a session that just ended is still exiting is lost: the reopen then showed a blank screen)."""
        for _ in range(3):
            self.tmux("new-session", "-d", "-s", self.name, "-x", "160", "-y", "50", command)
            if self.alive():
                break
            time.sleep(0.5)
        self.tmux("set-option", "-s", "escape-time", "0")  # Escape then q must not arrive as Alt+q
        self.tmux("set-option", "-s", "exit-empty", "off")  # the server stays up between a quit and a reopen

    def keys(self, *keys: str) -> None:
        for key in keys:
            self.tmux("send-keys", "-t", self.name, key)
            time.sleep(0.05)

    def screen(self) -> str:
        return self.tmux("capture-pane", "-p", "-t", self.name)

    def pid(self) -> int:
        return int(self.tmux("display-message", "-p", "-t", self.name, "#{pane_pid}").strip())

    def alive(self) -> bool:
        return self.name in self.tmux("list-sessions", "-F", "#{session_name}")

    def wait(self, what: Callable[[], bool], message: str, timeout: float = 30.0) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if what():
                return
            time.sleep(0.1)
        raise AssertionError(f"{message}; screen:\n{self.screen()}")

    def wait_ready(self) -> None:
        """Until the session is open and its analysis shown (the status bar says neither opening nor
        recomputing)."""
        self.wait(lambda: "segment 1/" in (screen := self.screen()) and "opening" not in screen
                  and "recomputing" not in screen, "the workbench never became ready")

    def wait_settled(self) -> None:
        """Until the analysis matches the journal (the status bar no longer says recomputing)."""
        self.wait(lambda: "segment " in (screen := self.screen()) and "opening" not in screen
                  and "recomputing" not in screen, "the workbench never settled")

    def wait_text(self, text: str, timeout: float = 30.0) -> None:
        self.wait(lambda: text in self.screen(), f"never showed {text!r}", timeout)


def acting_segment(session: Path, after: int = 0) -> int:
    """The number (from 1) of the first segment after segment ``after`` where some hand acts: where `c` offers
    verbs (for a hand holding nothing it refuses)."""
    from wecook_core.workflows import analyse_session
    from wecook_tui import review

    analysis = analyse_session(session, write=False).analysis
    segs = analysis.segmentation.segments
    return next(i + 1 for i, s in enumerate(segs) if i >= after and review.actions_of(analysis, s, i))


def go_to_segment(terminal: Terminal, number: int) -> None:
    terminal.keys("g")
    terminal.wait_text("Go to:")
    terminal.keys("#", *str(number), "Enter")
    terminal.wait(lambda: f"segment {number}/" in (screen := terminal.screen()) and "Go to:" not in screen,
                  f"never went to segment {number}")


@pytest.fixture
def terminal(tmp_path: Path) -> Iterator[Terminal]:
    term = Terminal(f"wecook-test-{os.getpid()}-{tmp_path.name}", "wb")
    yield term
    term.tmux("kill-server")


def open_command(session: Path, tmp_path: Path) -> str:
    env = f"WECOOK_KEYS={shlex.quote(str(tmp_path / 'none.toml'))} TERM=xterm-256color COLORTERM=truecolor"
    return (f"cd {shlex.quote(str(REPO))} && exec env -u COLUMNS -u LINES {env} {shlex.quote(str(WECOOK))} "
            f"open {session.name} --root {shlex.quote(str(session.parent))}")


@pytest.mark.tmux
def test_open_step_correct_export_in_a_real_terminal(session_path: Path, tmp_path: Path,
                                                     terminal: Terminal) -> None:
    terminal.start(open_command(session_path, tmp_path))
    terminal.wait_ready()
    terminal.keys("l", "l", "l")
    terminal.wait_text("frame 3/")
    go_to_segment(terminal, acting_segment(session_path))
    terminal.keys("c")
    terminal.wait_text("Action of")
    terminal.keys("Down", "Enter")
    terminal.wait(lambda: len(journal(session_path)) == 1, "the action change was not journaled")
    assert journal(session_path)[-1]["op"] == "set_verb"
    terminal.wait_text("✎ corrected")
    terminal.keys("a")
    terminal.wait(lambda: len(journal(session_path)) == 2, "accept was not journaled")
    terminal.wait_text("✓ accepted")
    terminal.keys("e")
    terminal.wait_text("Press w to write")
    terminal.keys("w")
    terminal.wait_text("still unreviewed")  # asks first
    terminal.keys("w")
    terminal.wait_text("Plan written to")
    assert (session_path / "plans" / "plan.yaml").is_file()
    terminal.keys("Escape")
    terminal.wait_text("Next segment")  # back on the main screen
    terminal.keys("q")
    terminal.wait(lambda: not terminal.alive(), "wecook did not quit on q")


@pytest.mark.tmux
@pilot_test
async def test_sigkill_mid_session_loses_nothing(session_path: Path, tmp_path: Path, terminal: Terminal) -> None:
    terminal.start(open_command(session_path, tmp_path))
    terminal.wait_ready()
    terminal.keys("a")
    terminal.wait(lambda: len(journal(session_path)) == 1, "accept was not journaled")
    terminal.keys("Down")
    terminal.wait_text("segment 2/")
    terminal.keys("x")
    terminal.wait(lambda: len(journal(session_path)) == 2, "reject was not journaled")
    go_to_segment(terminal, acting_segment(session_path, after=2))
    terminal.keys("c")
    terminal.wait_text("Action of")
    terminal.keys("Enter")
    terminal.wait(lambda: len(journal(session_path)) == 3, "the verb change was not journaled")
    terminal.keys("z")  # undo it: the kill comes right after, while the analysis recomputes
    terminal.wait(lambda: len(journal(session_path)) == 4, "the undo was not journaled")
    os.kill(terminal.pid(), signal.SIGKILL)
    terminal.wait(lambda: not terminal.alive(), "the app survived SIGKILL")
    entries = journal(session_path)
    assert [e["op"] for e in entries] == ["set_status", "set_status", "set_verb", "undo"]
    app = WecookApp(session_path)
    async with app.run_test(size=(150, 45)) as pilot:
        await settle(pilot, app)
        segs = app.analysis.segmentation.segments
        assert app.corrections.status == {0: SegmentStatus.ACCEPTED, segs[1].start: SegmentStatus.REJECTED}
        assert app.corrections.verbs == {}
        await pilot.press("y")  # the undone verb change can still be redone after the crash
        assert app.corrections.verbs and len(set(app.corrections.verbs.values())) == 1  # one change (its action)


@pytest.mark.tmux
def test_correct_a_multi_segment_action_with_one_key_sequence_quit_reopen(session_path: Path, tmp_path: Path,
                                                                        terminal: Terminal) -> None:
    """Open, split an action so it spans two segments, change its verb once (c, a verb, enter), quit, reopen:
    the change covers both segments, and the workbench resumes where it was."""
    from wecook_core.workflows import analyse_session
    from wecook_tui import review

    analysis = analyse_session(session_path, write=False).analysis
    segs = analysis.segmentation.segments
    index, seg, hand = next((i, s, h) for i, s in enumerate(segs) for h, a in
                            review.actions_of(analysis, s, i).items() if a.verb and a.kind == "tool" and len(s) > 4)
    terminal.start(open_command(session_path, tmp_path))
    terminal.wait_ready()
    middle = seg.start + len(seg) // 2
    terminal.keys("g")
    terminal.wait_text("Go to:")
    terminal.keys(*str(middle), "Enter")
    terminal.wait_text(f"frame {middle}/")
    terminal.keys("s")  # split the action's segment in two
    terminal.wait(lambda: len(journal(session_path)) == 1, "the split was not journaled")
    terminal.wait_settled()
    terminal.wait_text(f"segment {index + 2}/{len(segs) + 1}")
    for _ in range(4):  # the first acting hand is selected: t until it is this action's
        if f"hand {hand} " in terminal.screen():
            break
        terminal.keys("t")
        time.sleep(0.2)
    terminal.wait_text(f"hand {hand} ")
    terminal.keys("c")
    terminal.wait_text("its whole action")
    terminal.keys("Down", "Enter")
    terminal.wait(lambda: len(journal(session_path)) == 2, "the verb change was not journaled")
    entry = journal(session_path)[-1]
    assert entry["op"] == "set_verb" and entry["segment"] <= seg.start and entry["end"] >= seg.end
    terminal.wait_text(f"✎ verb of {hand} -> {entry['verb']}")  # the answer on the status line
    assert " segments" in terminal.screen()  # over the segments of the whole action
    terminal.wait_settled()
    terminal.keys("q")
    terminal.wait(lambda: not terminal.alive(), "wecook did not quit on q")
    terminal.start(open_command(session_path, tmp_path))
    terminal.wait_text(f"frame {middle}/")
    terminal.wait_settled()  # resumed where it was
    after = analyse_session(session_path, write=False).analysis
    halves = [s for s in after.segmentation.segments if seg.start <= s.start < seg.end]
    assert len(halves) == 2
    verbs = {review.actions_of(after, s, after.segmentation.segments.index(s))[hand].verb for s in halves}
    assert verbs == {entry["verb"]}
    terminal.wait_text("✎ corrected")
    terminal.keys("q")
    terminal.wait(lambda: not terminal.alive(), "wecook did not quit on q")
