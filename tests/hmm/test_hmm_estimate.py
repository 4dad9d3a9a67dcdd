"""ndlfd.hmm counts and estimation: estimate, merge, matrices, parameters."""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import DecodeError, NotFittedError, ValidationError
from ndlfd.hmm import DiscreteHMM, estimate, merge, viterbi

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))
sys.path.insert(0, str(TESTS / "data"))

from hmm_cases import same_model, training  # noqa: E402

import reference_hmm as ref  # noqa: E402


@settings(max_examples=40, deadline=None)
@given(training())
def test_matrices_match_dense_reference(case):
    m, nt, states, symbols, p, r, _, _ = case
    model = estimate(states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r)
    A, B, pi = ref.dense_model(states, symbols, m, nt, p, r)
    np.testing.assert_array_equal(model.transition_matrix(dense=True), A)
    np.testing.assert_array_equal(model.emission_matrix(dense=True), B)
    np.testing.assert_allclose(model.initial_distribution(), pi, rtol=1e-15)
    assert not np.isnan(model.transition_matrix(dense=True)).any()
    # sparse count part + per-row baseline reproduces the dense matrices
    K = model.transition_matrix()
    assert isinstance(K, sp.coo_array) and K.shape == (m, m)
    b = model.transition_baseline(np.arange(m))
    np.testing.assert_allclose(K.toarray() + b[:, None], A, rtol=1e-14, atol=0)
    KB = model.emission_matrix()
    c = model.emission_baseline(np.arange(m))
    np.testing.assert_allclose(KB.toarray() + c[:, None], B, rtol=1e-14, atol=0)
    # the array form round-trips
    back = DiscreteHMM.from_arrays(model.to_arrays())
    np.testing.assert_array_equal(back.transition_matrix(dense=True), A)
    np.testing.assert_array_equal(back.emission_matrix(dense=True), B)
    # rows of A and B are distributions or (no counts, no pseudo-count) all zero;
    # a sum of k correctly rounded ratios is 1 within k ulps
    for M in (model.transition_matrix(dense=True), model.emission_matrix(dense=True)):
        sums = M.sum(axis=1)
        tol = M.shape[1] * np.finfo(float).eps
        assert np.all((np.abs(sums - 1.0) <= tol) | (sums == 0.0))


def test_counts_follow_hmmestimate():
    model = estimate([[4, 2, 2, 7], [2, 7]], [[0, 1, 1, 0], [1, 2]], 10, 3)
    np.testing.assert_array_equal(model.states_, [2, 4, 7])
    C, E, F, D = ref.dense_counts([[4, 2, 2, 7], [2, 7]], [[0, 1, 1, 0], [1, 2]], 10, 3)
    seen = model.states_
    np.testing.assert_array_equal(
        model.transition_counts_.toarray(), C[np.ix_(seen, seen)]
    )
    np.testing.assert_array_equal(model.emission_counts_.toarray(), E[seen])
    np.testing.assert_array_equal(model.start_counts_, F[seen])
    np.testing.assert_array_equal(model.transition_totals_, [3, 1, 0])
    np.testing.assert_array_equal(model.emission_totals_, [3, 1, 2])
    assert model.n_sequences_ == D == 2
    assert model.pseudo_transition_ == 0.1
    assert model.pseudo_transition is None
    # no transition across the two demonstrations (7 -> 2)
    assert model.transition_counts_.toarray()[2, 0] == 0
    assert model.lowest_unseen_state_ == 0


def test_lowest_unseen_state():
    assert estimate([0, 1, 3], [0, 0, 0], 5, 1).lowest_unseen_state_ == 2
    assert estimate([0, 1], [0, 0], 3, 1).lowest_unseen_state_ == 2
    assert estimate([1, 0], [0, 0], 2, 1).lowest_unseen_state_ is None


