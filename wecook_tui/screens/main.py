"""The review screen: frame, timeline and inspector; every key of the review lives here."""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

from rich.text import Text
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal
from textual.reactive import var
from textual.screen import Screen
from textual.timer import Timer
from textual.widgets import Footer

from wecook_core.model import VERBS, Segment, SegmentStatus
from wecook_tui import edits, review
from wecook_tui.screens.links import LinkPickerScreen
from wecook_tui.screens.picker import PickerScreen
from wecook_tui.widgets.frame_view import FrameView
from wecook_tui.widgets.inspector import Inspector
from wecook_tui.widgets.status_line import StatusLine
from wecook_tui.widgets.timeline import Timeline
from wecook_tui.workbench_state import Workbench, workbench

if TYPE_CHECKING:
    from wecook_tui.resume import PositionKeeper

MAIN_BINDINGS: list[Binding] = [  # help and quit first: the footer is cut on the right in a narrow terminal
    Binding("question_mark,f1", "help", "Help", id="help"),
    Binding("q", "quit", "Quit", id="quit"),
    Binding("right,l", "step(1)", "Next frame", id="next-frame"),
    Binding("left,h", "step(-1)", "Prev frame", id="prev-frame"),
    Binding("shift+right,L", "step(10)", "+10 frames", show=False, id="forward-10"),
    Binding("shift+left,H", "step(-10)", "-10 frames", show=False, id="back-10"),
    Binding("down,n", "segment(1)", "Next segment", id="next-segment"),
    Binding("up,p", "segment(-1)", "Prev segment", show=False, id="prev-segment"),
    Binding("u", "next_unreviewed", "Next unreviewed", id="next-unreviewed"),
    Binding("U", "next_unreviewed(-1)", "Prev unreviewed", show=False, id="prev-unreviewed"),
    Binding("g", "go_to", "Go to frame/time/segment", show=False, id="go-to"),
    Binding("space", "play_pause", "Play/pause", id="play-pause"),
    Binding("t", "next_hand", "Select hand", show=False, id="next-hand"),
    Binding("a", "accept", "Accept", id="accept"),
    Binding("x", "reject", "Reject", id="reject"),
    Binding("c", "change_action", "Change action", id="change-action"),
    Binding("C", "change_action(False)", "Change action (segment only)", show=False, id="change-action-here"),
    Binding("o", "change_object", "Change object", show=False, id="change-object"),
    Binding("O", "change_object(False)", "Change object (segment only)", show=False, id="change-object-here"),
    Binding("k", "change_link", "Change link", show=False, id="change-link"),
    Binding("K", "change_link(False)", "Change link (segment only)", show=False, id="change-link-here"),
    Binding("s", "split", "Split here", show=False, id="split"),
    Binding("m", "merge", "Merge with next", show=False, id="merge"),
    Binding("z,ctrl+z", "undo", "Undo", id="undo"),
    Binding("y,ctrl+y", "redo", "Redo", show=False, id="redo"),
    Binding("e", "plan", "Plan / export", id="export-plan"),
    Binding("r", "run", "Run", id="run"),
    Binding("R", "runs", "Past runs", show=False, id="open-runs"),
    Binding("v", "run_live", "Run, served live for Foxglove", show=False, id="run-live"),
    Binding("B", "boxes", "Box mode: draw, track and correct boxes", show=False, id="box-mode"),
    Binding("N", "categorise", "Categorise labels nothing knows", show=False, id="categorise-labels"),
]


