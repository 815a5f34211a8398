"""Merging and the action graph (paper, "Action Graph Generation").

GGS over-segments: one action spans several segments. Per acting hand, consecutive segments merge when their
actions are identical up to ingredients that are not visible in some of them; a segment where the hand only
holds the same object (a grasp) joins the action next to it, so an action's frames run from the grasp that
starts it to the release that ends it. The merged actions become the graph's nodes (``a1``, ``a2``, ... by
start frame), one sequence per person, with an edge for each collaboration to the partner's actions before
and after it.

The graph file (YAML, ``wecook_graph: 1``)::

    wecook_graph: 1
    nodes:
    - {id: a1, person: P1, start: 0, end: 140, tree: "(HP (HP (H RH_P1) (O knife)) (AP (A cut) (O tomato)))"}
    sequences:
      P1: [a1, a3]
      P2: [a2]
    edges:
    - {source: a1, target: a3, kind: sequence}
"""

from __future__ import annotations

import bisect
import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from wecook_core.errors import InputError, read_input_text, yaml_error
from wecook_core.model import (
    HANDS,
    PERSONS,
    Action,
    ActionGraph,
    ActionKind,
    Category,
    GraphEdge,
    GraphNode,
    TreeSpan,
    person_of,
)
from wecook_core.trees.notation import TreeSyntaxError, action_of, format_tree, parse_tree, tree_of

if TYPE_CHECKING:
    from wecook_core.model import SegmentActions

FORMAT_KEY = "wecook_graph"
FORMAT_VERSION = 1

PARTNER = "partner"
"""Marks a segment where a hand acts inside another hand's collaboration."""


# -------------------------------------------------------------------------------------------- merging


def _grip(action: Action) -> str | None:
    if action.held is not None:
        return action.held
    return action.targets[0] if action.targets else None


def _key(action: Action) -> str:
    return format_tree(tree_of(action))


def _ingredients(action: Action, categories: Mapping[str, Category]) -> tuple[str, ...]:
    names = list(action.targets)
    if action.partner is not None:
        names += list(action.partner.targets)
    return tuple(n for n in names if categories.get(n, Category.INGREDIENT) is Category.INGREDIENT)


def _skeleton(action: Action, categories: Mapping[str, Category]) -> tuple[Any, ...]:
    """An action with its ingredient targets and its verb left out (what must agree for two segments to
    merge). The verb is left out when the hand keeps the same object on the same targets: GGS cuts one
    action into several segments, and the first strokes of a stir may not yet show its circles (the block's
    verb is the one recognised over most of its frames, :meth:`_Block.best`). A transfer keeps its verb."""
    partner = None
    if action.partner is not None:
        inner = action.partner
        if action.kind is ActionKind.HOLDING and action.held is not None and action.held not in inner.targets:
            inner = replace(inner, targets=(*inner.targets, action.held))  # the held object is a target too
        partner = _skeleton(inner, categories)
    kept = tuple(sorted(
        t for t in action.targets if categories.get(t, Category.INGREDIENT) is not Category.INGREDIENT))
    verb = action.verb if action.kind is ActionKind.TRANSFER else None
    return (action.kind, action.hand, verb, action.held, kept, partner)


def _verbs(action: Action) -> tuple[str | None, ...]:
    """The verbs of an action and of its partner, outermost first."""
    return (action.verb, *(_verbs(action.partner) if action.partner is not None else ()))


def compatible(a: Action, b: Action, categories: Mapping[str, Category]) -> bool:
    """Identical up to the verb (see :func:`_skeleton`) and the ingredients: one grasp of a tool on one
    container is one action, whichever ingredient in it the tool was nearest in each segment (a spoon
    stirring a pan of squash and turkey); the block names the ingredients seen over most of its frames. A
    transfer's ingredients must agree (one's contain the other's: an ingredient not visible in a segment)."""
    if _skeleton(a, categories) != _skeleton(b, categories):
        return False
    if a.kind is ActionKind.TRANSFER:
        ia, ib = set(_ingredients(a, categories)), set(_ingredients(b, categories))
        return ia <= ib or ib <= ia
    return True


def _span(action: Action, start: int, end: int) -> Action:
    partner = _span(action.partner, start, end) if action.partner is not None else None
    return replace(action, start=start, end=end, partner=partner)