def test_input_forms_are_equivalent():
    a = estimate([0, 1, 1], [0, 1, 1], 3, 2)
    b = estimate([np.array([0, 1, 1])], [np.array([0, 1, 1])], 3, 2)
    c = estimate(np.array([[0, 1, 1]]), np.array([[0, 1, 1]]), 3, 2)
    d = estimate(np.array([0.0, 1.0, 1.0]), (0, 1, 1), 3, 2)
    for other in (b, c, d):
        for k, v in a.to_arrays().items():
            np.testing.assert_array_equal(v, other.to_arrays()[k])


# ----------------------------------------------------------------- errors


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        (([0, 1], [0]), {}, r"states\[0\] and symbols\[0\] must have the same length"),
        (([[0], [1]], [[0]]), {}, r"same number of sequences; got 2 state and 1"),
        (([0, 5], [0, 0]), {}, r"states\[0\] must lie in 0..3; got states\[0\]\[1\]"),
        (([0, 1], [0, 2]), {}, r"symbols\[0\] must lie in 0..1"),
        (([[0, 1], []], [[0, 1], []]), {}, r"states\[1\] is empty"),
        (([], []), {}, r"at least one sequence"),
        (([0.5, 1], [0, 0]), {}, r"whole numbers"),
        (([0, np.nan], [0, 0]), {}, r"whole numbers"),
        ((["a"], [0]), {}, r"must be a 1-D array of integers"),
        (([[[0]]], [[[0]]]), {}, r"must be a 1-D array of integers"),
        ((np.zeros((1, 1, 1), int), [0]), {}, r"got an array of shape \(1, 1, 1\)"),
        (("01", [0]), {}, r"got str"),
        (([0], [0]), {"pseudo_transition": -1.0}, r"pseudo_transition must be .* >= 0"),
        (([0], [0]), {"pseudo_transition": np.inf}, r"pseudo_transition must be"),
        (([0], [0]), {"pseudo_emission": np.nan}, r"pseudo_emission must be"),
        (([0], [0]), {"pseudo_emission": "1"}, r"pseudo_emission must be"),
    ],
)
def test_estimate_errors(args, kwargs, match):
    with pytest.raises(ValidationError, match=match):
        estimate(*args, 4, 2, **kwargs)


@pytest.mark.parametrize(
    ("m", "nt", "match"),
    [
        (0, 2, r"n_states must be an integer >= 1; got 0"),
        (2.0, 2, r"n_states must be an integer >= 1; got 2.0"),
        (2, 0, r"n_symbols must be an integer >= 1; got 0"),
        (2, 2**63, r"n_symbols must fit in int64"),
    ],
)
def test_estimate_size_errors(m, nt, match):
    with pytest.raises(ValidationError, match=match):
        estimate([0], [0], m, nt)


def test_not_fitted():
    model = DiscreteHMM(3, 2)
    with pytest.raises(NotFittedError, match="not fitted yet"):
        viterbi(model, [0])
    with pytest.raises(NotFittedError, match="not fitted yet"):
        model.transition_matrix()
    with pytest.raises(NotFittedError, match="not fitted yet"):
        model.save("x.npz")
    fresh = DiscreteHMM(3, 2)
    assert fresh.fit([0, 1], [0, 1]) is fresh  # fit returns the model itself
    same_model(fresh, estimate([0, 1], [0, 1], 3, 2))
    assert "n_states=3" in repr(model)


def test_baseline_argument_checked():
    model = estimate([0, 1], [0, 1], 3, 2)
    with pytest.raises(ValidationError, match=r"states must lie in 0..2"):
        model.transition_baseline([3])


def _labelled(m, min_size, max_size):
    """Lists of (states, symbols) pairs over ``m`` states and 3 symbols."""
    return st.lists(
        st.integers(1, 6).flatmap(
            lambda n: st.tuples(
                st.lists(st.integers(0, m - 1), min_size=n, max_size=n),
                st.lists(st.integers(0, 2), min_size=n, max_size=n),
            )
        ),
        min_size=min_size,
        max_size=max_size,
    )


