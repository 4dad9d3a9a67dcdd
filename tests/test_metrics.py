import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from ndlfd import Demonstration, ValidationError
from ndlfd.metrics import (
    discrete_frechet,
    dtw_distance,
    endpoint_error,
    mean_demo_baseline,
    path_difference,
    path_errors,
    path_length,
    path_length_ratio,
    time_aligned_rmse,
    total_turning,
    turning_ratio,
)


def _couplings(n, k):
    """Every monotone coupling path from (0, 0) to (n-1, k-1), by brute force."""
    out = []

    def walk(i, j, path):
        if (i, j) == (n - 1, k - 1):
            out.append(path)
            return
        for di, dj in ((1, 0), (0, 1), (1, 1)):
            if i + di < n and j + dj < k:
                walk(i + di, j + dj, [*path, (i + di, j + dj)])

    walk(0, 0, [(0, 0)])
    return out


def _brute(A, B, combine):
    D = np.linalg.norm(A[:, None, :] - B[None, :, :], axis=2)
    return min(combine([D[i, j] for i, j in p]) for p in _couplings(len(A), len(B)))


paths = st.integers(1, 5).flatmap(
    lambda n: st.tuples(
        arrays(np.float64, (n, 2), elements=st.integers(-4, 4).map(float)),
        st.integers(1, 5).flatmap(
            lambda k: arrays(np.float64, (k, 2), elements=st.integers(-4, 4).map(float))
        ),
    )
)


@settings(max_examples=60, deadline=None)
@given(paths)
def test_dtw_and_frechet_match_brute_force(pair):
    A, B = pair
    assert dtw_distance(A, B) == pytest.approx(_brute(A, B, sum))
    assert discrete_frechet(A, B) == pytest.approx(_brute(A, B, max))


def test_known_answers():
    a = [[0, 0], [1, 0], [2, 0]]
    assert dtw_distance(a, a) == 0.0
    assert discrete_frechet(a, [[0, 1], [1, 1], [2, 1]]) == 1.0
    assert dtw_distance(a, [[0, 1], [1, 1], [2, 1]]) == 3.0
    assert dtw_distance(a, [[0, 1], [1, 1], [2, 1]], normalize=True) == 0.5
    assert endpoint_error([[0, 0], [1, 1]], [[5, 5], [4, 5]]) == 5.0


def test_time_aligned_rmse_interpolates_on_normalized_time():
    t = np.linspace(0, 1, 11)
    a = np.column_stack([t, 2 * t])
    # the same path sampled sparsely over a different duration
    tb = np.array([10.0, 30.0])
    b = np.array([[0.0, 0.0], [1.0, 2.0]])
    assert time_aligned_rmse(t, a, tb, b) == pytest.approx(0.0, abs=1e-15)
    assert time_aligned_rmse(t, a, tb, b + [3.0, 4.0]) == pytest.approx(5.0)


def test_path_difference_percent():
    t = np.linspace(0, 1, 5)
    a = np.column_stack([3 * t, 4 * t])  # bounding-box diagonal 5
    assert path_difference(t, a, t, a + [0.3, 0.4]) == pytest.approx(10.0)
    with pytest.raises(ValidationError, match="scale must be"):
        path_difference(t, np.zeros((5, 2)), t, a)


def test_errors():
    with pytest.raises(ValidationError, match="same number of columns"):
        dtw_distance(np.zeros((2, 2)), np.zeros((2, 3)))
    with pytest.raises(ValidationError, match="finite"):
        discrete_frechet([[np.nan, 0]], [[0, 0]])
    with pytest.raises(ValidationError, match="strictly increasing"):
        time_aligned_rmse([0, 0], [[0], [1]], [0, 1], [[0], [1]])


def test_brute_helper_counts_couplings():
    # Delannoy-like count for a 3x3 grid of monotone couplings is 13
    assert len(_couplings(3, 3)) == 13
    assert list(itertools.islice(_couplings(1, 1), 1)) == [[(0, 0)]]


# ---------------------------------------------------------------- smoothness
polylines = st.integers(1, 12).flatmap(
    lambda n: st.integers(2, 4).flatmap(
        lambda d: arrays(np.float64, (n, d), elements=st.integers(-5, 5).map(float))
    )
)


