"""ndlfd.hmm decoding: Viterbi against a dense reference, ties, plain arrays."""

from __future__ import annotations

import itertools
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import DecodeError, OptionError, ValidationError
from ndlfd.hmm import DENSE_LIMIT_BYTES, STARTS, estimate, posterior, viterbi
from ndlfd.hmm._counts import Counts, count
from ndlfd.hmm._decode import (
    filter_tables,
    forward_backward,
    forward_filter,
    log_tables,
    viterbi_path,
)

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))
sys.path.insert(0, str(TESTS / "data"))

from hmm_cases import training  # noqa: E402

import reference_hmm as ref  # noqa: E402


def _ours(m, nt, states, symbols, p, r, obs, start):
    model = estimate(states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r)
    try:
        return viterbi(model, obs, start=start)
    except DecodeError:
        return None, -np.inf


@settings(max_examples=300, deadline=None)
@given(training())
def test_viterbi_matches_dense_reference_exactly(case):
    m, nt, states, symbols, p, r, obs, start = case
    path, logp = _ours(*case)
    ref_path, ref_logp = ref.reference_viterbi(
        states, symbols, m, nt, obs, p=p, r=r, start=start
    )
    if ref_path is None:
        assert path is None
    else:
        assert path is not None
        np.testing.assert_array_equal(path, ref_path)
        assert path.dtype == np.int64
        # same ratio formula, same np.log, same order of additions: bit-exact
        assert logp == ref_logp


@settings(max_examples=60, deadline=None)
@given(training(max_m=4, max_nt=2, max_len=4))
def test_viterbi_log_probability_matches_brute_force(case):
    m, nt, states, symbols, p, r, obs, start = case
    path, logp = _ours(*case)
    A, B, pi = ref.dense_model(states, symbols, m, nt, p, r)
    logA, logB = ref.log(A), ref.log(B)
    logpi = ref.log(pi) if start == "learned" else logA[0]
    best = ref.brute_force_best(logA, logB, logpi, obs)
    if best == -np.inf:
        assert path is None
        return
    assert np.isclose(logp, best, rtol=1e-12, atol=1e-12)
    # the returned path really has that log-probability
    s = logpi[path[0]] + logB[path[0], obs[0]]
    for t in range(1, len(obs)):
        s += logA[path[t - 1], path[t]] + logB[path[t], obs[t]]
    assert np.isclose(s, logp, rtol=1e-12, atol=1e-12)


# ----------------------------------------------------------------- hand-built ties


def _four_state_model(symbols):
    # sequences [2, j], j = 0..3: C[2, j] = 1, n_2 = 4, p = 1/4 -> every A entry
    # is (1 + 1/4) / (4 + 1) = 1/4 (rows with n = 0: (1/4) / 1 = 1/4)
    states = [[2, j] for j in range(4)]
    nt = 1 + max(max(s) for s in symbols)
    model = estimate(states, symbols, 4, nt, pseudo_transition=0.25)
    np.testing.assert_array_equal(model.transition_matrix(dense=True), 0.25)
    return model


def test_tie_pseudo_count_candidate_wins_on_index():
    model = _four_state_model([[0, 0]] * 4)
    path, logp = viterbi(model, [0, 0, 0], start="state1")
    np.testing.assert_array_equal(path, [0, 0, 0])
    assert logp == 3 * np.log(0.25)


def test_tie_counted_candidate_wins_on_index():
    model = _four_state_model([[1, 0], [1, 0], [1, 1], [1, 1]])
    path, logp = viterbi(model, [1, 1], start="state1")
    np.testing.assert_array_equal(path, [2, 2])
    assert logp == 2 * np.log(0.25)


def test_unseen_states_are_one_class_represented_by_lowest_id():
    # seen: 1 and 3 only; with r > 0 every state may emit; m = 6
    states = [[3, 1]]
    symbols = [[0, 1]]
    case = (6, 2, states, symbols, None, 1.0, [1, 1, 1, 0], "learned")
    path, logp = _ours(*case)
    ref_path, ref_logp = ref.reference_viterbi(
        states, symbols, 6, 2, [1, 1, 1, 0], r=1.0
    )
    np.testing.assert_array_equal(path, ref_path)
    assert logp == ref_logp


