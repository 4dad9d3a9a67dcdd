"""The phase of a via point or a prefix (ndlfd.learner._phase)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.learner._blend import condition_offsets
from ndlfd.learner._phase import (
    MAX_BEND,
    MAX_PACE,
    MIN_RATE,
    RATES,
    SLACK,
    prefix_clock,
    prefix_warp,
    via_clock,
    warp_clock,
)


def _arc(p):
    """A quarter circle traversed at a varying speed (normalized units)."""
    a = 0.5 * np.pi * np.asarray(p) ** 1.3
    return np.column_stack([np.cos(a), np.sin(a)])


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    tau=st.floats(0.2, 0.8),
    shift=st.floats(-0.3, 0.3),
)
def test_the_via_clock_meets_the_closest_pass_and_stays_monotone(tau, shift):
    # the via point on the arc at phase tau + shift: the clock reaches that
    # phase at tau (less the slack), or goes as far as the monotone and the
    # curvature bounds let it (10 / sqrt(3): a minimum-jerk ramp's largest
    # curvature)
    p = float(np.clip(tau + shift, 0.0, 1.0))
    taus, deltas = via_clock(_arc, [tau], [([0, 1], _arc([p])[0])])
    at = np.linspace(0.0, 1.0, 2001)
    phase = warp_clock(at, taus, deltas)
    assert phase[0] == 0.0 and phase[-1] == 1.0
    slope = np.diff(phase) / np.diff(at)
    assert slope.min() >= MIN_RATE - 1e-6
    curvature = np.diff(phase, 2) / (at[1] - at[0]) ** 2
    assert np.abs(curvature).max() <= MAX_BEND * 1.01
    reach = (1.0 - MIN_RATE) / 1.875
    bend = MAX_BEND * np.sqrt(3.0) / 10.0
    # each piece's curvature bounds the shift both ways
    lo = -min(reach * tau, bend * tau**2, bend * (1.0 - tau) ** 2)
    hi = min(reach * (1.0 - tau), bend * tau**2, bend * (1.0 - tau) ** 2)
    want = float(np.clip(p - tau, lo, hi))
    want = np.sign(want) * max(abs(want) - SLACK, 0.0)
    assert abs(deltas[1] - want) <= 1.0 / 400 + 1e-9
    # brute force: no phase the clock may reach passes closer than the chosen
    reached = tau + deltas[1] + np.sign(deltas[1]) * SLACK
    d = np.linalg.norm(_arc([reached])[0] - _arc([p])[0])
    fine = np.linspace(0.0, 1.0, 20001)
    ok = (fine - tau >= lo) & (fine - tau <= hi)
    best = np.linalg.norm(_arc(fine[ok]) - _arc([p])[0], axis=1).min()
    assert d <= best + 0.01


def test_the_via_clock_is_smooth_at_the_via_time():
    taus, deltas = via_clock(_arc, [0.5], [([0, 1], _arc([0.35])[0])])
    at = np.linspace(0.0, 1.0, 4001)
    slope = np.gradient(warp_clock(at, taus, deltas), at)
    # the minimum-jerk pieces have zero slope at their knots: the clock runs
    # at rate 1 at the start, the via time and the end
    for knot in (0, 2000, 4000):
        assert abs(slope[knot] - 1.0) < 1e-3
    assert np.abs(np.diff(slope)).max() < 0.01


@settings(max_examples=30, deadline=None, derandomize=True)
@given(
    k=st.integers(0, RATES.size - 1),
    offset=st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2)),
)
def test_a_prefix_clock_recovers_the_rate_whatever_the_offset(k, offset):
    rate = float(RATES[k])
    taus = np.linspace(0.0, 0.3, 10)
    values = _arc(rate * taus) + np.array(offset)
    assert prefix_clock(_arc, taus, values, [0, 1]) == rate


def test_the_prefix_warp_reaches_the_phase_then_runs_on_to_the_end():
    at = np.linspace(0.0, 1.0, 11)
    phase = prefix_warp(at, 0.3, 1.5)
    np.testing.assert_allclose(phase[:4], 1.5 * at[:4])
    np.testing.assert_allclose(phase[3:], np.linspace(0.45, 1.0, 8))


@settings(max_examples=60, deadline=None, derandomize=True)
@given(last=st.floats(0.05, 0.995), rate=st.sampled_from(list(RATES)))
def test_the_prefix_warp_runs_on_within_its_pace_to_the_end_or_to_rest(last, rate):
    # the reference: the linear clock from rate * last to 1 where its slope
    # is within MAX_PACE times max(1, rate); else a clock that leaves at the
    # prefix's rate, never runs faster than the bound, and stops at the end
    if rate * last >= 1.0:
        return
    at = np.r_[np.linspace(0.0, last, 50), np.linspace(last, 1.0, 4001)[1:]]
    phase = prefix_warp(at, last, rate)
    np.testing.assert_allclose(phase[:50], rate * at[:50], atol=1e-12)
    after, t = phase[49:], at[49:]
    slope = np.diff(after) / np.diff(t)
    most = MAX_PACE * max(1.0, rate)
    assert slope.min() >= 0.0
    assert slope.max() <= most * (1.0 + 1e-3)
    need = (1.0 - rate * last) / (1.0 - last)
    if need <= most:
        np.testing.assert_allclose(after, rate * last + need * (t - last), atol=1e-12)
    else:
        assert after[-1] < 1.0
        assert abs(slope[0] - rate) <= 0.01 * most  # leaves at the prefix's pace
        assert slope[-1] <= 1e-3 * most  # and comes to rest
        # it goes as far as a clock that leaves at the rate and stops at the
        # end may within the bound: over half of the bound's reach
        assert after[-1] - after[0] >= 0.5 * most * (1.0 - last)


def test_condition_offsets_against_gaussian_conditioning():
    # the reference: the covariance of the templates' deviations over every
    # (row, column) as one vector, conditioned the textbook way
    rng = np.random.default_rng(3)
    W = rng.normal(size=(5, 7, 2))
    w = rng.uniform(0.2, 1.0, 5)
    w /= w.sum()
    mean = np.tensordot(w, W, axes=1)
    observed = [(1, [0, 1], np.array([0.3, -0.2])), (5, [1], np.array([1.0]))]
    D = (W - mean).reshape(5, -1)
    S = (D.T * w) @ D
    o = [1 * 2 + 0, 1 * 2 + 1, 5 * 2 + 1]
    r = np.array([0.3, -0.2, 1.0]) - mean.ravel()[o]
    noise = np.trace(S[np.ix_(o, o)]) / 3
    ref = S[:, o] @ np.linalg.solve(S[np.ix_(o, o)] + noise * np.eye(3), r)
    got = condition_offsets(W, w, mean, observed, ridge=1.0)
    np.testing.assert_allclose(got.ravel(), ref, atol=1e-12)


def test_one_template_gives_no_shift():
    W = np.ones((1, 4, 2))
    got = condition_offsets(W, np.array([1.0]), W[0], [(0, [0], np.array([5.0]))])
    np.testing.assert_array_equal(got, 0.0)
