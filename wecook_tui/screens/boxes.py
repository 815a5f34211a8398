"""Box mode: draw a box on the frame (mouse drag, or keys to move and resize it), name it, let OpenCV's tracker
carry it through the video until it loses the object, correct it at any frame (a keyframe; boxes between
keyframes are interpolated), export the boxes as CVAT for video XML and wecook CSV. `p` proposes boxes on the
current frame (a COCO detector, :mod:`wecook_tui.screens.box_proposals`) to keep, name and track instead of drawing.

The core is :mod:`wecook_core.observations.tracking`; this screen runs the tracker in a worker and makes every
edit a box correction (:mod:`wecook_core.session.boxes`) through a :class:`BoxEdits`: in the workbench
(:class:`SessionEdits`) they are journaled like every correction, so undo and redo work here and on the review
screen alike, they survive quitting, and the analysis re-runs on them; `wecook boxes` (no session) keeps them in
memory (:class:`MemoryEdits`). The tracks shown are always the fold of the corrections in effect.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

from textual import events, work
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.reactive import var
from textual.screen import Screen
from textual.widgets import Footer, Static

from wecook_core.observations.tracking import Box, BoxTrack, TrackParams, track_from_last_keyframe
from wecook_core.session.boxes import (
    UNNAMED,
    BoxCorrection,
    DropBoxKeyframe,
    SetBoxKeyframe,
    SetBoxLabel,
    rounded,
    tracked,
)
from wecook_tui.box_edits import BoxEdits, MemoryEdits
from wecook_tui.frames import BoxMark, FrameSource, Overlay
from wecook_tui.screens.box_name import NameScreen, known_labels
from wecook_tui.screens.box_proposals import PROPOSAL_BINDINGS, ProposalActions
from wecook_tui.widgets.frame_view import FrameView

STEP = 0.02
"""A key moves or resizes the box by this fraction of the frame."""

COLOURS = ((230, 90, 60), (80, 170, 240), (120, 210, 90), (240, 200, 60), (200, 110, 230), (90, 220, 210))

BOX_BINDINGS: list[Binding] = [
    Binding("right,l", "step(1)", "Next frame", id="boxes-next-frame"),
    Binding("left,h", "step(-1)", "Prev frame", id="boxes-prev-frame"),
    Binding("shift+right,L", "step(10)", "+10 frames", show=False, id="boxes-forward-10"),
    Binding("shift+left,H", "step(-10)", "-10 frames", show=False, id="boxes-back-10"),
    Binding("b", "new_box", "New box", id="boxes-new"),
    *PROPOSAL_BINDINGS,
    Binding("w", "move(0,-1)", "Up", show=False, id="boxes-up"),
    Binding("s", "move(0,1)", "Down", show=False, id="boxes-down"),
    Binding("a", "move(-1,0)", "Left", show=False, id="boxes-left"),
    Binding("d", "move(1,0)", "Right", show=False, id="boxes-right"),
    Binding("D", "resize(1,0)", "Wider", show=False, id="boxes-wider"),
    Binding("A", "resize(-1,0)", "Narrower", show=False, id="boxes-narrower"),
    Binding("S", "resize(0,1)", "Taller", show=False, id="boxes-taller"),
    Binding("W", "resize(0,-1)", "Shorter", show=False, id="boxes-shorter"),
    Binding("n", "name", "Name", id="boxes-name"),
    Binding("t", "track", "Track", id="boxes-track"),
    Binding("tab", "next_box", "Next box", show=False, id="boxes-next"),
    Binding("x", "drop_keyframe", "Drop keyframe", show=False, id="boxes-drop"),
    Binding("z,ctrl+z", "undo", "Undo", id="boxes-undo"),
    Binding("y,ctrl+y", "redo", "Redo", show=False, id="boxes-redo"),
    Binding("e", "export", "Export", id="boxes-export"),
    Binding("escape,q", "back", "Back", id="boxes-back"),
]


@dataclass(frozen=True)
class BoxVideo:
    """What the box mode works on."""

    path: str
    size: tuple[int, int]
    """(width, height) pixels."""
    fps: float
    frame_count: int


class BoxScreen(Screen[None], ProposalActions):
    BINDINGS: ClassVar[list[BindingType]] = list(BOX_BINDINGS)

    frame: var[int] = var(0, init=False)

    def __init__(self, video: BoxVideo, out_dir: Path, *, source: FrameSource | None = None,
                 labels: Callable[[], list[str]] = known_labels, params: TrackParams | None = None,
                 exit_on_back: bool = False, edits: BoxEdits | None = None, start: int = 0,
                 propose: bool = False) -> None:
        super().__init__()
        self.init_proposals()
        self.propose_on_open = propose
        """Propose boxes on the first frame shown when there is no box yet (a video alone: a start)."""
        self.start = max(0, min(video.frame_count - 1, start))
        """The frame shown first."""
        self.exit_on_back = exit_on_back
        """Back quits the app (`wecook boxes`) instead of returning to the workbench."""
        self.video = video
        self.out_dir = Path(out_dir)
        self.source = source if source is not None else FrameSource(video.path)
        self.labels = labels
        self.params = params or TrackParams()
        self.edits: BoxEdits = edits if edits is not None else MemoryEdits()
        self.tracks: list[BoxTrack] = list(self.edits.tracks())
        """The tracks the corrections in effect give (reloaded after every edit)."""
        self.selected: int | None = len(self.tracks) - 1 if self.tracks else None
        self._last_id = max((t.track_id for t in self.tracks), default=0)
        self._drag: tuple[float, float] | None = None
        self._marks: dict[int, str] = {}
        """The name each shown box is drawn with, by track (a click names the box it hit)."""
        self.tracking = False

    def compose(self) -> ComposeResult:
        yield FrameView(id="box-frame", graphics=True)
        yield Static("", id="box-status")
        yield Footer()

    def on_mount(self) -> None:
        view = self.query_one(FrameView)
        view.set_source(self.source, self.video.size)
        self.set_reactive(BoxScreen.frame, self.start)
        self._show()
        if self.propose_on_open and not self.tracks:
            self.action_propose()

    # --------------------------------------------------------------------------------- state

    def _apply(self, correction: BoxCorrection) -> None:
        """Record one correction, then show the tracks it gives (the same box stays selected)."""
        if self.edits.apply(correction):
            self._reload(correction.track)

    def _reload(self, select: int | None = None) -> None:
        current = self.current()
        keep = select if select is not None else (current.track_id if current is not None else None)
        self.tracks = list(self.edits.tracks())
        self._last_id = max(self._last_id, *(t.track_id for t in self.tracks), 0)
        ids = [t.track_id for t in self.tracks]
        self.selected = ids.index(keep) if keep in ids else (len(ids) - 1 if ids else None)
        self._show()

    def current(self) -> BoxTrack | None:
        if self.selected is None or not 0 <= self.selected < len(self.tracks):
            return None
        return self.tracks[self.selected]

    def box_at(self, track: BoxTrack, frame: int) -> Box | None:
        return track.boxes().get(frame)

    def _overlay(self) -> Overlay:
        marks = []
        self._marks = {}
        for i, track in enumerate(self.tracks):
            box = self.box_at(track, self.frame)
            if box is not None:
                key = " *" if self.frame in track.keyframes else ""
                self._marks[i] = f"{track.label}{key}"
                marks.append(BoxMark(self._marks[i], box, COLOURS[i % len(COLOURS)], held=i == self.selected))
        return Overlay(boxes=(*marks, *self.proposal_marks()))

    def _show(self) -> None:
        self.query_one(FrameView).show(self.frame, self._overlay())
        track = self.current()
        # Frames counted from 0, as on the review screen and in the files.
        seconds = f" ({self.frame / self.video.fps:.2f} s)" if self.video.fps > 0 else ""
        parts = [f"frame {self.frame}/{self.video.frame_count - 1}{seconds}"]
        if track is not None:
            keys = ", ".join(str(f) for f in sorted(track.keyframes))
            state = "tracking..." if self.tracking else (
                f"lost at frame {track.lost_at}" if track.lost_at is not None else
                f"tracked to frame {max(track.tracked)}" if track.tracked else "not tracked")
            name = f"{track.label} (unnamed: n names it)" if track.label == UNNAMED else track.label
            parts.append(f"{name} (keyframes {keys}; {state})")
        parts.append(f"{len(self.tracks)} boxes")
        proposals = self.proposal_status()
        if proposals:
            parts.append(proposals)
        message = self.edits.message()
        if message:
            parts.append(message)
        self.query_one("#box-status", Static).update("   ".join(parts))

    def watch_frame(self) -> None:
        self._show()

    # ------------------------------------------------------------------------------- actions

    def action_step(self, delta: int) -> None:
        self.frame = max(0, min(self.video.frame_count - 1, self.frame + delta))

    def action_new_box(self) -> None:
        w, h = self.video.size
        box = (0.4 * w, 0.4 * h, 0.6 * w, 0.6 * h)
        self.add_box(box)

    def add_box(self, box: Box, label: str = UNNAMED) -> None:
        """A new box at the current frame, selected. It is named only when the user asks (n): the keys typed
        next are meant to move and fit it, never to become its name."""
        track_id = self._last_id + 1
        if not self.edits.apply(SetBoxKeyframe(track_id, self.frame, rounded(self._clip(box)),
                                               None if label == UNNAMED else label)):
            return
        self._last_id = track_id
        self._reload(track_id)

    def set_keyframe(self, box: Box) -> None:
        """The selected box is ``box`` at the current frame (a keyframe)."""
        track = self.current()
        if track is not None:
            self._apply(SetBoxKeyframe(track.track_id, self.frame, rounded(self._clip(box))))

    def _edit(self, change: Callable[[Box], Box]) -> None:
        track = self.current()
        if track is None:
            self.notify("No box: draw one (b or a mouse drag).", severity="warning")
            return
        box = self.box_at(track, self.frame)
        if box is None:
            box = track.keyframes[max(f for f in track.keyframes if f <= self.frame)] if any(
                f <= self.frame for f in track.keyframes) else track.keyframes[min(track.keyframes)]
        self.set_keyframe(change(box))

    def _clip(self, box: Box) -> Box:
        w, h = self.video.size
        x1, y1, x2, y2 = box
        x1, x2 = sorted((min(max(x1, 0.0), w), min(max(x2, 0.0), w)))
        y1, y2 = sorted((min(max(y1, 0.0), h), min(max(y2, 0.0), h)))
        return (x1, y1, max(x2, x1 + 1), max(y2, y1 + 1))

    def action_move(self, dx: int, dy: int) -> None:
        w, h = self.video.size
        self._edit(lambda b: (b[0] + dx * STEP * w, b[1] + dy * STEP * h, b[2] + dx * STEP * w, b[3] + dy * STEP * h))

    def action_resize(self, dx: int, dy: int) -> None:
        w, h = self.video.size
        self._edit(lambda b: (b[0], b[1], b[2] + dx * STEP * w, b[3] + dy * STEP * h))

    def action_next_box(self) -> None:
        if self.tracks:
            self.selected = 0 if self.selected is None else (self.selected + 1) % len(self.tracks)
            self._show()

    def action_name(self) -> None:
        track = self.current()
        if track is None:
            return
        track_id = track.track_id

        def named(label: str | None) -> None:
            if label and label != track.label:
                self._apply(SetBoxLabel(track_id, label))

        current = self.hints.get(track_id, "") if track.label == UNNAMED else track.label
        self.app.push_screen(NameScreen(self.labels(), current), named)

    def action_drop_keyframe(self) -> None:
        track = self.current()
        if track is None or self.frame not in track.keyframes:
            return
        self._apply(DropBoxKeyframe(track.track_id, self.frame))

    def action_undo(self) -> None:
        self.edits.undo()
        self._reload()

    def action_redo(self) -> None:
        self.edits.redo()
        self._reload()

    def action_track(self) -> None:
        track = self.current()
        if track is None or self.tracking:
            return
        self.tracking = True
        self._show()
        self._track(track)

    @work(thread=True, exclusive=True, group="box-track", exit_on_error=False)
    def _track(self, track: BoxTrack) -> None:
        try:
            result = track_from_last_keyframe(self.video.path, track, self.video.fps, self.params)
        except Exception as error:  # say what failed, never a traceback
            self.app.call_from_thread(self._tracked, track, f"{type(error).__name__}: {error}")
            return
        self.app.call_from_thread(self._tracked, result, None)

    def _tracked(self, result: BoxTrack, error: str | None) -> None:
        self.tracking = False
        now = next((t for t in self.tracks if t.track_id == result.track_id), None)
        if error is not None:
            self.notify(f"Tracking failed: {error}", severity="error")
        elif now is not None and now.keyframes == result.keyframes:  # not edited meanwhile
            self._apply(tracked(result.track_id, result))
            end = result.lost_at if result.lost_at is not None else "the end"
            self.notify(f"{result.label}: followed {len(result.tracked)} frames (to {end})")
        self._show()

    def action_export(self) -> None:
        paths = self.export()
        if paths:
            self.notify(f"Wrote {paths[0]} and {paths[1]}")

    def export(self) -> tuple[Path, Path] | None:
        from wecook_core.formats.cvat_write import write_cvat
        from wecook_core.formats.native import write_objects_csv

        if not self.tracks:
            self.notify("No boxes to export.", severity="warning")
            return None
        objects = [t.object_track() for t in self.tracks]
        self.out_dir.mkdir(parents=True, exist_ok=True)
        xml, csv = self.out_dir / "boxes.xml", self.out_dir / "boxes.csv"
        write_cvat(xml, objects, size=self.video.size, keyframes={t.track_id: t.keyframes for t in self.tracks})
        write_objects_csv(csv, objects)
        return xml, csv

    def action_back(self) -> None:
        if self.exit_on_back:
            self.app.exit()
        else:
            self.app.pop_screen()

    # --------------------------------------------------------------------------------- mouse

    def pixel(self, x: int, y: int) -> tuple[float, float] | None:
        """The video pixel under cell (x, y) of the frame view, or None outside the picture (the view's own
        mapping: half-blocks or a graphics protocol's picture alike)."""
        return self.query_one(FrameView).pixel_at(x, y)

    def on_frame_view_clicked(self, message: FrameView.Clicked) -> None:
        """A click (no drag) on a box or its label selects that box; of boxes drawn with one name, the
        smallest under the click."""
        message.stop()
        if self.keep_clicked(message.box):
            return
        px, py = message.pixel

        def rank(i: int) -> tuple[bool, float]:
            x1, y1, x2, y2 = self.box_at(self.tracks[i], self.frame) or (0.0, 0.0, 0.0, 0.0)
            return (not (x1 <= px <= x2 and y1 <= py <= y2), (x2 - x1) * (y2 - y1))

        named = sorted((i for i, name in self._marks.items() if name == message.box), key=rank)
        if named and named[0] != self.selected:
            self.selected = named[0]
            self._show()

    def on_mouse_down(self, event: events.MouseDown) -> None:
        offset = event.get_content_offset(self.query_one(FrameView))
        self._drag = self.pixel(offset.x, offset.y) if offset is not None else None

    def on_mouse_up(self, event: events.MouseUp) -> None:
        start, self._drag = self._drag, None
        offset = event.get_content_offset(self.query_one(FrameView))
        end = self.pixel(offset.x, offset.y) if offset is not None else None
        if start is None or end is None or abs(end[0] - start[0]) < 2 or abs(end[1] - start[1]) < 2:
            return
        box = self._clip((min(start[0], end[0]), min(start[1], end[1]), max(start[0], end[0]),
                          max(start[1], end[1])))
        track = self.current()
        if track is not None and self.box_at(track, self.frame) is not None:
            self.set_keyframe(box)
        else:
            self.add_box(box)


def box_video(app: Any) -> BoxVideo | None:
    """The video of the workbench's open session (None before it opened)."""
    obs = getattr(app, "obs", None)
    if obs is None:
        return None
    video = obs.video
    return BoxVideo(video.path, (video.width, video.height), float(video.fps),
                    max(1, video.decoded_frames or video.frame_count))