def test_huge_state_count_uses_seen_states_only():
    m = 10**12
    rng = np.random.default_rng(3)
    ids = rng.choice(10**12, size=50, replace=False).astype(np.int64)
    states = [ids[rng.integers(0, 50, size=20)] for _ in range(10)]
    symbols = [np.sort(rng.integers(0, 8, size=20)) for _ in range(10)]
    model = estimate(states, symbols, m, 8)
    np.testing.assert_array_equal(model.states_, np.unique(np.concatenate(states)))
    obs = np.arange(8)
    path, logp = viterbi(model, obs)
    assert path.shape == (8,) and np.all(np.isin(path, model.states_))
    # logp is the log-probability of that path, recomputed from plain counts
    # (p = 1/m, r = 0); summed in another order, so equal up to rounding
    C, E, F = {}, {}, {}
    for seq, sym in zip(states, symbols, strict=True):
        F[seq[0]] = F.get(seq[0], 0) + 1
        for k in range(len(seq)):
            E[seq[k], sym[k]] = E.get((seq[k], sym[k]), 0) + 1
            if k + 1 < len(seq):
                C[seq[k], seq[k + 1]] = C.get((seq[k], seq[k + 1]), 0) + 1
    p = 1.0 / m

    def log_a(i, j):
        n_i = sum(c for (a, _), c in C.items() if a == i)
        return np.log((C.get((i, j), 0) + p) / (n_i + m * p))

    def log_b(i, o):
        return np.log(E.get((i, o), 0) / sum(c for (a, _), c in E.items() if a == i))

    want = np.log((F.get(path[0], 0) + p) / (len(states) + m * p))
    want += log_b(path[0], obs[0])
    for t in range(1, 8):
        want += log_a(path[t - 1], path[t]) + log_b(path[t], obs[t])
    assert np.isfinite(logp)
    np.testing.assert_allclose(logp, want, rtol=1e-13)
    K = model.transition_matrix()
    assert K.shape == (m, m) and K.nnz == model.transition_counts_.nnz
    with pytest.raises(ValidationError, match=r"dense transition matrix .* MiB"):
        model.transition_matrix(dense=True)
    with pytest.raises(ValidationError, match=r"dense emission matrix .* MiB"):
        model.emission_matrix(dense=True)
    with pytest.raises(ValidationError, match=r"initial distribution .* limit"):
        model.initial_distribution()
    assert DENSE_LIMIT_BYTES == 256 * 2**20
    # with r > 0 an unseen state may be on the path: the lowest unseen id
    model_r = estimate(states, symbols, m, 8, pseudo_emission=1.0)
    path_r, _ = viterbi(model_r, [0, 7, 0])
    assert np.all(np.isin(path_r, np.append(model_r.states_, 0)))


# ----------------------------------------------------------------- textbook example