@dataclass
class _Block:
    start: int
    end: int
    variants: dict[str, tuple[Action, int]] = field(default_factory=dict)
    """Tree text -> (an action with that tree, frames it covers)."""

    def add(self, action: Action, frames: int) -> None:
        key = _key(action)
        old = self.variants.get(key)
        self.variants[key] = (old[0] if old else action, (old[1] if old else 0) + frames)

    def best(self, categories: Mapping[str, Category]) -> Action:
        """Among the variants with the verbs recognised over the most frames, the one naming the most
        ingredients (seen in the fewest segments when they do not agree), then the most targets, then the
        most frames."""
        frames: dict[tuple[str | None, ...], int] = {}
        for action, count in self.variants.values():
            frames[_verbs(action)] = frames.get(_verbs(action), 0) + count
        verbs = max(frames, key=lambda v: frames[v])

        def rank(v: tuple[Action, int]) -> tuple[int, int, int]:
            a = v[0]
            targets = len(a.targets) + (len(a.partner.targets) if a.partner is not None else 0)
            return (len(_ingredients(a, categories)), targets, v[1])

        same = [v for v in self.variants.values() if _verbs(v[0]) == verbs]
        by_ingredients: dict[tuple[str, ...], int] = {}
        for action, count in same:
            key = tuple(sorted(_ingredients(action, categories)))
            by_ingredients[key] = by_ingredients.get(key, 0) + count
        # ingredient sets nested in one another are one (an ingredient not seen in some segments); else the
        # set seen over most frames
        def weight(key: tuple[str, ...]) -> int:
            return sum(n for other, n in by_ingredients.items() if set(other) <= set(key))

        chosen = max(by_ingredients, key=lambda key: (weight(key), len(key)))
        action, _ = max((v for v in same if tuple(sorted(_ingredients(v[0], categories))) == chosen), key=rank)
        return _span(action, self.start, self.end)

    def sample(self) -> Action:
        return next(iter(self.variants.values()))[0]


def merge_lane(
    items: Sequence[tuple[int, int, Action | str | None]], categories: Mapping[str, Category]
) -> list[Action]:
    """Merge one hand's consecutive segments ``(start, end, action | PARTNER | None)`` into actions."""
    out: list[Action] = []
    current: _Block | None = None
    lead: tuple[str | None, int, int] | None = None  # a run of grasps not yet given to an action

    def flush_lead() -> None:
        nonlocal lead
        if lead is not None and lead[0] is not None and lead_action is not None:
            out.append(_span(lead_action, lead[1], lead[2]))
        lead = None

    lead_action: Action | None = None
    for start, end, item in items:
        if item is None:
            if current is not None:
                out.append(current.best(categories))
                current = None
            flush_lead()
            continue
        if isinstance(item, str):  # partner inside a collaboration: neutral, extends what is open
            if current is not None:
                current.end = end
            elif lead is not None:
                lead = (lead[0], lead[1], end)
            continue
        if item.kind is ActionKind.GRASP:
            if current is not None and _grip(current.sample()) == item.held:
                current.end = end
                continue
            if current is not None:
                out.append(current.best(categories))
                current = None
            if lead is not None and lead[0] == item.held:
                lead = (lead[0], lead[1], end)
            else:
                flush_lead()
                lead, lead_action = (item.held, start, end), item
            continue
        if current is not None and compatible(current.sample(), item, categories):
            current.end = end
            current.add(item, end - start)
            continue
        if current is not None:
            out.append(current.best(categories))
            current = None
        block_start = start
        if lead is not None and lead[0] == _grip(item):
            block_start = lead[1]
            lead = None
        else:
            flush_lead()
        current = _Block(block_start, end)
        current.add(item, end - start)
    if current is not None:
        out.append(current.best(categories))
    flush_lead()
    return out


def merge_actions(
    segment_actions: Sequence[SegmentActions],
    categories: Mapping[str, Category],
    rejected: Iterable[int] = (),
    *,
    min_hold: int = 0,
    rejoin: int = 0,
    shots: Sequence[int] = (),
) -> tuple[Action, ...]:
    """The merged actions of a video, in order of start frame (then hand). Segments whose start frame is in
    ``rejected`` give nothing and break merges. An action or bare hold shorter than ``min_hold`` frames is
    left out: a hand touching a pot for a moment on its way to the knife, or lingering on the board after a
    cut, is the reach or release of an action, not an action, a graph node or a step of the plan. Nor is a
    bare hold of the object a collaboration's partner holds while the collaboration lasts: it is that
    partner's part of the collaboration. ``rejoin``, ``shots``: see :func:`rejoined` (a rejected segment walls
    off as a shot cut does)."""
    rejected = set(rejected)
    merged: list[Action] = []
    for hand in HANDS:
        items: list[tuple[int, int, Action | str | None]] = []
        for entry in segment_actions:
            segment = entry.segment
            if segment.start in rejected:
                items.append((segment.start, segment.end, None))
            elif hand in entry.partners:
                items.append((segment.start, segment.end, PARTNER))
            else:
                items.append((segment.start, segment.end, entry.action_of(hand)))
        merged += merge_lane(items, categories)
    walls = [f for e in segment_actions if e.segment.start in rejected for f in (e.segment.start, e.segment.end)]
    merged = [a for a in rejoined(merged, rejoin, (*shots, *walls)) if a.end - a.start >= min_hold]
    partners = [(a.partner, a) for a in merged if a.partner is not None]
    merged = [a for a in merged if not (a.kind is ActionKind.GRASP and any(
        p.hand == a.hand and _grip(p) == a.held and c.start < a.end and a.start < c.end for p, c in partners))]
    return tuple(sorted(merged, key=lambda a: (a.start, HANDS.index(a.hand), a.end)))


