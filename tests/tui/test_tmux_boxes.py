"""From a video alone to a tree, in a real terminal: `wecook new` with neither boxes nor hands (MediaPipe finds
the hand), `wecook open`, B: two boxes drawn with keys and tracked by OpenCV in the workbench's box mode, and the
workbench's own analysis gives a tree of them (and `wecook analyze` the same, from the journal). The video holds
a real hand (tests/data/hand_four.png, Apache-2.0) carrying a drawn tomato into a drawn bowl."""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from test_tmux import Terminal
from tui_driving import journal

from tests.hand_video import hand_and_tomato
from wecook_core.observations.hand_assign import iou
from wecook_core.session.boxes import fold_boxes
from wecook_core.session.store import open_session
from wecook_core.trees.treefile import read_tree_file

WECOOK = Path(sys.executable).with_name("wecook")
REPO = Path(__file__).resolve().parents[2]
"""The checkout under test: the wecook script's own directory is first on its path, so without this a worktree's
test would drive the code of the checkout the venv was installed from."""


@pytest.fixture
def term(tmp_path: Path) -> Iterator[Terminal]:
    terminal = Terminal(f"wecook-boxes-{os.getpid()}-{tmp_path.name}", "boxes")
    yield terminal
    terminal.tmux("kill-server")


def draw(terminal: Terminal, label: str, keys: str) -> None:
    """b: a new box in the middle; n: the name prompt; the label; then the keys that fit it to the object;
    then t: track it, and wait for the tracker to finish."""
    terminal.keys("b")
    terminal.wait_text("unnamed: n names it")
    terminal.keys("n")
    terminal.wait_text("Name the box")
    terminal.keys(label, "Enter")
    terminal.wait(lambda: "Name the box" not in terminal.screen(), "the name prompt stayed")
    for key in keys:
        terminal.keys(key)
    terminal.keys("t")
    terminal.wait(lambda: f"{label}: followed" in terminal.screen() or "tracked to frame" in terminal.screen(),
                  f"{label} was never tracked", timeout=60)


@pytest.mark.tmux
def test_video_alone_to_a_tree(tmp_path: Path, term: Terminal) -> None:
    video = tmp_path / "kitchen.avi"
    truth = hand_and_tomato(video)  # 640x360: the box mode's new box is 256-384 x 144-216
    root = tmp_path / "sessions"
    made = subprocess.run([str(WECOOK), "new", "kitchen", "--video", str(video), "--root", str(root),
                           "--hand-model", "lite"], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(REPO)})
    assert made.returncode == 0, made.stderr
    assert "RH_P1" in (root / "kitchen.hands.csv").read_text() and "objects  none yet" in made.stdout
    session = root / "kitchen"
    env = (f"WECOOK_KEYS={shlex.quote(str(tmp_path / 'none.toml'))} TERM=xterm-256color COLORTERM=truecolor "
           f"PYTHONPATH={shlex.quote(str(REPO))}")
    term.start(f"exec env -u COLUMNS -u LINES {env} {shlex.quote(str(WECOOK))} open kitchen "
               f"--root {shlex.quote(str(root))}")
    term.wait_ready()
    term.keys("B")
    term.wait_text("frame 0/59")
    draw(term, "tomato", "AAAAAWW" + "a" * 11 + "s" * 8)  # onto the tomato, about 115-179 x 202-259
    draw(term, "bowl", "D" + "S" * 9 + "d" * 11 + "ss")  # onto the bowl, about 397-538 x 158-295
    term.keys("Escape")
    term.wait_ready()  # back on the review screen, the analysis re-run on the drawn boxes
    term.wait(lambda: (session / "trees.yaml").exists() and "tomato" in (session / "trees.yaml").read_text(),
              "the workbench wrote no tree of the drawn boxes")
    term.keys("q")
    term.wait(lambda: not term.alive() or "$" in term.screen(), "the workbench did not quit")

    ops = [e["op"] for e in journal(session)]
    assert ops.count("box_tracked") == 2 and "box_label" in ops
    tomato, bowl = fold_boxes(open_session(session).applied_corrections)
    assert (tomato.label, bowl.label) == ("tomato", "bowl")
    assert iou(tomato.keyframes[0], truth["tomato"]) > 0.6 and iou(bowl.keyframes[0], truth["bowl"]) > 0.6
    assert len(tomato.boxes()) > 40  # carried into the bowl and followed
    shown = [str(t.tree) for t in read_tree_file(session / "trees.yaml")]
    assert any("tomato" in t and "RH_P1" in t for t in shown), shown
    # `wecook analyze` reads the same journal and finds the same trees.
    analysed = subprocess.run([str(WECOOK), "analyze", "kitchen", "--root", str(root)], capture_output=True,
                              text=True, timeout=300)
    assert analysed.returncode == 0, analysed.stderr
    assert [str(t.tree) for t in read_tree_file(session / "trees.yaml")] == shown
