"""Greedy Gaussian Segmentation against the reference code's answers and brute force; BIC choice of k;
segmenting hand trajectories with known breakpoints; the series reader and the `wecook segment` command."""

from __future__ import annotations

import itertools
import json
import random
from pathlib import Path

import numpy as np
import pytest
import yaml

from wecook_core.errors import InputError
from wecook_core.model import HANDS, HandTrack, Observations, VideoInfo
from wecook_core.perception.filters import running_median
from wecook_core.perception.params import Params
from wecook_core.perception.segmentation import (
    choose_k,
    ggs,
    load_series,
    refine_breakpoints,
    segment_hands,
    segment_objective,
)
from wecook_core.perception.segmentation.hands import union_breakpoints
from wecook_core.perception.segmentation.synthetic import hand_trajectory
from wecook_tui.cli import main


@pytest.fixture(scope="module")
def expected(shared: Path) -> dict:
    return yaml.safe_load((shared / "data" / "ggs" / "expected.yaml").read_text())["cases"]


@pytest.fixture(scope="module")
def returns(shared: Path) -> np.ndarray:
    return np.loadtxt(shared / "data" / "ggs" / "Returns.txt")[:, [0, 3, 7]]


def helloworld() -> np.ndarray:
    np.random.seed(0)  # the reference case is defined on numpy's legacy global RNG
    series = np.concatenate([np.random.normal(1, 1, 1000), np.random.normal(0, 0.5, 1000),
                             np.random.normal(-1, 1, 1000)])
    return series[:, None]


def direct_objective(x: np.ndarray, breakpoints: tuple[int, ...], lamb: float) -> float:
    """The reference's objective computed segment by segment with np.cov, slogdet and inv."""
    total = 0.0
    for a, b in itertools.pairwise([0, *breakpoints, len(x)]):
        part = x[a:b]
        n = x.shape[1]
        sigma = np.cov(part.T, bias=True).reshape(n, n) + lamb * np.eye(n) / len(part)
        total -= len(part) * np.linalg.slogdet(sigma)[1] - lamb * np.trace(np.linalg.inv(sigma))
    return total


# ------------------------------------------------------------------------------------ reference answers


def assert_matches(result, case: dict) -> None:
    assert [list(b) for b in result.breakpoints_by_k] == case["interior_breakpoints_by_k"]
    np.testing.assert_allclose(result.objective_by_k, case["objective_by_k"], rtol=1e-10)


def test_helloworld_matches_reference(expected):
    case = expected["helloworld"]
    assert_matches(ggs(helloworld(), case["k_max"], case["lamb"]), case)


@pytest.mark.parametrize("quirk", [False, True])
def test_returns_matches_reference(expected, returns, quirk):
    case = expected["returns"]
    result = ggs(returns, case["k_max"], case["lamb"], reference_quirk=quirk)
    assert_matches(result, case)


def test_objective_equals_direct_computation(returns):
    breaks = (208, 1757, 2736, 3044)
    assert segment_objective(returns, breaks, 1e-4) == pytest.approx(direct_objective(returns, breaks, 1e-4),
                                                                     rel=1e-12)


@pytest.mark.parametrize("features", [1, 2, 3, 4])
def test_first_breakpoint_is_the_brute_force_best_split(features):
    rng = np.random.default_rng(features)
    x = np.concatenate([rng.normal(0, 1, (40, features)), rng.normal(0.7, 2.0, (25, features))])
    lamb = 0.05
    scores = {t: direct_objective(x, (t,), lamb) for t in range(2, len(x) - 1)}
    best = max(scores, key=lambda t: (scores[t], -t))
    result = ggs(x, 1, lamb)
    assert result.breakpoints_by_k[1] == (best,)
    assert result.objective_by_k[1] == pytest.approx(scores[best], rel=1e-10)
    assert result.objective_by_k[0] == pytest.approx(direct_objective(x, (), lamb), rel=1e-10)


@pytest.mark.slow
def test_adjustment_leaves_no_breakpoint_with_a_better_place():
    rng = np.random.default_rng(5)
    x = np.concatenate([rng.normal(m, s, (60, 2)) for m, s in [(0, 1), (3, 0.2), (-1, 2), (1, 0.5)]])
    result = ggs(x, 3, 0.1)
    breaks = [0, *result.breakpoints_by_k[3], len(x)]
    for i in range(1, len(breaks) - 1):
        here = direct_objective(x, tuple(breaks[1:-1]), 0.1)
        for t in range(breaks[i - 1] + 2, breaks[i + 1] - 1):
            moved = (*breaks[1:i], t, *breaks[i + 1 : -1])
            assert direct_objective(x, moved, 0.1) <= here + 1e-9


