"""The task kinds of a synthetic script, one function each: what the hands do, what the objects do, and the true
:class:`~wecook_core.model.Action` (from the grasp that starts it to the release that ends it).

Each function takes the :class:`~wecook_core.synth.writer.Writer`, the acting person, the start frame and the
draft it writes into; :data:`INDIVIDUAL` names the one-person tasks for the scheduler.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from wecook_core.model import Action, ActionKind
from wecook_core.synth.draft import Draft, point
from wecook_core.synth.events import Appear, Effect, Glide, Resize, Ride, Turn
from wecook_core.synth.kitchen import MAX_DOUGH
from wecook_core.synth.layout import Thing
from wecook_core.synth.motion import Move, Work, rotation
from wecook_core.synth.writer import Writer, angle_of, half_extent, reach_out


def tool_on(w: Writer, draft: Draft, person: str, t: int, tool: Thing, target: np.ndarray, pattern: str,
            along: float, amplitude: tuple[float, float], frequency: tuple[float, float],
            seconds: tuple[float, float], *, drift: float = 0.0, across: bool = False,
            hand: str | None = None, grip_side: bool = False,
            during: Callable[[int, int], None] | None = None) -> tuple[str, int, int, int]:
    """A held tool worked on ``target`` (a point): its centre put ``along`` pixels before the target on
    the line from the shoulder, pointing there (``across``: lying across that line, a rolling pin)."""
    body = w.body(person)
    hand = hand or body.hand_towards((tool.home + target) / 2)
    direction = body.direction_to(hand, target)
    work_angle = angle_of(direction) + (np.pi / 2 if across else 0.0)
    grip = np.array([tool.kind.grip, 0.0])
    if grip_side:  # take the end of the pin on the side of the hand
        axis = np.array([np.cos(tool.angle), np.sin(tool.angle)])
        grip = np.array([abs(tool.kind.grip) * (1 if axis @ body.outward(hand) > 0 else -1), 0.0])
    centre = target - along * direction
    hand_at = centre + rotation(work_angle) @ grip
    length = draft.span(*seconds)
    amp, freq = w.rng.uniform(*amplitude), w.rng.uniform(*frequency)

    def station(t0: int) -> int:
        end = draft.work(hand, t0, hand_at, pattern, direction, amp, freq, length, drift)
        if during is not None:
            during(t0, end)
        return end

    t1, release, end, _ = w.take(draft, hand, t, tool, grip, [station], [(hand_at, work_angle)])
    return hand, t1, release, end

def cut(w: Writer, person: str, t: int, draft: Draft) -> Action:
    knife, tomato = w.thing("knife"), w.thing("tomato")
    drift = float(w.rng.uniform(-7, 7))
    hand, t1, release, end = tool_on(w, draft, person, t, knife, tomato.home, "saw", 10.0, (4.5, 6.0),
                                          (2.0, 2.8), (2.5, 4.5), drift=drift,
                                          during=lambda a, b: draft.marks["tomato"].append((a + b) // 2))
    for name in ("tomato", "chopping_board"):
        draft.use(name, end)
    return Action(ActionKind.TOOL, hand, t1, release, verb="cut", held="knife",
                  targets=("tomato", "chopping_board"))

def peel(w: Writer, person: str, t: int, draft: Draft) -> Action:
    peeler, potato = w.thing("peeler"), w.thing("potato")
    hand, t1, release, end = tool_on(w, draft, person, t, peeler, potato.home, "peel", 14.0, (7.0, 9.0),
                                          (1.2, 1.7), (2.5, 4.0),
                                          during=lambda a, b: draft.marks["potato"].append((a + b) // 2))
    draft.use("potato", end)
    return Action(ActionKind.TOOL, hand, t1, release, verb="peel", held="peeler", targets=("potato",))

def roll(w: Writer, person: str, t: int, draft: Draft) -> Action:
    pin, dough = w.thing("rolling_pin"), w.thing("dough")
    body = w.body(person)
    hand = body.hand_towards((pin.home + dough.home) / 2)
    # the pin's middle rides a little off the dough's centre, away from the hand holding its end
    target = dough.home + 12 * body.outward(hand)
    old = w.dough_scale
    new = (min(old[0] * 1.1, MAX_DOUGH[0] / 58), min(old[1] * 1.08, MAX_DOUGH[1] / 42))

    def grow(t0: int, t1: int) -> None:
        draft.sizes["dough"].append(Resize(t0, t1, new))

    hand, t1, release, end = tool_on(w, draft, person, t, pin, target, "roll", 0.0,
                                          (13.0, 17.0), (0.6, 0.9), (3.0, 4.5), across=True, hand=hand,
                                          grip_side=True, during=grow)
    draft.use("dough", end)

    def done() -> None:
        w.dough_scale = new

    draft.commits.append(done)
    return Action(ActionKind.TOOL, hand, t1, release, verb="roll", held="rolling_pin", targets=("dough",))

def stir(w: Writer, person: str, t: int, draft: Draft) -> Action:
    spoon, pot = w.thing("spoon"), w.thing("pot")
    hand, t1, release, end = tool_on(w, draft, person, t, spoon, pot.home, "circle", 14.0, (7.0, 10.0),
                                          (0.8, 1.2), (2.5, 4.0))
    draft.use("pot", end)
    return Action(ActionKind.TOOL, hand, t1, release, verb="stir", held="spoon", targets=("pot",))

def squeeze(w: Writer, person: str, t: int, draft: Draft) -> Action:
    lemon = w.thing("lemon")
    body = w.body(person)
    hand = body.hand_towards(lemon.home)
    direction = body.direction_to(hand, lemon.home)
    grip = rotation(lemon.angle).T @ (-3.0 * direction)
    length = draft.span(2.0, 3.2)

    def station(t0: int) -> int:
        end = draft.work(hand, t0, w.grip_point(lemon, grip), "squeeze", direction, 1.2, 2.0, length)
        draft.sizes["lemon"].append(Resize(t0, end, (0.9, 0.86), pulses=float(w.rng.uniform(1.2, 1.8))))
        return end

    point = w.grip_point(lemon, grip)
    t1, release, _, _ = w.take(draft, hand, t, lemon, grip, [station], [(point, lemon.angle)])
    return Action(ActionKind.HAND, hand, t1, release, verb="squeeze", targets=("lemon",))

def pour_like(w: Writer, person: str, t: int, draft: Draft, name: str, verb: str) -> Action:
    bottle, pot = w.thing(name), w.thing("pot")
    body = w.body(person)
    hand = body.hand_towards((bottle.home + pot.home) / 2)
    direction = body.direction_to(hand, pot.home)
    tilt = float(np.radians(65 if verb == "pour" else 40)) * (1 if w.rng.random() < 0.5 else -1)
    tilted = bottle.angle + tilt
    reach = reach_out(half_extent(bottle, tilted), direction)
    pot_edge = reach_out(half_extent(pot), direction)
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
            t_end = draft.work(hand, t_up, hand_at, "shake", direction, float(w.rng.uniform(3.5, 5.0)),
                               float(w.rng.uniform(3.5, 4.5)), length)
        draft.effects.append(Effect(verb, t_up, t_end, name, "pot"))
        back = draft.hold(hand, t_end, hand_at, tilting)
        draft.turns[name].append(Turn(t_end, back, bottle.angle))
        return back

    t1, release, end, _ = w.take(draft, hand, t, bottle, grip, [station], [(hand_at, bottle.angle)])
    draft.use("pot", end)
    return Action(ActionKind.TOOL, hand, t1, release, verb=verb, held=name, targets=("pot",))

def pour(w: Writer, person: str, t: int, draft: Draft) -> Action:
    return pour_like(w, person, t, draft, "oil", "pour")

def sprinkle(w: Writer, person: str, t: int, draft: Draft) -> Action:
    return pour_like(w, person, t, draft, "salt", "sprinkle")

def into_pot(w: Writer, draft: Draft, content: Thing, start: int, seconds: float, refill: Callable[[], np.ndarray]
              ) -> int:
    """``content`` slides into the pot from ``start``, lies there a moment, is stirred in (vanishes) and
    comes back in its container a few seconds later (a refill). Returns when the pot is clear again."""
    pot = w.thing("pot")
    drop = pot.home + w.rng.uniform(-8, 8, 2)
    glide_end = start + draft.frames(seconds)
    draft.moves[content.name].append(Glide(start, glide_end, point(drop)))
    gone = glide_end + draft.span(1.1, 1.5)
    draft.moves[content.name].append(Appear(gone, False))
    back = gone + draft.span(2.0, 3.5)
    draft.moves[content.name].append(Appear(back, True, point(refill())))
    draft.use(content.name, back + draft.frames(0.5))
    draft.use("pot", gone + draft.frames(0.3))
    return gone

def transfer_tool(w: Writer, person: str, t: int, draft: Draft) -> Action:
    spoon, pot = w.thing("spoon"), w.thing("pot")
    source_name, content_name = w.layout.groups["spoon"][1:]
    source, content = w.thing(source_name), w.thing(content_name)
    body = w.body(person)
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
        end = draft.work(hand, t0, at_source, "scoop", d1, 6.0, 1.0 / (scoop_len / w.fps), scoop_len)
        riding_from.append(end)
        return end

    def tip_out(t0: int) -> int:
        end = draft.work(hand, t0, drop_at, "scoop", d2, 4.0, 1.0 / (tip_len / w.fps), tip_len)
        riding_from.append(t0 + tip_len // 3)
        return end

    t1, release, end, _ = w.take(draft, hand, t, spoon, grip, [scoop, tip_out],
                                    [(at_source, angle_of(d1)), (drop_at, angle_of(d2))])
    on_spoon, off_spoon = riding_from
    draft.moves[content.name].append(Ride(on_spoon, off_spoon, hand, "spoon", (tip - spoon.kind.grip, 0.0)))
    home = source.home + rotation(source.angle) @ content.offset
    into_pot(w, draft, content, off_spoon, 0.3, lambda: home)
    draft.use(source.name, end)
    return Action(ActionKind.TRANSFER, hand, t1, release, verb="transfer", held="spoon",
                  targets=(content.name, source.name, pot.name))

def transfer_tip(w: Writer, person: str, t: int, draft: Draft) -> Action:
    bowl, pot = w.thing("bowl"), w.thing("pot")
    content = w.thing(w.layout.groups["bowl"][1])
    body = w.body(person)
    hand = body.hand_towards((bowl.home + pot.home) / 2)
    grip = np.array([-28.0, 0.0])
    direction = body.direction_to(hand, pot.home)
    radius = bowl.kind.size[0] / 2
    centre = pot.home - (reach_out(half_extent(pot), direction) + radius - 18.0) * direction
    angle = angle_of(direction)
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

    t1, release, _, _ = w.take(draft, hand, t, bowl, grip, [tip], [(hand_at, angle)])
    vector = np.asarray(-grip) + content.offset
    draft.moves[content.name].append(Ride(t1, glide_at[0], hand, "bowl", point(vector)))
    home = bowl.home + rotation(bowl.angle) @ content.offset
    into_pot(w, draft, content, glide_at[0], 0.5, lambda: home)
    return Action(ActionKind.TRANSFER, hand, t1, release, verb="transfer", held="bowl",
                  targets=(content.name, bowl.name, pot.name))

def holding(w: Writer, t: int, draft: Draft, on: str) -> Action:
    """One person holds the pot (or the chopping board) while the other stirs in it (or cuts on it)."""
    actor = w.owner("spoon" if on == "pot" else "knife")
    holder = "P2" if actor == "P1" else "P1"
    held = w.thing(on)
    body = w.body(holder)
    hand = body.hand_towards(held.home)
    # the handle (or the board's end) on the side of the holding hand
    half_long = held.kind.size[1] / 2 - 6.0
    grips = [np.array([0.0, half_long]), np.array([0.0, -half_long])]
    grip = max(grips, key=lambda g: float((rotation(held.angle) @ g) @ body.outward(hand))
               - 0.01 * float(np.hypot(*(w.grip_point(held, g) - np.asarray(body.neck)))))
    point = w.grip_point(held, grip)
    t1 = draft.move(hand, t, np.asarray(body.rests[hand]), point)
    partner_start = t1 + draft.span(-0.2, 0.3)
    if on == "pot":
        partner = stir(w, actor, partner_start, draft)
    else:
        partner = cut(w, actor, partner_start, draft)
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

def handover(w: Writer, t: int, draft: Draft, name: str) -> tuple[Action, Action]:
    thing = w.thing(name)
    giver_person = thing.owner or "P1"
    receiver_person = "P2" if giver_person == "P1" else "P1"
    giver, receiver = w.body(giver_person), w.body(receiver_person)
    meeting = w.layout.meeting
    assert meeting is not None
    towards = np.asarray(receiver.neck) - np.asarray(giver.neck)
    towards /= np.hypot(*towards)
    g_hand = giver.hand_towards((thing.home + meeting) / 2)
    r_hand = receiver.hand_towards(meeting)
    reach = float(np.hypot(*half_extent(thing) * towards)) * 0.35 + 4.0
    g_grip = rotation(thing.angle).T @ (-reach * towards)
    r_grip = rotation(thing.angle).T @ (reach * towards)
    # giver: reach, grasp, carry to the middle, wait for the receiver, let go, return
    start_point = w.grip_point(thing, g_grip)
    t1 = draft.move(g_hand, t, np.asarray(giver.rests[g_hand]), start_point)
    t2 = draft.hold(g_hand, t1, start_point, draft.span(0.15, 0.3))
    g_at = meeting + rotation(thing.angle) @ g_grip
    t3 = draft.move(g_hand, t2, start_point, g_at, pace=1.1)
    # receiver: arrives a moment after the giver, takes it, carries it to its side
    r_at = meeting + rotation(thing.angle) @ r_grip
    r_rest = np.asarray(receiver.rests[r_hand])
    probe = Draft(w.fps, w.rng)
    r_reach = probe.move(r_hand, 0, r_rest, r_at)
    t_grasp = t3 + draft.span(0.1, 0.3)
    r_start = max(t_grasp - r_reach, w.free[receiver_person] + draft.frames(0.2))
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


def _bulge(draft: Draft, hand: str) -> tuple[float, float]:
    move = draft.phases[hand][-1]
    assert isinstance(move, Move)
    return move.bulge, move.skew


Task = Callable[[Writer, str, int, Draft], Action]

INDIVIDUAL: dict[str, Task] = {
    "cut": cut, "peel": peel, "roll": roll, "stir": stir, "squeeze": squeeze, "pour": pour,
    "sprinkle": sprinkle, "transfer_tool": transfer_tool, "transfer_tip": transfer_tip,
}
"""One-person task kind -> the function that writes it."""
