"""Action trees: built from recognised actions, parsed from and formatted to bracket notation.

The grammar is data (``grammar.lark``); every tree the code emits parses under it, and
``format_tree(parse_tree(s)) == s`` for every canonical string ``s``.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import LarkError

from wecook_core.model import Action, ActionKind, Node

GRAMMAR_PATH = Path(__file__).with_name("grammar.lark")


class TreeSyntaxError(ValueError):
    """A string that is not a tree of the action grammar; the message says where."""


@cache
def _parser() -> Lark:
    return Lark(GRAMMAR_PATH.read_text(), parser="lalr", maybe_placeholders=False)


@v_args(inline=True)
class _ToNode(Transformer[Token, Node]):
    def start(self, hp: Node) -> Node:
        return hp

    def hp_hold(self, *c: Node) -> Node:
        return Node("HP", c)

    hp_act = hp_collab = hp_hold_phrase = hp_hand_act = hp_hold

    def ap(self, *c: Node) -> Node:
        return Node("AP", c)

    def cp(self, *c: Node) -> Node:
        return Node("CP", c)

    def op(self, *c: Node) -> Node:
        return Node("OP", c)

    def h(self, token: object) -> Node:
        return Node("H", word=str(token))

    def o(self, token: object) -> Node:
        return Node("O", word=str(token))

    def a(self, token: object) -> Node:
        return Node("A", word=str(token))

    def c(self, token: object) -> Node:
        return Node("C", word=str(token))


def parse_tree(text: str) -> Node:
    """Parse one bracketed tree; raises :class:`TreeSyntaxError` naming the column on bad input."""
    try:
        return _ToNode().transform(_parser().parse(text.strip()))
    except LarkError as error:
        column = getattr(error, "column", None)
        where = f"column {column}: " if column not in (None, -1) else ""
        first_line = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise TreeSyntaxError(f"{where}not a tree of the action grammar ({first_line})") from None


def format_tree(node: Node) -> str:
    """Canonical one-line bracket notation, one space between items."""
    if node.word is not None:
        return f"({node.label} {node.word})"
    return "(" + " ".join([node.label, *(format_tree(child) for child in node.children)]) + ")"


def is_valid(node: Node) -> bool:
    try:
        parse_tree(format_tree(node))
    except TreeSyntaxError:
        return False
    return True


# ------------------------------------------------------------------------------ actions <-> trees


def _leaf(label: str, word: str) -> Node:
    return Node(label, word=word)


def _objects(names: tuple[str, ...]) -> Node:
    """One object, or a right-nested OP chain: (a, b, c) -> (OP (O a) (OP (O b) (O c)))."""
    if not names:
        raise ValueError("an action needs at least one object")
    if len(names) == 1:
        return _leaf("O", names[0])
    if len(names) == 2:
        return Node("OP", (_leaf("O", names[0]), _leaf("O", names[1])))
    return Node("OP", (_leaf("O", names[0]), _objects(names[1:])))


def _held(hand: str, held: str) -> Node:
    return Node("HP", (_leaf("H", hand), _leaf("O", held)))


def tree_of(action: Action) -> Node:
    """The tree of one action, following the cases of DESIGN.md's table."""
    kind = action.kind
    if kind is ActionKind.GRASP:
        if action.held is None:
            raise ValueError("a grasp needs a held object")
        return _held(action.hand, action.held)
    if kind in (ActionKind.TOOL, ActionKind.TRANSFER, ActionKind.HAND):
        verb = action.verb or ("transfer" if kind is ActionKind.TRANSFER else None)
        if verb is None:
            raise ValueError(f"a {kind} action needs a verb")
        ap = Node("AP", (_leaf("A", verb), _objects(action.targets)))
        if action.held is None:
            return Node("HP", (_leaf("H", action.hand), ap))
        return Node("HP", (_held(action.hand, action.held), ap))
    if kind in (ActionKind.HOLDING, ActionKind.HANDOVER):
        if action.held is None or action.partner is None:
            raise ValueError(f"a {kind} needs a held object and a partner action")
        cp = Node("CP", (_leaf("C", str(kind)), tree_of(action.partner)))
        return Node("HP", (_held(action.hand, action.held), cp))
    raise ValueError(f"unknown action kind {kind!r}")


def _object_words(node: Node) -> tuple[str, ...]:
    if node.label == "O":
        assert node.word is not None
        return (node.word,)
    return tuple(word for child in node.children for word in _object_words(child))


def action_of(node: Node, start: int = 0, end: int = 1) -> Action:
    """The action a tree describes (inverse of :func:`tree_of` for the trees it emits)."""
    if node.label != "HP" or len(node.children) != 2:
        raise ValueError(f"not a hand phrase: {format_tree(node)}")
    first, second = node.children
    if first.label == "H":
        hand = first.word or ""
        if second.label == "O":
            return Action(ActionKind.GRASP, hand, start, end, held=second.word)
        if second.label == "OP":  # a hand holding an object phrase: treat as holding the first object
            words = _object_words(second)
            return Action(ActionKind.GRASP, hand, start, end, held=words[0])
        verb = second.children[0].word
        targets = _object_words(second.children[1])
        kind = ActionKind.TRANSFER if verb == "transfer" else ActionKind.HAND
        return Action(kind, hand, start, end, verb=verb, targets=targets)
    held_node = first
    inner = action_of(held_node, start, end)
    hand, held = inner.hand, inner.held
    if second.label == "AP":
        verb = second.children[0].word
        targets = _object_words(second.children[1])
        kind = ActionKind.TRANSFER if verb == "transfer" else ActionKind.TOOL
        return Action(kind, hand, start, end, verb=verb, held=held, targets=targets)
    collaboration = ActionKind(second.children[0].word or "")
    partner = action_of(second.children[1], start, end)
    return Action(collaboration, hand, start, end, held=held, partner=partner)


def has_action(node: Node) -> bool:
    """True when a tree contains an action or a collaboration (the trees evaluation counts)."""
    if node.label in ("A", "C"):
        return True
    return any(has_action(child) for child in node.children)
