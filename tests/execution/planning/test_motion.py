"""The planner interface on a toy 2D problem (no simulator): a wall with a gap."""

import numpy as np
import pytest

from wecook_core.execution.planning.motion import MotionProblem, path_free, plan_motion


def wall(q: np.ndarray) -> bool:
    """A wall at x in [0.45, 0.55] with a gap at y in [0.8, 0.9]."""
    return bool(0.45 <= q[0] <= 0.55 and not 0.8 <= q[1] <= 0.9)


def problem(**kwargs) -> MotionProblem:
    return MotionProblem(start=np.array([0.1, 0.1]), goal=np.array([0.9, 0.1]), lower=np.zeros(2),
                         upper=np.ones(2), collision_fn=wall, resolution=0.005, **kwargs)


@pytest.mark.parametrize("planner", ["rrtconnect", "birrt"])
def test_path_goes_through_the_gap(planner):
    result = plan_motion(problem(), planner=planner, time_limit=5.0, seed=3)
    assert result.ok, result.status
    path = result.path
    assert np.allclose(path[0], [0.1, 0.1]) and np.allclose(path[-1], [0.9, 0.1])
    assert path_free(wall, path, 0.005)
    crossing = [q for q in path if 0.45 <= q[0] <= 0.55]
    assert len(path) <= 6  # shortened: a few corners, not the raw tree path
    assert all(0.8 <= q[1] <= 0.9 for q in crossing)


@pytest.mark.parametrize("planner", ["rrtconnect", "birrt"])
def test_same_seed_same_path(planner):
    a = plan_motion(problem(), planner=planner, time_limit=5.0, seed=11)
    b = plan_motion(problem(), planner=planner, time_limit=5.0, seed=11)
    assert a.ok and b.ok
    assert len(a.path) == len(b.path) and all(np.allclose(x, y) for x, y in zip(a.path, b.path, strict=True))


@pytest.mark.parametrize("planner", ["rrtconnect", "birrt"])
def test_impossible_query_stops_at_its_time_limit(planner):
    def closed(q: np.ndarray) -> bool:
        return bool(0.45 <= q[0] <= 0.55)

    p = MotionProblem(start=np.array([0.1, 0.1]), goal=np.array([0.9, 0.1]), lower=np.zeros(2),
                      upper=np.ones(2), collision_fn=closed, resolution=0.01)
    result = plan_motion(p, planner=planner, time_limit=0.3, seed=0)
    assert result.status == "timeout" and result.path == ()
    assert result.seconds < 1.5


def test_invalid_goal_is_reported_without_search():
    p = MotionProblem(start=np.array([0.1, 0.1]), goal=np.array([0.5, 0.1]), lower=np.zeros(2),
                      upper=np.ones(2), collision_fn=wall)
    result = plan_motion(p, time_limit=5.0, seed=0)
    assert result.status == "invalid_goal" and result.checks == 2


def test_unknown_backend_is_named():
    with pytest.raises(ValueError, match="birrt"):
        plan_motion(problem(), planner="prm")
