"""The scenario's script: which actions happen, who does them with which hand, and when.

A script is a list of tasks (cut the tomato, pass the lemon, hold the pot while the other stirs...) shuffled by
seed, scheduled on two persons working in parallel: a task starts when its persons and its objects are free,
after a short pause. Each task writes hand phases (reach, grasp, carry, work, carry back, release, return),
object events (ride on a hand, turn, squash, glide into the pot, vanish, come back) and its true
:class:`~wecook_core.model.Action`, whose frames run from the grasp that starts it to the release that ends it.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from wecook_core.model import Action, ActionKind
from wecook_core.synth.draft import Draft, point
from wecook_core.synth.events import Appear, Effect, Glide, PositionEvent, Resize, Ride, Turn
from wecook_core.synth.kitchen import MAX_DOUGH
from wecook_core.synth.layout import Body, Layout, Thing, extent, make_layout
from wecook_core.synth.motion import Move, Phase, Work, rotation

# -------------------------------------------------------------------------------------------- script


@dataclass(eq=False)
class Script:
    """Everything the scheduler decided; positions are resolved per frame by :mod:`wecook_core.synth.scene`."""

    layout: Layout
    fps: float
    frames: int
    phases: dict[str, list[Phase]] = field(default_factory=lambda: defaultdict(list))
    """Hand -> its phases, in time order."""
    moves: dict[str, list[PositionEvent]] = field(default_factory=lambda: defaultdict(list))
    """Object name -> position events, in time order."""
    turns: dict[str, list[Turn]] = field(default_factory=lambda: defaultdict(list))
    sizes: dict[str, list[Resize]] = field(default_factory=lambda: defaultdict(list))
    marks: dict[str, list[int]] = field(default_factory=lambda: defaultdict(list))
    """Object name -> frames where it was worked once more (a cut, a peel): drawn, not detected."""
    effects: list[Effect] = field(default_factory=list)
    actions: list[Action] = field(default_factory=list)
    """The true actions (one tree each), plus the receiver's carry after a handover (a GRASP)."""
    tasks: list[str] = field(default_factory=list)
    """Task kinds in the order they were scheduled."""
    initial_homes: dict[str, np.ndarray] = field(default_factory=dict)
    """Object name -> where it lay at the start (handovers move ``Thing.home`` while scheduling)."""


TASKS: tuple[str, ...] = (
    "cut", "peel", "roll", "squeeze", "transfer_tool", "transfer_tip", "pour", "sprinkle", "stir",
    "holding", "handover",
)
"""Every task kind; one cycle of a two-person script does each once (one person: all but the last two)."""

TAIL_SECONDS = 1.5
"""Idle time after the last task."""


def _angle(d: np.ndarray) -> float:
    return float(np.arctan2(d[1], d[0]))


def _reach_out(box_half: np.ndarray, direction: np.ndarray) -> float:
    """Distance from a box's centre to its edge along ``direction`` (a unit vector)."""
    dx, dy = abs(float(direction[0])), abs(float(direction[1]))
    return min(box_half[0] / dx if dx > 1e-9 else np.inf, box_half[1] / dy if dy > 1e-9 else np.inf)


def _half(thing: Thing, angle: float | None = None, scale: tuple[float, float] = (1.0, 1.0)) -> np.ndarray:
    size = (thing.kind.size[0] * scale[0], thing.kind.size[1] * scale[1])
    return extent(size, thing.angle if angle is None else angle, thing.kind.round)


# -------------------------------------------------------------------------------------------- writer


