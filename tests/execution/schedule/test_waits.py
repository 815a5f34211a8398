"""Every wait explained: an arm that waits says what for (an action, a collaboration partner, the other arm's
region), and the run says how long each arm waited."""

from __future__ import annotations

import pytest

from tests.execution.schedule.test_scheduler import FakeWorld, plan
from wecook_core.execution.schedule.executor import WAIT_REPORTED, run_schedule
from wecook_core.plan import PlanAction


class Events:
    def __init__(self) -> None:
        self.events: list = []

    def on_event(self, t, event) -> None:
        self.events.append((t, event))

    def on_log(self, t, level, message) -> None:
        pass


def test_an_arm_waiting_on_an_action_says_which_and_for_how_long() -> None:
    """P2's pour needs P1's cut (1 s of work): P2 says it waits for a1, then that it waited about 1 s."""
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P2",), "pour", "oil", after=("a1",)))
    observer, waited = Events(), {}
    results = run_schedule(p, FakeWorld(ticks=100), observer, waited=waited)
    assert [r.status for r in results] == ["done", "done"]
    waits = [(t, e) for t, e in observer.events if e.kind == "wait"]
    assert [e.agent for _, e in waits] == ["P2", "P2"]
    (t0, told), (_, ended) = waits
    assert told.detail == "waits for a1 (cut) to end" and told.action_id == "a2"
    assert t0 == pytest.approx(WAIT_REPORTED, abs=0.02)
    assert ended.data["for"] == "a1 (cut) to end"
    assert ended.data["seconds"] == pytest.approx(results[0].end, abs=0.02)
    assert waited["P2"] == pytest.approx(results[0].end, abs=0.02)
    assert waited.get("P1", 0.0) == 0.0


def test_a_collaboration_partner_waited_for_is_named() -> None:
    """P1 is busy with its cut; P2 arrives at the handover first and waits for P1 to come."""
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("h", ("P2", "P1"), "handover", "lemon"))
    observer = Events()
    run_schedule(p, FakeWorld(ticks=100), observer)
    details = [e.detail for _, e in observer.events if e.kind == "wait" and e.agent == "P2"]
    assert details[0] == "waits for the collaboration partner P1 to come to h (handover)"


def test_a_short_wait_is_counted_but_not_told() -> None:
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P2",), "pour", "oil", after=("a1",)))
    observer, waited = Events(), {}
    run_schedule(p, FakeWorld(ticks=10), observer, waited=waited)  # a1 takes 0.1 s
    assert not [e for _, e in observer.events if e.kind == "wait"]
    assert waited["P2"] == pytest.approx(0.1, abs=0.02)