REJOINED_KINDS = frozenset({ActionKind.TOOL, ActionKind.HAND})
"""What a short break does not end: working with a tool or a hand goes on through a pause (a stir, a cut). A
transfer is one trip (two scoops are two transfers), a collaboration its own event."""


def rejoined(actions: Sequence[Action], gap: int, shots: Sequence[int] = ()) -> list[Action]:
    """``actions`` with each person's consecutive runs of one action (same kind, verb, held object and targets:
    :data:`REJOINED_KINDS` only) broken by at most ``gap`` frames joined into one, within one shot. A person
    does not pass the spoon to the other hand and back in the middle of a stir, nor stop stirring for a moment
    to stir again: the break is the detector's (a hand lost for a moment, or named by the other side for a
    while). The joined action is given to the hand that did more of it. ``gap`` 0 joins nothing."""
    if gap <= 0:
        return list(actions)
    cuts = sorted(set(shots))

    def shot_of(frame: int) -> int:
        return bisect.bisect_right(cuts, frame)

    out: list[Action] = []
    for action in sorted(actions, key=lambda a: (a.start, HANDS.index(a.hand) if a.hand in HANDS else 9)):
        person = person_of(action.hand)
        join = next((i for i in range(len(out) - 1, -1, -1)
                     if person_of(out[i].hand) == person and _same_work(out[i], action)
                     and action.start - out[i].end <= gap and shot_of(out[i].end - 1) == shot_of(action.start)),
                    None)
        if join is None:
            out.append(action)
            continue
        before = out[join]
        hand = before.hand if before.end - before.start >= action.end - action.start else action.hand
        out[join] = replace(before, hand=hand, start=min(before.start, action.start), end=max(before.end, action.end))
    # the other hand's bare hold of the same tool inside a joined action is that action's, not a tree of its own
    works = [a for a in out if a.kind in REJOINED_KINDS]
    return [a for a in out if not (a.kind is ActionKind.GRASP and any(
        w.held == a.held and person_of(w.hand) == person_of(a.hand) and w.start <= a.start and a.end <= w.end
        for w in works))]


def _same_work(a: Action, b: Action) -> bool:
    return (a.kind in REJOINED_KINDS and a.kind is b.kind and a.verb == b.verb and a.held == b.held
            and a.targets == b.targets)


def tree_spans(actions: Iterable[Action]) -> tuple[TreeSpan, ...]:
    """One tree per action, in the order given."""
    return tuple(TreeSpan(a.start, a.end, tree_of(a)) for a in actions)


# ---------------------------------------------------------------------------------------------- graph


def build_graph(actions: Iterable[Action]) -> ActionGraph:
    """Nodes ``a1, a2, ...`` by start frame (then hand); one sequence per person; ``sequence`` edges between a
    person's consecutive actions; for each collaboration, an edge from the partner's previous action to it and
    from it to the partner's next action (kind ``handover`` or ``holding``)."""
    ordered = sorted(actions, key=lambda a: (a.start, HANDS.index(a.hand) if a.hand in HANDS else 9, a.end))
    nodes = tuple(
        GraphNode(f"a{i + 1}", person_of(a.hand), TreeSpan(a.start, a.end, tree_of(a)), a)
        for i, a in enumerate(ordered)
    )
    return _graph_of(nodes)


def _graph_of(nodes: Sequence[GraphNode]) -> ActionGraph:
    sequences: dict[str, list[GraphNode]] = {}
    for node in nodes:
        sequences.setdefault(node.person, []).append(node)
    edges: list[GraphEdge] = []
    for seq in sequences.values():
        edges += [GraphEdge(a.id, b.id, "sequence") for a, b in itertools.pairwise(seq)]
    for node in nodes:
        action = node.action
        if action.kind not in (ActionKind.HANDOVER, ActionKind.HOLDING) or action.partner is None:
            continue
        partner_seq = sequences.get(person_of(action.partner.hand), [])
        before = [n for n in partner_seq if n.span.start < node.span.start]
        after = [n for n in partner_seq if n.span.start > node.span.start]
        if before:
            edges.append(GraphEdge(before[-1].id, node.id, str(action.kind)))
        if after:
            edges.append(GraphEdge(node.id, after[0].id, str(action.kind)))
    order = [p for p in PERSONS if p in sequences] + sorted(p for p in sequences if p not in PERSONS)
    return ActionGraph(nodes=tuple(nodes), sequences={p: tuple(n.id for n in sequences[p]) for p in order},
                       edges=tuple(edges))


