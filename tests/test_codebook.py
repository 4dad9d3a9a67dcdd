from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from ndlfd._errors import ValidationError
from ndlfd.codebook import Codebook, TimeBins, intern_cells, lowest_unseen_cell


def _reference_state(q, levels):
    # plain Python mixed radix, first column most significant
    s = 0
    for digit, cb in zip(q, levels, strict=True):
        s = s * cb + int(digit)
    return s


def test_mixed_radix_order_small_example():
    cb = Codebook([2, 3])
    all_q = list(itertools.product(range(2), range(3)))
    # enumeration order of itertools.product is exactly the mixed-radix order
    np.testing.assert_array_equal(cb.from_levels(all_q), np.arange(6))
    np.testing.assert_array_equal(cb.to_levels(np.arange(6)), all_q)
    assert cb.n_states == 6 and isinstance(cb.n_states, int)
    assert cb.n_dims == 2 and cb.levels == (2, 3)
    assert repr(cb) == "Codebook(levels=[2, 3])"


def test_encode_known_values():
    cb = Codebook([10, 4])
    U = [[0.0, 0.0], [0.05, 0.3], [0.999, 0.74], [1.0, 1.0], [0.1, 0.25]]
    # q = floor(u * CB): (0,0) (0,1) (9,2) (9 clipped from 10, 3 clipped from 4)
    # and 0.1*10 = 1, 0.25*4 = 1
    np.testing.assert_array_equal(cb.encode(U), [0, 1, 38, 39, 5])
    states, n_clipped = cb.encode(U, return_n_clipped=True)
    assert n_clipped == 0  # u = 1 is inside [0, 1]: it lands in the top level
    assert states.dtype == np.int64


def test_out_of_range_values_are_clipped_and_counted():
    cb = Codebook([5, 5])
    states, n = cb.encode(
        [[-0.1, 1.2], [3.0, 0.5], [-1e300, 1e300]], return_n_clipped=True
    )
    assert n == 5
    np.testing.assert_array_equal(cb.to_levels(states), [[0, 4], [4, 2], [0, 4]])


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.integers(1, 40), min_size=1, max_size=5),
    st.data(),
)
def test_round_trip_on_level_centres(levels, data):
    cb = Codebook(levels)
    n = data.draw(st.integers(1, 20))
    Q = np.column_stack(
        [
            data.draw(hnp.arrays(np.int64, n, elements=st.integers(0, c - 1)))
            for c in levels
        ]
    )
    states = cb.from_levels(Q)
    expected = [_reference_state(q, levels) for q in Q]
    np.testing.assert_array_equal(states, expected)
    centres = cb.decode(states)
    np.testing.assert_allclose(centres, (Q + 0.5) / np.array(levels))
    np.testing.assert_array_equal(cb.encode(centres), states)
    np.testing.assert_array_equal(cb.to_levels(states), Q)


@settings(max_examples=60, deadline=None)
@given(
    hnp.arrays(
        np.float64,
        st.tuples(st.integers(1, 15), st.just(3)),
        elements=st.floats(-0.5, 1.5, allow_nan=False),
    )
)
def test_encode_matches_elementwise_reference(U):
    levels = [7, 1, 20]
    states, n = Codebook(levels).encode(U, return_n_clipped=True)
    expected = []
    for row in U:
        q = [
            min(max(int(np.floor(u * c)), 0), c - 1)
            for u, c in zip(row, levels, strict=True)
        ]
        expected.append(_reference_state(q, levels))
    np.testing.assert_array_equal(states, expected)
    assert n == int(((U < 0) | (U > 1)).sum())


def test_large_codebooks_use_exact_integers():
    levels = [100] * 9  # 1e18 states, fits in int64
    cb = Codebook(levels)
    assert cb.n_states == 10**18
    top = cb.encode(np.ones((1, 9)))
    assert int(top[0]) == 10**18 - 1
    q = np.array([[99, 0, 1, 2, 3, 4, 5, 6, 97]])
    s = cb.from_levels(q)
    assert int(s[0]) == _reference_state(q[0], levels)
    np.testing.assert_array_equal(cb.to_levels(s), q)


