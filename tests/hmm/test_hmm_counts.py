"""ndlfd.hmm._counts: counting sequences given as lists, arrays and 2-D arrays.

A list of int64 arrays and a 2-D integer array are checked at once (the
learner counts thousands of short sequences); these tests hold them to the
plain lists' answers, to the dense reference, and to the same errors.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import ValidationError
from ndlfd.hmm._counts import count

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))
sys.path.insert(0, str(TESTS / "data"))

from hmm_cases import training  # noqa: E402

import reference_hmm as ref  # noqa: E402


def _same_counts(a, b) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype
            np.testing.assert_array_equal(x, y)
        else:
            assert x == y


def _dense(c):
    """C, E, F of Counts over all states (from the CSR rows)."""
    m, nt = c.n_states, c.n_symbols
    C, E, F = np.zeros((m, m)), np.zeros((m, nt)), np.zeros(m)
    for k, s in enumerate(c.states):
        lo, hi = c.transition_indptr[k], c.transition_indptr[k + 1]
        C[s, c.states[c.transition_targets[lo:hi]]] = c.transition_counts[lo:hi]
        lo, hi = c.emission_indptr[k], c.emission_indptr[k + 1]
        E[s, c.emission_symbols[lo:hi]] = c.emission_counts[lo:hi]
        F[s] = c.start_counts[k]
    return C, E, F


@settings(max_examples=60, deadline=None)
@given(training(max_m=12, max_nt=4, max_len=6), st.sampled_from(["int64", "uint8"]))
def test_arrays_count_as_the_plain_lists(case, dtype):
    m, nt, states, symbols, p, r, _, _ = case
    plain = count(states, symbols, m, nt, p, r)
    arrays = count(
        [np.array(s, dtype=dtype) for s in states],
        [np.array(o, dtype=dtype) for o in symbols],
        m, nt, p, r,
    )  # fmt: skip
    _same_counts(plain, arrays)
    C, E, F, D = ref.dense_counts(states, symbols, m, nt)
    got = _dense(arrays)
    for want, have in zip((C, E, F), got, strict=True):
        np.testing.assert_array_equal(have, want)
    assert arrays.n_sequences == D
    if len({len(s) for s in states}) == 1:  # equal lengths: one 2-D array
        _same_counts(plain, count(np.array(states), np.array(symbols), m, nt, p, r))


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40), st.integers(1, 300))
def test_many_sequences_match_the_dense_reference(seed, n_seq, m):
    rng = np.random.default_rng(seed)
    nt = int(rng.integers(1, 30))
    lengths = rng.integers(1, 30, n_seq)
    states = [rng.integers(0, m, n) for n in lengths]
    symbols = [np.sort(rng.integers(0, nt, n)) for n in lengths]
    c = count(states, symbols, m, nt)
    C, E, F, D = ref.dense_counts(states, symbols, m, nt)
    assert c.n_sequences == D == n_seq
    for want, have in zip((C, E, F), _dense(c), strict=True):
        np.testing.assert_array_equal(have, want)
    # symbols so many that a pair's key a * n_symbols + b would not fit int64:
    # the pairs are then sorted as pairs, with the same counts
    huge = count(states, symbols, m, 2**62)
    _same_counts(c[4:], huge[4:])


@pytest.mark.parametrize(
    ("states", "symbols", "match"),
    [
        (
            [np.array([0, 1]), np.array([0, 5])],
            [np.array([0, 0]), np.array([0, 0])],
            r"states\[1\] must lie in 0..2; got states\[1\]\[1\] = 5",
        ),
        (
            [np.array([0, 1]), np.array([-1, 0])],
            [np.array([0, 0]), np.array([0, 0])],
            r"states\[1\] must lie in 0..2; got states\[1\]\[0\] = -1",
        ),
        (
            [np.array([0, 1]), np.array([], dtype=np.int64)],
            [np.array([0, 0]), np.array([], dtype=np.int64)],
            r"states\[1\] is empty",
        ),
        (
            [np.array([0, 1]), np.array([2])],
            [np.array([0, 0]), np.array([0, 1])],
            r"states\[1\] and symbols\[1\] must have the same length; got 1 and 2",
        ),
        (
            [np.array([0, 1]), np.array([2])],
            [np.array([0, 0])],
            r"the same number of sequences; got 2 state and 1 symbol",
        ),
        (
            np.array([[0, 1], [2, 3]]),
            np.zeros((2, 2), dtype=np.int64),
            r"states\[1\] must lie in 0..2; got states\[1\]\[1\] = 3",
        ),
        (
            np.array([[0, 1], [2, 1]]),
            np.array([[0, 0], [0, 2]]),
            r"symbols\[1\] must lie in 0..1; got symbols\[1\]\[1\] = 2",
        ),
        (
            np.zeros((2, 0), dtype=np.int64),
            np.zeros((2, 0), dtype=np.int64),
            r"states\[0\] is empty",
        ),
    ],
)
def test_arrays_refused_with_the_sequence_named(states, symbols, match):
    with pytest.raises(ValidationError, match=match):
        count(states, symbols, 3, 2)
