"""The box mode's proposals: `p` runs the COCO detector (:mod:`wecook_core.observations.proposals`) on the current
frame in a worker and draws what it finds, numbered, in grey, with the detector's class as a hint (``2 bowl?``);
a digit, a click on one or `K` (all) keeps proposals as boxes at that frame, which the user then names (`n`, the
prompt starts from the hint), fits and tracks like a drawn box.

Proposals are computed on demand, for the frame the user looks at (a frame takes about 50 ms on a CPU), and kept
for the screen's life: they depend on the pixels alone, so nothing is stored in the session and nothing goes
stale. A proposal that a box at its frame already covers (IoU 0.5) is not shown, so a kept one disappears, and
comes back when the keep is undone.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from textual.binding import Binding

from wecook_core.observations.proposals import Proposal, iou, propose_at
from wecook_tui.frames import BoxMark

if TYPE_CHECKING:
    from wecook_core.observations.tracking import Box, BoxTrack

PROPOSAL_COLOUR = (190, 190, 190)
COVERED_IOU = 0.5
"""A proposal overlapping a box of its frame by this IoU is taken as boxed already, and not shown."""

PROPOSAL_BINDINGS: list[Binding] = [
    Binding("p", "propose", "Propose boxes", id="boxes-propose"),
    *(Binding(str(n), f"keep({n})", f"Keep proposal {n}", show=False, id=f"boxes-keep-{n}") for n in range(1, 10)),
    Binding("K", "keep_all", "Keep all proposals", show=False, id="boxes-keep-all"),
]


class ProposalActions:
    """The proposal half of the box screen (:class:`~wecook_tui.screens.boxes.BoxScreen` mixes it in)."""

    if TYPE_CHECKING:
        frame: int
        tracks: list[BoxTrack]
        _last_id: int
        app: Any

        video: Any
        def box_at(self, track: BoxTrack, frame: int) -> Box | None: ...
        def add_box(self, box: Box, label: str = ...) -> None: ...
        def _show(self) -> None: ...
        def notify(self, message: str, *, severity: Any = ...) -> None: ...
        def run_worker(self, work: Any, *, thread: bool = ..., group: str = ..., exclusive: bool = ...,
                       exit_on_error: bool = ...) -> Any: ...

    def init_proposals(self) -> None:
        self.proposals: dict[int, tuple[Proposal, ...]] = {}
        """What the detector proposed, by frame (0-based)."""
        self.proposing: int | None = None
        """The frame the detector runs on now, if any."""
        self.proposals_hidden: set[int] = set()
        """Frames whose proposals the user hid (p again)."""
        self.hints: dict[int, str] = {}
        """Track id -> the name its proposal suggested (the name prompt starts from it)."""
        self._proposal_names: dict[str, int] = {}
        """The name each shown proposal is drawn with -> its number (a click keeps the proposal it hit)."""

    def shown_proposals(self) -> list[tuple[int, Proposal]]:
        """The current frame's proposals that no box there covers, numbered from 1 (best score first)."""
        if self.frame in self.proposals_hidden:
            return []
        boxes = [box for track in self.tracks if (box := self.box_at(track, self.frame)) is not None]
        return [(n, p) for n, p in enumerate(self.proposals.get(self.frame, ()), 1)
                if all(iou(p.box, box) < COVERED_IOU for box in boxes)]

    def proposal_marks(self) -> list[BoxMark]:
        self._proposal_names = {}
        marks = []
        for number, proposal in self.shown_proposals():
            name = f"{number} {proposal.hint}?"
            self._proposal_names[name] = number
            marks.append(BoxMark(name, proposal.box, PROPOSAL_COLOUR))
        return marks

    def proposal_status(self) -> str | None:
        """The status line's word on proposals at the current frame (None: nothing to say)."""
        if self.proposing == self.frame:
            return "proposing boxes..."
        if self.frame not in self.proposals:
            return None
        if self.frame in self.proposals_hidden:
            return "proposals hidden (p shows them)"
        found = len(self.proposals[self.frame])
        if found == 0:
            return "no box proposed on this frame: draw one (b)"
        shown = len(self.shown_proposals())
        if shown == 0:
            return f"all {found} proposals boxed"
        return f"{shown} of {found} proposals: 1-9 or a click keeps one, K all, p hides"

    def action_propose(self) -> None:
        frame = self.frame
        if frame in self.proposals:  # computed already: p shows or hides them
            self.proposals_hidden ^= {frame}
            self._show()
            return
        if self.proposing is not None:
            self.notify(f"Still proposing boxes on frame {self.proposing}.", severity="warning")
            return
        self.proposing = frame
        self._show()
        path = self.video.path
        self.run_worker(lambda: self._propose(path, frame), thread=True, group="box-propose", exit_on_error=False)

    def _propose(self, path: str, frame: int) -> None:
        try:
            found = propose_at(path, frame)
        except Exception as error:  # one line (an InputError says what to install), never a traceback
            self.app.call_from_thread(self._proposed, frame, (), str(error) or type(error).__name__)
            return
        self.app.call_from_thread(self._proposed, frame, found, None)

    def _proposed(self, frame: int, found: tuple[Proposal, ...], error: str | None) -> None:
        self.proposing = None
        if error is not None:
            self.notify(f"Proposals failed: {error}", severity="error")
        else:
            self.proposals[frame] = found
            self.proposals_hidden.discard(frame)
        self._show()

    def action_keep(self, number: int) -> None:
        proposal = dict(self.shown_proposals()).get(number)
        if proposal is None:
            self.notify(f"No proposal {number} on this frame (p proposes boxes).", severity="warning")
            return
        self.keep(proposal)

    def action_keep_all(self) -> None:
        shown = self.shown_proposals()
        if not shown:
            self.notify("No proposal to keep on this frame (p proposes boxes).", severity="warning")
        for _, proposal in shown:
            self.keep(proposal)

    def keep(self, proposal: Proposal) -> None:
        """The proposal becomes a box at the current frame, selected and unnamed; its hint waits for `n`."""
        before = self._last_id
        self.add_box(proposal.box)
        if self._last_id != before:
            self.hints[self._last_id] = proposal.hint

    def keep_clicked(self, name: str | None) -> bool:
        """Keep the proposal drawn as ``name`` (a click on it); False when no proposal is drawn so."""
        number = self._proposal_names.get(name or "")
        if number is None:
            return False
        self.action_keep(number)
        return True