def test_wikipedia_healthy_fever_example():
    # Healthy = 0, Fever = 1; normal = 0, cold = 1, dizzy = 2.
    # Counts chosen so that pi = (.6, .4), A = [[.7, .3], [.4, .6]],
    # B = [[.5, .4, .1], [.1, .3, .6]] (p = r = 0):
    # pairs [0,0]x42 [0,1]x18 [1,0]x16 [1,1]x24 and singletons [0]x12 [1]x8
    # give F = (72, 48), C rows (42, 18)/60 and (16, 24)/40, e = (130, 90).
    states = (
        [[0, 0]] * 42 + [[0, 1]] * 18 + [[1, 0]] * 16 + [[1, 1]] * 24
        + [[0]] * 12 + [[1]] * 8
    )  # fmt: skip
    emit = {0: [0] * 65 + [1] * 52 + [2] * 13, 1: [0] * 9 + [1] * 27 + [2] * 54}
    used = {0: 0, 1: 0}
    symbols = []
    for seq in states:
        row = []
        for s in seq:
            row.append(emit[s][used[s]])
            used[s] += 1
        symbols.append(row)
    model = estimate(states, symbols, 2, 3, pseudo_transition=0)
    # with zero pseudo-counts every entry is one correctly rounded count ratio
    # (72/120, 42/60, 65/130, ...), which is the double nearest the decimal
    np.testing.assert_array_equal(model.initial_distribution(), [0.6, 0.4])
    np.testing.assert_array_equal(
        model.transition_matrix(dense=True), [[0.7, 0.3], [0.4, 0.6]]
    )
    np.testing.assert_array_equal(
        model.emission_matrix(dense=True), [[0.5, 0.4, 0.1], [0.1, 0.3, 0.6]]
    )
    # worked by hand: delta1 = (.3, .04); delta2 = (.084, .027);
    # delta3 = (.00588, .01512); best path Healthy, Healthy, Fever
    path, logp = viterbi(model, [0, 1, 2])
    np.testing.assert_array_equal(path, [0, 0, 1])
    assert np.isclose(np.exp(logp), 0.01512, rtol=1e-12)


