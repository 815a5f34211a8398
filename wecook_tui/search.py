"""Search actions and objects from the command palette (ctrl+p): choosing one moves the cursor there."""

from __future__ import annotations

from collections.abc import Iterator
from functools import partial

from textual.command import Hit, Hits, Provider

from wecook_tui.review import action_label
from wecook_tui.workbench_state import workbench


def targets(app: object) -> Iterator[tuple[str, int, str]]:
    """(text, frame, help) of every action (by its tree span) and every object (its first frame seen)."""
    wb = workbench(app)  # type: ignore[arg-type]
    fps = wb.fps
    if wb.analysis is not None:
        for action in wb.analysis.actions:
            objects = " ".join(dict.fromkeys(n for n in (action.held, *action.targets) if n))
            yield (f"action {action_label(action)} {action.hand} {objects}".strip(), action.start,
                   f"frames [{action.start}, {action.end}), {action.start / fps:.1f} s")
    if wb.obs is not None:
        for track in wb.obs.objects:
            if len(track.frames):
                first = int(track.frames[0])
                yield (f"object {track.name}", first, f"first seen at frame {first}, {first / fps:.1f} s")


class SearchProvider(Provider):
    """Actions and objects of the session, matched fuzzily."""

    async def search(self, query: str) -> Hits:
        matcher = self.matcher(query)
        for text, frame, help_text in targets(self.app):
            score = matcher.match(text)
            if score > 0:
                yield Hit(score, matcher.highlight(text), partial(self._go, frame), help=help_text)

    def _go(self, frame: int) -> None:
        workbench(self.app).go_to(frame)
