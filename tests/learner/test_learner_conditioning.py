"""Conditioning (ndlfd.learner._conditioning): the kernel width."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.learner._conditioning import (
    BANDWIDTH_FACTOR,
    BRUTE_FORCE_POINTS,
    condition_bandwidth,
)


def _reference_width(points):
    """Loops over every pair: the median nearest-other distance, times the factor."""
    n = len(points)
    nearest = []
    for i in range(n):
        others = [np.sqrt(np.sum((points[i] - points[j]) ** 2)) for j in range(n)
                  if j != i]  # fmt: skip
        nearest.append(float(min(others)))
    return BANDWIDTH_FACTOR * float(np.median(nearest))


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(2, 2 * BRUTE_FORCE_POINTS),
    d=st.integers(1, 6),
    seed=st.integers(0, 2**31 - 1),
)
def test_both_ways_give_the_median_nearest_distance(n, d, seed):
    # all pairs up to BRUTE_FORCE_POINTS points, a k-d tree beyond: the same width
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n, d)) * rng.uniform(0.01, 100.0)
    if n > 3:
        points[1] = points[0]  # a duplicate: its nearest distance is 0
    expected = _reference_width(points)
    if not expected > 0:  # most coincide: the width of the set (not drawn here)
        return
    assert np.isclose(condition_bandwidth(points), expected, rtol=1e-12, atol=0.0)


def test_coinciding_points_take_the_width_of_the_set():
    points = np.array([[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [3.0, 4.0]])
    assert condition_bandwidth(points) == 5.0
    assert condition_bandwidth(np.zeros((1, 2))) == 1.0


def test_contact_window_is_judged_while_moving_not_at_rest():
    from ndlfd.learner._conditioning import contact_window

    # a brute-force reference: the typical speed is the median of the speeds
    # of at least a tenth of the 95th percentile; the first slow step after
    # the first at that speed or faster, the last the same backwards
    def reference(x, tq):
        v = np.abs(np.diff(x)) / np.diff(tq)
        fast = np.quantile(v, 0.95)
        typical = np.median([s for s in v if s >= 0.1 * fast])
        go = [i for i, s in enumerate(v) if s >= typical]
        first = next((tq[i] for i in range(go[0], len(v)) if v[i] < 0.2 * typical), 1.0)
        last = next(
            (tq[i + 1] for i in range(go[-1], -1, -1) if v[i] < 0.2 * typical), 0.0
        )
        return first, last

    rng = np.random.default_rng(0)
    tq = np.linspace(0.0, 1.0, 1000)
    # at rest for 70 % of the time (noise only), moving 10 %, a stop, moving
    x = np.concatenate([np.zeros(700), np.linspace(0, 1, 101)[1:],
                        np.ones(50), np.linspace(1, 2, 151)[1:]])  # fmt: skip
    x = x + rng.normal(0, 1e-5, x.size)
    first, last = contact_window(x[:, None], tq)
    assert (first, last) == reference(x, tq)
    # the stop at 80 % is the first slow-down, not the rest before the motion
    assert 0.79 < first < 0.81
    assert 0.84 < last < 0.86