def test_adjustment_order_is_pythons_seeded_shuffle():
    from wecook_core.perception.segmentation.ggs import _shuffle

    for size in (2, 3, 17, 64, 300):
        ours, theirs = list(range(size)), list(range(size))
        mine, reference = random.Random(0), random.Random(0)
        for _ in range(3):  # successive passes draw from the same generator
            _shuffle(ours, mine)
            reference.shuffle(theirs)
            assert ours == theirs


def test_stops_when_no_split_helps_and_on_min_gain():
    constant = np.ones((50, 2))
    assert ggs(constant, 5, 0.1).breakpoints_by_k == ((),)
    x = helloworld()
    full = ggs(x, 10, 0.1)
    early = ggs(x, 10, 0.1, min_gain=50.0, patience=2)
    count = len(early.breakpoints_by_k)
    assert 3 < count < len(full.breakpoints_by_k)
    assert early.breakpoints_by_k == full.breakpoints_by_k[:count]
    assert all(g < 50 for g in np.diff(early.objective_by_k)[-2:])


def test_rejects_bad_arguments():
    with pytest.raises(ValueError, match="lamb"):
        ggs(np.zeros((10, 1)), 2, 0.0)
    with pytest.raises(ValueError, match="finite"):
        ggs(np.array([1.0, np.nan, 2.0]), 2, 0.1)


# ------------------------------------------------------------------------------------------ choosing k


@pytest.mark.parametrize("seed", range(4))
def test_choose_k_finds_the_true_number_of_gaussian_segments(seed):
    rng = np.random.default_rng(seed)
    true_k = int(rng.integers(2, 6))
    lengths = rng.integers(80, 300, true_k + 1)
    x = np.concatenate([rng.normal(rng.uniform(-2, 2, 2), rng.uniform(0.2, 1.5), (n, 2)) for n in lengths])
    result = ggs(x, 12, 1e-3)
    assert choose_k(result, samples=len(x), features=2) == true_k
    truth = np.cumsum(lengths)[:-1]
    assert np.abs(np.array(result.breakpoints_by_k[true_k]) - truth).max() <= 10


def test_choose_k_keeps_no_breakpoint_in_stationary_noise():
    x = np.random.default_rng(1).normal(0, 1, (2000, 2))
    assert choose_k(ggs(x, 6, 1e-3), samples=2000, features=2) == 0


def test_choose_k_prefers_a_late_strong_gain_and_scales_with_strength():
    from wecook_core.model import GGSResult

    result = GGSResult(breakpoints_by_k=((), (1,), (1, 2)), objective_by_k=(0.0, 10.0, 400.0), seconds=0.0)
    assert choose_k(result, samples=100, features=1) == 2  # price 3 ln 100 ~ 13.8 per breakpoint
    assert choose_k(result, samples=100, features=1, strength=20.0) == 0


# ----------------------------------------------------------------------------------------------- hands


def observations(tracks: dict[str, tuple[np.ndarray, np.ndarray]], frames: int) -> Observations:
    hands = tuple(HandTrack(hand, f.astype(np.int64), xy, np.zeros((len(f), 4))) for hand, (f, xy) in tracks.items())
    return Observations(VideoInfo("synthetic.mp4", 30.0, frames, 1280, 720), (), hands, {})


def test_segment_hands_recovers_the_phases_of_every_hand():
    frames = 2400
    rng = np.random.default_rng(7)
    truth = {hand: hand_trajectory(rng, frames) for hand in HANDS}
    obs = observations({h: (np.arange(frames), t.xy) for h, t in truth.items()}, frames)
    seg = segment_hands(obs, Params(lamb=1e-4, min_segment_s=0))  # the plain union
    for hand, trajectory in truth.items():
        found, true = np.array(seg.per_hand[hand]), np.array(trajectory.breakpoints)
        distance = np.abs(true[:, None] - found[None, :])
        assert distance.min(axis=1)[true < frames - 30].max() <= 8, hand  # every phase change found...
        assert distance.min(axis=0).max() <= 8, hand  # ...and nothing else (a reach starts slowly: ±8 frames)
    assert seg.interpolated == dict.fromkeys(HANDS, 0)
    starts = [s.start for s in seg.segments]
    assert starts == sorted({0, *itertools.chain.from_iterable(seg.per_hand.values())})
    assert seg.segments[-1].end == frames
    assert all(a.end == b.start for a, b in itertools.pairwise(seg.segments))


