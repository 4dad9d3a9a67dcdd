"""The fit's kernels against the numpy code they replaced, bit for bit."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import ValidationError
from ndlfd.learner._exact import N_LIMBS, scale_exponents, to_limbs
from ndlfd.learner._fit_kernels import (
    column_extremes,
    group_sums,
    segment_rows,
    split_limbs,
)


def _values(seed, n, d, zeros):
    rng = np.random.default_rng(seed)
    X = rng.normal(0, rng.uniform(1e-3, 1e3), (n, d))
    if zeros:  # signed zeros and repeated values at the extremes
        X[rng.random((n, d)) < 0.3] = 0.0
        X[rng.random((n, d)) < 0.2] = -0.0
        X[rng.random((n, d)) < 0.1] = X.max()
    return X


@settings(max_examples=80, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 80), st.integers(1, 13), st.booleans())
def test_column_extremes_are_numpys_min_and_max(seed, n, d, zeros):
    # tiles of 8 rows and the rest; a zero extreme takes numpy's sign of zero
    X = _values(seed, n, d, zeros)
    lo, hi = column_extremes(X)
    assert lo.tobytes() == X.min(axis=0).tobytes()  # -0.0 and 0.0 differ here
    assert hi.tobytes() == X.max(axis=0).tobytes()


def _numpy_limbs(values, quanta):
    # the numpy code that split_limbs replaced (ndlfd 2026-12-01, _exact.to_limbs)
    r = np.asarray(values, dtype=np.float64)
    out = np.empty((len(quanta), *r.shape), dtype=np.int64)
    for k, q in enumerate(quanta):
        a = np.trunc(r / q)
        out[k] = a
        r = r - a * q
    return out


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40), st.integers(1, 7), st.booleans())
def test_split_limbs_is_the_numpy_split(seed, n, d, zeros):
    V = _values(seed, n, d, zeros)
    E = scale_exponents(np.abs(V).max(axis=0))
    quanta = np.array([np.ldexp(1.0, E - 31 * (k + 1)) for k in range(N_LIMBS)])
    want = _numpy_limbs(V, quanta)
    assert split_limbs(V, quanta).tobytes() == want.tobytes()
    assert to_limbs(V, E).tobytes() == want.tobytes()


def test_split_limbs_hand_worked():
    # 0.75 = 1 * 0.5 + 1 * 0.25; -0.375 = -0 * 0.5 - 1 * 0.25 - 1 * 0.125
    q = np.array([[0.5], [0.25], [0.125]])
    got = split_limbs(np.array([[0.75], [-0.375]]), q)
    np.testing.assert_array_equal(got[:, :, 0], [[1, 0], [1, -1], [0, -1]])


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 6), st.integers(1, 40))
def test_segment_rows_are_the_searchsorted_segments(seed, n_demos, n_bins):
    # the compiled segments against the per-demonstration numpy code they replaced
    rng = np.random.default_rng(seed)
    n_keys = rng.integers(1, 9, n_demos)
    bins = [np.sort(rng.integers(0, n_bins, k)) for k in n_keys]
    states = [rng.integers(0, 1000, k) for k in n_keys]
    ends = np.cumsum(n_keys)
    got = segment_rows(np.concatenate(bins), np.concatenate(states), ends - n_keys,
                       ends, n_bins)  # fmt: skip
    for r in range(n_demos):
        pos = np.searchsorted(bins[r], np.arange(n_bins), side="right") - 1
        np.testing.assert_array_equal(got[r], states[r][np.maximum(pos, 0)])


def test_segment_rows_refuse_a_demonstration_without_key_points():
    with pytest.raises(ValidationError, match=r"at least one key point.*got starts"):
        segment_rows(
            np.array([0]), np.array([3]), np.array([0, 1]), np.array([1, 1]), 4
        )


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 60), st.integers(1, 5))
def test_group_sums_are_numpys_reduceat(seed, n, d):
    rng = np.random.default_rng(seed)
    limbs = rng.integers(-(2**31), 2**31, (3, n, d))
    order = rng.permutation(n)
    starts = np.unique(np.concatenate([[0], rng.integers(0, n, 5)]))
    want = np.add.reduceat(limbs[:, order], starts, axis=1)
    assert group_sums(limbs, order, starts).tobytes() == want.tobytes()