class MainScreen(Screen[None]):
    BINDINGS: ClassVar[list[BindingType]] = [*MAIN_BINDINGS]

    # `var`: a change calls the watcher but does not repaint the whole screen (widgets refresh themselves)
    frame: var[int] = var(0, init=False)
    """The cursor: a 0-based frame index."""
    selected_hand: var[str | None] = var(None, init=False)
    """The hand that change-action / change-object / change-link act on."""
    playing: var[bool] = var(False, init=False)

    def __init__(self) -> None:
        super().__init__()
        self._inspected: tuple | None = None
        self._timer: Timer | None = None
        self._hand_chosen = False
        """The user picked a hand (t) in this segment; until then the first hand acting there is selected."""
        self._segment: Segment | None = None
        self._clock = (0.0, 0)
        """(perf_counter, frame) when playback started."""
        self._told: set[str] = set()
        """Unknown labels the user was told about (each once)."""
        self._keeper: PositionKeeper | None = None
        self._keep_timer: Timer | None = None

    @property
    def wb(self) -> Workbench:
        return workbench(self.app)

    def compose(self) -> ComposeResult:
        with Horizontal(id="top"):
            yield FrameView(id="frame", graphics=True)
            yield Inspector(id="inspector")
        yield Timeline(id="timeline")
        yield StatusLine(id="status")
        yield Footer()

    # ------------------------------------------------------------------------------- view state

    @property
    def frame_count(self) -> int:
        return self.wb.frame_count

    def segments(self) -> tuple[Segment, ...]:
        return review.segments(self.wb.analysis, self.frame_count)

    def current(self) -> tuple[int, Segment]:
        segs = self.segments()
        index = review.segment_index(segs, self.frame)
        return index, segs[index]

    def data_changed(self) -> None:
        """Session, analysis or corrections changed: redraw everything."""
        wb = self.wb
        self._select_acting_hand()
        hands = review.hands_of(wb.obs)
        if wb.obs is not None:
            timeline = self.query_one(Timeline)
            segs = self.segments()
            corrections = wb.corrections
            status = {s.start: review.status_of(corrections, s.start) for s in segs}
            unsure = {s.start for s in segs if review.unsure_of(wb.analysis, s)
                      and review.to_review(corrections, s.start, {s.start: ""})}
            timeline.set_data(self.frame_count, review.lanes(wb.analysis, hands, self.frame_count), segs, status,
                              unsure)
        self._inspected = None
        self.refresh_view()
        self._tell_unknown_labels()

    def _tell_unknown_labels(self) -> None:
        """Say once per label that labels nothing categorises were taken as ingredients, and how to answer."""
        new = [label for label in review.unknown_labels(self.wb.opened) if label not in self._told]
        if new:
            self._told.update(new)
            self.notify(f"No category known for {', '.join(repr(label) for label in new)}: taken as ingredient "
                        "until you say. Press N to choose tool, container or ingredient.",
                        title="Unknown labels", severity="warning", timeout=20)

    def _select_acting_hand(self) -> None:
        """Select the first hand acting in the segment, unless the user chose one (t) here."""
        hands = review.hands_of(self.wb.obs)
        if self.selected_hand in hands and self._hand_chosen:
            return
        index, seg = self.current()
        acting = [h for h in hands if h in review.actions_of(self.wb.analysis, seg, index)]
        choices: list[str | None] = [*acting, *hands, None]
        self.selected_hand = choices[0]

    def jump_to(self, span: tuple[int, int | None] | None) -> None:
        """Show what an edit changed: move the cursor to ``span``'s start unless it is already inside (None:
        the edit has no place, a category)."""
        if span is None:
            return
        start, end = span
        if not (start <= self.frame < (end if end is not None else start + 1)):
            self.frame = max(0, min(self.frame_count - 1, start))

    def refresh_view(self) -> None:
        wb = self.wb
        index, seg = self.current()
        if seg != self._segment:
            self._segment = seg
            self._hand_chosen = False
            self._select_acting_hand()
            if wb.opened is not None:
                self._remember()
        assoc = review.associations_of(wb.analysis, index, seg)
        self.query_one(FrameView).show(self.frame, review.overlay(wb.obs, assoc, self.frame, self.selected_hand))
        timeline = self.query_one(Timeline)
        timeline.cursor = self.frame
        timeline.selected_hand = self.selected_hand
        status = review.status_of(wb.corrections, seg.start)
        key = (id(wb.analysis), index, seg, status, self.selected_hand, wb.pending, id(wb.corrections))
        if key != self._inspected:
            self._inspected = key
            actions = review.actions_of(wb.analysis, seg, index)
            rankings = {hand: review.ranking_of(wb.analysis, seg, index, hand) for hand in actions}
            self.query_one(Inspector).show(
                index, len(self.segments()), seg, status, review.trees_of(wb.analysis, seg), assoc,
                actions, self.selected_hand, wb.pending, rankings, self._unsure(seg))
        fps = wb.fps
        state = ("  ▶ playing" if self.playing else "",
                 ("  recomputing…" if wb.pending else ("  opening…" if wb.opened is None else ""), "bold yellow"),
                 (f"  {wb.last_message}" if wb.last_message else "", "bold #ffb300"))
        line = Text.assemble(
            (f" {wb.session_name} ", "bold reverse"),
            f"  frame {self.frame}/{max(0, self.frame_count - 1)} ({self.frame / fps:.2f} s)",
            f"  segment {index + 1}/{len(self.segments())}",
            f"  hand {self.selected_hand or '-'}", *state)
        if line.cell_len > self.size.width:  # a narrow terminal: the short form, so the answer still shows
            line = Text.assemble(f" {self.frame}/{max(0, self.frame_count - 1)}",
                                 f" seg {index + 1}/{len(self.segments())}", f" {self.selected_hand or '-'}",
                                 *state)
        self.query_one(StatusLine).show(line)

    def _unsure(self, seg: Segment) -> str | None:
        """Why ``seg`` is unsure, while it is still to review (an accepted or rejected one is settled)."""
        reason = review.unsure_of(self.wb.analysis, seg)
        if reason and review.to_review(self.wb.corrections, seg.start, {seg.start: reason}):
            return reason
        return None

    def watch_frame(self) -> None:
        self.refresh_view()

    def watch_selected_hand(self) -> None:
        self.refresh_view()

    # ----------------------------------------------------------------------------------- moving

    def action_step(self, delta: int) -> None:
        self.frame = max(0, min(self.frame_count - 1, self.frame + delta))

    def action_segment(self, delta: int) -> None:
        segs = self.segments()
        index = review.segment_index(segs, self.frame)
        self.frame = segs[max(0, min(len(segs) - 1, index + delta))].start

    def action_next_unreviewed(self, direction: int = 1) -> None:
        segs = self.segments()
        unsure = getattr(self.wb.analysis, "unsure", None)
        index = review.next_unreviewed(segs, self.wb.corrections, review.segment_index(segs, self.frame), direction,
                                       unsure)
        if index is None:
            self.notify("Every segment is reviewed.")
        else:
            self.frame = segs[index].start

    def on_timeline_seek(self, message: Timeline.Seek) -> None:
        self.frame = max(0, min(self.frame_count - 1, message.frame))

    def on_frame_view_clicked(self, message: FrameView.Clicked) -> None:
        """A click on a hand selects it; on a box, selects that object and the hand holding it here."""
        self.query_one(FrameView).select_box(message.box)
        if message.hand is not None:
            self._hand_chosen = True
            self.selected_hand = message.hand
            self.wb.say(f"Hand {message.hand} selected")
        elif message.box is not None:
            index, seg = self.current()
            assoc = review.associations_of(self.wb.analysis, index, seg)
            holder = next((hand for hand, name in assoc.hand_object.items() if name == message.box), None) \
                if assoc is not None else None
            if holder is not None:
                self._hand_chosen = True
                self.selected_hand = holder
            self.wb.say(f"{message.box}: " + (f"held by {holder}" if holder else "no hand holds it in this segment"))

    def action_go_to(self) -> None:
        from wecook_tui.screens.goto import GoToScreen, parse_target

        def chosen(text: str | None) -> None:
            if text is None:
                return
            frame = parse_target(text, self.wb.fps, tuple(s.start for s in self.segments()))
            if frame is None:
                self.notify(f"Cannot go to {text!r}: type a frame (120), a time (4.5s, 1:05) or a segment (#12).",
                            severity="warning")
                return
            self.frame = max(0, min(self.frame_count - 1, frame))

        self.app.push_screen(GoToScreen(), chosen)

    def action_next_hand(self) -> None:
        hands = review.hands_of(self.wb.obs)
        if hands:
            self._hand_chosen = True
            current = hands.index(self.selected_hand) if self.selected_hand in hands else -1
            self.selected_hand = hands[(current + 1) % len(hands)]

    def action_play_pause(self) -> None:
        self.playing = not self.playing

    def watch_playing(self, playing: bool) -> None:
        if playing:
            import time

            self._clock = (time.perf_counter(), self.frame)
            self._timer = self.set_interval(1 / max(1.0, self.wb.fps), self._tick)
        elif self._timer is not None:
            self._timer.stop()
            self._timer = None
        self.refresh_view()

    def _tick(self) -> None:
        """Show the frame the video's clock has reached (frames are dropped, never slowed, when painting lags)."""
        import time

        started, first = self._clock
        target = first + int((time.perf_counter() - started) * self.wb.fps)
        if target >= self.frame_count - 1:
            self.frame = self.frame_count - 1
            self.playing = False
        elif target != self.frame:
            self.frame = target

    # ------------------------------------------------------------------------------ corrections

    def action_accept(self) -> None:
        self.wb.correct(edits.set_status(self.current()[1], SegmentStatus.ACCEPTED))

    def action_reject(self) -> None:
        self.wb.correct(edits.set_status(self.current()[1], SegmentStatus.REJECTED))

    def _hand_or_warn(self) -> str | None:
        if self.selected_hand is None:
            self.notify("No hand tracks in this session.", severity="warning")
        return self.selected_hand

    def _target(self, hand: str, whole: bool, verb: bool = False) -> tuple[Segment, tuple[int, int] | None, str]:
        """(segment, the span of the whole action corrected, or None for this segment only; where, for titles).
        A verb covers the segments of the action that carry it; an object or link the whole action."""
        _, seg = self.current()
        if whole:
            if verb:
                span = review.verb_span(self.wb.analysis, seg, hand)
            else:
                action = review.whole_action(self.wb.analysis, seg, hand)
                span = (action.start, action.end) if action is not None else None
            if span is not None and span != (seg.start, seg.end):
                return seg, span, f"its whole action [{span[0]}, {span[1]})"
        return seg, None, f"segment [{seg.start}, {seg.end}) only"

    def action_change_action(self, whole: bool = True) -> None:
        hand = self._hand_or_warn()
        if hand is None:
            return
        index, seg = self.current()
        assoc = review.associations_of(self.wb.analysis, index, seg)
        action = review.actions_of(self.wb.analysis, seg, index).get(hand)
        held = assoc.hand_object.get(hand) if assoc else None
        if action is None and not held:
            self.notify(f"Not recorded: {hand} holds nothing in [{seg.start}, {seg.end}), so it has no verb; "
                        "set its object first (o) or select another hand (t).", severity="warning")
            return
        seg, whole_action, where = self._target(hand, whole, verb=True)
        ranking = list(review.ranking_of(self.wb.analysis, seg, index, hand))
        if not ranking:
            ranking = self.wb.rank(review.segment_objects(assoc, action, hand))
        ranked = dict(ranking)
        options = [(verb, f"{verb:<10} {p:.3f}") for verb, p in ranking]
        options += [(verb, f"{verb:<10} -") for verb in VERBS if verb not in ranked]
        current = action.verb if action else None

        def chosen(verb: str | None) -> None:
            if verb:
                self.wb.correct(edits.set_verb(seg, hand, verb, whole_action))

        self.app.push_screen(PickerScreen(f"Action of {hand}, {where}", options, current), chosen)

    def action_change_object(self, whole: bool = True) -> None:
        hand = self._hand_or_warn()
        obs = self.wb.obs
        if hand is None or obs is None:
            return
        index, seg = self.current()
        near = review.objects_near_hand(obs, hand, self.frame, seg)
        options = [(name, f"{name:<16} {d:6.0f} px") for name, d in near] + [(review.NOTHING, "(nothing)")]
        assoc = review.associations_of(self.wb.analysis, index, seg)
        current = assoc.hand_object.get(hand) if assoc else None
        seg, whole_action, where = self._target(hand, whole)

        def chosen(name: str | None) -> None:
            if name:
                held = None if name == review.NOTHING else name
                self.wb.correct(edits.set_hand_object(seg, hand, held, whole_action))

        self.app.push_screen(PickerScreen(f"Object held by {hand}, {where}", options, current), chosen)

    def action_change_link(self, whole: bool = True) -> None:
        hand = self._hand_or_warn()
        obs = self.wb.obs
        if hand is None or obs is None:
            return
        index, seg = self.current()
        assoc = review.associations_of(self.wb.analysis, index, seg)
        action = review.actions_of(self.wb.analysis, seg, index).get(hand)
        held = (assoc.hand_object.get(hand) if assoc else None) or (action.held if action else None)
        if not held:
            self.notify(f"{hand} holds nothing here: set its object first (change object).", severity="warning")
            return
        near = review.link_candidates(obs, held, self.frame, seg)
        options = [(name, f"{name:<16} {d:6.0f} px") for name, d in near]
        targets = assoc.object_object.get(held, ()) if assoc else ()
        seg, whole_action, where = self._target(hand, whole)

        def chosen(new: tuple[str, ...] | None) -> None:
            if new is not None and new != tuple(targets):
                self.wb.correct(edits.set_object_object(seg, held, new, whole_action))

        self.app.push_screen(LinkPickerScreen(f"What {held} acts on, {where}", options, targets), chosen)

    def action_split(self) -> None:
        _, seg = self.current()
        if self.frame <= seg.start:
            self.notify("Move the cursor inside the segment to split it.", severity="warning")
            return
        self.wb.correct(edits.split(self.frame))

    def action_merge(self) -> None:
        segs = self.segments()
        index = review.segment_index(segs, self.frame)
        if index + 1 >= len(segs):
            self.notify("The last segment has no next segment to merge with.", severity="warning")
            return
        self.wb.correct(edits.merge(segs[index + 1].start))

    def action_undo(self) -> None:
        self.wb.undo()

    def action_redo(self) -> None:
        self.wb.redo()

    # ---------------------------------------------------------------------------------- screens

    def action_plan(self) -> None:
        self.wb.open_plan()

    def action_run(self) -> None:
        self.wb.open_runs(start=True)

    def action_run_live(self) -> None:
        """Run the plan served over Foxglove's WebSocket (`wecook execute --live`); the run screen says where."""
        from wecook_core.recording.live import DEFAULT_PORT

        self.wb.open_runs(start=True, live_port=DEFAULT_PORT)

    def action_runs(self) -> None:
        self.wb.open_runs(start=False)

    def action_help(self) -> None:
        self.wb.open_help()

    def action_boxes(self) -> None:
        """Box mode (screens/boxes.py) on the session's video at the cursor: every box drawn, named, tracked or
        corrected is journaled, and the analysis re-runs on it. With no box yet, it opens proposing boxes on its
        frame (a video alone: a start to keep, name and track)."""
        from wecook_tui.box_edits import SessionEdits
        from wecook_tui.screens.boxes import BoxScreen, box_video

        video = box_video(self.app)
        if video is None or self.wb.opened is None:
            self.notify("The session is not open yet.", severity="warning")
            return
        self.app.push_screen(BoxScreen(video, self.wb.session_path / "boxes", edits=SessionEdits(self.app),
                                       start=self.frame, propose=self.wb.obs is None or not self.wb.obs.objects))

    def action_categorise(self) -> None:
        """Ask what each label nothing categorises is (screens/categorise.py)."""
        from wecook_tui.screens.categorise import ask_categories

        ask_categories(self.app)

    def _remember(self) -> None:
        """Keep the cursor for the next opening: at most one write a second (a playback changes segment
        often), the last position written once the second is over, and on quitting."""
        if self._keeper is None:
            from wecook_tui.resume import PositionKeeper

            self._keeper = PositionKeeper(self.wb.session_path)
        if not self._keeper.note(self.frame) and self._keep_timer is None:
            self._keep_timer = self.set_timer(self._keeper.due(), self._flush_position)

    def _flush_position(self) -> None:
        self._keep_timer = None
        if self._keeper is not None:
            self._keeper.flush()

    def on_unmount(self) -> None:
        self._flush_position()

    async def action_quit(self) -> None:
        if self.wb.opened is not None:
            self._remember()
            self._flush_position()
        self.app.exit()