def test_union_merges_near_simultaneous_cuts_of_different_hands():
    assert union_breakpoints([(100, 300), (103, 200), (95,)], 1000, 9) == [100, 200, 300]
    assert union_breakpoints([(5, 500), (995,)], 1000, 9) == [500]  # slivers at the ends go
    assert union_breakpoints([(10, 18, 26)], 1000, 9) == [18]  # a chain of near cuts is one group
    assert union_breakpoints([(10, 18, 23, 40)], 1000, 9) == [18, 40]
    assert union_breakpoints([(10, 20)], 1000, 1) == [10, 20]


@pytest.mark.slow
def test_segments_are_never_slivers():
    frames = 2400
    rng = np.random.default_rng(7)
    obs = observations({h: (np.arange(frames), hand_trajectory(rng, frames).xy) for h in HANDS}, frames)
    seg = segment_hands(obs, Params(lamb=1e-4, min_segment_s=0.3))
    assert min(len(s) for s in seg.segments) >= 9
    plain = segment_hands(obs, Params(lamb=1e-4, min_segment_s=0))
    assert min(len(s) for s in plain.segments) < 9  # the four hands do cut slivers without merging
    assert seg.per_hand == plain.per_hand


def test_segment_hands_interpolates_gaps_and_skips_absent_hands():
    frames = 1500
    trajectory = hand_trajectory(np.random.default_rng(3), frames)
    seen = np.ones(frames, dtype=bool)
    seen[200:230] = seen[700:712] = False  # tracker lost the hand twice
    seen[:5] = False  # and at the very start
    kept = np.nonzero(seen)[0]
    obs = observations({
        "RH_P1": (np.append(kept, [frames + 3]), np.vstack([trajectory.xy[kept], [[0.0, 0.0]]])),  # one stray
        "LH_P1": (np.array([], dtype=np.int64), np.zeros((0, 2))),
    }, frames)
    seg = segment_hands(obs, Params(lamb=1e-4))
    assert seg.interpolated == {"RH_P1": 30 + 12 + 5}
    assert seg.per_hand["LH_P1"] == ()
    found, true = np.array(seg.per_hand["RH_P1"]), np.array(trajectory.breakpoints)
    assert len(found) == len(true)
    assert np.abs(true[:, None] - found[None, :]).min(axis=1).max() <= 8


def test_segment_hands_ignores_one_frame_tracker_jumps():
    frames = 2400
    rng = np.random.default_rng(5)
    trajectory = hand_trajectory(rng, frames)
    xy = trajectory.xy.copy()
    jumps = rng.random(frames) < 0.02  # ~48 detections on the wrong spot, 150 px away on average
    xy[jumps] += rng.normal(0, 150, (int(jumps.sum()), 2))
    found = np.array(segment_hands(observations({"RH_P2": (np.arange(frames), xy)}, frames),
                                   Params(lamb=1e-4)).per_hand["RH_P2"])
    true = np.array(trajectory.breakpoints)
    distance = np.abs(true[:, None] - found[None, :])
    assert distance.min(axis=0).max() <= 8  # no segment cut around a jump
    assert distance.min(axis=1)[true < frames - 30].max() <= 8


def test_segment_hands_uses_the_forced_k_and_refines_at_full_rate():
    frames = 1200
    trajectory = hand_trajectory(np.random.default_rng(11), frames)
    obs = observations({"LH_P2": (np.arange(frames), trajectory.xy)}, frames)
    assert segment_hands(obs, Params(lamb=1e-4, k={"LH_P2": 0})).per_hand["LH_P2"] == ()
    found = segment_hands(obs, Params(lamb=1e-4, k={"LH_P2": 3})).per_hand["LH_P2"]
    assert len(found) == 3
    assert len(segment_hands(obs, Params(lamb=1e-4, k_max=5, k={"LH_P2": 12})).per_hand["LH_P2"]) == 12
    series = running_median(trajectory.xy / [1280, 720], 5)
    coarse = tuple(3 * b for b in ggs(series[1::3], 3, 1e-4 / 3).breakpoints_by_k[3])  # 10 Hz of 30 fps
    assert found != coarse
    assert segment_objective(series, found, 1e-4) > segment_objective(series, coarse, 1e-4)
    assert max(abs(a - b) for a, b in zip(found, coarse, strict=True)) <= 5


