"""Action recognition per segment (paper, "Action Recognition"): individual, transfer, collaborative.

- Individual: a held tool acts on the ingredient it comes near (in its container) or else on a container; a
  held ingredient acts on a container (pour oil into the pot) or, held still with nothing near and when the
  commonsense model says hands work it (``Params.hand_share``), is worked by the hand itself (squeeze the
  lemon). The verb is the argmax over candidate verbs of P(A) prod_k P(O_k | A)
  (:func:`wecook_core.recognize.rank`) over the held object and the targets. The candidates come from
  the evidence other than the tables: a held tool is the instrument, and only the verbs it affords by
  itself are candidates (:func:`afforded`: a peeler peels, even on a board that says "cut"); the held
  object's own motion narrows them further (:mod:`.motion`: circles stir, a tipped bottle pours, an
  ingredient stroked by the hand is peeled and one gripped in place squeezed). A held object lying where
  its hold begins or ends acts on nothing it lies beside (:mod:`.resting`: bread picked up next to a cup
  is not dipped in it).
- Transfer: an ingredient whose container changes (tracked over the whole video) while a hand, or the object
  it holds, moves it: targets ``(ingredient, source, destination)``.
- Collaborative: a handover when an object passes from one person's hand to the other's (before the
  exchange, in the same hold, the giver only grasps it: a pause with it is not hand work); a holding when
  one person holds an object that the other acts on (or holds too).

A hand that holds something without acting is a GRASP: no action, but it tells the graph when the action's
grasp starts and its release ends.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from wecook_core.model import (
    HANDS,
    Action,
    ActionKind,
    Associations,
    Category,
    Corrections,
    Observations,
    Ranking,
    Segment,
    SegmentActions,
    Segmentation,
    person_of,
)
from wecook_core.perception.association.associate import Timeline, associate_segments, dwelling_points
from wecook_core.perception.geometry import video_diagonal
from wecook_core.perception.label_runs import longest_runs, runs
from wecook_core.perception.params import Params
from wecook_core.perception.recognition.motion import Role
from wecook_core.perception.recognition.resting import SpanCache, acting_links
from wecook_core.perception.recognition.transfers import (
    HandoverEvent,
    TransferEvent,
    handover_events,
    hold_spans,
    transfer_events,
)

if TYPE_CHECKING:
    from wecook_core.knowledge.recognize import Knowledge
    from wecook_core.perception.params import FrameParams

HAND_VERBS: tuple[str, ...] = ("squeeze", "peel", "roll", "wrap")
"""Verbs a bare hand performs on the ingredient it holds."""
STILL_HAND_VERBS: tuple[str, ...] = ("squeeze", "peel", "wrap")
"""The candidates of a HAND action: a hand works an ingredient by itself only while it stays put
(:func:`hand_still`), and rolling moves the hand back and forth."""
TOOL_VERBS: tuple[str, ...] = ("cut", "peel", "stir", "roll", "spread")
"""The candidates of a held tool acting on an ingredient or a container (DESIGN.md's "tool" case): a tool
works what it touches; pouring, sprinkling and dipping are done with the held ingredient itself, and
squeezing and wrapping with the bare hand."""
HELD_VERBS: tuple[str, ...] = ("pour", "sprinkle", "dip")
"""The candidates of a held ingredient acting on a container (DESIGN.md's "held" case): without a tool
it cannot cut, peel or stir."""
SHEET_VERBS: tuple[str, ...] = ("wrap",)
"""What a sheet does (foil, cling film, parchment): it is held and laid over what it covers, like a tool, but
only wraps; no other tool wraps."""
SHEET_SHARE = 0.5
"""A held tool is a sheet (:data:`SHEET_VERBS` are its candidates) when wrapping takes at least this share of
what the commonsense model says it does among the tool and sheet verbs: a thing with one use, wrapping, is a
wrapping material; a whisk or a brush the tables also tie to "wrap" now and then is not."""
AFFORD_RATIO = 5.0
"""A held tool affords the tool verbs the commonsense model gives it, alone, at least ``1 / AFFORD_RATIO`` of
the probability of its main one (:func:`afforded`): a knife cuts, and may spread or peel; a peeler peels and
nothing else, however much the board under the cucumber says "cut"."""


# ------------------------------------------------------------------------------------------ individual


def _candidates(knowledge: Knowledge, allowed: Sequence[str] | None = None) -> list[str]:
    verbs = [v for v in knowledge.verbs if v != "transfer"]
    if allowed is not None:
        verbs = [v for v in verbs if v in allowed] or verbs
    return verbs


RANKINGS_KEPT = 4096
"""Most rankings one :class:`Ranker` keeps (a long video asks ever new object lists)."""


class Ranker:
    """The commonsense rankings of one analysis, each computed once: a video asks the same few dozen (objects,
    allowed verbs) over and over. Made per :func:`recognize_actions` call and dropped with it (no state outlives
    the stage)."""

    def __init__(self, knowledge: Knowledge) -> None:
        self.knowledge = knowledge
        self._known: dict[tuple[tuple[str, ...], tuple[str, ...] | None], Ranking] = {}

    def rank(self, objects: Sequence[str], allowed: Sequence[str] | None = None) -> Ranking:
        from wecook_core.knowledge.recognize import rank

        key = (tuple(objects), None if allowed is None else tuple(allowed))
        ranking = self._known.get(key)
        if ranking is None:
            if len(self._known) >= RANKINGS_KEPT:
                self._known.clear()
            ranking = self._known[key] = rank(self.knowledge, list(objects), _candidates(self.knowledge, allowed))
        return ranking


def _ranker(knowledge: Knowledge | Ranker) -> Ranker:
    return knowledge if isinstance(knowledge, Ranker) else Ranker(knowledge)


def _with_container(name: str, assoc: Associations) -> tuple[str, ...]:
    container = assoc.containment.get(name)
    return (name, container) if container is not None else (name,)


def individual_action(
    hand: str,
    assoc: Associations,
    categories: Mapping[str, Category],
    knowledge: Knowledge | Ranker,
    *,
    still: bool | Callable[[bool], bool] = True,
    verb: str | None = None,
    hand_share: float = Params.hand_share,
    moves: Callable[[str, Role], frozenset[str] | None] | None = None,
) -> tuple[Action | None, Ranking]:
    """The action of one hand in one segment from its associations (no transfer, no collaboration).

    ``still``: the hand hardly moves during the segment (a held ingredient is worked, not carried); a
    callable is asked only when it matters, with ``True`` when the hand must stay put for a whole
    ``Params.min_action_s`` (an ingredient worked by hand whatever the commonsense share of the hand verbs),
    ``False`` for ``Params.min_link_s`` (enough when the hand verbs get ``hand_share``).
    ``verb``: the user's choice, replacing the recognised verb. ``hand_share``: see ``Params.hand_share``.
    ``moves``: (object name, its :data:`~.motion.Role`: a held tool, an ingredient held over a container,
    an ingredient worked by the hand) -> the verbs its own motion in the segment allows (:mod:`.motion`;
    None: no say);
    the candidates are narrowed to those when any is left. A held ingredient over a container is poured,
    sprinkled or dipped (:data:`HELD_VERBS`), a held tool cuts, peels, stirs, rolls or spreads
    (:data:`TOOL_VERBS`); a hand that works an ingredient by itself while staying put
    squeezes, peels or wraps it (:data:`STILL_HAND_VERBS`)."""
    segment = assoc.segment
    held = assoc.hand_object.get(hand)
    if held is None:
        return None, ()
    ranker = _ranker(knowledge)
    category = categories.get(held, Category.INGREDIENT)
    links = assoc.object_object.get(held, ())
    ingredients = [o for o in links if categories.get(o, Category.INGREDIENT) is Category.INGREDIENT]
    containers = [o for o in links if categories.get(o) is Category.CONTAINER]
    grasp = Action(ActionKind.GRASP, hand, segment.start, segment.end, held=held)
    targets: tuple[str, ...] = ()
    kind = ActionKind.TOOL
    allowed: Sequence[str] | None = None
    if category is Category.TOOL:
        allowed = afforded(ranker, held)
        if ingredients:
            targets = _with_container(ingredients[0], assoc)
        elif containers:
            targets = (containers[0],)
    elif category is Category.INGREDIENT:
        if containers:  # poured, sprinkled, dipped into a container
            targets, allowed = (containers[0],), HELD_VERBS
        elif ingredients:
            pass  # an ingredient held beside another is not acting on it
        elif _worked_by_hand(ranker, held, hand_share, still):
            kind, targets, allowed = ActionKind.HAND, (held,), STILL_HAND_VERBS
    if not targets:
        if verb is None:
            return grasp, ()
        # the user named a verb for a hand that only holds: the hand works the object it holds
        return Action(ActionKind.HAND, hand, segment.start, segment.end, verb=verb, targets=(held,)), ()
    objects = targets if kind is ActionKind.HAND else (held, *targets)
    poured = allowed is HELD_VERBS
    moved = None
    if moves is not None:
        moved = moves(held, "hand" if kind is ActionKind.HAND else "held" if poured else "tool")
    if moved is not None:
        narrowed = [v for v in (allowed if allowed is not None else ranker.knowledge.verbs) if v in moved]
        allowed = narrowed or allowed
    # a held ingredient is ranked by itself: it decides whether it is poured, sprinkled or dipped, and any
    # container receives all three (rule C3a)
    ranking = ranker.rank((held,) if poured else objects, allowed)
    chosen = verb or (ranking[0][0] if ranking else None)
    if chosen is None:
        return grasp, ranking
    if kind is ActionKind.HAND:
        return Action(kind, hand, segment.start, segment.end, verb=chosen, targets=targets, scores=ranking), ranking
    return Action(kind, hand, segment.start, segment.end, verb=chosen, held=held, targets=targets,
                  scores=ranking), ranking


def afforded(knowledge: Knowledge | Ranker, tool: str) -> tuple[str, ...]:
    """The verbs of :data:`TOOL_VERBS` that ``tool`` itself affords: P(A | tool) at least ``1 / AFFORD_RATIO``
    of its best. The tool in the hand is the instrument: it decides the verb, and what it works on (the
    ingredient, the board or pot under it) only chooses among the verbs it affords. An object the model
    does not know affords them all (its ranking is flat). A sheet (:data:`SHEET_SHARE`: foil, film) wraps."""
    ranker = _ranker(knowledge)
    sheet = dict(ranker.rank([tool], (*TOOL_VERBS, *SHEET_VERBS)))
    if sum(sheet.get(verb, 0.0) for verb in SHEET_VERBS) >= SHEET_SHARE * sum(sheet.values()) > 0:
        return SHEET_VERBS
    ranking = ranker.rank([tool], TOOL_VERBS)
    if not ranking:
        return TOOL_VERBS
    best = ranking[0][1]
    return tuple(verb for verb, p in ranking if p * AFFORD_RATIO >= best)


def _worked_by_hand(ranker: Ranker, held: str, hand_share: float, still: bool | Callable[[bool], bool]) -> bool:
    """A held ingredient with nothing near is worked by the hand when the hand stays put on it: briefly when
    the commonsense model says hands work it, for ``min_action_s`` whatever it says (an egg held still for
    seconds is being peeled, not carried)."""
    if not callable(still):
        return still and _hand_share(ranker, held) >= hand_share
    if _hand_share(ranker, held) >= hand_share:
        return still(False)
    return still(True)


def _hand_share(ranker: Ranker, ingredient: str) -> float:
    """How much of P(A | ingredient) the verbs of a bare hand take (lemon: squeeze; oil: hardly any)."""
    return sum(p for verb, p in ranker.rank([ingredient]) if verb in HAND_VERBS)


def hand_still(obs: Observations, hand: str, segment: Segment, params: Params, diagonal: float,
               long: bool = False, *, rate: FrameParams | None = None) -> bool:
    """The hand stays put (:func:`~wecook_core.associate.dwelling` within ``still_fraction`` of the image
    diagonal) for ``min_link_s`` (``long``: ``min_action_s``) without a break in the segment: it works what it
    holds, it does not just grasp it on the way somewhere."""
    track = obs.hand(hand)
    if track is None:
        return False
    rate = rate or params.at(obs.video.fps)
    window = rate.dwell_frames
    lo, hi = segment.start - window, segment.end + window
    a, b = np.searchsorted(track.frames, [lo, hi])
    xy = np.full((hi - lo, 2), np.nan)
    xy[track.frames[a:b] - lo] = track.xy[a:b]
    still = dwelling_points(xy, window, params.still_fraction * diagonal)[window : window + len(segment)]
    needed = rate.min_action_frames if long else min(rate.min_frames, len(segment))
    return bool(longest_runs(still[:, None])[0] >= needed)


def _moves(obs: Observations, segment: Segment, timeline: Timeline | None,
           hold_runs: Mapping[str, list[tuple[int, int, int]]],
           cache: dict[tuple[str, int, int, Role], frozenset[str] | None], hand: str, name: str,
           role: Role = "tool") -> frozenset[str] | None:
    """The verbs object ``name``'s own motion allows (:func:`.motion.verbs_of`), read over the whole hold
    of it by ``hand`` that ``segment`` lies in (grasp to release: the run of ``hold_runs[hand]``, the runs
    of the timeline's held labels; the segment alone when unknown): an actuation pattern is the hold's, and
    the pauses at its ends, cut into segments of their own, show none. ``cache``: answers already found
    for this video (a hold spans many segments)."""
    import bisect

    from wecook_core.perception.recognition.motion import motion_of, verbs_of

    try:
        track = obs.object(name)
    except KeyError:
        return None
    start, end = segment.start, segment.end
    lane = hold_runs.get(hand)
    if timeline is not None and lane and name in timeline.names:
        column = timeline.column(name)
        i = bisect.bisect_right([r[0] for r in lane], segment.start) - 1
        for run_start, run_end, value in lane[max(i, 0):]:
            if run_start >= segment.end:
                break
            if value == column and run_end > segment.start:
                start, end = min(start, run_start), max(end, run_end)
                break
    key = (name, start, end, role)
    if key not in cache:
        lo, hi = np.searchsorted(track.frames, [start, end])
        cache[key] = verbs_of(motion_of(track.boxes[lo:hi], obs.video.fps), role)
    return cache[key]


# ------------------------------------------------------------------------------------------- segments


def _without(targets: tuple[str, ...], obj: str) -> tuple[str, ...]:
    rest = tuple(t for t in targets if t != obj)
    return rest or targets


def _holding(
    acts: dict[str, Action],
    assoc: Associations,
    categories: Mapping[str, Category],
    partners: set[str],
) -> None:
    """Rewrite ``acts`` (hand -> action) for the holdings of a segment, in place."""
    holders = {hand: obj for hand, obj in assoc.hand_object.items()}
    for actor, action in sorted(acts.items(), key=lambda item: HANDS.index(item[0])):
        if actor in partners or action.kind not in (ActionKind.TOOL, ActionKind.HAND):
            continue
        reached = set(action.targets)
        reached |= {assoc.containment[t] for t in action.targets if t in assoc.containment}
        for holder, obj in holders.items():
            if person_of(holder) == person_of(actor) or holder in partners or obj not in reached:
                continue
            if obj == action.held or categories.get(obj) is Category.TOOL:
                continue
            partner = replace(action, targets=_without(action.targets, obj))
            acts[holder] = Action(ActionKind.HOLDING, holder, action.start, action.end, held=obj, partner=partner)
            partners.add(actor)
            break


def _at_exchange(handover: HandoverEvent, segment: Segment, acts: Mapping[str, Action], gap: int) -> bool:
    """The segment tells the handover: it overlaps the exchange and the giver acts in it, or the giver still
    holds the object in it and it ends at most ``gap`` frames (``handover_gap_s``) before the exchange begins
    (the segmentation cut the giver's hold a few frames before it ended, and the segment with the exchange
    has the giver's hold on too few frames to count)."""
    if handover.giver not in acts or not segment.start < handover.end:
        return False
    if handover.start < segment.end:
        return True
    return acts[handover.giver].held == handover.obj and handover.start < segment.end + gap


def _before_handover(acts: dict[str, Action], handover: HandoverEvent, segment: Segment) -> None:
    """In the hold that ends by passing the object on, before the exchange, the giver holds it to give it:
    a bare hand seemingly working it (a pause after the grasp, held still) is only its grasp, so the
    handover's tree starts at the giver's grasp. A tool the giver uses on something else is still an
    action."""
    if not (handover.grasped < segment.end and segment.start < handover.start):
        return
    action = acts.get(handover.giver)
    if action is not None and action.kind is ActionKind.HAND and action.targets == (handover.obj,):
        acts[handover.giver] = Action(ActionKind.GRASP, handover.giver, segment.start, segment.end, held=handover.obj)


def _same_object_holding(acts: dict[str, Action], assoc: Associations, timeline: Timeline, rate: FrameParams,
                         partners: set[str]) -> None:
    """Both persons' hands on one object without a handover: the one who grasped it first holds it."""
    segment = assoc.segment
    by_object: dict[str, list[str]] = {}
    for hand, obj in assoc.hand_object.items():
        by_object.setdefault(obj, []).append(hand)
    for obj, hands in by_object.items():
        persons = {person_of(h) for h in hands}
        if len(persons) < 2 or any(h in partners or acts.get(h) is None for h in hands):
            continue
        if any(acts[h].kind in (ActionKind.HANDOVER, ActionKind.HOLDING) for h in hands):
            continue
        column = timeline.column(obj)

        def grasped(hand: str, column: int = column) -> int:
            labels = timeline.held[: segment.end, HANDS.index(hand)]
            spans = hold_spans(labels, column, rate.min_frames)
            return spans[-1][0] if spans else segment.start

        ordered = sorted(hands, key=lambda h: (grasped(h), HANDS.index(h)))
        holder = ordered[0]
        actor = next(h for h in ordered if person_of(h) != person_of(holder))
        partner_action = acts[actor]
        acts[holder] = Action(ActionKind.HOLDING, holder, segment.start, segment.end, held=obj,
                              partner=partner_action)
        partners.add(actor)


def recognize_actions(
    obs: Observations,
    segmentation: Segmentation,
    associations: Sequence[Associations],
    knowledge: Knowledge,
    params: Params,
    corrections: Corrections | None = None,
    timeline: Timeline | None = None,
    *,
    rate: FrameParams | None = None,
) -> tuple[SegmentActions, ...]:
    """Each segment's actions, from its associations and the whole video's per-frame links (``timeline``,
    recomputed from ``segmentation`` when not given). ``corrections.verbs`` replace recognised verbs."""
    rate = rate or params.at(obs.video.fps)
    if timeline is None:
        _, timeline = associate_segments(obs, segmentation.segments, params, corrections, rate=rate)
    corrections = corrections or Corrections()
    categories = obs.categories
    diagonal = video_diagonal(obs)
    transfers = transfer_events(obs, timeline, params, rate)
    handovers = handover_events(timeline, params, rate)
    hold_runs = {hand: runs(timeline.held[:, column]) for column, hand in enumerate(HANDS)}
    ranker = Ranker(knowledge)
    motion_cache: dict[tuple[str, int, int, Role], frozenset[str] | None] = {}
    result = []
    spans: SpanCache = {}
    min_frames = rate.min_frames
    for assoc in associations:
        assoc = acting_links(assoc, obs, timeline, min_frames, spans)
        segment = assoc.segment
        acts: dict[str, Action] = {}
        rankings: dict[str, Ranking] = {}
        partners: set[str] = set()
        for hand in HANDS:
            verb = corrections.verbs.get((segment.start, hand))
            still = partial(hand_still, obs, hand, segment, params, diagonal, rate=rate)
            action, ranking = individual_action(hand, assoc, categories, ranker, still=still, verb=verb,
                                                hand_share=params.hand_share,
                                                moves=partial(_moves, obs, segment, timeline, hold_runs, motion_cache,
                                                              hand))
            if action is not None:
                acts[hand] = action
            if ranking:
                rankings[hand] = ranking
        for event in transfers:
            if event.start < segment.end and segment.start < event.end and event.hand in acts:
                current = acts[event.hand]
                if event.carrier is not None and current.held != event.carrier:
                    continue
                acts[event.hand] = Action(
                    ActionKind.TRANSFER, event.hand, segment.start, segment.end, verb="transfer",
                    held=event.carrier, targets=(event.ingredient, event.source, event.destination),
                )
        for handover in handovers:
            _before_handover(acts, handover, segment)
            if _at_exchange(handover, segment, acts, rate.handover_gap):
                receiver = Action(ActionKind.GRASP, handover.receiver, segment.start, segment.end, held=handover.obj)
                acts[handover.giver] = Action(ActionKind.HANDOVER, handover.giver, segment.start, segment.end,
                                              held=handover.obj, partner=receiver)
                partners.add(handover.receiver)
        _holding(acts, assoc, categories, partners)
        _same_object_holding(acts, assoc, timeline, rate, partners)
        ordered = tuple(acts[h] for h in HANDS if h in acts and h not in partners)
        result.append(SegmentActions(segment, ordered, rankings, tuple(h for h in HANDS if h in partners)))
    return tuple(result)


__all__ = [
    "HAND_VERBS",
    "TOOL_VERBS",
    "HandoverEvent",
    "Ranking",
    "SegmentActions",
    "TransferEvent",
    "hand_still",
    "handover_events",
    "hold_spans",
    "individual_action",
    "recognize_actions",
    "transfer_events",
]