def test_path_length_and_turning_known_answers():
    assert path_length([[1, 1]]) == 0.0
    assert path_length([[0, 0, 0], [1, 2, 2], [1, 2, 2], [1, 2, 0]]) == 5.0
    # a square traced once: three right angles
    square = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]
    assert total_turning(square) == pytest.approx(1.5 * np.pi)
    # going back the way it came is a turn of pi, in 3-D as well
    assert total_turning([[0, 0, 0], [0, 0, 2], [0, 0, 1]]) == pytest.approx(np.pi)
    # 45 degrees in 3-D: (1, 0, 0) then (1, 1, 0)
    assert total_turning([[0, 0, 0], [1, 0, 0], [2, 1, 0]]) == pytest.approx(np.pi / 4)
    # fewer than two segments, or only repeated points: no turning
    assert total_turning([[0, 0], [1, 1]]) == 0.0
    assert total_turning([[0, 0], [0, 0], [0, 0]]) == 0.0
    # the zero-length segment is skipped: the turn is measured across it
    assert total_turning([[0, 0], [1, 0], [1, 0], [1, 1]]) == pytest.approx(np.pi / 2)
    # a short wiggle is ignored above min_segment
    wiggle = [[0, 0], [1, 0], [1, 0.01], [2, 0.01]]
    assert total_turning(wiggle) == pytest.approx(np.pi)
    assert total_turning(wiggle, min_segment=0.1) == pytest.approx(0.0, abs=1e-12)


def test_ratios_known_answers_and_degenerate_references():
    line = [[0, 0], [2, 0]]
    bent = [[0, 0], [1, 0], [1, 1]]
    assert path_length_ratio(line, bent) == 1.0
    assert path_length_ratio(bent, line) == 1.0
    assert turning_ratio(bent, [[0, 0], [1, 0], [1, 1], [2, 1]]) == pytest.approx(2.0)
    # a straight or motionless reference: 1 if the other is too, else inf
    assert turning_ratio(line, line) == 1.0
    assert turning_ratio(line, bent) == np.inf
    assert path_length_ratio([[1, 1], [1, 1]], [[0, 0]]) == 1.0
    assert path_length_ratio([[1, 1], [1, 1]], line) == np.inf
    with pytest.raises(ValidationError, match="same number of columns"):
        turning_ratio(line, [[0, 0, 0], [1, 1, 1]])
    with pytest.raises(ValidationError, match="min_segment"):
        total_turning(line, min_segment=-1.0)


@settings(max_examples=80, deadline=None)
@given(polylines)
def test_a_path_against_itself_has_ratio_one(P):
    assert turning_ratio(P, P) == pytest.approx(1.0)
    assert path_length_ratio(P, P) == pytest.approx(1.0)


@settings(max_examples=80, deadline=None)
@given(polylines, st.floats(0.01, 100.0), st.integers(0, 2**32 - 1))
def test_scaling_rotating_and_shifting(P, scale, seed):
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.normal(size=(P.shape[1], P.shape[1])))
    moved = scale * P @ Q + rng.normal(size=P.shape[1])
    if path_length(P) > 0:
        assert path_length_ratio(P, moved) == pytest.approx(scale)
    assert total_turning(moved) == pytest.approx(total_turning(P), abs=1e-6)
    # repeating points changes neither length nor turning
    doubled = np.repeat(P, 2, axis=0)
    assert path_length(doubled) == pytest.approx(path_length(P))
    assert total_turning(doubled) == pytest.approx(total_turning(P), abs=1e-9)
    # reversing a path keeps its length and its turning
    assert total_turning(P[::-1]) == pytest.approx(total_turning(P), abs=1e-9)
    assert 0.0 <= total_turning(P) <= np.pi * max(P.shape[0] - 2, 0) + 1e-9


# ----------------------------------------------------- baseline and path errors
def test_mean_demo_baseline_averages_on_normalized_time():
    a = Demonstration.from_arrays([0, 1], position=[[0, 0], [2, 2]])
    b = Demonstration.from_arrays([5, 7], position=[[2, 0], [4, 2]])
    got = mean_demo_baseline([a, b], np.linspace(3, 4, 5))
    np.testing.assert_allclose(
        got, np.column_stack([np.linspace(1, 3, 5)] * 2) - [0, 1]
    )
    with pytest.raises(ValidationError, match="at least one"):
        mean_demo_baseline([], [0, 1])


def test_path_errors_hand_worked():
    test = Demonstration.from_arrays([0, 1], position=[[0, 0], [3, 4]])
    path = Demonstration.from_arrays([0, 2], position=[[0.3, 0.4], [3.3, 4.4]])
    got = path_errors(test, path)
    assert got == pytest.approx(
        {"difference_pct": 10.0, "dtw_mean": 0.25, "frechet": 0.5}
    )


