"""What each hand holds on every frame: motion coherence of hand and box, smoothed over time by Viterbi.

Per frame, a hand may hold any object whose box overlaps its own, or nothing. Overlap alone cannot tell the
bottle in the hand from the pan under it, nor the spoon from the pot it stirs: both boxes overlap the hand.
What tells them apart is motion (the "common fate" cue of motion segmentation, and the way object-in-hand
trackers decide what is grasped): a held object moves with the hand that holds it, a container under it
stays where it is. And holding persists: a grasp lasts until a release, it does not flicker frame by frame.
So the association is a hidden Markov model per hand, decoded by Viterbi (the standard HMM smoother, as in
tracking-by-detection's data association over time):

- states: nothing, or one of the video's objects;
- emission cost of a state on a frame (lower is likelier):

  - an object whose box does not overlap the hand: impossible;
  - when the hand moves (its centre travels more than ``Params.moving_fraction`` of its box's diagonal over
    the ``Params.dwell_s`` before the frame, or over those after it): 0 for an overlapping object whose box
    moves the same way on either side (``Params.coherent_fraction``; one side suffices, since at a grasp the
    hand will carry the object and at a release it has), 1 for one that stays behind, 0.9 for nothing (a
    hand moving over static boxes carries none of them);
  - when the hand's motion says nothing (it is still, or not detected at an end of the window: on real
    footage the detector loses it for long stretches, and an interpolated position is not evidence) the
    objects' own motion may: an object no bigger than the hand whose box moves by itself while the hand
    overlaps it is carried by that hand (0), unless a hand seen moving more like it carries it, and the
    static boxes under it are not (1; nothing 0.9): the small jar shaken over the big still pan
    (:func:`_carried`);
  - when neither says anything (or the hand came from afar, or a box is not seen at both ends of the
    window): 0 for every overlapping object and 1 for nothing (a hand that stays on an object for longer
    than the switching cost is taken to hold it);
  - a tie-break of at most :data:`TIE` per frame, too small to outweigh motion: closer box centres (over
    the two boxes' sizes), smaller boxes (a hand on a knife lying on a board holds the knife; a pan's box
    covers the whole close-up), and a container before an ingredient it contains that it overlaps too (a
    hand that tips a bowl of onions holds the bowl; the onions ride in it);

- transition cost: changing state costs ``Params.hold_switch_s`` seconds of full contrary evidence
  (``hold_switch_s * fps`` cost units), so a few noisy frames never flip a grasp, while a real release and
  a new grasp, which motion supports for longer than that, do.

The decoding is exact within a block of frames (:data:`~wecook_core.perception.association.frame_links.BLOCK_FRAMES`);
the
forward costs carry over from one block to the next, so a block starts where the last one ended (the path
is only ever revised inside a block).

Consequences the rest of the pipeline relies on: the container under a held bottle, spoon or bread is never
the held object (it is the destination, found by object-object association); a hand that moves over a pan
holds nothing unless something moves with it; a hand at rest keeps holding what it held when it last moved.
"""

from __future__ import annotations

import numpy as np

from wecook_core.perception.geometry import box_diagonal
from wecook_core.perception.label_runs import NONE

TIE = 0.01
"""Most cost per frame the tie-breaks add: over ``hold_switch_s`` seconds, a hundred times less than motion."""
TIE_CLOSER, TIE_SMALLER, TIE_CONTAINER = 0.4, 0.3, 0.3
"""Shares of :data:`TIE` given to each tie-break (they sum to 1): closer box centres first (the paper's
closest object), then the smaller box, then a container before the ingredient in it. Their order matters only
where two of them disagree on one frame; the sizes are such that no two of them outweigh the third alone."""
SIZE_DECADES = 1.0
"""The smaller-box tie-break saturates at this many powers of ten between the object's and the hand's
diagonals: a box ten times the hand's (a pan filling the close-up) gets the whole of its share."""
MOVING_WITH, STAYING, NOTHING_MOVING, NOTHING_STILL = 0.0, 1.0, 0.9, 1.0
"""Emission costs (see the module docstring)."""
OUTSIDE = 10.0
"""Cost of a frame where an object does not overlap the hand, inside a bin that is decoded as one (see
:func:`held_objects`' ``step``)."""


def centres(boxes: np.ndarray) -> np.ndarray:
    return np.stack([(boxes[..., 0] + boxes[..., 2]) / 2, (boxes[..., 1] + boxes[..., 3]) / 2], axis=-1)