def test_viterbi_errors():
    model = estimate([[0, 1, 2]], [[0, 1, 1]], 4, 3, pseudo_transition=0)
    with pytest.raises(OptionError, match=r"unknown start 'first'; expected one of"):
        viterbi(model, [0], start="first")
    with pytest.raises(OptionError, match=r"unknown start None; expected one of"):
        model.decode([0], start=None)
    with pytest.raises(ValidationError, match=r"at least one symbol; got length 0"):
        viterbi(model, [])
    with pytest.raises(ValidationError, match=r"symbols must lie in 0..2; got"):
        viterbi(model, [0, 3])
    with pytest.raises(ValidationError, match=r"must be a fitted DiscreteHMM; got"):
        viterbi("model", [0])
    with pytest.raises(DecodeError, match=r"symbol 2 at step 1: it was never emitted"):
        viterbi(model, [0, 2])
    # symbol 1 is emitted only by states 1 and 2; from 2 nothing is reachable
    with pytest.raises(DecodeError, match=r"symbol 1 at step 3: no state .* reachable"):
        viterbi(model, [0, 1, 1, 1])
    # state1: with p = 0 the chain leaves state 0 for 1, which cannot emit 0
    with pytest.raises(DecodeError, match=r"symbol 0 at step 0: no state.*'state1'"):
        viterbi(model, [0], start="state1")
    np.testing.assert_array_equal(viterbi(model, [0])[0], [0])


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize(
    ("p", "r"), [(None, 0.0), (None, 0.01), (0.0, 0.0), (2.0, 1.0)]
)
def test_medium_models_match_dense_reference(seed, p, r):
    # random-walk state sequences over part of m = 60 states, as key points do
    rng = np.random.default_rng(seed)
    m, nt = 60, 12
    states, symbols = [], []
    for _ in range(20):
        n = int(rng.integers(5, 25))
        walk = np.clip(np.cumsum(rng.integers(-2, 3, size=n)) + 20, 0, 45)
        states.append(walk)
        symbols.append(np.minimum((np.arange(n) * nt) // n, nt - 1))
    obs = np.sort(rng.integers(0, nt, size=30))
    for start in ("learned", "state1"):
        model = estimate(states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r)
        ref_path, ref_logp = ref.reference_viterbi(
            states, symbols, m, nt, obs, p=p, r=r, start=start
        )
        if ref_path is None:
            with pytest.raises(DecodeError):
                viterbi(model, obs, start=start)
            continue
        path, logp = viterbi(model, obs, start=start)
        np.testing.assert_array_equal(path, ref_path)
        assert logp == ref_logp


# -- merge: counts add up across chunks of demonstrations ------------------------


# -- the decoders take plain arrays, never the model class ------------------------


@settings(max_examples=150, deadline=None)
@given(training())
def test_decoders_on_plain_arrays_match_the_model_calls(case):
    m, nt, states, symbols, p, r, obs, start = case
    model = estimate(states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r)
    counts = count(states, symbols, m, nt, p, r)  # no DiscreteHMM involved
    for got, want in (
        (lambda: viterbi_path(log_tables(counts), obs, start), viterbi),
        (lambda: forward_backward(counts, obs, start), posterior),
    ):
        try:
            expected = want(model, obs, start=start)
        except DecodeError as exc:
            with pytest.raises(DecodeError, match=re.escape(str(exc))):
                got()
            continue
        result = got()
        assert type(result) is type(expected)
        for a, b in zip(result, expected, strict=True):
            np.testing.assert_array_equal(a, b)  # bit for bit


def test_decoders_on_hand_written_arrays():
    # two sequences 0 -> 1 and 0 -> 2 over m = 3 states, both emit (0, 1); p = r = 0
    counts = Counts(
        n_states=3,
        n_symbols=2,
        pseudo_transition=0.0,
        pseudo_emission=0.0,
        n_sequences=2,
        states=np.array([0, 1, 2]),
        transition_indptr=np.array([0, 2, 2, 2]),
        transition_targets=np.array([1, 2]),
        transition_counts=np.array([1, 1]),
        emission_indptr=np.array([0, 1, 2, 3]),
        emission_symbols=np.array([0, 1, 1]),
        emission_counts=np.array([2, 1, 1]),
        start_counts=np.array([2, 0, 0]),
    )
    path, logp = viterbi_path(log_tables(counts), [0, 1])
    np.testing.assert_array_equal(path, [0, 1])  # tie: the lowest state
    assert logp == np.log(0.5)
    post = forward_backward(counts, [0, 1], "learned")
    np.testing.assert_array_equal(post.probabilities, [[1, 0, 0], [0, 0.5, 0.5]])
    # the same arrays as counting the sequences, and the same answers as the model
    counted = count([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2, 0.0, 0.0)
    for name in Counts._fields:
        np.testing.assert_array_equal(getattr(counts, name), getattr(counted, name))
    model = estimate([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2, pseudo_transition=0)
    want_path, want_logp = viterbi(model, [0, 1])
    np.testing.assert_array_equal(path, want_path)
    assert logp == want_logp
    with pytest.raises(ValidationError, match=r"symbols must lie in 0..1"):
        viterbi_path(log_tables(counts), [2])
    with pytest.raises(OptionError, match=r"unknown start 'first'"):
        forward_backward(counts, [0], "first")


def test_start_modes_are_one_registry():
    import ndlfd.hmm

    assert ndlfd.hmm.STARTS is STARTS
    assert STARTS.names == ("learned", "state1")
    assert "STARTS" in ndlfd.hmm.__all__


# --------------------------------------------------------------- forward filtering


def _brute_filter(A, B, pi, obs, L):
    """P(last state), log p(symbols, observations): every state path enumerated.

    ``L[t, s]`` is the observation's likelihood in state ``s`` (all ones: the
    symbols alone).
    """
    m = A.shape[0]
    last = np.zeros(m)
    for path in itertools.product(range(m), repeat=len(obs)):
        p = pi[path[0]] * B[path[0], obs[0]] * L[0, path[0]]
        for t in range(1, len(obs)):
            p *= A[path[t - 1], path[t]] * B[path[t], obs[t]] * L[t, path[t]]
        last[path[-1]] += p
    total = last.sum()
    return (last / total if total > 0 else last), ref.log(total)


@settings(max_examples=120, deadline=None)
@given(
    training(max_m=4, max_nt=2, max_len=4),
    st.booleans(),
    st.lists(st.floats(-3.0, 3.0), min_size=16, max_size=16),
    st.sampled_from([None, 0, 3]),
)
def test_forward_filter_matches_brute_force_enumeration(case, observe, values, gone):
    m, nt, states, symbols, p, r, obs, start = case
    counts = count(states, symbols, m, nt, p, r)
    A, B, pi = ref.dense_model(states, symbols, m, nt, p, r)
    if start == "state1":
        pi = A[0]
    seen = counts.states
    L = np.ones((len(obs), m))
    loglik = None
    if observe:  # an observation per step and seen state; unseen states none
        loglik = np.array(values[: len(obs) * seen.size]).reshape(len(obs), -1)
        if gone is not None and gone < loglik.size:
            loglik.flat[gone] = -np.inf  # a state that cannot be observed so
        L = np.zeros((len(obs), m))
        L[:, seen] = np.exp(loglik)
    want, want_logp = _brute_filter(A, B, pi, obs, L)
    if not want_logp > -np.inf:
        with pytest.raises(DecodeError, match="probability zero"):
            forward_filter(counts, obs, start, log_likelihood=loglik)
        return
    got = forward_filter(counts, obs, start, log_likelihood=loglik)
    again = forward_filter(counts, obs, start, loglik, filter_tables(counts, start))
    for a, b in zip(got, again, strict=True):
        np.testing.assert_array_equal(a, b)  # the tables built once: bit for bit
    np.testing.assert_array_equal(got.states, seen)
    np.testing.assert_allclose(got.probabilities, want[seen], rtol=1e-9, atol=1e-12)
    unseen = np.setdiff1d(np.arange(m), seen)
    assert got.unseen == pytest.approx(want[unseen].sum(), rel=1e-9, abs=1e-12)
    assert got.log_likelihood == pytest.approx(float(want_logp), rel=1e-9, abs=1e-9)
    if loglik is None:  # the last row of the posterior, and its likelihood
        post = forward_backward(counts, obs, start)
        np.testing.assert_allclose(got.probabilities, post.probabilities[-1])
        assert got.log_likelihood == pytest.approx(post.log_likelihood)


def test_forward_filter_costs_the_seen_states_not_the_codebook():
    # 10**15 codebook states, 5 seen: anything of size n_states would not fit;
    # the same counts give the same filter whatever the codebook's size
    states = [[5, 7, 9, 9], [5, 8, 9, 11]]
    symbols = [[0, 1, 2, 3]] * 2
    loglik = np.zeros((4, 5))
    loglik[3, 4] = np.log(3.0)  # the last observation 3 times likelier in 11
    got = [
        forward_filter(count(states, symbols, m, 4, 0.0, 0.0), [0, 1, 2, 3],
                       log_likelihood=loglik)
        for m in (12, 10**15)
    ]  # fmt: skip
    # by hand: both paths reach 9 at step 2 (B[9, 2] = 2/3); then 9 -> 9 or
    # 9 -> 11 (1/2 each), B[9, 3] = 1/3, B[11, 3] = 1, and the observation
    # 1 : 3, so 1/6 : 3/2 = 1 : 9, and p = 2/3 * (1/6 + 3/2) = 10/9
    for f in got:
        np.testing.assert_array_equal(f.states, [5, 7, 8, 9, 11])
        np.testing.assert_allclose(f.probabilities, [0, 0, 0, 0.1, 0.9])
        assert f.log_likelihood == pytest.approx(np.log(10 / 9))
    np.testing.assert_array_equal(got[0].probabilities, got[1].probabilities)


def test_forward_filter_errors():
    counts = count([[0, 1]], [[0, 1]], 3, 2, 0.0, 0.0)
    expected = r"shape \(n_steps, n_seen\) = \(2, 2\); got \(2, 3\)"
    with pytest.raises(ValidationError, match=expected):
        forward_filter(counts, [0, 1], log_likelihood=np.zeros((2, 3)))
    with pytest.raises(ValidationError, match="NaN or \\+inf"):
        forward_filter(counts, [0, 1], log_likelihood=[[0.0, np.nan], [0.0, 0.0]])
    with pytest.raises(DecodeError, match="probability zero"):
        forward_filter(counts, [0, 1], log_likelihood=[[0.0, 0.0], [0.0, -np.inf]])
    tables = filter_tables(counts, "state1")
    with pytest.raises(ValidationError, match="start='state1'; got start='learned'"):
        forward_filter(counts, [0, 1], tables=tables)
