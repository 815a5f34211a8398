"""Plan review: each person's action sequence, the collaborations between them, each action's source frames;
export writes the plan YAML into the session and says where."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

from rich.console import Group
from rich.table import Table
from rich.text import Text
from textual import work
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Footer, Static

from wecook_tui.messages import PlanBuilt, PlanExported

PLAN_BINDINGS: list[Binding] = [
    Binding("w,enter", "export", "Export plan YAML", id="plan-export"),
    Binding("escape,q", "back", "Back", id="plan-back"),
]



def plan_file(session_path: Path) -> Path:
    """Where export writes: ``plans/plan.yaml`` in the session (as `wecook export` does)."""
    from wecook_core.session.paths import session_paths

    return session_paths(session_path).plan


def plan_renderable(plan: Any) -> Group:
    """One table per person (agents' order) and one of collaborations; plain Rich, no Textual."""
    parts: list[Any] = []
    pids = [agent.pid for agent in plan.agents]
    for pid in pids:
        table = Table(title=f"{pid}: action sequence", expand=True, title_justify="left")
        for column in ("id", "verb", "tool", "ingredients", "location", "after", "frames", "with"):
            table.add_column(column, no_wrap=column in ("id", "frames"))
        for action in plan.actions:
            if pid not in action.pids:
                continue
            others = [p for p in action.pids if p != pid]
            frames = f"[{action.frames[0]}, {action.frames[1]})" if action.frames else "-"
            verb = action.verb
            if action.partner is not None:
                verb += f" ({action.partner.verb})"
            table.add_row(action.id, verb, action.tool or "-", ", ".join(action.ingredients) or "-",
                          action.location or "-", ", ".join(action.after) or "-", frames,
                          ", ".join(others) or "")
        parts.append(table)
    collab = Table(title="Collaborations", expand=True, title_justify="left")
    for column in ("id", "kind", "persons", "object", "frames"):
        collab.add_column(column)
    links = [a for a in plan.actions if len(a.pids) > 1]
    for action in links:
        frames = f"[{action.frames[0]}, {action.frames[1]})" if action.frames else "-"
        collab.add_row(action.id, action.verb, " ⇄ ".join(action.pids), action.tool or "-", frames)
    cross = [(a.id, b) for a in plan.actions for b in a.after
             if not set(plan.action(b).pids) & set(a.pids)] if plan.actions else []
    parts.append(collab if links else Text("No collaborations.", style="dim"))
    if cross:
        parts.append(Text("Waits across persons: " + ", ".join(f"{a} after {b}" for a, b in cross)))
    parts.append(Text(f"{len(plan.actions)} actions, {len(plan.scene.objects)} objects in the scene",
                      style="dim"))
    return Group(*parts)


@dataclass(frozen=True)
class ReviewCounts:
    """How far the review got: segments, unreviewed ones, rejected ones (left out of the plan)."""

    segments: int
    unreviewed: int
    rejected: int

    def line(self) -> Text:
        if not self.segments:
            return Text("")
        style = "bold yellow" if self.unreviewed else "bold green"
        return Text.assemble(
            (f"{self.unreviewed} of {self.segments} segments unreviewed" if self.unreviewed
             else f"all {self.segments} segments reviewed", style),
            (f", {self.rejected} rejected (left out of the plan)" if self.rejected else "", "red"))


class PlanReviewScreen(Screen[None]):
    BINDINGS: ClassVar[list[BindingType]] = [*PLAN_BINDINGS]

    def __init__(self, analysis: Any, obs: Any, session_path: Path, review: ReviewCounts | None = None) -> None:
        super().__init__()
        self.analysis = analysis
        self.obs = obs
        self.session_path = session_path
        self.review = review or ReviewCounts(0, 0, 0)
        self.plan: Any = None
        self.exported: Path | None = None
        self.asked = False
        """The user was told the plan is not fully reviewed; the next export goes ahead."""

    def compose(self) -> ComposeResult:
        yield Static(self.review.line(), id="plan-review")
        with VerticalScroll(id="plan"):
            yield Static("Building the plan…", id="plan-body")
        yield Static(id="plan-status")
        yield Footer()

    def on_mount(self) -> None:
        self._build()

    @work(thread=True, exclusive=True, group="plan", exit_on_error=False)
    def _build(self) -> None:
        from wecook_core.workflows import plan_of

        try:
            plan = plan_of(self.analysis, self.obs)
        except Exception as error:  # shown, never a traceback
            self.post_message(PlanBuilt(None, f"{type(error).__name__}: {error}"))
            return
        self.post_message(PlanBuilt(plan))

    def on_plan_built(self, message: PlanBuilt) -> None:
        body = self.query_one("#plan-body", Static)
        if message.error:
            body.update(Text(f"The plan cannot be built: {message.error}", style="red"))
            return
        self.plan = message.plan
        body.update(plan_renderable(message.plan))
        self.query_one("#plan-status", Static).update(
            f"Press w to write {plan_file(self.session_path)}")

    def action_export(self) -> None:
        if self.plan is None:
            self.notify("The plan is not built yet.", severity="warning")
            return
        if self.review.unreviewed and not self.asked:
            self.asked = True
            self.query_one("#plan-status", Static).update(Text(
                f"{self.review.unreviewed} of {self.review.segments} segments are still unreviewed: press w again "
                "to export anyway, escape to go back and review", style="bold yellow"))
            return
        self._export(self.plan, plan_file(self.session_path))

    @work(thread=True, exclusive=True, group="plan-export", exit_on_error=False)
    def _export(self, plan: Any, path: Path) -> None:
        from wecook_core.workflows import write_checked_plan

        try:
            written = write_checked_plan(plan, path)
        except Exception as error:
            self.post_message(PlanExported(path, f"{type(error).__name__}: {error}"))
            return
        self.post_message(PlanExported(Path(written)))

    def on_plan_exported(self, message: PlanExported) -> None:
        if message.error:
            self.notify(f"Export failed: {message.error}", severity="error")
            return
        self.exported = message.path
        self.query_one("#plan-status", Static).update(Text(f"Plan written to {message.path}", style="bold green"))
        self.notify(f"Plan written to {message.path}", title="Export")

    def action_back(self) -> None:
        self.dismiss(None)