# ----------------------------------------------------------- phase envelope
def _envelope_by_loops(demos, n_bins, q):
    """Loops: each demonstration's largest speed / acceleration per phase bin."""
    per_v, per_a = [], []
    for d in demos:
        tau = (d.t - d.t[0]) / (d.t[-1] - d.t[0])
        P = d.get("position")
        V = np.gradient(P, tau, axis=0, edge_order=2)
        A = np.gradient(V, tau, axis=0, edge_order=2)
        bv, ba = [np.nan] * n_bins, [np.nan] * n_bins
        for i in range(len(tau)):
            b = min(int(tau[i] * n_bins), n_bins - 1)
            v, a = float(np.linalg.norm(V[i])), float(np.linalg.norm(A[i]))
            bv[b] = v if np.isnan(bv[b]) else max(bv[b], v)
            ba[b] = a if np.isnan(ba[b]) else max(ba[b], a)
        per_v.append(bv)
        per_a.append(ba)
    out = []
    for per in (per_v, per_a):
        e = [float(np.nanquantile([p[b] for p in per], q)) for b in range(n_bins)]
        out.append(np.array([max(e[max(b - 1, 0) : b + 2]) for b in range(n_bins)]))
    return out


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 10_000), n_demos=st.integers(1, 6), n_bins=st.integers(2, 30)
)
def test_phase_envelope_against_loops(seed, n_demos, n_bins):
    from ndlfd.metrics import phase_envelope

    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n_demos):
        n = int(rng.integers(20, 80))
        t = np.cumsum(rng.uniform(0.5, 1.5, n))
        demos.append(Demonstration.from_arrays(t, position=rng.normal(size=(n, 2))))
    got = phase_envelope(demos, n_bins=n_bins, quantile=0.9)
    want = _envelope_by_loops(demos, n_bins, 0.9)
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g, np.nan_to_num(w), rtol=1e-12)


def test_a_path_twice_as_fast_midway_has_twice_the_envelope_speed():
    from ndlfd.metrics import envelope_ratios, phase_envelope

    t = np.linspace(0.0, 1.0, 201)
    demo = Demonstration.from_arrays(t, position=np.column_stack([t, 0 * t]))
    # the same line, but the middle fifth at twice the speed (slower elsewhere)
    s = np.interp(t, [0, 0.4, 0.6, 1], [0, 0.35, 0.65, 1])
    path = Demonstration.from_arrays(t, position=np.column_stack([s, 0 * t]))
    speed, _ = envelope_ratios(path, phase_envelope([demo], n_bins=20))
    assert speed == pytest.approx(1.5, rel=1e-9)  # 0.3 in 0.2 of the time


def test_envelope_ratios_since_counts_only_the_rest_and_its_first_step():
    from ndlfd.metrics import envelope_ratios, phase_envelope

    t = np.linspace(0.0, 1.0, 201)
    demo = Demonstration.from_arrays(t, position=np.column_stack([t, 0 * t]))
    env = phase_envelope([demo], n_bins=20)
    # three times as fast over the first 40 samples, then the line's pace:
    # from sample 60 on only the line's own speed is counted
    s = np.where(t < 0.2, 3.0 * t, 0.6 + (t - 0.2) * 0.4 / 0.8)
    path = Demonstration.from_arrays(t, position=np.column_stack([s, 0 * t]))
    assert envelope_ratios(path, env)[0] == pytest.approx(3.0, rel=1e-9)
    assert envelope_ratios(path, env, since=60)[0] == pytest.approx(0.5, rel=1e-9)
    # a jump at sample 100 counts from its last sample before (since=99)
    jump = s + np.where(np.arange(t.size) >= 100, 0.05, 0.0)
    path = Demonstration.from_arrays(t, position=np.column_stack([jump, 0 * t]))
    assert envelope_ratios(path, env, since=99)[0] > 5.0
    assert envelope_ratios(path, env, since=101)[0] == pytest.approx(0.5, rel=1e-9)


@pytest.mark.parametrize("since", [-1, 201, 1.5, True, "3"])
def test_envelope_ratios_since_out_of_range_says_so(since):
    from ndlfd import ValidationError
    from ndlfd.metrics import envelope_ratios, phase_envelope

    t = np.linspace(0.0, 1.0, 201)
    demo = Demonstration.from_arrays(t, position=np.column_stack([t, 0 * t]))
    with pytest.raises(ValidationError, match="since must be"):
        envelope_ratios(demo, phase_envelope([demo]), since=since)
