import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from ndlfd import ValidationError
from ndlfd.metrics import (
    discrete_frechet,
    dtw_distance,
    endpoint_error,
    path_difference,
    time_aligned_rmse,
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
