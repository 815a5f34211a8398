"""The workbench app: opens a session, holds the analysis, journals corrections and recomputes in workers.

Screens show; this class wires. Every stage is a core function called in a worker that posts a typed message
(`messages.py`); the UI thread only journals corrections (fsynced by ``Session.record``) and updates views.
"""

from __future__ import annotations

import gc
import os
import time
from collections.abc import Callable, Iterable, Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from textual import work
from textual.app import App, SystemCommand
from textual.reactive import var
from textual.screen import Screen

from wecook_core.errors import InputError
from wecook_core.session.journal import JournalChangedError
from wecook_tui import graphics
from wecook_tui.keymap import LoadedKeymap, load_keymap
from wecook_tui.messages import (
    AnalysisFailed,
    AnalysisReady,
    FirstFramePainted,
    SessionFailed,
    SessionOpened,
    VideoOpened,
)
from wecook_tui.review import shown_observations
from wecook_tui.screens.catalogue import binding_ids
from wecook_tui.screens.help import HelpScreen
from wecook_tui.screens.main import MAIN_BINDINGS, MainScreen
from wecook_tui.search import SearchProvider
from wecook_tui.widgets.frame_view import FrameView, report_moment
from wecook_tui.workspace import Opened, analyze_workspace, open_video, open_workspace

if TYPE_CHECKING:
    from wecook_core.model import Corrections, Segment
    from wecook_core.perception.pipeline import Analysis
    from wecook_core.session.corrections import Correction
    from wecook_tui.frames import FrameSource


