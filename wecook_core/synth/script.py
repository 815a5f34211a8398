"""The scenario's script: which actions happen, who does them with which hand, and when.

A script is a list of tasks (cut the tomato, pass the lemon, hold the pot while the other stirs...) shuffled by
seed, scheduled on two persons working in parallel: a task starts when its persons and its objects are free,
after a short pause. Each task writes hand phases (reach, grasp, carry, work, carry back, release, return),
object events (ride on a hand, turn, squash, glide into the pot, vanish, come back) and its true
:class:`~wecook_core.model.Action`, whose frames run from the grasp that starts it to the release that ends it.
"""

from __future__ import annotations

import numpy as np

from wecook_core.synth.draft import Draft
from wecook_core.synth.events import Appear
from wecook_core.synth.layout import make_layout
from wecook_core.synth.tasks import INDIVIDUAL, handover, holding
from wecook_core.synth.writer import TAIL_SECONDS, Script, Writer

TASKS: tuple[str, ...] = (
    "cut", "peel", "roll", "squeeze", "transfer_tool", "transfer_tip", "pour", "sprinkle", "stir",
    "holding", "handover",
)
"""Every task kind; one cycle of a two-person script does each once (one person: all but the last two)."""


_TASK_OBJECTS: dict[str, tuple[str, tuple[str, ...]]] = {
    "cut": ("knife", ("knife", "tomato", "chopping_board")),
    "peel": ("peeler", ("peeler", "potato")),
    "roll": ("rolling_pin", ("rolling_pin", "dough")),
    "squeeze": ("lemon", ("lemon",)),
    "transfer_tool": ("spoon", ("spoon", "@source", "@scooped", "pot")),
    "transfer_tip": ("bowl", ("bowl", "@tipped", "pot")),
    "pour": ("oil", ("oil", "pot")),
    "sprinkle": ("salt", ("salt", "pot")),
    "stir": ("spoon", ("spoon", "pot")),
}
"""Task -> (the group whose owner does it, the objects it keeps busy)."""


def _ready_for(w: Writer, kind: str, extra: str | None) -> int:
    """The first frame a task could start (before the pause)."""
    middle = ("pot", "chopping_board", "tomato")
    if kind == "holding":
        return w.ready(("P1", "P2"), (str(extra), "spoon" if extra == "pot" else "knife", *middle))
    if kind == "handover":
        giver = w.thing(str(extra)).owner or "P1"
        receiver = "P2" if giver == "P1" else "P1"
        return max(w.ready((giver,), (str(extra), *middle)), w.free[receiver] - round(w.fps))
    group, objects = _TASK_OBJECTS[kind]
    return w.ready((w.owner(group),), tuple(_resolve(w, o) for o in objects))


def _schedule(w: Writer, kind: str, extra: str | None = None) -> bool:
    draft = Draft(w.fps, w.rng)
    middle = ("pot", "chopping_board", "tomato")
    if kind == "holding":
        assert extra is not None
        busy = (extra, "spoon" if extra == "pot" else "knife", *middle)
        t = w.start_after(("P1", "P2"), busy)
        draft.actions.append(holding(w, t, draft, extra))
        return w.commit(draft, ("P1", "P2"), kind)
    if kind == "handover":
        assert extra is not None
        t = w.start_after((w.thing(extra).owner or "P1",), (extra, *middle))
        t = max(t, w.free["P2" if w.thing(extra).owner == "P1" else "P1"] - draft.frames(1.0))
        action, carry = handover(w, t, draft, extra)
        draft.actions.extend([action, carry])
        return w.commit(draft, ("P1", "P2"), kind)
    group, objects = _TASK_OBJECTS[kind]
    names = tuple(_resolve(w, o) for o in objects)
    person = w.owner(group)
    t = w.start_after((person,), names)
    action = INDIVIDUAL[kind](w, person, t, draft)
    draft.actions.append(action)
    return w.commit(draft, (person,), kind)

def _resolve(w: Writer, name: str) -> str:
    if name == "@source":
        return w.layout.groups["spoon"][1]
    if name == "@scooped":
        return w.layout.groups["spoon"][2]
    if name == "@tipped":
        return w.layout.groups["bowl"][1]
    return name


def write_script(seed_rng: np.random.Generator, persons: int, fps: float, limit: int | None) -> Script:
    """Lay out the table and schedule cycles of tasks (one cycle without ``limit``; with a frame limit,
    cycles until no further task fits)."""
    layout = make_layout(persons, seed_rng)
    writer = Writer(layout, fps, seed_rng, limit)
    kinds = [k for k in (TASKS if persons == 2 else TASKS[:-2])
             if k in ("holding", "handover") or _TASK_OBJECTS[k][0] in layout.groups]
    last: str | None = None
    while True:
        # each step takes, among the tasks left in this cycle, one that could start soonest (ties broken at
        # random, up to a second and a half apart): the persons rarely wait for each other
        left: list[tuple[str, str | None]] = []
        for kind in kinds:
            extra = None
            if kind == "holding":
                extra = "pot" if seed_rng.random() < 0.6 else "chopping_board"
            elif kind == "handover":
                extra = layout.handed
            left.append((kind, extra))
        placed = 0
        while left:
            ready = np.array([_ready_for(writer, kind, extra) for kind, extra in left], dtype=float)
            ready += seed_rng.uniform(0, 1.5 * fps, len(left))
            ready[[kind == last for kind, _ in left]] += 3 * fps
            kind, extra = left.pop(int(np.argmin(ready)))
            placed += _schedule(writer, kind, extra)
            last = kind
        if limit is None or placed == 0:
            break
    script = writer.script
    tail = round(TAIL_SECONDS * fps)
    script.frames = limit if limit is not None else script.frames + tail
    script.actions.sort(key=lambda a: (a.start, a.hand))
    for moves in script.moves.values():
        moves.sort(key=lambda e: e.frame if isinstance(e, Appear) else e.start)
    for turns in script.turns.values():
        turns.sort(key=lambda e: e.start)
    for sizes in script.sizes.values():
        sizes.sort(key=lambda e: e.start)
    for phases in script.phases.values():
        phases.sort(key=lambda p: p.start)
    return script