def test_codebook_past_int64_has_cells_but_no_state_numbers():
    cb = Codebook([10] * 20)  # 1e20 cells: no int64 state number, still cells
    assert cb.n_states == 10**20 and not cb.fits_int64
    U = np.linspace(0, 1, 40).reshape(2, 20)
    np.testing.assert_array_equal(cb.cells(U), np.minimum(np.floor(U * 10), 9))
    for call in (cb.encode, cb.decode, cb.to_levels):
        arg = U if call is cb.encode else [0]
        with pytest.raises(ValidationError, match=r"1e\+20 cells .* fit in int64"):
            call(arg)
    assert not Codebook([2] * 63 + [1, 1]).fits_int64  # 2**63: one too many
    assert Codebook([2] * 62 + [1]).fits_int64


def _lex_reference(rows):
    """Distinct rows sorted as tuples, each row's index among them (brute force)."""
    distinct = sorted(set(map(tuple, rows)))
    where = {r: i for i, r in enumerate(distinct)}
    return np.array(distinct, dtype=np.int64).reshape(-1, len(rows[0])), np.array(
        [where[tuple(r)] for r in rows], dtype=np.int64
    )


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 6).flatmap(
        lambda d: st.lists(
            st.lists(st.integers(0, 30), min_size=d, max_size=d),
            min_size=1,
            max_size=40,
        )
    ),
    st.booleans(),
)
def test_intern_cells_is_the_sorted_distinct_tuples(rows, wide):
    q = np.array(rows, dtype=np.int64)
    if wide:  # ranges whose product passes int64: the column-wise sort
        q = q * (2**40)
    distinct, ids = intern_cells(q)
    want_distinct, want_ids = _lex_reference(q.tolist())
    np.testing.assert_array_equal(distinct, want_distinct)
    np.testing.assert_array_equal(ids, want_ids)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.lists(st.integers(1, 5), min_size=1, max_size=5))
def test_interned_ids_rank_the_mixed_radix_numbers(seed, levels):
    # the paper's state numbers and the interned ids order cells alike
    cb = Codebook(levels)
    U = np.random.default_rng(seed).random((30, len(levels)))
    numbers = cb.encode(U)
    distinct, ids = intern_cells(cb.cells(U))
    np.testing.assert_array_equal(np.unique(numbers)[ids], numbers)
    np.testing.assert_array_equal(cb.from_levels(distinct), np.unique(numbers))
    np.testing.assert_array_equal(cb.centres(cb.cells(U)), cb.decode(numbers))


def test_lowest_unseen_cell_known_answers():
    assert lowest_unseen_cell(np.array([[0, 0], [0, 1], [1, 1]]), [2, 2]).tolist() == [
        1,
        0,
    ]
    assert lowest_unseen_cell(np.array([[0, 1]]), [2, 2]).tolist() == [0, 0]
    full = np.array(list(itertools.product(range(2), range(3))))
    assert lowest_unseen_cell(full, [2, 3]) is None
    assert lowest_unseen_cell(full[:4], [2, 3]).tolist() == [1, 1]
    # past int64: the walk needs no state number
    big = np.zeros((1, 30), dtype=np.int64)
    assert lowest_unseen_cell(big, [20] * 30).tolist() == [0] * 29 + [1]


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.lists(st.integers(1, 4), min_size=1, max_size=4))
def test_lowest_unseen_cell_is_the_lowest_missing_number(seed, levels):
    cb = Codebook(levels)
    rng = np.random.default_rng(seed)
    numbers = np.unique(rng.integers(0, cb.n_states, size=rng.integers(1, 8)))
    missing = sorted(set(range(cb.n_states)) - set(numbers.tolist()))
    got = lowest_unseen_cell(cb.to_levels(numbers), levels)
    if not missing:
        assert got is None
    else:
        assert int(cb.from_levels(got[None])[0]) == missing[0]