class WecookApp(App[None]):
    CSS_PATH = "workbench.tcss"
    TITLE = "wecook"
    COMMANDS = App.COMMANDS | {SearchProvider}

    pending: var[bool] = var(False, init=False)
    """An analysis is being recomputed for the latest corrections."""

    def __init__(self, session_path: Path, *, keys: LoadedKeymap | None = None,
                 opener: Callable[..., Opened] = open_workspace,
                 analyzer: Callable[[Opened, Sequence[Correction]], Analysis] = analyze_workspace,
                 video_opener: Callable[[Path], FrameSource | None] | None = None) -> None:
        """``opener(path)`` opens the session; with ``video_opener`` (the default with the default opener), the
        video is opened first and shown while ``opener(path, frames)`` loads the rest."""
        super().__init__()
        self.session_path = Path(session_path)
        self.session_name = self.session_path.name
        self.opener = opener
        self.video_opener = video_opener if video_opener is not None or opener is not open_workspace else open_video
        self.analyzer = analyzer
        self.keys = keys if keys is not None else load_keymap(known_ids=binding_ids())
        protocol = graphics.choose(os.environ)
        self.graphics = graphics.load(protocol) if protocol is not None else None
        """The terminal's graphics protocol the frame view draws with (None: half-blocks); chosen before the
        app starts, while the terminal can still be asked its cell size."""
        self.opened: Opened | None = None
        self.analysis: Analysis | None = None
        self.last_message = ""
        """The answer to the latest edit, undo or redo."""
        self._folded: tuple[tuple[int, int], Corrections] | None = None
        self.generation = 0
        self._analysing = False
        """Bumped by every journal change; an analysis of an older generation is dropped."""
        self.main = MainScreen()
        self.run_command: Callable[[Path, Path], list[str]] | None = None
        """argv that executes a plan (plan path, MCAP path); None: `wecook execute`."""
        if self.keys.keymap:
            self.set_keymap(self.keys.keymap)

    # ---------------------------------------------------------------------------------- data

    @property
    def session(self) -> Any:
        return self.opened.session if self.opened else None

    @property
    def obs(self) -> Any:
        """The observations shown and analysed: the imported ones with the boxes drawn in the box mode."""
        return shown_observations(self.opened)

    @property
    def corrections(self) -> Corrections | None:
        """The journal's corrections in effect, folded against the current segments (span corrections cover
        each segment of their action), so statuses show at once, before the analysis returns."""
        from wecook_core.session.corrections import fold

        if self.session is None:
            return None
        key = (self.generation, id(self.analysis))
        if self._folded is None or self._folded[0] != key:
            self._folded = (key, fold(self.session.applied_corrections, self._segments()))
        return self._folded[1]

    def _segments(self) -> tuple[Segment, ...] | None:
        """The segments the corrections in effect give: GGS's cut by the journal's splits and merges."""
        from wecook_core.perception.pipeline import final_segments
        from wecook_core.session.corrections import fold

        ggs = self.opened.segmentation if self.opened is not None else None
        if ggs is not None and self.session is not None and self.analysis is not None and self.obs is not None:
            # the video's own cuts (shots, unseen holds) are the analysis's; the journal's splits and merges now
            return final_segments(ggs, self.analysis.shots, self.analysis.unseen, self.session.params,
                                  self.obs.video.fps, fold(self.session.applied_corrections)).segments
        return self.analysis.segmentation.segments if self.analysis is not None else None

    @property
    def frame_count(self) -> int:
        if self.obs is not None:
            video = self.obs.video
            return max(1, video.decoded_frames or video.frame_count)
        return 1

    @property
    def fps(self) -> float:
        return float(self.obs.video.fps) if self.obs is not None and self.obs.video.fps else 30.0

    def rank(self, objects: tuple[str, ...]) -> list[tuple[str, float]]:
        """The action picker's order: the commonsense model's ranking for the segment's objects."""
        knowledge = self.opened.knowledge if self.opened else None
        if knowledge is None:
            return []
        from wecook_core.knowledge.recognize import rank

        return list(rank(knowledge, objects))

    def watch_pending(self) -> None:
        """Show and clear the "recomputing" state at once."""
        if self.main.is_mounted:
            self.main.refresh_view()

    # -------------------------------------------------------------------------------- opening

    def on_mount(self) -> None:
        tune_gc()
        self.push_screen(self.main)
        for problem in self.keys.problems:
            self.notify(problem, title="Key file", severity="warning", timeout=15)
        self._open()

    @work(thread=True, exclusive=True, group="open", exit_on_error=False)
    def _open(self) -> None:
        try:
            frames = self.video_opener(self.session_path) if self.video_opener is not None else None
            if frames is not None:
                self.post_message(VideoOpened(frames))
                opened = self.opener(self.session_path, frames)
            else:
                opened = self.opener(self.session_path)
        except InputError as error:
            self.post_message(SessionFailed(str(error)))
            return
        except Exception as error:  # never a traceback on screen: say what failed
            self.post_message(SessionFailed(f"{self.session_path}: cannot open session ({type(error).__name__}: "
                                            f"{error})"))
            return
        self.post_message(SessionOpened(opened, tuple(opened.warnings)))

    def on_video_opened(self, message: VideoOpened) -> None:
        """The first picture, before the boxes and hands: the frame where the user left off."""
        from wecook_tui.resume import load_position

        if self.opened is not None:
            return
        frames = message.frames
        view = self.main.query_one(FrameView)
        view.hold_prefetch = True  # decoding ahead would slow the import of the boxes and hands down
        view.set_source(frames, (frames.facts.width, frames.facts.height))
        resume = load_position(self.session_path)
        if resume is not None and frames.facts.frame_count:
            self.main.frame = max(0, min(resume, frames.facts.frame_count - 1))

    def on_session_opened(self, message: SessionOpened) -> None:
        self.opened = message.opened
        self.main.query_one(FrameView).hold_prefetch = False
        for warning in message.warnings:
            self.notify(warning, title="Session", severity="warning", timeout=30)
        obs = self.obs
        if obs is not None:
            from wecook_tui.resume import load_position

            view = self.main.query_one(FrameView)
            view.set_source(self.opened.frames, (obs.video.width, obs.video.height))
            resume = load_position(self.session_path)
            if resume is not None:
                self.main.frame = min(resume, self.frame_count - 1)
            frames = self.opened.frames if self.opened is not None else None
            self.pending = True  # recomputing from the start: the first analysis is on its way
            self.call_after_refresh(report_moment, "session")
            if view.first_painted:  # the video showed first: analyse once the boxes are on screen
                self.call_after_refresh(self.recompute_once)
            elif frames is not None and frames.ok:
                self.set_timer(1.0, self.recompute_once)  # in case no frame ever paints
            else:
                self.recompute_once()
        self.main.data_changed()

    def on_first_frame_painted(self, message: FirstFramePainted) -> None:
        if self.opened is not None:
            self.recompute_once()

    def recompute_once(self) -> None:
        """The first analysis, started once the first frame is on screen (or at once without a video)."""
        if self.analysis is None and not self._analysing:
            self.recompute()

    def on_session_failed(self, message: SessionFailed) -> None:
        self.notify(message.error, title="Cannot open session", severity="error", timeout=60)

    # ---------------------------------------------------------------------------- corrections

    def correct(self, correction: Correction) -> bool:
        """Journal one correction (fsynced before this returns), say what changed, show it, recompute."""
        from wecook_core.session.corrections import describe
        from wecook_tui.edits import where

        if self.session is None:
            self.notify("The session is not open yet.", severity="warning")
            return False
        try:
            self.session.record(correction)
        except (InputError, ValueError, KeyError, OSError, JournalChangedError) as error:
            self.notify(f"Not recorded: {error}", severity="error", timeout=30)
            return False
        self.journal_changed(f"✎ {describe(correction)}{where(correction, self._segments())}", correction)
        return True

    def go_to(self, frame: int) -> None:
        self.main.frame = max(0, min(self.frame_count - 1, frame))

    def undo(self) -> None:
        self._history("undo")

    def redo(self) -> None:
        self._history("redo")

    def _history(self, name: str) -> None:
        from wecook_core.session.corrections import describe
        from wecook_tui.edits import where

        if self.session is None:
            return
        try:
            changed = getattr(self.session, name)()
        except (InputError, ValueError, IndexError, OSError, JournalChangedError) as error:
            self.notify(str(error), severity="warning")
            return
        if not changed:
            self.say(f"Nothing to {name}.")
            return
        verb = "Undone" if name == "undo" else "Redone"
        self.journal_changed(f"{verb}: {describe(changed)}{where(changed, self._segments())}", changed)

    def say(self, message: str) -> None:
        """The one-line answer to an edit, undo or redo, on the status line (a notice would cover it)."""
        self.last_message = message
        self.main.refresh_view()

    def journal_changed(self, message: str = "", correction: Correction | None = None) -> None:
        """The journal moved on: show it at once (statuses), jump to what changed, recompute the analysis."""
        from wecook_core.session.corrections import span_of

        self.generation += 1
        self._folded = None
        if correction is not None:
            self.main.jump_to(span_of(correction))
        self.main.data_changed()
        self.recompute()
        if message:
            self.say(message)

    def recompute(self) -> None:
        """Analyse the latest corrections: at most one analysis runs; corrections made meanwhile are folded
        into the next one (a burst of keys costs two analyses, not one thread per key)."""
        if self.opened is None or self.obs is None:
            return
        self.pending = True
        if self._analysing:
            return
        self._analysing = True
        self._analyze(self.generation, self.session.applied_corrections)

    def _analysed(self, generation: int) -> bool:
        """An analysis ended; start the next if the journal moved on. True if ``generation`` is current."""
        self._analysing = False
        if generation != self.generation:
            self.recompute()
            return False
        self.pending = False
        return True

    @work(thread=True, group="analysis", exit_on_error=False)
    def _analyze(self, generation: int, corrections: tuple[Correction, ...]) -> None:
        assert self.opened is not None
        started = time.perf_counter()
        try:
            analysis = self.analyzer(self.opened, corrections)
        except Exception as error:  # a pipeline bug must not take the workbench (and the journal) down
            self.post_message(AnalysisFailed(f"{type(error).__name__}: {error}", generation))
            return
        self.post_message(AnalysisReady(analysis, generation, time.perf_counter() - started))

    def on_analysis_ready(self, message: AnalysisReady) -> None:
        if self._analysed(message.generation):
            self.analysis = message.analysis
            self.main.data_changed()
            self._write_results(message.analysis)

    @work(thread=True, exclusive=True, group="results", exit_on_error=False)
    def _write_results(self, analysis: Analysis) -> None:
        """Keep the session's ``trees.yaml`` and ``graph.yaml`` in step with the corrections."""
        from wecook_core.workflows import write_results

        try:
            write_results(self.session, analysis)
        except (OSError, AttributeError, ValueError) as error:
            self.call_from_thread(self.notify, f"Cannot write the analysis results: {error}", severity="warning")

    def on_analysis_failed(self, message: AnalysisFailed) -> None:
        if self._analysed(message.generation):
            self.notify(f"Analysis failed: {message.error}", severity="error", timeout=30)
            self.main.data_changed()

    # -------------------------------------------------------------------------------- screens

    def open_help(self) -> None:
        from wecook_tui.screens.catalogue import other_screens

        self.push_screen(HelpScreen(list(MAIN_BINDINGS), dict(self.keys.keymap), other_screens()))

    def open_plan(self) -> None:
        if self.analysis is None:
            self.notify("The analysis is not ready yet.", severity="warning")
            return
        from wecook_core.model import SegmentStatus
        from wecook_tui.review import status_of
        from wecook_tui.screens.plan_review import PlanReviewScreen, ReviewCounts

        segs = self.analysis.segmentation.segments
        statuses = [status_of(self.corrections, s.start) for s in segs]
        counts = ReviewCounts(len(segs), statuses.count(SegmentStatus.UNREVIEWED),
                              statuses.count(SegmentStatus.REJECTED))
        self.push_screen(PlanReviewScreen(self.analysis, self.obs, self.session_path, counts))

    def open_runs(self, start: bool, live_port: int | None = None) -> None:
        if start and self.analysis is None:
            self.notify("The analysis is not ready yet.", severity="warning")
            return
        from wecook_tui.screens.run import RunScreen

        command = {"command": self.run_command} if self.run_command is not None else {}
        self.push_screen(RunScreen(self.session_path, self.analysis if start else None, self.obs, **command,
                                   live_port=live_port if start else None))

    def get_system_commands(self, screen: Screen) -> Iterable[SystemCommand]:
        yield from super().get_system_commands(screen)
        if isinstance(screen, MainScreen):
            for binding in MAIN_BINDINGS:
                keys = self.keys.keymap.get(binding.id or "", binding.key)
                yield SystemCommand(binding.description, f"keys: {keys}   id: {binding.id}",
                                    partial(self.run_action, binding.action, screen))


def tune_gc() -> None:
    """Collect the young generation less often. Every frame step allocates a few thousand short-lived segments,
    and with the default thresholds that triggers full (generation 2) collections of 50-130 ms every dozen
    steps: the p95 of key -> repaint fell from about 100 ms to about 30 ms with these (bench.workbench)."""
    gc.set_threshold(20_000, 50, 100)