# ------------------------------------------------------------------------------------------ graph file


def dump_graph(graph: ActionGraph) -> str:
    """The graph file's text (see the module docstring): one node or edge a line, trees in bracket notation."""
    lines = [f"{FORMAT_KEY}: {FORMAT_VERSION}", "nodes:" if graph.nodes else "nodes: []"]
    for node in graph.nodes:
        tree = format_tree(node.span.tree)
        lines.append(f'- {{id: {node.id}, person: {node.person}, start: {node.span.start}, end: {node.span.end}, '
                     f'tree: "{tree}"}}')
    lines.append("sequences:" if graph.sequences else "sequences: {}")
    for person, ids in graph.sequences.items():
        lines.append(f"  {person}: [{', '.join(ids)}]")
    lines.append("edges:" if graph.edges else "edges: []")
    for edge in graph.edges:
        lines.append(f"- {{source: {edge.source}, target: {edge.target}, kind: {edge.kind}}}")
    return "\n".join(lines) + "\n"


def write_graph_file(path: str | Path, graph: ActionGraph) -> None:
    """Write the graph file atomically (a reader sees the old file or the new one, never a torn one)."""
    from wecook_core.files import write_atomic

    write_atomic(path, dump_graph(graph), replace=True, what="graph file")


def read_graph_file(path: str | Path) -> ActionGraph:
    """Read a graph file; bad content raises :class:`InputError` naming the entry and the field."""
    path = Path(path)
    text = read_input_text(path)
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise yaml_error(path, error, "not YAML") from None
    if not isinstance(data, dict) or data.get(FORMAT_KEY) != FORMAT_VERSION:
        raise InputError(path, f"not a graph file (expected {FORMAT_KEY}: {FORMAT_VERSION})")
    nodes = []
    for i, item in enumerate(data.get("nodes") or []):
        place = f"nodes[{i + 1}]"
        if not isinstance(item, dict) or not {"id", "person", "start", "end", "tree"} <= set(item):
            raise InputError(path, "expected id, person, start, end and tree", place=place)
        start, end = item["start"], item["end"]
        if not (isinstance(start, int) and isinstance(end, int) and 0 <= start < end):
            raise InputError(path, f"expected frames 0 <= start < end, found {start!r}, {end!r}", place=place)
        try:
            tree = parse_tree(str(item["tree"]))
        except TreeSyntaxError as error:
            raise InputError(path, f"tree {error}", place=place) from None
        nodes.append(GraphNode(str(item["id"]), str(item["person"]), TreeSpan(start, end, tree),
                               action_of(tree, start, end)))
    ids = {n.id for n in nodes}
    sequences = {}
    for person, seq in (data.get("sequences") or {}).items():
        if not isinstance(seq, list) or any(str(s) not in ids for s in seq):
            raise InputError(path, "expected a list of node ids", place=f"sequences.{person}")
        sequences[str(person)] = tuple(str(s) for s in seq)
    edges = []
    for i, item in enumerate(data.get("edges") or []):
        place = f"edges[{i + 1}]"
        if not isinstance(item, dict) or not {"source", "target", "kind"} <= set(item):
            raise InputError(path, "expected source, target and kind", place=place)
        if str(item["source"]) not in ids or str(item["target"]) not in ids:
            raise InputError(path, "source and target must be node ids", place=place)
        edges.append(GraphEdge(str(item["source"]), str(item["target"]), str(item["kind"])))
    return ActionGraph(tuple(nodes), sequences, tuple(edges))


# ---------------------------------------------------------------------------------------------- cases


CASES: tuple[str, ...] = ("tool", "container", "hand", "held", "transfer", "holding", "handover", "grasp")
"""The tree cases of DESIGN.md's table: ``tool`` (an action with a tool), ``container`` (with the target in
its container), ``hand`` (by the hand itself), ``held`` (pour, sprinkle, dip with a held ingredient or
container), ``transfer``, ``holding``, ``handover``, ``grasp`` (no action)."""


def case_of(action: Action, categories: Mapping[str, Category]) -> str:
    """Which of :data:`CASES` an action's tree is."""
    kind = action.kind
    if kind in (ActionKind.GRASP, ActionKind.HAND, ActionKind.TRANSFER, ActionKind.HOLDING, ActionKind.HANDOVER):
        return str(kind)
    if action.held is not None and categories.get(action.held, Category.INGREDIENT) is not Category.TOOL:
        return "held"
    return "container" if len(action.targets) > 1 else "tool"
