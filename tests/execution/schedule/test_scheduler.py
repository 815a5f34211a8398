"""The scheduler with a fake world: no simulator, scripted primitives."""

from wecook_core.execution.schedule.executor import run_schedule
from wecook_core.execution.schedule.program import WAIT, WORK, ActionFailed, Meeting
from wecook_core.plan import Act, Plan, PlanAction, Scene, agents_for


class FakeWorld:
    """Each role takes ``ticks`` steps; actions named in ``fail`` raise; collaborations meet on a signal."""

    def __init__(self, ticks=5, fail=()):
        self.ticks, self.fail, self.steps = ticks, set(fail), 0
        self.log: list[tuple[float, str, str]] = []

    @property
    def time(self):
        return self.steps * 0.01

    @property
    def dt(self):
        return 0.01

    def step(self):
        self.steps += 1

    def program(self, action, pid, meeting: Meeting):
        self.log.append((self.time, action.id, pid))
        if len(action.pids) > 1:
            first = pid == action.pids[0]
            if first:
                meeting.signal("ready")
            else:
                yield from meeting.wait_for("ready")
        for _ in range(self.ticks):
            yield WORK
        if action.id in self.fail and pid == action.pids[-1]:
            raise ActionFailed(f"scripted failure of {action.id}")

    def recover(self, pid):
        yield WORK

    def action_boundary(self, action, kind):
        pass


def plan(*actions):
    return Plan(agents=agents_for(["P1", "P2"]), scene=Scene(), actions=tuple(actions))


def test_arms_run_concurrently_and_wait_on_after_edges():
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P2",), "stir", "spoon"),
             PlanAction("a3", ("P2",), "pour", "oil", after=("a1", "a2")))
    world = FakeWorld(ticks=10)
    results = run_schedule(p, world)
    assert [r.status for r in results] == ["done", "done", "done"]
    starts = {a: t for t, a, _ in world.log}
    assert starts["a1"] == starts["a2"] == 0.0  # both arms at once
    assert starts["a3"] >= results[0].end and starts["a3"] >= results[1].end


def test_failure_skips_dependents_transitively_and_the_rest_goes_on():
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P1",), "roll", "pin", after=("a1",)),
             PlanAction("a3", ("P2",), "stir", "spoon"), PlanAction("a4", ("P2",), "dip", "bread", after=("a2",)))
    results = {r.action_id: r for r in run_schedule(p, FakeWorld(fail={"a1"}))}
    assert results["a1"].status == "failed" and "scripted failure" in results["a1"].reason
    assert results["a2"].status == "skipped" and "a1" in results["a2"].reason
    assert results["a3"].status == "done"
    assert results["a4"].status == "skipped" and "a2" in results["a4"].reason


def test_collaboration_waits_for_both_arms_and_failure_reaches_both():
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"),
             PlanAction("h", ("P2", "P1"), "handover", "lemon"),
             PlanAction("g", ("P1", "P2"), "holding", "bowl", partner=Act("stir", "spoon", (), "bowl"),
                        after=("h",)))
    world = FakeWorld(ticks=20, fail={"g"})
    results = {r.action_id: r for r in run_schedule(p, world)}
    handover_starts = [t for t, a, _ in world.log if a == "h"]
    assert len(handover_starts) == 2 and min(handover_starts) >= results["a1"].end  # P1 was busy with a1
    assert results["h"].status == "done"
    assert results["g"].status == "failed" and "scripted" in results["g"].reason


def test_deadlock_is_reported_not_hung():
    class Stuck(FakeWorld):
        def program(self, action, pid, meeting):
            while True:
                yield WAIT

    results = run_schedule(plan(PlanAction("a1", ("P1",), "cut", "knife")), Stuck())
    assert results[0].status == "failed" and "deadlock" in results[0].reason


def test_a_skipped_action_names_the_failure_it_depends_on():
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P1",), "roll", "pin", after=("a1",)),
             PlanAction("a3", ("P1",), "pour", "oil"), PlanAction("a4", ("P2",), "dip", "bread", after=("a2",)))
    results = {r.action_id: r for r in run_schedule(p, FakeWorld(fail={"a1"}))}
    assert results["a4"].reason == "needs a2 (roll), which depends on a1 (cut), which failed"
    assert results["a3"].status == "done"  # the same arm goes on with what does not depend on a1


def test_stop_at_first_failure_skips_everything_after_it():
    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P1",), "pour", "oil"),
             PlanAction("a3", ("P2",), "dip", "bread"))
    world = FakeWorld(ticks=10, fail={"a1"})
    results = {r.action_id: r for r in run_schedule(p, world, stop_at_first_failure=True)}
    assert results["a1"].status == "failed"
    assert results["a2"].status == "skipped" and "first failure, a1" in results["a2"].reason
    assert results["a3"].status == "done"  # it had started with a1, on the other arm


def test_a_wall_clock_limit_ends_the_run():
    class Slow(FakeWorld):
        def program(self, action, pid, meeting):
            import time

            while True:
                time.sleep(0.01)
                yield WORK

    p = plan(PlanAction("a1", ("P1",), "cut", "knife"), PlanAction("a2", ("P1",), "pour", "oil"))
    results = run_schedule(p, Slow(), timeout=0.2)
    assert results[0].status == "failed" and "wall-clock limit" in results[0].reason
    assert results[1].status == "skipped"
