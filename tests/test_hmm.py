from __future__ import annotations

import itertools
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import (
    DecodeError,
    ModelFormatError,
    NotFittedError,
    OptionError,
    ValidationError,
)
from ndlfd.hmm import DENSE_LIMIT_BYTES, DiscreteHMM, estimate, merge, viterbi

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "data"))

import make_hmm_v1  # noqa: E402

import reference_hmm as ref  # noqa: E402

# ----------------------------------------------------------------- random models


@st.composite
def training(draw, max_m=8, max_nt=3, max_len=5):
    m = draw(st.integers(1, max_m))
    nt = draw(st.integers(1, max_nt))
    # a subset of the states is used, so unseen states (also below seen ones) exist
    pool = draw(
        st.lists(st.integers(0, m - 1), min_size=1, max_size=min(m, 4), unique=True)
    )
    n_seq = draw(st.integers(1, 4))
    states, symbols = [], []
    for _ in range(n_seq):
        n = draw(st.integers(1, max_len))
        states.append(draw(st.lists(st.sampled_from(pool), min_size=n, max_size=n)))
        symbols.append(draw(st.lists(st.integers(0, nt - 1), min_size=n, max_size=n)))
    p = draw(st.sampled_from([None, 0.0, 0.5, 1.0]))
    r = draw(st.sampled_from([0.0, 0.5, 1.0]))
    obs = draw(st.lists(st.integers(0, nt - 1), min_size=1, max_size=max_len))
    start = draw(st.sampled_from(["learned", "state1"]))
    return m, nt, states, symbols, p, r, obs, start


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
        (2**63, 2, r"n_states must fit in int64"),
    ],
)
def test_estimate_size_errors(m, nt, match):
    with pytest.raises(ValidationError, match=match):
        estimate([0], [0], m, nt)


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
    _same(fresh, estimate([0, 1], [0, 1], 3, 2))
    assert "n_states=3" in repr(model)


def test_baseline_argument_checked():
    model = estimate([0, 1], [0, 1], 3, 2)
    with pytest.raises(ValidationError, match=r"states must lie in 0..2"):
        model.transition_baseline([3])


# ----------------------------------------------------------------- persistence


def _same(a: DiscreteHMM, b: DiscreteHMM) -> None:
    ta, tb = a.to_arrays(), b.to_arrays()
    assert ta.keys() == tb.keys()
    for k in ta:
        np.testing.assert_array_equal(ta[k], tb[k])
    assert (a.n_states, a.n_symbols, a.pseudo_transition, a.pseudo_emission) == (
        b.n_states,
        b.n_symbols,
        b.pseudo_transition,
        b.pseudo_emission,
    )


@pytest.mark.parametrize("p", [None, 0.0, 0.3])
def test_save_load_round_trip(tmp_path, p):
    model = estimate(
        [[5, 1, 1, 9], [1, 9]], [[0, 1, 1, 2], [1, 2]], 10**9, 3,
        pseudo_transition=p, pseudo_emission=0.5,
    )  # fmt: skip
    f = tmp_path / "m.npz"
    model.save(f)
    back = DiscreteHMM.load(f)
    _same(model, back)
    for obs in ([0, 1, 2], [2, 2], [1]):
        a, la = viterbi(model, obs)
        b, lb = viterbi(back, obs)
        np.testing.assert_array_equal(a, b)
        assert la == lb


def test_to_arrays_prefix_embeds_in_other_dicts():
    model = estimate([0, 1], [0, 1], 2, 2)
    arrays = {"other": np.zeros(3), **model.to_arrays(prefix="hmm/")}
    _same(model, DiscreteHMM.from_arrays(arrays, prefix="hmm/"))
    with pytest.raises(ModelFormatError, match=r"missing array 'x/sizes'"):
        DiscreteHMM.from_arrays(arrays, prefix="x/")


