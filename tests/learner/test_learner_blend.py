"""The blended generation's pieces, against brute force and hand-worked cases."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.learner._blend import align_to_skeleton, blend, skeleton_times
from ndlfd.learner._conditioning import condition_weights, minimum_jerk
from ndlfd.learner._segments import segment_states
from ndlfd.metrics import dtw_distance


def brute_align(U, C):
    """All index tuples (ends pinned, monotone); the cheapest, earliest on ties."""
    n, k = len(U), len(C)
    strict = k <= n
    best, arg = np.inf, None
    inner = (
        itertools.combinations(range(1, n - 1), k - 2)
        if strict
        else itertools.combinations_with_replacement(range(n), k - 2)
    )
    for mid in inner:
        idx = (0, *mid, n - 1)
        if strict and len(set(idx)) < k:
            continue
        cost = sum(float(np.sum((U[i] - C[j]) ** 2)) for j, i in enumerate(idx))
        if cost < best:
            best, arg = cost, idx
    return np.array(arg), best


@settings(max_examples=200, deadline=None)
@given(
    st.integers(2, 7),
    st.integers(2, 5),
    st.integers(1, 2),
    st.integers(0, 2**31),
)
def test_alignment_is_the_cheapest_monotone_match(n, k, d, seed):
    rng = np.random.default_rng(seed)
    # integer values: costs are exact, so ties are real ties
    U = rng.integers(0, 4, size=(n, d)).astype(float)
    C = rng.integers(0, 4, size=(k, d)).astype(float)
    got = align_to_skeleton(U, C)
    _, best = brute_align(U, C)
    cost = sum(float(np.sum((U[i] - C[j]) ** 2)) for j, i in enumerate(got))
    assert cost == best
    assert got[0] == 0 and got[-1] == n - 1
    assert np.all(np.diff(got) > 0) if k <= n else np.all(np.diff(got) >= 0)


def test_segment_states_hand_worked():
    # key points at bins 0, 2, 2, 4: the later of two in one bin wins
    got = segment_states(np.array([0, 2, 2, 4]), np.array([7, 8, 9, 5]), 6)
    np.testing.assert_array_equal(got, [7, 7, 9, 9, 5, 5])


def test_minimum_jerk_is_minimum_jerk():
    s = np.linspace(0, 1, 101)
    r = minimum_jerk(s)
    np.testing.assert_allclose(r, 10 * s**3 - 15 * s**4 + 6 * s**5, atol=1e-15)
    assert r[0] == 0 and r[-1] == 1 and np.all(np.diff(r) >= 0)
    np.testing.assert_allclose(r + minimum_jerk(1 - s), 1.0, atol=1e-15)


def test_condition_weights_separate_two_routes():
    rng = np.random.default_rng(0)
    a = rng.normal([0, 0], 0.02, size=(4, 2))
    b = rng.normal([1, 1], 0.02, size=(3, 2))
    w = condition_weights(np.vstack([a, b]), np.array([1.0, 1.0]))
    assert w.max() == 1.0
    assert np.all(w[4:] > 0.5) and np.all(w[:4] < 1e-10)
    assert condition_weights(a[:1], np.zeros(2)).tolist() == [1.0]


def _blend(values, taus, index, weights, tq, **kw):
    """The blend on the knots a plan gives it: (path, knots)."""
    w = np.asarray(weights, dtype=np.float64)
    knots = skeleton_times(taus, index, w / w.sum())
    return blend(values, taus, index, weights, knots, tq, **kw), knots


def test_blend_of_one_curve_at_different_speeds_is_the_curve():
    # the same shape traversed with three different timings: a time-aligned
    # mean cuts the corner, the aligned blend does not
    s = np.linspace(0, 1, 401)
    shape = np.column_stack(
        [np.minimum(2 * s, 1.0), np.maximum(2 * s - 1, 0.0)]
    )  # an L: right, then up
    taus, values = [], []
    for warp in (0.6, 1.0, 1.7):
        tau = s
        progress = s**warp  # how far along the shape at time tau
        values.append(np.column_stack([np.interp(progress, s, c) for c in shape.T]))
        taus.append(tau)
    keys = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    index = [align_to_skeleton(u, keys) for u in values]
    tq = np.linspace(0, 1, 401)
    out, key_tau = _blend(values, taus, index, np.ones(3), tq)
    mean = np.mean(values, axis=0)
    assert dtw_distance(out, shape, normalize=True) < 2e-3
    assert dtw_distance(mean, shape, normalize=True) > 1e-2
    np.testing.assert_allclose(out[[0, -1]], [[0, 0], [1, 1]], atol=1e-12)
    np.testing.assert_array_equal(key_tau, skeleton_times(taus, index, np.ones(3)))


def test_blend_with_one_weight_copies_that_demonstration():
    rng = np.random.default_rng(1)
    tau = np.linspace(0, 1, 50)
    U = [np.cumsum(rng.normal(size=(50, 2)), axis=0) for _ in range(3)]
    index = [np.array([0, 20, 49])] * 3
    out, _ = _blend(U, [tau] * 3, index, np.array([0.0, 1.0, 0.0]), tau)
    # read at its own times: no window (window_half), the samples themselves
    np.testing.assert_allclose(out, U[1], atol=1e-12)


@pytest.mark.parametrize("flip", [False, True])
def test_blend_sign_aligns_quaternions(flip):
    tau = np.linspace(0, 1, 5)
    q = np.tile([0.6, 0.8, 0.0, 0.0], (5, 1))
    other = -q if flip else q
    out, _ = _blend(
        [q, other], [tau, tau], [np.array([0, 4])] * 2, np.ones(2), tau,
        quat_cols=[0, 1, 2, 3],
    )  # fmt: skip
    np.testing.assert_allclose(out, q, atol=1e-15)


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 30), st.integers(0, 2**31))
def test_row_interpolation_matches_numpy_interp(n, seed):
    from ndlfd.learner._blend import _interp_rows

    rng = np.random.default_rng(seed)
    tau = np.sort(rng.uniform(0, 1, n)) if n > 1 else np.zeros(1)
    if n > 1:
        tau = np.unique(tau)
    U = rng.normal(size=(tau.size, 3))
    at = np.concatenate([np.sort(rng.uniform(-0.1, 1.1, 20)), rng.uniform(0, 1, 5)])
    got = _interp_rows(U, tau, at)
    ref = np.column_stack([np.interp(at, tau, c) for c in U.T])
    # the same two-point formula; numpy may compute it in another order
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12)


def test_align_many_on_threads_equals_one_by_one():
    from ndlfd.learner._blend import align_many

    rng = np.random.default_rng(3)
    U = [rng.normal(size=(int(rng.integers(5, 60)), 3)) for _ in range(9)]
    C = rng.normal(size=(5, 3))
    serial = [align_to_skeleton(u, C) for u in U]
    for n_jobs in (None, 1, 2):
        got = align_many(U, C, n_jobs)
        assert all(np.array_equal(a, b) for a, b in zip(got, serial, strict=True))


def test_alignment_to_a_subset_of_candidates_is_the_best_on_that_subset():
    rng = np.random.default_rng(5)
    U = rng.integers(0, 5, size=(40, 2)).astype(float)
    C = rng.integers(0, 5, size=(4, 2)).astype(float)
    got = align_to_skeleton(U, C, max_candidates=9)
    cand = np.unique(np.linspace(0, 39, 9).astype(np.int64))
    ref, _ = brute_align(U[cand], C)
    np.testing.assert_array_equal(got, cand[ref])
    np.testing.assert_array_equal(align_to_skeleton(U, C, 100), align_to_skeleton(U, C))


@settings(max_examples=50, deadline=None)
@given(st.integers(1, 30), st.integers(1, 3), st.integers(0, 8), st.integers(0, 99))
def test_moving_average_is_the_mean_of_the_window(n, d, half, seed):
    from ndlfd.learner._blend import moving_average

    U = np.random.default_rng(seed).normal(size=(n, d))
    ref = np.array([U[max(i - half, 0) : i + half + 1].mean(axis=0) for i in range(n)])
    # cumulative sums against plain sums: equal up to rounding
    np.testing.assert_allclose(moving_average(U, half), ref, rtol=0, atol=1e-12)


def test_the_window_matches_on_the_moving_average():
    from ndlfd.learner._blend import align_many, moving_average

    rng = np.random.default_rng(8)
    U = [rng.normal(size=(int(rng.integers(20, 90)), 2)) for _ in range(6)]
    C = rng.normal(size=(6, 2))
    for u, got in zip(U, align_many(U, C, 2, None, 0.05), strict=True):
        half = round(0.05 * len(u))
        ref = align_to_skeleton(moving_average(u, half), C)
        np.testing.assert_array_equal(got, ref)
    # with raw matching (window 0) it is another alignment on noisy data
    assert any(
        not np.array_equal(a, b)
        for a, b in zip(align_many(U, C, 1, None, 0.05), align_many(U, C), strict=True)
    )


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_no_spikes_towards_the_skeleton_on_noisy_data(seed):
    # the paper's square, 10 % white noise, identical timing: the mean of the
    # demonstrations is the best one can do. Matching raw samples pulled the
    # blend 0.8-1.2 away from it at skeleton points (DTW 1.035-1.065x the mean's);
    # matching the moving average keeps it within 0.4 (0.998-1.007x).
    from ndlfd import synth
    from ndlfd.jobs.demo import DEMO_SETTINGS
    from ndlfd.learner import KeypointHMM
    from ndlfd.metrics import mean_demo_baseline

    train, test = synth.make_dataset("square", n_demos=100, random_state=seed)
    model = KeypointHMM(**DEMO_SETTINGS["square"]).fit(train)
    P = model.generate(test.t, dense=True).get("position")
    M = mean_demo_baseline(train, test.t)
    T = test.get("position")
    assert np.linalg.norm(P - M, axis=1).max() < 0.5
    ratio = dtw_distance(P, T, normalize=True) / dtw_distance(M, T, normalize=True)
    assert ratio < 1.02


def test_condition_weights_with_a_known_bandwidth_are_the_same():
    from ndlfd.learner._conditioning import BANDWIDTH_FACTOR, condition_bandwidth

    rng = np.random.default_rng(4)
    pts = rng.normal(size=(50, 3))
    target = rng.normal(size=3)
    h = condition_bandwidth(pts)
    # reference: the median nearest-other distance by brute force
    D = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    np.fill_diagonal(D, np.inf)
    assert h == pytest.approx(BANDWIDTH_FACTOR * np.median(D.min(axis=1)), rel=1e-12)
    np.testing.assert_array_equal(
        condition_weights(pts, target), condition_weights(pts, target, h)
    )


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n_knots=st.integers(2, 12),
    half=st.floats(0.001, 0.2),
)
def test_smooth_warp_is_the_windowed_mean_and_stays_monotone(seed, n_knots, half):
    from ndlfd.learner._blend import smooth_warp

    rng = np.random.default_rng(seed)
    knots = np.sort(np.concatenate([[0.0, 1.0], rng.uniform(size=n_knots - 2)]))
    at = np.sort(rng.uniform(size=n_knots))
    tq = np.concatenate([[0.0, 1.0], rng.uniform(size=40)])
    got = smooth_warp(tq, knots, at, half)
    # the mean another way: the trapezoid rule over the window's ends and
    # every knot inside it (exact for a piecewise-linear warp)
    for x, g in zip(tq, got, strict=True):
        h = min(half, x, 1.0 - x)
        if h <= 1e-12:
            assert g == np.interp(x, knots, at)  # the ends exactly
            continue
        inside = knots[(knots > x - h) & (knots < x + h)]
        xs = np.concatenate([[x - h], inside, [x + h]])
        mean = np.trapezoid(np.interp(xs, knots, at), xs) / (2 * h)
        assert g == pytest.approx(mean, rel=1e-9, abs=1e-12)
    order = np.argsort(tq)
    assert np.all(np.diff(got[order]) >= -1e-12)


def test_alignment_of_values_near_the_float_limit_matches_the_scaled_one():
    # squared distances of values near 1e300 overflowed to inf: no finite
    # path, and the backtracking read indices from uninitialized memory
    rng = np.random.default_rng(7)
    U = np.cumsum(rng.normal(size=(40, 2)), axis=0)
    C = U[[0, 9, 17, 30, 39]] + rng.normal(0, 0.1, (5, 2))
    want = align_to_skeleton(U, C)
    got = align_to_skeleton(U * 1e300, C * 1e300)
    np.testing.assert_array_equal(got, want)
    assert got[0] == 0 and got[-1] == 39


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 30), st.integers(0, 2**31), st.floats(0.0, 0.3))
def test_window_rows_is_the_windowed_mean_of_the_interpolant(n, seed, half):
    from ndlfd.learner._blend import _window_rows

    rng = np.random.default_rng(seed)
    tau = np.unique(rng.uniform(0, 1, n)) if n > 1 else np.zeros(1)
    U = rng.normal(size=(tau.size, 3))
    at = np.concatenate([np.sort(rng.uniform(-0.1, 1.1, 20)), rng.uniform(0, 1, 5)])
    got = _window_rows(U, tau, at, half)
    # the reference: the trapezoid rule over the window's ends and every
    # sample inside it (exact for a piecewise-linear function), on the
    # interpolant continued past its ends by point reflection
    lo, hi = tau[0], tau[-1]
    h = min(half, hi - lo)

    def ext(s, c):
        inner = np.interp(np.clip(s, lo, hi), tau, c)
        below = 2 * c[0] - np.interp(2 * lo - s, tau, c)
        above = 2 * c[-1] - np.interp(2 * hi - s, tau, c)
        return np.where(s < lo, below, np.where(s > hi, above, inner))

    for x, g in zip(at, got, strict=True):
        x = min(max(x, lo), hi)
        if h <= 1e-9 * (hi - lo):  # too narrow: read linearly
            np.testing.assert_allclose(g, [np.interp(x, tau, c) for c in U.T])
            continue
        knots = np.concatenate([tau, 2 * lo - tau, 2 * hi - tau])
        inside = np.sort(knots[(knots > x - h) & (knots < x + h)])
        xs = np.concatenate([[x - h], inside, [x + h]])
        # the mean as the value at x plus the mean difference to it (the
        # window's ends x -+ h are rounded: a mean of the values themselves
        # would carry that rounding over a window as narrow as 1e-9)
        base = np.array([np.interp(x, tau, c) for c in U.T])
        want = [
            b + np.trapezoid(ext(xs, c) - b, xs) / (2 * h)
            for b, c in zip(base, U.T, strict=True)
        ]
        # summed over the few segments in the window, against a sum over
        # the same pieces in another order
        tol = 1e-12 * (1.0 + np.abs(U).max())
        np.testing.assert_allclose(g, want, rtol=0, atol=tol)
    # the ends are read as the end samples; a constant column as itself
    ends = _window_rows(U, tau, np.array([lo, hi]), half)
    tol = 1e-12 * (1.0 + np.abs(U).max())
    np.testing.assert_allclose(ends, U[[0, -1]], rtol=0, atol=tol)
    flat = np.full((tau.size, 1), 40.0)
    assert np.all(_window_rows(flat, tau, at, half) == 40.0)


def test_window_keeps_a_noisy_template_s_acceleration_at_any_sampling():
    # a zigzag of 50 samples read at steps from its own to 40 times finer:
    # linear reading gives second differences that grow with the sampling (a
    # kink per sample); through the window they stay within the template's
    # own at its spacing (TEMPLATE_WINDOW)
    from ndlfd.learner._blend import _interp_rows, _window_rows, window_half

    tau = np.linspace(0.0, 1.0, 50)
    U = (np.arange(50) % 2).astype(float)[:, None] * 0.01
    own = np.abs(np.diff(U[:, 0], 2)).max() / np.diff(tau)[0] ** 2

    def acceleration(read, at):
        return np.abs(np.diff(read[:, 0], 2)).max() / np.diff(at)[0] ** 2

    for fine in (*range(50, 130), 150, 500, 2000):
        at = np.linspace(0.0, 1.0, fine)
        half = window_half(tau, np.diff(at)[0])
        win = acceleration(_window_rows(U, tau, at, half), at)
        assert win <= own * (1 + 1e-9), fine
        if fine >= 500:  # linear reading amplifies the zigzag
            assert acceleration(_interp_rows(U, tau, at), at) > 4.0 * own
    # at its own sampling it is read as it is
    np.testing.assert_array_equal(
        _window_rows(U, tau, tau, window_half(tau, np.diff(tau)[0])), U
    )


def _conditioned_and_reference(U, tau, rows, observed):
    """The conditioned blend, and the unsmoothed shift on the same rows."""
    from ndlfd.learner._blend import condition_offsets, warped

    index = [np.array([0, tau.size - 1])] * len(U)
    w = np.ones(len(U))
    knots = skeleton_times([tau] * len(U), index, w / w.sum())
    got = blend(U, [tau] * len(U), index, w, knots, rows, observed=observed)
    W, wn = warped(U, [tau] * len(U), index, w, knots, rows)
    mean = np.tensordot(wn, W, axes=1)
    return got - mean, condition_offsets(W, wn, mean, observed)


def test_conditioned_shift_of_straight_deviations_is_not_changed_by_its_window():
    # deviations linear in the phase: their average over any window, the
    # ends continued by point reflection, is themselves
    tau = np.linspace(0.0, 1.0, 101)
    U = [np.column_stack([np.sin(3 * tau) + a * (0.5 + tau), tau]) for a in
         (-0.2, 0.0, 0.1, 0.3)]  # fmt: skip
    rows = np.linspace(0.0, 1.0, 301)
    observed = [(120, [0], np.array([1.2]))]
    got, ref = _conditioned_and_reference(U, tau, rows, observed)
    assert np.abs(ref).max() > 0.05  # a real shift
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12)


def test_conditioned_shift_of_a_fast_turn_is_averaged_over_its_window():
    # templates that differ by a step blurred over 1 % of the motion (a
    # template that turns earlier than the others): the unsmoothed shift
    # turns as fast, the blend's over CONDITION_SMOOTH
    from ndlfd.learner._blend import CONDITION_SMOOTH

    tau = np.linspace(0.0, 1.0, 1001)
    step = np.clip((tau - 0.5) / 0.01 + 0.5, 0.0, 1.0)
    U = [np.column_stack([tau + a * step]) for a in (-0.1, 0.0, 0.05, 0.2)]
    rows = np.linspace(0.0, 1.0, 1001)
    got, ref = _conditioned_and_reference(U, tau, rows, [(900, [0], np.array([1.1]))])

    def turn(x):  # the largest second difference
        return np.abs(np.diff(x[:, 0], 2)).max()

    # a ramp over 2 h: the second difference of the window's mean of a
    # step of size s is at most s * dt^2 / (2 h * 0.01)
    size = np.ptp(ref[:, 0])
    assert size > 0.01
    dt = rows[1] - rows[0]
    assert turn(got) <= 1.05 * size * dt**2 / (2 * CONDITION_SMOOTH * 0.01)
    assert turn(ref) > 10 * turn(got)
    # and the shift is the same size where the motion is steady
    np.testing.assert_allclose(got[[100, 800]], ref[[100, 800]], atol=1e-12)