@settings(max_examples=80, deadline=None)
@given(
    st.integers(2, 9).flatmap(
        lambda m: st.tuples(st.just(m), _labelled(m, 2, 7), st.integers(1, 6))
    ),
    st.sampled_from([None, 0.0, 0.5]),
    st.sampled_from([0.0, 0.25]),
)
def test_merge_of_chunks_equals_estimate_on_all(case, p, r):
    m, seqs, cut = case
    cut = min(cut, len(seqs) - 1)
    states = [s for s, _ in seqs]
    symbols = [o for _, o in seqs]
    kw = dict(pseudo_transition=p, pseudo_emission=r)
    whole = estimate(states, symbols, m, 3, **kw)
    parts = [
        estimate(states[:cut], symbols[:cut], m, 3, **kw),
        estimate(states[cut:], symbols[cut:], m, 3, **kw),
    ]
    merged = merge(parts)
    a, b = whole.to_arrays(), merged.to_arrays()
    assert a.keys() == b.keys()
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    assert merged.n_sequences_ == whole.n_sequences_
    obs = symbols[0]
    for start in ("learned", "state1"):
        try:
            expected = viterbi(whole, obs, start=start)
        except DecodeError:
            with pytest.raises(DecodeError):
                viterbi(merged, obs, start=start)
            continue
        got = viterbi(merged, obs, start=start)
        np.testing.assert_array_equal(got[0], expected[0])
        assert got[1] == expected[1]


def _assert_same_model(got, want):
    a, b = want.to_arrays(), got.to_arrays()
    assert a.keys() == b.keys()
    for k in a:
        np.testing.assert_array_equal(b[k], a[k], err_msg=k)
        assert b[k].dtype == a[k].dtype, k
    assert got.n_sequences_ == want.n_sequences_


@settings(max_examples=60, deadline=None)
@given(
    st.integers(2, 9).flatmap(lambda m: st.tuples(st.just(m), _labelled(m, 3, 9))),
    st.data(),
    st.sampled_from([None, 0.0, 0.5]),
    st.sampled_from([0.0, 0.25]),
)
def test_merge_of_three_or_more_chunks_equals_estimate_on_all(case, data, p, r):
    m, seqs = case
    n = len(seqs)
    n_chunks = data.draw(st.integers(3, n), label="n_chunks")
    inner = data.draw(st.permutations(range(1, n)), label="cuts")
    cuts = [0, *sorted(inner[: n_chunks - 1]), n]
    states = [s for s, _ in seqs]
    symbols = [o for _, o in seqs]
    kw = dict(pseudo_transition=p, pseudo_emission=r)
    whole = estimate(states, symbols, m, 3, **kw)
    parts = [
        estimate(states[lo:hi], symbols[lo:hi], m, 3, **kw)
        for lo, hi in itertools.pairwise(cuts)
    ]
    assert len(parts) == n_chunks >= 3
    _assert_same_model(merge(parts), whole)
    # counts add up whatever the order and grouping of the chunks
    _assert_same_model(merge(parts[::-1]), whole)
    _assert_same_model(merge([merge(parts[:2]), *parts[2:]]), whole)
    _assert_same_model(merge([parts[0], merge(parts[1:])]), whole)


def test_merge_errors():
    from ndlfd.hmm import merge

    a = estimate([[0, 1]], [[0, 1]], 3, 2)
    with pytest.raises(ValidationError, match="at least one"):
        merge([])
    with pytest.raises(ValidationError, match=r"models\[1\] must be a DiscreteHMM"):
        merge([a, "b"])
    with pytest.raises(ValidationError, match="must share n_states"):
        merge([a, estimate([[0, 1]], [[0, 1]], 4, 2)])
    with pytest.raises(ValidationError, match="must share"):
        merge([a, estimate([[0, 1]], [[0, 1]], 3, 2, pseudo_emission=1.0)])
    with pytest.raises(NotFittedError):
        merge([a, DiscreteHMM(3, 2)])
    same_model(merge(a), a)  # one model merges to itself
    same_model(merge([a]), a)