def test_committed_v1_fixture_loads_and_decodes():
    model = DiscreteHMM.load(make_hmm_v1.FIXTURE)
    _same(model, make_hmm_v1.build())
    path, logp = viterbi(model, make_hmm_v1.DECODE)
    np.testing.assert_array_equal(path, make_hmm_v1.EXPECTED_PATH)
    ref_path, ref_logp = ref.reference_viterbi(
        make_hmm_v1.STATES,
        make_hmm_v1.SYMBOLS,
        make_hmm_v1.N_STATES,
        make_hmm_v1.N_SYMBOLS,
        make_hmm_v1.DECODE,
        r=make_hmm_v1.PSEUDO_EMISSION,
    )
    np.testing.assert_array_equal(path, ref_path)
    assert logp == ref_logp


def test_foreign_and_broken_files(tmp_path):
    np.savez(tmp_path / "plain.npz", a=np.zeros(3))
    with pytest.raises(ModelFormatError, match="without ndlfd metadata"):
        DiscreteHMM.load(tmp_path / "plain.npz")
    (tmp_path / "noise.npz").write_bytes(np.random.default_rng(0).bytes(300))
    with pytest.raises(ModelFormatError, match="not readable"):
        DiscreteHMM.load(tmp_path / "noise.npz")
    good = make_hmm_v1.FIXTURE.read_bytes()
    (tmp_path / "trunc.npz").write_bytes(good[: len(good) // 2])
    with pytest.raises(ModelFormatError, match="not readable"):
        DiscreteHMM.load(tmp_path / "trunc.npz")
    with pytest.raises(ModelFormatError, match="no such file"):
        DiscreteHMM.load(tmp_path / "missing.npz")


def _tampered(tmp_path, key, value):
    with np.load(make_hmm_v1.FIXTURE, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays[key] = value(arrays[key])
    f = tmp_path / f"tampered_{key}.npz"
    np.savez(f, **arrays)
    return f


@pytest.mark.parametrize(
    ("key", "change", "match"),
    [
        ("states", lambda a: a[::-1].copy(), "strictly increasing ids"),
        ("states", lambda a: a + 100, "strictly increasing ids in 0..11"),
        ("states", lambda a: a.astype(float), "integer array"),
        ("transition_counts", lambda a: a * 0, "must be >= 1"),
        ("transition_counts", lambda a: a + 1, "inconsistent"),
        ("transition_targets", lambda a: a + 50, r"must lie in 0..\d"),
        ("transition_indptr", lambda a: a[:-1], "must have shape"),
        ("emission_symbols", lambda a: a[::-1].copy(), "strictly increasing in each"),
        ("emission_counts", lambda a: a[:-1], "one per entry"),
        ("start_counts", lambda a: a * 2, "summing to n_sequences"),
        ("sizes", lambda a: a[:2], r"shape \(3,\)"),
        ("sizes", lambda a: np.array([0, a[1], a[2]]), "must be >= 1"),
        ("pseudo", lambda a: np.array([-1.0, a[1]]), "pseudo_transition must be"),
        ("pseudo", lambda a: np.array([a[0], np.inf]), "pseudo_emission must be"),
        ("pseudo", lambda a: a.reshape(1, 2), "1-D float array"),
    ],
)
def test_tampered_arrays_are_refused(tmp_path, key, change, match):
    f = _tampered(tmp_path, key, change)
    with pytest.raises(ModelFormatError, match=match):
        DiscreteHMM.load(f)


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


@settings(max_examples=80, deadline=None)
@given(
    st.integers(2, 9).flatmap(
        lambda m: st.tuples(
            st.just(m),
            st.lists(
                st.integers(1, 6).flatmap(
                    lambda n: st.tuples(
                        st.lists(st.integers(0, m - 1), min_size=n, max_size=n),
                        st.lists(st.integers(0, 2), min_size=n, max_size=n),
                    )
                ),
                min_size=2,
                max_size=7,
            ),
            st.integers(1, 6),
        )
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
    st.integers(2, 9).flatmap(
        lambda m: st.tuples(
            st.just(m),
            st.lists(
                st.integers(1, 6).flatmap(
                    lambda n: st.tuples(
                        st.lists(st.integers(0, m - 1), min_size=n, max_size=n),
                        st.lists(st.integers(0, 2), min_size=n, max_size=n),
                    )
                ),
                min_size=3,
                max_size=9,
            ),
        )
    ),
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
    _same(merge(a), a)  # one model merges to itself
    _same(merge([a]), a)