def motion_coherence(hands: np.ndarray, objects: np.ndarray, overlap: np.ndarray, window: int,
                     moving_fraction: float, coherent_fraction: float, shot: np.ndarray | None = None,
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(moving (frames, hands), together, informative (frames, hands, objects))``, each judged over the
    ``window`` frames before a frame and over the ``window`` frames after it: where the hand moves on either
    side, where an object's box moves along with it on a side where the hand moves, and where that side says
    anything (the hand moves, and overlaps the object at both ends: a hand coming to an object from afar
    says nothing about holding it; both ends in the same shot, ``shot`` giving each frame's: a cut is not
    motion). One side suffices: at a grasp the hand has
    not carried the object yet but will, at a release it has but will not."""
    length = hands.shape[0]
    index = np.arange(length)
    hand_centres, object_centres = centres(hands), centres(objects)
    with np.errstate(invalid="ignore"):
        hand_size = box_diagonal(hands)
    moving = np.zeros(hands.shape[:2], dtype=bool)
    together = np.zeros((*hands.shape[:2], objects.shape[1]), dtype=bool)
    informative = together.copy()
    # only the (frame, hand, object) entries where the boxes overlap can say anything: the distances are read
    # there alone (a few percent of them), as sqrt(x * x + y * y) on the two components, np.linalg.norm's own
    # arithmetic, bit for bit
    rows, hand, column = np.nonzero(overlap)
    for a, b in ((np.maximum(index - window, 0), index), (index, np.minimum(index + window, length - 1))):
        hand_step = hand_centres[b] - hand_centres[a]
        object_step = object_centres[b] - object_centres[a]
        hx, hy = hand_step[..., 0], hand_step[..., 1]
        with np.errstate(invalid="ignore"):
            hand_move = np.sqrt(hx * hx + hy * hy)
            side_moving = hand_move > moving_fraction * hand_size
            dx = object_step[rows, column, 0] - hx[rows, hand]
            dy = object_step[rows, column, 1] - hy[rows, hand]
            apart = np.sqrt(dx * dx + dy * dy)
            moves = side_moving[rows, hand]
            said_here = moves & np.isfinite(apart) & overlap[a[rows] if b is index else b[rows], hand, column]
            if shot is not None:
                said_here &= shot[a[rows]] == shot[b[rows]]
            with_it = said_here & moves & (apart < coherent_fraction * hand_move[rows, hand])
        side_together = np.zeros(overlap.shape, dtype=bool)
        side_together[rows, hand, column] = with_it
        side_informative = np.zeros(overlap.shape, dtype=bool)
        side_informative[rows, hand, column] = said_here
        moving |= side_moving
        together |= side_together
        informative |= side_informative
        # where the hand's own motion says nothing on this side (it is not detected at an end, or its big box
        # barely moves while it shakes a small jar), the objects' own motion may (:func:`_carried`)
        carried, said = _carried(hand_step, object_centres, objects, overlap, a, b, moving_fraction,
                                 np.asarray(side_together.any(axis=1)), hand_size, shot)
        said &= ~side_informative
        together |= carried & said
        informative |= said
    return moving, together, informative


def _carried(hand_step: np.ndarray, object_centres: np.ndarray, objects: np.ndarray, overlap: np.ndarray,
             a: np.ndarray, b: np.ndarray, moving_fraction: float, claimed: np.ndarray, hand_size: np.ndarray,
             shot: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """``(carried, said)``, both ``(frames, hands, objects)``, from the objects' own boxes between frames ``a``
    and ``b`` (``hand_step``: each hand's displacement there, NaN where it is not seen at both ends).

    An object *moves* when its centre travels more than ``moving_fraction`` of its own diagonal (both ends
    seen, in one shot) and no moving hand carries it along already (``claimed``, ``(frames, objects)``).
    Something moves it: of the hands seen at both ends that overlap a moving object, the one whose
    displacement is closest to the object's carries it (common fate: the hand shaking the jar, whose big box
    pivots at the wrist and moves less than the jar), and the others say they do not (a still hand on the pan
    while the other carries the jar across it); a hand not seen at an end carries it unless a seen hand does.
    Only an object no bigger than the hand (``hand_size``, diagonals) is carried this way: what moves under
    a still hand and is bigger than it, such as the contents poured out of a bowl, is not.
    A hand that carries an object says, for each other object it overlaps that is seen at both ends, that
    it does not move along (the still pan under the jar)."""
    shape = (*hand_step.shape[:2], objects.shape[1])
    with np.errstate(invalid="ignore"):
        object_step = object_centres[b] - object_centres[a]
        ox, oy = object_step[..., 0], object_step[..., 1]
        travel = np.sqrt(ox * ox + oy * oy)  # np.linalg.norm's arithmetic, bit for bit
        size = box_diagonal(objects)
        seen = np.isfinite(travel)
        if shot is not None:
            seen &= (shot[a] == shot[b])[:, None]
        moving = seen & (travel > moving_fraction * size) & ~claimed
        if not moving.any():  # nothing moves by itself: nothing carried, nothing said
            return np.zeros(shape, dtype=bool), np.zeros(shape, dtype=bool)
        # only the entries where a moving object overlaps a hand are read (often a few frames)
        rows, hand, column = np.nonzero(overlap & moving[:, None, :])
        hand_seen = np.isfinite(hand_step).all(axis=-1)[rows, hand]
        dx = ox[rows, column] - hand_step[rows, hand, 0]
        dy = oy[rows, column] - hand_step[rows, hand, 1]
        judged = np.where(hand_seen, np.sqrt(dx * dx + dy * dy), np.inf)
        closest = np.full(moving.shape, np.inf)  # per frame and object, over the hands
        np.minimum.at(closest, (rows, column), judged)
        follows = np.isfinite(judged) & (judged == closest[rows, column])
        refuses = hand_seen & ~follows
        followed = np.zeros(moving.shape, dtype=bool)
        followed[rows[follows], column[follows]] = True
        unread = ~hand_seen & ~followed[rows, column]
        small = size[rows, column] <= hand_size[rows, hand]
    carries = (follows | unread) & small
    carried = np.zeros(shape, dtype=bool)
    carried[rows, hand, column] = carries
    carrying = np.zeros(shape[:2], dtype=bool)
    carrying[rows[carries], hand[carries]] = True
    said = carrying[:, :, None] & overlap & seen[:, None, :]
    said[rows[refuses], hand[refuses], column[refuses]] = True
    return carried, said


def emission_costs(
    hands: np.ndarray,
    objects: np.ndarray,
    overlap: np.ndarray,
    contained: np.ndarray,
    window: int,
    moving_fraction: float,
    coherent_fraction: float,
    shot: np.ndarray | None = None,
    reach_only: np.ndarray | None = None,
) -> np.ndarray:
    """float64 ``(frames, hands, 1 + objects)``: state 0 is "nothing", state ``1 + k`` object column ``k``;
    ``inf`` where impossible. ``overlap``: bool ``(frames, hands, objects)``; ``contained``: bool, the same
    shape: the object is an ingredient whose container the hand overlaps too. ``reach_only``: bool, the same
    shape: the boxes do not overlap but the object is a tool within reach of the hand; there it may be held
    only where it moves with the hand (common fate), never by default."""
    length, n_hands = hands.shape[:2]
    n_objects = objects.shape[1]
    moving, together, informative = motion_coherence(hands, objects, overlap, window, moving_fraction,
                                                     coherent_fraction, shot)
    # the object states are possible only where the boxes overlap (a few percent of the entries): their
    # costs are computed there alone
    rows, hand, column = np.nonzero(overlap)
    object_cost = np.where(informative[rows, hand, column],
                           np.where(together[rows, hand, column], MOVING_WITH, STAYING), MOVING_WITH)
    if reach_only is not None:
        # the hand's own motion must carry the tool: a still hand beside a tool that some unseen hand moves
        # does not hold it (what the objects' motion alone says, :func:`_carried`, is for what the hand touches)
        moved_with = informative[rows, hand, column] & together[rows, hand, column] & moving[rows, hand]
        object_cost = np.where(reach_only[rows, hand, column] & ~moved_with, np.inf, object_cost)
    # tie-breaks: closer centres, smaller boxes, a container before the ingredient it holds
    own, other = hands[rows, hand], objects[rows, column]
    with np.errstate(invalid="ignore", divide="ignore"):
        hand_size = box_diagonal(own)
        object_size = box_diagonal(other)
        dx = (own[:, 0] + own[:, 2]) / 2 - (other[:, 0] + other[:, 2]) / 2
        dy = (own[:, 1] + own[:, 3]) / 2 - (other[:, 1] + other[:, 3]) / 2
        distance = np.sqrt(dx * dx + dy * dy)  # np.linalg.norm of the centres' difference, bit for bit
        closeness = np.clip(np.nan_to_num(distance / (hand_size + object_size), nan=1.0), 0.0, 1.0)
        bigness = np.clip(np.nan_to_num(np.log(object_size / hand_size) / np.log(10.0 ** SIZE_DECADES), nan=1.0),
                          0.0, 1.0)
    object_cost = object_cost + TIE * (TIE_CLOSER * closeness + TIE_SMALLER * bigness
                                       + TIE_CONTAINER * contained[rows, hand, column])
    costs = np.full((length, n_hands, 1 + n_objects), np.inf)
    costs[rows, hand, 1 + column] = object_cost
    anything = overlap.any(axis=2)
    said = informative.any(axis=2)
    costs[:, :, 0] = np.where(anything, np.where(said, NOTHING_MOVING, NOTHING_STILL), 0.0)
    return costs


def viterbi(costs: np.ndarray, switch: float, start: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Cheapest state path per hand through ``costs`` ``(frames, hands, states)`` when a change of state
    costs ``switch``. ``start``: forward costs ``(hands, states)`` at the frame before the first (None: any
    state is free). Returns ``(path (frames, hands) int, forward costs at the last frame)``."""
    length, n_hands, n_states = costs.shape
    path = np.zeros((length, n_hands), dtype=np.int32)
    if length == 0:
        return path, start if start is not None else np.zeros((n_hands, n_states))
    total = np.zeros((n_hands, n_states)) if start is None else start - start.min(axis=1, keepdims=True)
    # forward pass, in place: only the costs, each frame's kept; the back pointers (stay, or switch from the
    # best) are then read from them all at once
    totals = np.empty((length, n_hands, n_states))
    smallest, cheaper, add, subtract = np.minimum.reduce, np.minimum, np.add, np.subtract
    low = np.empty((n_hands, 1))
    for t in range(length):
        totals[t] = total
        smallest(total, axis=1, keepdims=True, out=low)
        low += switch
        cheaper(total, low, out=total)
        add(total, costs[t], out=total)
        smallest(total, axis=1, keepdims=True, out=low)
        subtract(total, low, out=total)  # keeps the numbers small; inf stays inf
    best = np.argmin(totals, axis=2)
    stay = totals <= (np.take_along_axis(totals, best[:, :, None], axis=2) + switch)
    back = np.where(stay, np.arange(n_states, dtype=np.int16), best[:, :, None].astype(np.int16)).tolist()
    state = np.argmin(total, axis=1).tolist()
    states = [state] * length
    for t in range(length - 1, -1, -1):
        states[t] = state
        pointers = back[t]
        state = [pointers[h][s] for h, s in enumerate(state)]
    path[:] = states
    return path, total


def riding(objects: np.ndarray, container: np.ndarray, window: int, moving_fraction: float,
           coherent_fraction: float, shot: np.ndarray | None = None) -> np.ndarray:
    """bool ``(frames, objects)``: the ingredient rides in its container on that frame. Over the ``window``
    frames before the frame, or over those after it (both ends seen, in one shot), the ingredient moves (its
    centre travels more than ``moving_fraction`` of its own diagonal) and its container moves the same way
    (their displacements differ by less than ``coherent_fraction`` of the ingredient's): common fate, as
    for a hand and what it holds. An ingredient moving over a container that stays put (the oil bottle tipped
    over the pot) does not ride in it."""
    length, n_objects = objects.shape[:2]
    rides = np.zeros((length, n_objects), dtype=bool)
    rows, columns = np.nonzero(container >= 0)
    if not len(rows):
        return rides
    holders = container[rows, columns]
    centre = centres(objects)
    box = objects[rows, columns]
    with np.errstate(invalid="ignore"):
        size = box_diagonal(box)
        for a, b in ((np.maximum(rows - window, 0), rows), (rows, np.minimum(rows + window, length - 1))):
            own = centre[b, columns] - centre[a, columns]
            travel = np.hypot(own[:, 0], own[:, 1])
            apart = np.hypot(*(centre[b, holders] - centre[a, holders] - own).T)
            side = (travel > moving_fraction * size) & (apart < coherent_fraction * travel)
            if shot is not None:
                side &= shot[a] == shot[b]
            rides[rows[side], columns[side]] = True
    return rides


def _ride_in_containers(costs: np.ndarray, container: np.ndarray, overlap: np.ndarray, columns: np.ndarray,
                        rides: np.ndarray) -> None:
    """The paper's hand-object rule ("Object Association": when the closest object is an ingredient contained by
    another object, the hand is associated with its container), where the physics agrees: on a frame where an
    ingredient rides in its container (:func:`riding`) and the hand overlaps both, the hand does not hold the
    ingredient but the container it rides in (the egg in the small bowl a hand tips into a bigger one; the dough
    in the bowl held for the partner). What says the ingredient moves with the hand says it of its container:
    the container's state costs the cheaper of the two, the ingredient's is impossible. An ingredient moving
    over a still container (the oil bottle poured over the pot) is not riding: the bottle is held, not the pot.
    ``costs`` ``(frames, hands, 1 + len(columns))`` is changed in place; state ``1 + k`` is object
    ``columns[k]``."""
    if not len(columns):
        return
    state_of = np.zeros(container.shape[1], dtype=np.intp)
    state_of[columns] = 1 + np.arange(len(columns))
    for k, column in enumerate(columns):
        holders = container[:, column]
        frames = np.flatnonzero((holders >= 0) & rides[:, column])
        if not len(frames):
            continue
        holder = holders[frames]
        for h in range(costs.shape[1]):
            both = overlap[frames, h, holder] & overlap[frames, h, column]
            at, states = frames[both], state_of[holder[both]]  # one container per frame: no index repeats
            costs[at, h, states] = np.minimum(costs[at, h, states], costs[at, h, 1 + k])
            costs[at, h, 1 + k] = np.inf


def held_objects(
    hands: np.ndarray,
    objects: np.ndarray,
    overlap: np.ndarray,
    container: np.ndarray,
    *,
    window: int,
    moving_fraction: float,
    coherent_fraction: float,
    switch: float,
    start: np.ndarray | None = None,
    step: int = 1,
    shot: np.ndarray | None = None,
    reach_only: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """int32 ``(frames, hands)``: the object column each hand holds on each frame (:data:`NONE`: nothing),
    and the forward costs to pass on as ``start`` of the next block of frames.

    ``step``: decode on bins of this many frames (their costs summed; a state impossible on some frames of a
    bin costs :data:`OUTSIDE` on those), then hold nothing on the frames where the chosen object does not
    overlap the hand. Hands grasp and release over tenths of a second, so bins of a tenth lose nothing that
    matters and make decoding ``step`` times cheaper."""
    columns = np.flatnonzero(overlap.any(axis=(0, 1)))  # only objects some hand overlaps can be held
    if start is not None:
        start = start[:, np.concatenate([[0], 1 + columns])]
    rows = np.arange(len(container))[:, None]
    holder = np.maximum(container, 0)
    contained = ((container >= 0)[:, None, :] & overlap[rows, :, holder].transpose(0, 2, 1))[:, :, columns]
    costs = emission_costs(hands, objects[:, columns], overlap[:, :, columns], contained, window, moving_fraction,
                           coherent_fraction, shot, None if reach_only is None else reach_only[:, :, columns])
    _ride_in_containers(costs, container, overlap, columns,
                        riding(objects, container, window, moving_fraction, coherent_fraction, shot))
    length = len(costs)
    if step > 1 and length > step:
        bins = -(-length // step)
        padded = np.full((bins * step, *costs.shape[1:]), 0.0)
        padded[:length] = np.where(np.isfinite(costs), costs, OUTSIDE)
        binned = padded.reshape(bins, step, *costs.shape[1:]).sum(axis=1)
        path, forward = viterbi(binned, switch, start)
        path = np.repeat(path, step, axis=0)[:length]
        possible = np.take_along_axis(np.isfinite(costs), path[:, :, None], axis=2)[:, :, 0]
        path = np.where(possible, path, 0)
    else:
        path, forward = viterbi(costs, switch, start)
    full = np.full((forward.shape[0], 1 + objects.shape[1]), np.inf)
    full[:, 0] = forward[:, 0]
    full[:, 1 + columns] = forward[:, 1:]
    held = np.where(path > 0, columns[np.maximum(path - 1, 0)] if len(columns) else NONE, NONE)
    return held.astype(np.int32), full
