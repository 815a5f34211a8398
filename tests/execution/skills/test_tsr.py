import numpy as np
import pytest

from wecook_core.execution.skills import tsr as T


def test_fixed_region_gives_the_offset_pose():
    frame = T.xyzrpy_to_matrix([0.3, -0.2, 0.1, 0, 0, np.pi / 2])
    region = T.make_tsr(frame, offset=[0.1, 0, 0, 0, 0, 0])
    pose = T.sample(region, np.random.default_rng(0))
    # offset x in the frame rotated by +90 deg about z lands on +y in the world
    assert np.allclose(pose[:3, 3], [0.3, -0.1, 0.1])
    assert T.contains(region, pose)


def test_samples_stay_inside_bounds_and_cover_them():
    bounds = [[-0.05, 0.05], [0, 0], [0.1, 0.2], [0, 0], [0, 0], [-np.pi, np.pi]]
    region = T.make_tsr(np.eye(4), bounds=bounds)
    rng = np.random.default_rng(1)
    poses = [T.sample(region, rng) for _ in range(300)]
    xs = np.array([p[0, 3] for p in poses])
    zs = np.array([p[2, 3] for p in poses])
    assert xs.min() >= -0.05 and xs.max() <= 0.05 and xs.max() - xs.min() > 0.08
    assert zs.min() >= 0.1 and zs.max() <= 0.2
    assert all(T.contains(region, p) for p in poses)


def test_distance_outside_is_positive_and_measures_the_excess():
    region = T.make_tsr(np.eye(4), bounds=[[0, 0.1], [0, 0], [0, 0], [0, 0], [0, 0], [-0.1, 0.1]])
    outside = T.xyzrpy_to_matrix([0.3, 0, 0, 0, 0, 0])
    assert T.distance(region, outside) == pytest.approx(0.2)
    turned = T.xyzrpy_to_matrix([0.05, 0, 0, 0, 0, 0.5])
    assert T.distance(region, turned) == pytest.approx(0.4)


def test_same_seed_same_samples_and_pose_round_trip():
    region = T.make_tsr(np.eye(4), bounds=[[-1, 1]] * 6)
    a = T.sample(region, np.random.default_rng(7))
    b = T.sample(region, np.random.default_rng(7))
    assert np.array_equal(a, b)
    assert np.allclose(T.pose_to_matrix(T.matrix_to_pose(a)), a)


def test_bad_bounds_are_rejected():
    with pytest.raises(ValueError, match="low <= high"):
        T.make_tsr(np.eye(4), bounds=[[1, 0]] + [[0, 0]] * 5)
