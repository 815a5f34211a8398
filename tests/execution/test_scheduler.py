"""The scheduler with a fake world: no simulator, scripted primitives."""

from wecook_core.execution.executor import run_schedule
from wecook_core.execution.program import WAIT, WORK, ActionFailed, Meeting
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
