"""ndlfd.hmm.sample_paths (FFBS) against brute force over all state paths."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from ndlfd import DecodeError, ValidationError, hmm


def path_posterior(model, obs, start):
    """P(path | obs) of every path with positive probability, by enumeration.

    Unseen states are written as the lowest unseen id (as the decoders do), so
    the paths through them are summed.
    """
    A = model.transition_matrix(dense=True)
    B = model.emission_matrix(dense=True)
    pi = model.initial_distribution() if start == "learned" else A[0]
    m = A.shape[0]
    low = model.lowest_unseen_state_
    as_class = np.array(
        [s if (s in model.states_ or low is None) else low for s in range(m)]
    )
    probs = {}
    for path in itertools.product(range(m), repeat=len(obs)):
        p = pi[path[0]] * B[path[0], obs[0]]
        for t in range(1, len(obs)):
            p *= A[path[t - 1], path[t]] * B[path[t], obs[t]]
        if p > 0:
            key = tuple(int(s) for s in as_class[list(path)])
            probs[key] = probs.get(key, 0.0) + p
    total = sum(probs.values())
    return {k: v / total for k, v in probs.items()}


def frequencies(paths):
    keys, counts = np.unique(paths, axis=0, return_counts=True)
    return {tuple(int(s) for s in k): int(c) for k, c in zip(keys, counts, strict=True)}


@st.composite
def small_models(draw):
    m = draw(st.integers(2, 4))
    nt = draw(st.integers(1, 3))
    pool = draw(
        st.lists(st.integers(0, m - 1), min_size=1, max_size=min(m, 3), unique=True)
    )
    states, symbols = [], []
    for _ in range(draw(st.integers(1, 3))):
        n = draw(st.integers(1, 3))
        states.append(draw(st.lists(st.sampled_from(pool), min_size=n, max_size=n)))
        symbols.append(draw(st.lists(st.integers(0, nt - 1), min_size=n, max_size=n)))
    p = draw(st.sampled_from([None, 0.0, 0.25]))
    r = draw(st.sampled_from([0.0, 0.5]))
    model = hmm.estimate(states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r)
    obs = draw(st.lists(st.integers(0, nt - 1), min_size=1, max_size=4))
    return model, np.array(obs)


@settings(max_examples=120, deadline=None)
@given(small_models(), st.sampled_from(["learned", "state1"]))
def test_drawn_paths_follow_the_brute_force_posterior(case, start):
    model, obs = case
    try:
        exact = path_posterior(model, obs, start)
    except ZeroDivisionError:  # pragma: no cover - no path has mass
        exact = {}
    if not exact:
        with pytest.raises(DecodeError, match="probability zero"):
            hmm.sample_paths(model, obs, 10, start=start, random_state=0)
        return
    n = 4000
    paths = hmm.sample_paths(model, obs, n, start=start, random_state=1)
    assert paths.shape == (n, obs.size) and paths.dtype == np.int64
    seen = frequencies(paths)
    # every drawn path has positive probability
    assert set(seen) <= set(exact)
    # frequencies: a chi-square test over the paths (cells with expected
    # count below 5 pooled); seed fixed, level 1e-4 over 240 cases
    keys = sorted(exact)
    expected = np.array([exact[k] * n for k in keys])
    observed = np.array([seen.get(k, 0) for k in keys], dtype=float)
    small = expected < 5
    if small.any():
        expected = np.r_[expected[~small], expected[small].sum()]
        observed = np.r_[observed[~small], observed[small].sum()]
    if expected.size > 1:
        assert stats.chisquare(observed, expected).pvalue > 1e-4


def test_pseudo_counts_reach_unseen_and_uncounted_states():
    # p > 0: the chain may leave the counted transitions, and with r > 0 pass
    # through states never seen (the lowest unseen id stands for them)
    model = hmm.estimate([[1, 3, 3]], [[0, 1, 1]], 5, 2,
                         pseudo_transition=0.5, pseudo_emission=0.5)  # fmt: skip
    obs = np.array([0, 1, 1])
    exact = path_posterior(model, obs, "learned")
    assert any(0 in k for k in exact)  # the unseen class, as state 0
    n = 20000
    seen = frequencies(hmm.sample_paths(model, obs, n, random_state=3))
    assert set(seen) <= set(exact)
    for k, p in exact.items():  # 4 standard errors, plus a floor for tiny p
        assert abs(seen.get(k, 0) / n - p) < 4 * np.sqrt(p * (1 - p) / n) + 1e-3


def test_reproducible_with_random_state():
    model = hmm.estimate([[0, 1, 2], [0, 2, 2]], [[0, 1, 2], [0, 1, 2]], 6, 3)
    a = hmm.sample_paths(model, [0, 1, 2], 50, random_state=7)
    b = hmm.sample_paths(model, [0, 1, 2], 50, random_state=7)
    np.testing.assert_array_equal(a, b)
    rng = np.random.default_rng(7)
    np.testing.assert_array_equal(
        hmm.sample_paths(model, [0, 1, 2], 50, random_state=rng), a
    )


def test_cost_follows_the_seen_states_not_the_codebook():
    # m near the int64 range: nothing of size m is made
    model = hmm.estimate([[3, 5, 5], [3, 7]], [[0, 1, 2], [0, 2]], 10**15, 3)
    paths = hmm.sample_paths(model, [0, 1, 2], 200, random_state=0)
    assert set(np.unique(paths[:, 0])) <= {3} | {0}
    assert set(np.unique(paths[:, 2]).tolist()) <= {0, 3, 5, 7}


def test_errors():
    model = hmm.estimate([[0, 1]], [[0, 1]], 2, 2, pseudo_transition=0)
    with pytest.raises(DecodeError, match="probability zero"):
        hmm.sample_paths(model, [1, 1], 3, random_state=0)
    with pytest.raises(ValidationError, match="n_samples"):
        hmm.sample_paths(model, [0, 1], 0)
    with pytest.raises(ValidationError, match="model must be a fitted DiscreteHMM"):
        hmm.sample_paths("model", [0, 1])
    with pytest.raises(ValidationError, match="random_state"):
        hmm.sample_paths(model, [0, 1], random_state="x")