def test_from_groups():
    cb = Codebook.from_groups(
        {"position": 20, "velocity": 10}, ["position", "position", "velocity"]
    )
    assert cb.levels == (20, 20, 10)
    with pytest.raises(
        ValidationError, match=r"no codebook level given for group\(s\) \['force'\]"
    ):
        Codebook.from_groups({"position": 20}, ["position", "force"])
    with pytest.raises(ValidationError, match=r"unknown group\(s\) \['velocity'\]"):
        Codebook.from_groups({"position": 20, "velocity": 10}, ["position"])
    with pytest.raises(ValidationError, match=r"group 'position' .* >= 1; got 0"):
        Codebook.from_groups({"position": 0}, ["position"])
    with pytest.raises(ValidationError, match=r"group 'position' must be an integer"):
        Codebook.from_groups({"position": 2.5}, ["position"])
    with pytest.raises(ValidationError, match=r"must be a mapping"):
        Codebook.from_groups([20], ["position"])
    with pytest.raises(ValidationError, match=r"sequence of group names"):
        Codebook.from_groups({"position": 20}, "position")


@pytest.mark.parametrize(
    ("levels", "match"),
    [
        ([], r"got an empty sequence"),
        ([3, 0], r"levels\[1\] must be an integer >= 1; got 0"),
        ([3, 2.0], r"levels\[1\] must be an integer >= 1; got 2.0 of type float"),
        ([True], r"levels\[0\] must be an integer"),
        (5, r"sequence of integers >= 1, .* got 5 of type int"),
        ("20", r"got '20' of type str"),
        (np.array([[2, 3]]), r"got an array of shape \(1, 2\)"),
    ],
)
def test_bad_levels(levels, match):
    with pytest.raises(ValidationError, match=match):
        Codebook(levels)


def test_numpy_levels_accepted():
    assert Codebook(np.array([3, 4])).n_states == 12


def test_encode_errors():
    cb = Codebook([4, 4])
    with pytest.raises(
        ValidationError, match=r"U must have 2 column\(s\).* got shape \(1, 3\)"
    ):
        cb.encode([[0.1, 0.2, 0.3]])
    with pytest.raises(ValidationError, match=r"U must be finite; got .* at row 1"):
        cb.encode([[0.1, 0.2], [np.nan, 0.1]])
    with pytest.raises(ValidationError, match=r"U must be finite"):
        cb.encode([[np.inf, 0.2]])
    with pytest.raises(ValidationError, match=r"np.column_stack"):
        cb.encode([0.1, 0.2])
    with pytest.raises(ValidationError, match=r"at least 1 row"):
        cb.encode(np.empty((0, 2)))
    with pytest.raises(ValidationError, match=r"real numbers"):
        cb.encode([["a", "b"]])


def test_state_errors():
    cb = Codebook([4, 4])
    with pytest.raises(
        ValidationError, match=r"states must lie in 0..15; got states\[1\] = 16"
    ):
        cb.decode([0, 16])
    with pytest.raises(
        ValidationError, match=r"states must lie in 0..15; got states\[0\] = -1"
    ):
        cb.to_levels([-1])
    with pytest.raises(ValidationError, match=r"whole numbers"):
        cb.decode([0.5])
    with pytest.raises(
        ValidationError, match=r"1-D array of integers; got shape \(1, 1\)"
    ):
        cb.decode([[1]])
    with pytest.raises(
        ValidationError, match=r"Q\[:, 1\] must lie in 0..3; got Q\[0, 1\] = 4"
    ):
        cb.from_levels([[0, 4]])
    with pytest.raises(ValidationError, match=r"Q must have 2 column"):
        cb.from_levels([[0, 1, 2]])
    with pytest.raises(ValidationError, match=r"Q must have shape \(n_points, 2\)"):
        cb.from_levels([0, 1])
    with pytest.raises(ValidationError, match=r"whole numbers"):
        cb.from_levels([[0.5, 1]])
    with pytest.raises(ValidationError, match=r"integer array"):
        cb.from_levels([["a", "b"]])


# ----------------------------------------------------------------- TimeBins