class _Writer:
    """Schedules tasks onto the persons and writes each into the script."""

    def __init__(self, layout: Layout, fps: float, rng: np.random.Generator, limit: int | None) -> None:
        self.layout = layout
        self.fps = fps
        self.rng = rng
        self.limit = limit
        self.script = Script(layout, fps, 0)
        self.script.initial_homes = {name: thing.home.copy() for name, thing in layout.things.items()}
        self.free: dict[str, int] = {b.person: round(rng.uniform(0.4, 1.2) * fps) for b in layout.bodies}
        self.object_free: dict[str, int] = defaultdict(int)
        self.dough_scale = (1.0, 1.0)

    # ---- helpers
    def thing(self, name: str) -> Thing:
        return self.layout.things[name]

    def owner(self, group: str) -> str:
        first = self.layout.groups[group][0]
        return self.thing(first).owner or "P1"

    def body(self, person: str) -> Body:
        return self.layout.body(person)

    def pause(self) -> int:
        return round(self.rng.uniform(0.3, 1.3) * self.fps)

    def start_after(self, persons: tuple[str, ...], objects: tuple[str, ...]) -> int:
        return self.ready(persons, objects) + self.pause()

    def ready(self, persons: tuple[str, ...], objects: tuple[str, ...]) -> int:
        return max([self.free[p] for p in persons] + [self.object_free[o] for o in objects])

    def ready_for(self, kind: str, extra: str | None) -> int:
        """The first frame a task could start (before the pause)."""
        middle = ("pot", "chopping_board", "tomato")
        if kind == "holding":
            return self.ready(("P1", "P2"), (str(extra), "spoon" if extra == "pot" else "knife", *middle))
        if kind == "handover":
            giver = self.thing(str(extra)).owner or "P1"
            receiver = "P2" if giver == "P1" else "P1"
            return max(self.ready((giver,), (str(extra), *middle)), self.free[receiver] - round(self.fps))
        group, objects = _TASK_OBJECTS[kind]
        return self.ready((self.owner(group),), tuple(self._resolve(o) for o in objects))

    def grip_point(self, thing: Thing, grip: np.ndarray, angle: float | None = None) -> np.ndarray:
        return thing.home + rotation(thing.angle if angle is None else angle) @ grip

    def commit(self, draft: Draft, persons: tuple[str, ...], kind: str) -> bool:
        if self.limit is not None and draft.end + round(TAIL_SECONDS * self.fps) > self.limit:
            return False
        s = self.script
        for hand, phases in draft.phases.items():
            s.phases[hand].extend(phases)
        for name, moves in draft.moves.items():
            s.moves[name].extend(moves)
        for name, turns in draft.turns.items():
            s.turns[name].extend(turns)
        for name, sizes in draft.sizes.items():
            s.sizes[name].extend(sizes)
        for name, marks in draft.marks.items():
            s.marks[name].extend(marks)
        s.effects.extend(draft.effects)
        s.actions.extend(draft.actions)
        for person in persons:
            self.free[person] = max(self.free[person], draft.end)
        for name, until in draft.busy.items():
            self.object_free[name] = max(self.object_free[name], until)
        for change in draft.commits:
            change()
        s.tasks.append(kind)
        s.frames = max(s.frames, draft.end)
        return True

    # ---- the common shape of a task: take an object, visit stations, put it back
    def take(
        self, draft: Draft, hand: str, t: int, thing: Thing, grip: np.ndarray,
        stations: list[Callable[[int], int]], poses: list[tuple[np.ndarray, float]],
        back: tuple[np.ndarray, float] | None = None,
    ) -> tuple[int, int, int, list[int]]:
        """Reach ``thing``, grasp it at ``grip`` (local frame), visit each pose (hand position, object angle)
        and run its station there (which returns the frame it ends), carry it to ``back`` (default: home),
        release and return to rest. Returns (grasp frame, release frame, end frame, station start frames)."""
        body = self.body(hand[-2:])
        rest = np.asarray(body.rests[hand])
        start_point = self.grip_point(thing, grip)
        t1 = draft.move(hand, t, rest, start_point)
        t = draft.hold(hand, t1, start_point, draft.span(0.15, 0.3))
        here, angle = start_point, thing.angle
        starts = []
        for (pose, pose_angle), station in zip(poses, stations, strict=True):
            if float(np.hypot(*(pose - here))) > 0.5:
                end = draft.move(hand, t, here, pose, pace=1.1)
                if abs(pose_angle - angle) > 1e-6:
                    draft.turns[thing.name].append(Turn(t, end, pose_angle))
                t = end
            here, angle = pose, pose_angle
            starts.append(t)
            t = station(t)
        home_point, home_angle = back if back is not None else (start_point, thing.angle)
        if float(np.hypot(*(home_point - here))) > 0.5:
            end = draft.move(hand, t, here, home_point, pace=1.1)
            if abs(home_angle - angle) > 1e-6:
                draft.turns[thing.name].append(Turn(t, end, home_angle))
            t = end
        release = draft.hold(hand, t, home_point, draft.span(0.15, 0.3))
        end = draft.move(hand, release, home_point, rest)
        vector = -np.asarray(grip, dtype=float)
        draft.moves[thing.name].append(Ride(t1, release, hand, thing.name, point(vector)))
        draft.use(thing.name, end)
        return t1, release, end, starts

    # ---- tasks
    def tool_on(self, draft: Draft, person: str, t: int, tool: Thing, target: np.ndarray, pattern: str,
                along: float, amplitude: tuple[float, float], frequency: tuple[float, float],
                seconds: tuple[float, float], *, drift: float = 0.0, across: bool = False,
                hand: str | None = None, grip_side: bool = False,
                during: Callable[[int, int], None] | None = None) -> tuple[str, int, int, int]:
        """A held tool worked on ``target`` (a point): its centre put ``along`` pixels before the target on
        the line from the shoulder, pointing there (``across``: lying across that line, a rolling pin)."""
        body = self.body(person)
        hand = hand or body.hand_towards((tool.home + target) / 2)
        direction = body.direction_to(hand, target)
        work_angle = _angle(direction) + (np.pi / 2 if across else 0.0)
        grip = np.array([tool.kind.grip, 0.0])
        if grip_side:  # take the end of the pin on the side of the hand
            axis = np.array([np.cos(tool.angle), np.sin(tool.angle)])
            grip = np.array([abs(tool.kind.grip) * (1 if axis @ body.outward(hand) > 0 else -1), 0.0])
        centre = target - along * direction
        hand_at = centre + rotation(work_angle) @ grip
        length = draft.span(*seconds)
        amp, freq = self.rng.uniform(*amplitude), self.rng.uniform(*frequency)

        def station(t0: int) -> int:
            end = draft.work(hand, t0, hand_at, pattern, direction, amp, freq, length, drift)
            if during is not None:
                during(t0, end)
            return end

        t1, release, end, _ = self.take(draft, hand, t, tool, grip, [station], [(hand_at, work_angle)])
        return hand, t1, release, end

    def cut(self, person: str, t: int, draft: Draft) -> Action:
        knife, tomato = self.thing("knife"), self.thing("tomato")
        drift = float(self.rng.uniform(-7, 7))
        hand, t1, release, end = self.tool_on(draft, person, t, knife, tomato.home, "saw", 10.0, (4.5, 6.0),
                                              (2.0, 2.8), (2.5, 4.5), drift=drift,
                                              during=lambda a, b: draft.marks["tomato"].append((a + b) // 2))
        for name in ("tomato", "chopping_board"):
            draft.use(name, end)
        return Action(ActionKind.TOOL, hand, t1, release, verb="cut", held="knife",
                      targets=("tomato", "chopping_board"))

    def peel(self, person: str, t: int, draft: Draft) -> Action:
        peeler, potato = self.thing("peeler"), self.thing("potato")
        hand, t1, release, end = self.tool_on(draft, person, t, peeler, potato.home, "peel", 14.0, (7.0, 9.0),
                                              (1.2, 1.7), (2.5, 4.0),
                                              during=lambda a, b: draft.marks["potato"].append((a + b) // 2))
        draft.use("potato", end)
        return Action(ActionKind.TOOL, hand, t1, release, verb="peel", held="peeler", targets=("potato",))

    def roll(self, person: str, t: int, draft: Draft) -> Action:
        pin, dough = self.thing("rolling_pin"), self.thing("dough")
        body = self.body(person)
        hand = body.hand_towards((pin.home + dough.home) / 2)
        # the pin's middle rides a little off the dough's centre, away from the hand holding its end
        target = dough.home + 12 * body.outward(hand)
        old = self.dough_scale
        new = (min(old[0] * 1.1, MAX_DOUGH[0] / 58), min(old[1] * 1.08, MAX_DOUGH[1] / 42))

        def grow(t0: int, t1: int) -> None:
            draft.sizes["dough"].append(Resize(t0, t1, new))

        hand, t1, release, end = self.tool_on(draft, person, t, pin, target, "roll", 0.0,
                                              (13.0, 17.0), (0.6, 0.9), (3.0, 4.5), across=True, hand=hand,
                                              grip_side=True, during=grow)
        draft.use("dough", end)

        def done() -> None:
            self.dough_scale = new

        draft.commits.append(done)
        return Action(ActionKind.TOOL, hand, t1, release, verb="roll", held="rolling_pin", targets=("dough",))

    def stir(self, person: str, t: int, draft: Draft) -> Action:
        spoon, pot = self.thing("spoon"), self.thing("pot")
        hand, t1, release, end = self.tool_on(draft, person, t, spoon, pot.home, "circle", 14.0, (7.0, 10.0),
                                              (0.8, 1.2), (2.5, 4.0))
        draft.use("pot", end)
        return Action(ActionKind.TOOL, hand, t1, release, verb="stir", held="spoon", targets=("pot",))

    def squeeze(self, person: str, t: int, draft: Draft) -> Action:
        lemon = self.thing("lemon")
        body = self.body(person)
        hand = body.hand_towards(lemon.home)
        direction = body.direction_to(hand, lemon.home)
        grip = rotation(lemon.angle).T @ (-3.0 * direction)
        length = draft.span(2.0, 3.2)

        def station(t0: int) -> int:
            end = draft.work(hand, t0, self.grip_point(lemon, grip), "squeeze", direction, 1.2, 2.0, length)
            draft.sizes["lemon"].append(Resize(t0, end, (0.9, 0.86), pulses=float(self.rng.uniform(1.2, 1.8))))
            return end

        point = self.grip_point(lemon, grip)
        t1, release, _, _ = self.take(draft, hand, t, lemon, grip, [station], [(point, lemon.angle)])
        return Action(ActionKind.HAND, hand, t1, release, verb="squeeze", targets=("lemon",))

    def pour_like(self, person: str, t: int, draft: Draft, name: str, verb: str) -> Action:
        bottle, pot = self.thing(name), self.thing("pot")
        body = self.body(person)
        hand = body.hand_towards((bottle.home + pot.home) / 2)
        direction = body.direction_to(hand, pot.home)
        tilt = float(np.radians(65 if verb == "pour" else 40)) * (1 if self.rng.random() < 0.5 else -1)
        tilted = bottle.angle + tilt
        reach = _reach_out(_half(bottle, tilted), direction)
        pot_edge = _reach_out(_half(pot), direction)
        centre = pot.home - (pot_edge + 4.0 + reach) * direction
        grip = np.zeros(2)
        hand_at = centre
        tilting = draft.span(0.4, 0.6)
        length = draft.span(1.6, 2.6) if verb == "pour" else draft.span(1.5, 2.4)

        def station(t0: int) -> int:
            t_up = t0 + tilting
            draft.hold(hand, t0, hand_at, tilting)
            draft.turns[name].append(Turn(t0, t_up, tilted))
            if verb == "pour":
                t_end = draft.work(hand, t_up, hand_at, "squeeze", direction, 0.8, 1.5, length)
            else:
                t_end = draft.work(hand, t_up, hand_at, "shake", direction, float(self.rng.uniform(3.5, 5.0)),
                                   float(self.rng.uniform(3.5, 4.5)), length)
            draft.effects.append(Effect(verb, t_up, t_end, name, "pot"))
            back = draft.hold(hand, t_end, hand_at, tilting)
            draft.turns[name].append(Turn(t_end, back, bottle.angle))
            return back

        t1, release, end, _ = self.take(draft, hand, t, bottle, grip, [station], [(hand_at, bottle.angle)])
        draft.use("pot", end)
        return Action(ActionKind.TOOL, hand, t1, release, verb=verb, held=name, targets=("pot",))

    def pour(self, person: str, t: int, draft: Draft) -> Action:
        return self.pour_like(person, t, draft, "oil", "pour")

    def sprinkle(self, person: str, t: int, draft: Draft) -> Action:
        return self.pour_like(person, t, draft, "salt", "sprinkle")

    def _into_pot(self, draft: Draft, content: Thing, start: int, seconds: float, refill: Callable[[], np.ndarray]
                  ) -> int:
        """``content`` slides into the pot from ``start``, lies there a moment, is stirred in (vanishes) and
        comes back in its container a few seconds later (a refill). Returns when the pot is clear again."""
        pot = self.thing("pot")
        drop = pot.home + self.rng.uniform(-8, 8, 2)
        glide_end = start + draft.frames(seconds)
        draft.moves[content.name].append(Glide(start, glide_end, point(drop)))
        gone = glide_end + draft.span(1.1, 1.5)
        draft.moves[content.name].append(Appear(gone, False))
        back = gone + draft.span(2.0, 3.5)
        draft.moves[content.name].append(Appear(back, True, point(refill())))
        draft.use(content.name, back + draft.frames(0.5))
        draft.use("pot", gone + draft.frames(0.3))
        return gone

    def transfer_tool(self, person: str, t: int, draft: Draft) -> Action:
        spoon, pot = self.thing("spoon"), self.thing("pot")
        source_name, content_name = self.layout.groups["spoon"][1:]
        source, content = self.thing(source_name), self.thing(content_name)
        body = self.body(person)
        hand = body.hand_towards((source.home + pot.home) / 2)
        grip = np.array([spoon.kind.grip, 0.0])
        tip = 20.0
        d1 = body.direction_to(hand, content.home)
        at_source = content.home - (tip - spoon.kind.grip) * d1
        d2 = body.direction_to(hand, pot.home)
        drop_at = pot.home - (tip - spoon.kind.grip + 10.0) * d2
        scoop_len = draft.span(0.7, 1.0)
        tip_len = draft.span(0.5, 0.8)
        riding_from: list[int] = []

        def scoop(t0: int) -> int:
            end = draft.work(hand, t0, at_source, "scoop", d1, 6.0, 1.0 / (scoop_len / self.fps), scoop_len)
            riding_from.append(end)
            return end

        def tip_out(t0: int) -> int:
            end = draft.work(hand, t0, drop_at, "scoop", d2, 4.0, 1.0 / (tip_len / self.fps), tip_len)
            riding_from.append(t0 + tip_len // 3)
            return end

        t1, release, end, _ = self.take(draft, hand, t, spoon, grip, [scoop, tip_out],
                                        [(at_source, _angle(d1)), (drop_at, _angle(d2))])
        on_spoon, off_spoon = riding_from
        draft.moves[content.name].append(Ride(on_spoon, off_spoon, hand, "spoon", (tip - spoon.kind.grip, 0.0)))
        home = source.home + rotation(source.angle) @ content.offset
        self._into_pot(draft, content, off_spoon, 0.3, lambda: home)
        draft.use(source.name, end)
        return Action(ActionKind.TRANSFER, hand, t1, release, verb="transfer", held="spoon",
                      targets=(content.name, source.name, pot.name))

    def transfer_tip(self, person: str, t: int, draft: Draft) -> Action:
        bowl, pot = self.thing("bowl"), self.thing("pot")
        content = self.thing(self.layout.groups["bowl"][1])
        body = self.body(person)
        hand = body.hand_towards((bowl.home + pot.home) / 2)
        grip = np.array([-28.0, 0.0])
        direction = body.direction_to(hand, pot.home)
        radius = bowl.kind.size[0] / 2
        centre = pot.home - (_reach_out(_half(pot), direction) + radius - 18.0) * direction
        angle = _angle(direction)
        hand_at = centre + rotation(angle) @ grip
        squash = draft.span(0.3, 0.45)
        length = draft.span(0.9, 1.3)
        glide_at: list[int] = []

        def tip(t0: int) -> int:
            draft.hold(hand, t0, hand_at, squash)
            draft.sizes["bowl"].append(Resize(t0, t0 + squash, (0.72, 1.0)))
            t_hold = draft.work(hand, t0 + squash, hand_at, "squeeze", direction, 1.0, 1.2, length)
            glide_at.append(t0 + squash + draft.frames(0.15))
            back = draft.hold(hand, t_hold, hand_at, squash)
            draft.sizes["bowl"].append(Resize(t_hold, back, (1.0, 1.0)))
            return back

        t1, release, _, _ = self.take(draft, hand, t, bowl, grip, [tip], [(hand_at, angle)])
        vector = np.asarray(-grip) + content.offset
        draft.moves[content.name].append(Ride(t1, glide_at[0], hand, "bowl", point(vector)))
        home = bowl.home + rotation(bowl.angle) @ content.offset
        self._into_pot(draft, content, glide_at[0], 0.5, lambda: home)
        return Action(ActionKind.TRANSFER, hand, t1, release, verb="transfer", held="bowl",
                      targets=(content.name, bowl.name, pot.name))

    def holding(self, t: int, draft: Draft, on: str) -> Action:
        """One person holds the pot (or the chopping board) while the other stirs in it (or cuts on it)."""
        actor = self.owner("spoon" if on == "pot" else "knife")
        holder = "P2" if actor == "P1" else "P1"
        held = self.thing(on)
        body = self.body(holder)
        hand = body.hand_towards(held.home)
        # the handle (or the board's end) on the side of the holding hand
        half_long = held.kind.size[1] / 2 - 6.0
        grips = [np.array([0.0, half_long]), np.array([0.0, -half_long])]
        grip = max(grips, key=lambda g: float((rotation(held.angle) @ g) @ body.outward(hand))
                   - 0.01 * float(np.hypot(*(self.grip_point(held, g) - np.asarray(body.neck)))))
        point = self.grip_point(held, grip)
        t1 = draft.move(hand, t, np.asarray(body.rests[hand]), point)
        partner_start = t1 + draft.span(-0.2, 0.3)
        if on == "pot":
            partner = self.stir(actor, partner_start, draft)
        else:
            partner = self.cut(actor, partner_start, draft)
            partner = Action(partner.kind, partner.hand, partner.start, partner.end, verb=partner.verb,
                             held=partner.held, targets=("tomato",))
        work_end = max(p.end for p in draft.phases[partner.hand] if isinstance(p, Work))
        release = max(work_end + draft.span(0.3, 0.6), t1 + draft.frames(1.0))
        draft.hold(hand, t1, point, release - t1)
        end = draft.move(hand, release, point, np.asarray(body.rests[hand]))
        draft.use(on, end)
        if on == "chopping_board":
            draft.use("tomato", end)
        return Action(ActionKind.HOLDING, hand, t1, release, held=on, partner=partner)

    def handover(self, t: int, draft: Draft, name: str) -> tuple[Action, Action]:
        thing = self.thing(name)
        giver_person = thing.owner or "P1"
        receiver_person = "P2" if giver_person == "P1" else "P1"
        giver, receiver = self.body(giver_person), self.body(receiver_person)
        meeting = self.layout.meeting
        assert meeting is not None
        towards = np.asarray(receiver.neck) - np.asarray(giver.neck)
        towards /= np.hypot(*towards)
        g_hand = giver.hand_towards((thing.home + meeting) / 2)
        r_hand = receiver.hand_towards(meeting)
        reach = float(np.hypot(*_half(thing) * towards)) * 0.35 + 4.0
        g_grip = rotation(thing.angle).T @ (-reach * towards)
        r_grip = rotation(thing.angle).T @ (reach * towards)
        # giver: reach, grasp, carry to the middle, wait for the receiver, let go, return
        start_point = self.grip_point(thing, g_grip)
        t1 = draft.move(g_hand, t, np.asarray(giver.rests[g_hand]), start_point)
        t2 = draft.hold(g_hand, t1, start_point, draft.span(0.15, 0.3))
        g_at = meeting + rotation(thing.angle) @ g_grip
        t3 = draft.move(g_hand, t2, start_point, g_at, pace=1.1)
        # receiver: arrives a moment after the giver, takes it, carries it to its side
        r_at = meeting + rotation(thing.angle) @ r_grip
        r_rest = np.asarray(receiver.rests[r_hand])
        probe = Draft(self.fps, self.rng)
        r_reach = probe.move(r_hand, 0, r_rest, r_at)
        t_grasp = t3 + draft.span(0.1, 0.3)
        r_start = max(t_grasp - r_reach, self.free[receiver_person] + draft.frames(0.2))
        t_grasp = r_start + r_reach
        draft.phases[r_hand].append(Move(r_start, t_grasp, point(r_rest), point(r_at), *_bulge(probe, r_hand)))
        g_release = max(t_grasp, t3) + draft.span(0.5, 0.85)
        draft.hold(g_hand, t3, g_at, g_release - t3)
        g_end = draft.move(g_hand, g_release, g_at, np.asarray(giver.rests[g_hand]))
        r_wait = draft.hold(r_hand, t_grasp, r_at, g_release + draft.frames(0.15) - t_grasp)
        landing = thing.homes[receiver_person]
        r_land = landing + rotation(thing.angle) @ r_grip
        t_land = draft.move(r_hand, r_wait, r_at, r_land, pace=1.1)
        r_release = draft.hold(r_hand, t_land, r_land, draft.span(0.15, 0.3))
        r_end = draft.move(r_hand, r_release, r_land, r_rest)
        draft.moves[name].append(Ride(t1, g_release, g_hand, name, point(-g_grip)))
        draft.moves[name].append(Ride(g_release, r_release, r_hand, name, point(-r_grip)))
        draft.use(name, max(g_end, r_end))
        for middle in ("pot", "chopping_board"):
            draft.use(middle, max(g_end, r_end))
        draft.end = max(draft.end, g_end, r_end)

        def done() -> None:
            thing.owner = receiver_person
            thing.home = landing

        draft.commits.append(done)
        grasp = Action(ActionKind.GRASP, r_hand, t_grasp, r_release, held=name)
        action = Action(ActionKind.HANDOVER, g_hand, t1, g_release, held=name, partner=grasp)
        carry = Action(ActionKind.GRASP, r_hand, g_release, r_release, held=name)
        return action, carry

    # ---- scheduling
    def schedule(self, kind: str, extra: str | None = None) -> bool:
        draft = Draft(self.fps, self.rng)
        middle = ("pot", "chopping_board", "tomato")
        if kind == "holding":
            assert extra is not None
            busy = (extra, "spoon" if extra == "pot" else "knife", *middle)
            t = self.start_after(("P1", "P2"), busy)
            draft.actions.append(self.holding(t, draft, extra))
            return self.commit(draft, ("P1", "P2"), kind)
        if kind == "handover":
            assert extra is not None
            t = self.start_after((self.thing(extra).owner or "P1",), (extra, *middle))
            t = max(t, self.free["P2" if self.thing(extra).owner == "P1" else "P1"] - draft.frames(1.0))
            action, carry = self.handover(t, draft, extra)
            draft.actions.extend([action, carry])
            return self.commit(draft, ("P1", "P2"), kind)
        group, objects = _TASK_OBJECTS[kind]
        names = tuple(self._resolve(o) for o in objects)
        person = self.owner(group)
        t = self.start_after((person,), names)
        action = getattr(self, kind)(person, t, draft)
        draft.actions.append(action)
        return self.commit(draft, (person,), kind)

    def _resolve(self, name: str) -> str:
        if name == "@source":
            return self.layout.groups["spoon"][1]
        if name == "@scooped":
            return self.layout.groups["spoon"][2]
        if name == "@tipped":
            return self.layout.groups["bowl"][1]
        return name


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


def _bulge(draft: Draft, hand: str) -> tuple[float, float]:
    move = draft.phases[hand][-1]
    assert isinstance(move, Move)
    return move.bulge, move.skew


def write_script(seed_rng: np.random.Generator, persons: int, fps: float, limit: int | None) -> Script:
    """Lay out the table and schedule cycles of tasks (one cycle without ``limit``; with a frame limit,
    cycles until no further task fits)."""
    layout = make_layout(persons, seed_rng)
    writer = _Writer(layout, fps, seed_rng, limit)
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
            ready = np.array([writer.ready_for(kind, extra) for kind, extra in left], dtype=float)
            ready += seed_rng.uniform(0, 1.5 * fps, len(left))
            ready[[kind == last for kind, _ in left]] += 3 * fps
            kind, extra = left.pop(int(np.argmin(ready)))
            placed += writer.schedule(kind, extra)
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
