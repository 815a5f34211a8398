"""What a role's program is made of: ticks, the failure it raises, the meeting of a collaboration's roles, and the
world the scheduler drives (:mod:`wecook_core.execution.schedule.executor` runs them; :mod:`wecook_core.execution.world`
builds them)."""

from __future__ import annotations

from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass, field
from typing import Literal, Protocol, cast

from wecook_core.plan import PlanAction

Tick = Literal["work", "wait"]
WORK: Tick = "work"
WAIT: Tick = "wait"
Program = Generator[Tick, None, None]


class _Wait(str):
    """A WAIT tick that says what it waits for (it equals :data:`WAIT`)."""

    what: str

    def __new__(cls, what: str) -> _Wait:
        tick = super().__new__(cls, WAIT)
        tick.what = what
        return tick


def waiting(what: str) -> Tick:
    """A :data:`WAIT` tick naming what the arm waits for ("a3 (cut) to end", "P1 to let go of the knife"): the
    scheduler turns waits into ``wait`` events."""
    return cast(Tick, _Wait(what))


def waits_for(tick: Tick) -> str | None:
    """What a WAIT tick waits for (None: it does not say)."""
    return getattr(tick, "what", None)


class ActionFailed(Exception):
    """A role of an action cannot go on; the message is the reason shown to the user."""


class PathBlocked(ActionFailed):
    """A straight path that reaches its poses but passes through something (not: out of reach)."""


@dataclass
class Meeting:
    """Where the roles of one collaboration meet: who has arrived, signals raised, a failure."""

    needed: frozenset[str]
    arrived: set[str] = field(default_factory=set)
    finished: set[str] = field(default_factory=set)
    signals: set[str] = field(default_factory=set)
    failure: str | None = None

    def signal(self, name: str) -> None:
        self.signals.add(name)

    def fail(self, reason: str) -> None:
        if self.failure is None:
            self.failure = reason

    def wait_for(self, name: str, ticks: Callable[[], Iterator[Tick]] | None = None, pid: str | None = None
                 ) -> Program:
        """Yield WAIT until ``name`` is signalled; raise :class:`ActionFailed` if the partner failed."""
        partner = "+".join(sorted(self.needed - {pid})) if pid is not None else "the partner"
        tick = waiting(f"the collaboration partner {partner} ({name.replace('_', ' ')})")
        while name not in self.signals:
            if self.failure is not None:
                raise ActionFailed(f"partner failed: {self.failure}")
            yield tick
        if self.failure is not None:
            raise ActionFailed(f"partner failed: {self.failure}")


class World(Protocol):
    """What the scheduler needs from a simulation (the PyBullet world, or a fake in tests)."""

    @property
    def time(self) -> float: ...

    @property
    def dt(self) -> float: ...

    def step(self) -> None: ...

    def program(self, action: PlanAction, pid: str, meeting: Meeting) -> Program:
        """The primitives of ``pid``'s role in ``action``; raises :class:`ActionFailed` with the reason."""
        ...

    def recover(self, pid: str) -> Program:
        """After a failure: let go of what the arm holds and return it home (best effort, never raises)."""
        ...

    def action_boundary(self, action: PlanAction, kind: str) -> None:
        """Called at action start and end (the PyBullet world takes a camera image)."""
        ...