def test_time_bins_known_values():
    tb = TimeBins(5)
    t = [10.0, 10.5, 11.0, 12.0, 14.0, 15.0]
    np.testing.assert_array_equal(tb.normalize(t), [0, 0.1, 0.2, 0.4, 0.8, 1.0])
    np.testing.assert_array_equal(tb.transform(t), [0, 0, 1, 2, 4, 4])
    np.testing.assert_array_equal(tb.transform([3.0]), [0])
    np.testing.assert_array_equal(tb.normalize([3.0]), [0.0])
    assert tb.transform(t).dtype == np.int64
    assert repr(tb) == "TimeBins(n_bins=5)"


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 100),
    hnp.arrays(
        np.float64, st.integers(1, 40), elements=st.floats(-1e6, 1e6), unique=True
    ),
)
def test_time_bins_properties(n_bins, t):
    t = np.sort(t)
    sym = TimeBins(n_bins).transform(t)
    assert sym[0] == 0
    assert np.all(np.diff(sym) >= 0)
    assert sym.min() >= 0 and sym.max() <= n_bins - 1
    if t.size > 1:
        assert sym[-1] == n_bins - 1
        tau = (t - t[0]) / (t[-1] - t[0])
        expected = [min(int(np.floor(x * n_bins)), n_bins - 1) for x in tau]
        np.testing.assert_array_equal(sym, expected)


@pytest.mark.parametrize(
    ("t", "match"),
    [
        ([0.0, 1.0, 1.0], r"strictly increasing"),
        ([0.0, np.nan], r"t must be finite"),
        ([], r"at least one time stamp"),
        ([[0.0, 1.0]], r"shape \(n_samples,\)"),
    ],
)
def test_time_bins_errors(t, match):
    with pytest.raises(ValidationError, match=match):
        TimeBins(3).transform(t)


@pytest.mark.parametrize("n", [0, -1, 2.5, True])
def test_time_bins_bad_n(n):
    with pytest.raises(ValidationError, match=r"n_bins must be an integer >= 1"):
        TimeBins(n)


def _numpy_encode(P, levels):
    # the numpy code the compiled encoder replaced (ndlfd 2026-12-01)
    cb = np.array(levels, dtype=np.int64)
    n_clipped = int(np.count_nonzero((P < 0.0) | (P > 1.0)))
    cbf = cb.astype(np.float64)
    Q = np.floor(P * cbf)
    np.clip(Q, 0.0, cbf - 1.0, out=Q)
    Q = Q.astype(np.int64)
    s = Q[:, 0].copy()
    for k in range(1, cb.size):
        s *= cb[k]
        s += Q[:, k]
    return s, n_clipped


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(1, 40),
    st.lists(st.integers(1, 120), min_size=1, max_size=6),
)
def test_encode_is_the_numpy_encoding(seed, n, levels):
    rng = np.random.default_rng(seed)
    P = rng.uniform(-0.2, 1.2, (n, len(levels)))
    P[rng.random(P.shape) < 0.2] = 1.0  # the top edge
    P[rng.random(P.shape) < 0.1] = -0.0
    P[:, 0] = np.array([k / levels[0] for k in range(n)])[:n] % 1.0  # level edges
    states, clipped = Codebook(levels).encode(P, return_n_clipped=True)
    want, want_clipped = _numpy_encode(P, levels)
    assert states.dtype == np.int64 and states.tobytes() == want.tobytes()
    assert clipped == want_clipped
    # the fit's path for its own checked values: the same states and count
    trusted, trusted_clipped = Codebook(levels).encode_checked(P)
    assert trusted.tobytes() == want.tobytes() and trusted_clipped == want_clipped


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 300), st.integers(1, 60))
def test_symbols_are_the_numpy_binning(seed, n_bins, n):
    # the compiled binning against the numpy code it replaced
    rng = np.random.default_rng(seed)
    tau = np.concatenate([[0.0, 1.0], np.arange(n_bins + 1) / n_bins, rng.random(n)])
    want = np.floor(tau * n_bins)
    np.clip(want, 0, n_bins - 1, out=want)
    got = TimeBins(n_bins).symbols(tau)
    assert got.dtype == np.int64 and got.tobytes() == want.astype(np.int64).tobytes()


def test_symbols_of_normalized_times_are_the_transform():
    t = np.cumsum(np.random.default_rng(3).uniform(0.1, 2.0, 57))
    bins = TimeBins(13)
    np.testing.assert_array_equal(bins.symbols(bins.normalize(t)), bins.transform(t))
    np.testing.assert_array_equal(bins.symbols(np.array([0.0, 0.5, 1.0, 1.2])),
                                  [0, 6, 12, 12])  # fmt: skip