def test_segment_hands_on_tiny_or_unsized_videos():
    xy = np.column_stack([np.arange(10.0), np.zeros(10)])
    tiny = Observations(VideoInfo("t.mp4", 30.0, 10, 0, 0), (), (HandTrack("LH_P1", np.arange(10), xy,
                                                                             np.zeros((10, 4))),), {})
    seg = segment_hands(tiny, Params())
    assert seg.per_hand == {"LH_P1": ()}
    assert [(s.start, s.end) for s in seg.segments] == [(0, 10)]
    empty = Observations(VideoInfo("e.mp4", 0.0, 0, 640, 480), (), (), {})
    assert segment_hands(empty, Params()).segments == ()
    # no video size: positions scaled by the trajectory's own extent; no frame rate: GGS at full rate
    frames = 600
    trajectory = hand_trajectory(np.random.default_rng(4), frames)
    unsized = Observations(VideoInfo("u.mp4", 0.0, frames, 0, 0), (),
                           (HandTrack("RH_P1", np.arange(frames), trajectory.xy, np.zeros((frames, 4))),), {})
    found = np.array(segment_hands(unsized, Params(lamb=1e-4)).per_hand["RH_P1"])
    true = np.array(trajectory.breakpoints)
    assert np.abs(true[:, None] - found[None, :]).min(axis=0).max() <= 8
    assert len(found) >= len(true) - 1


def test_refine_breakpoints_moves_a_coarse_breakpoint_to_the_true_change():
    rng = np.random.default_rng(2)
    x = np.concatenate([rng.normal(0, 0.1, (300, 2)), rng.normal(1, 0.1, (300, 2))])
    assert refine_breakpoints(x, (297,), 1e-3, radius=4) == (300,)
    assert refine_breakpoints(x, (290,), 1e-3, radius=4) == (294,)  # never further than the radius


@pytest.mark.slow
def test_four_ten_minute_hands_segment():
    frames = 18_000
    rng = np.random.default_rng(0)
    obs = observations({h: (np.arange(frames), hand_trajectory(rng, frames).xy) for h in HANDS}, frames)
    seg = segment_hands(obs, Params(lamb=1e-4))  # speed: bench/ggs.py
    assert all(len(b) == 40 for b in seg.per_hand.values())  # capped by k_max: ~270 phase changes per hand


# -------------------------------------------------------------------------------------- reading series


def test_load_series_reads_whitespace_and_commas(tmp_path):
    path = tmp_path / "s.txt"
    path.write_text("# header comment\n1 2 3\n4,5,6\n\n7, 8\t9  # trailing\n")
    np.testing.assert_array_equal(load_series(path), [[1, 2, 3], [4, 5, 6], [7, 8, 9]])
    np.testing.assert_array_equal(load_series(path, [2, 0]), [[3, 1], [6, 4], [9, 7]])


@pytest.mark.parametrize(("text", "columns", "message"), [
    ("1 2\n3 x\n", None, r"s\.txt:line 2: column 1: 'x' is not a finite number"),
    ("1 2\n3 4 5\n", None, r"s\.txt:line 2: 3 columns, expected 2"),
    ("\n# nothing\n", None, r"s\.txt: no samples"),
    ("1 2\n3 nan\n", None, r"line 2: column 1: 'nan' is not a finite number"),
    ("1 2\n", [0, 2], r"s\.txt:line 1: column 2 out of range"),
])
def test_load_series_names_file_and_line(tmp_path, text, columns, message):
    path = tmp_path / "s.txt"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        load_series(path, columns)


def test_load_series_missing_file(tmp_path):
    with pytest.raises(InputError, match=r"nope\.txt: no such file"):
        load_series(tmp_path / "nope.txt")


# -------------------------------------------------------------------------------------------- the CLI


def test_cli_json_matches_reference(shared, expected, capsys):
    case = expected["returns"]
    code = main(["segment", str(shared / "data" / "ggs" / "Returns.txt"), "--lamb", "1e-4", "--k-max", "10",
                 "--columns", "0,3,7", "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"breakpoints_by_k", "objective_by_k", "seconds"}
    assert out["breakpoints_by_k"] == case["interior_breakpoints_by_k"]
    np.testing.assert_allclose(out["objective_by_k"], case["objective_by_k"], rtol=1e-10)
    assert out["seconds"] > 0


def test_cli_table_and_errors(tmp_path, capsys):
    path = tmp_path / "series.csv"
    path.write_text("\n".join(f"{v:.6f}" for v in helloworld()[:, 0]))
    assert main(["segment", str(path), "--lamb", "0.1", "--k-max", "3"]) == 0
    out = capsys.readouterr().out
    assert "998 1999" in out and "chosen by BIC: k = 2" in out
    bad = tmp_path / "bad.csv"
    bad.write_text("1,2\n3\n")
    assert main(["segment", str(bad), "--lamb", "0.1", "--k-max", "3"]) == 2
    assert "bad.csv:line 2: 1 columns, expected 2" in capsys.readouterr().err
