"""The inspector: the current segment's trees (a Tree widget), its associations, its actions and their scores."""

from __future__ import annotations

from collections.abc import Mapping

from rich.text import Text
from textual.app import ComposeResult
from textual.containers import VerticalScroll
from textual.widgets import Static, Tree
from textual.widgets.tree import TreeNode

from wecook_core.model import Action, Associations, Node, Segment, SegmentStatus, TreeSpan
from wecook_tui.review import STATUS_GLYPHS, UNSURE_GLYPH, action_label


class SegmentTree(Tree[str]):
    """The action trees of a segment; not focusable, so the screen's keys always reach the screen."""

    can_focus = False


def _add(parent: TreeNode[str], node: Node) -> None:
    if node.word is not None:
        parent.add_leaf(Text.assemble((node.label, "bold"), " ", (node.word, "cyan")), data=node.word)
        return
    branch = parent.add(Text(node.label, style="bold magenta"), data=node.label, expand=True)
    for child in node.children:
        _add(branch, child)


class Inspector(VerticalScroll):
    """Read-only view of one segment; the screen calls :meth:`show` whenever the segment or analysis changes."""

    can_focus = False

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self._shown: dict[str, object] = {}
        """What each part shows now (header, actions, associations texts; the trees): a part whose content did
        not change is not rebuilt (playback crosses segments of one action, whose trees are the same)."""
        self.rebuilds = 0
        """Times the tree was rebuilt (the tests count them)."""

    def compose(self) -> ComposeResult:
        yield Static(id="segment-header")
        yield Static(id="segment-actions")
        yield Static(id="segment-associations")
        yield SegmentTree("trees", id="segment-trees")

    def show(self, index: int, count: int, seg: Segment, status: SegmentStatus, trees: tuple[TreeSpan, ...],
             assoc: Associations | None, actions: Mapping[str, Action], selected: str | None,
             pending: bool, rankings: Mapping[str, tuple[tuple[str, float], ...]] | None = None,
             unsure: str | None = None) -> None:
        """``unsure``: why the evidence in the segment is too thin to trust what was recognised (None: it is not)."""
        glyph, colour = STATUS_GLYPHS[status]
        header = Text.assemble(
            ("segment ", "dim"), (f"{index + 1}/{count}", "bold"), ("  frames ", "dim"),
            f"[{seg.start}, {seg.end})", "  ", (f"{glyph} {status}", colour),
            ("  (recomputing…)", "italic yellow") if pending else "",
        )
        if unsure:
            mark, tone = UNSURE_GLYPH
            header.append_text(Text.assemble("\n", (f"{mark} unsure: ", f"bold {tone}"), (unsure, tone)))
        self._update("#segment-header", header)
        self._update("#segment-actions", self._actions(actions, selected, rankings or {}))
        self._update("#segment-associations", self._associations(assoc))
        if self._shown.get("trees") == trees:
            return
        self._shown["trees"] = trees
        self.rebuilds += 1
        tree = self.query_one("#segment-trees", SegmentTree)
        tree.clear()
        if trees:
            from wecook_core.trees.notation import format_tree  # lark: loaded with the first trees, not at start
        tree.root.set_label(Text(f"{len(trees)} tree(s)", style="dim"))
        for span in trees:
            node = tree.root.add(Text(f"[{span.start}, {span.end})  {format_tree(span.tree)}", style="dim"),
                                 data=format_tree(span.tree), expand=True)
            _add(node, span.tree)
        tree.root.expand()

    def _update(self, part: str, text: Text) -> None:
        if self._shown.get(part) != text:
            self._shown[part] = text
            self.query_one(part, Static).update(text)

    @staticmethod
    def _actions(actions: Mapping[str, Action], selected: str | None,
                 rankings: Mapping[str, tuple[tuple[str, float], ...]]) -> Text:
        text = Text("Actions\n", style="bold underline")
        if not actions:
            text.append("  none recognised\n", style="dim")
        for hand, action in sorted(actions.items()):
            marker = "▶ " if hand == selected else "  "
            text.append(f"{marker}{hand}: ", style="bold" if hand == selected else "")
            text.append(action_label(action), style="bold cyan")
            if action.held:
                text.append(f"  held {action.held}")
            if action.targets:
                text.append(f"  on {', '.join(action.targets)}")
            text.append("\n")
            scores = rankings.get(hand) or action.scores
            if scores:
                top = "  ".join(f"{verb} {p:.2f}" for verb, p in scores[:5])
                text.append(f"    scores: {top}\n", style="dim")
        return text

    @staticmethod
    def _associations(assoc: Associations | None) -> Text:
        text = Text("Associations\n", style="bold underline")
        if assoc is None:
            text.append("  (analysis pending)\n", style="dim")
            return text
        for hand, name in sorted(assoc.hand_object.items()):
            text.append(f"  {hand} holds {name}\n")
        for name, targets in sorted(assoc.object_object.items()):
            if targets:
                text.append(f"  {name} → {', '.join(targets)}\n")
        for name, container in sorted(assoc.containment.items()):
            text.append(f"  {name} in {container}\n", style="dim")
        if not (assoc.hand_object or assoc.object_object or assoc.containment):
            text.append("  none\n", style="dim")
        return text
