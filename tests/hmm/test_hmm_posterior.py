"""ndlfd.hmm.posterior against brute force over all state paths (tiny models)."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import DecodeError, hmm


def brute_force(model, obs, start):
    """Posterior by enumerating every state path of the dense model."""
    A = model.transition_matrix(dense=True)
    B = model.emission_matrix(dense=True)
    pi = model.initial_distribution() if start == "learned" else A[0]
    m = A.shape[0]
    G = np.zeros((len(obs), m))
    total = 0.0
    for path in itertools.product(range(m), repeat=len(obs)):
        p = pi[path[0]] * B[path[0], obs[0]]
        for t in range(1, len(obs)):
            p *= A[path[t - 1], path[t]] * B[path[t], obs[t]]
        total += p
        for t, s in enumerate(path):
            G[t, s] += p
    return G, total


def full(post, m):
    """Expand the seen-state posterior and the unseen class to all m states."""
    out = np.zeros((post.probabilities.shape[0], m))
    out[:, post.states] = post.probabilities
    unseen = np.setdiff1d(np.arange(m), post.states)
    if unseen.size:
        out[:, unseen] = post.unseen[:, None] / unseen.size
    return out


@st.composite
def small_models(draw):
    m = draw(st.integers(2, 4))
    nt = draw(st.integers(1, 3))
    n_seq = draw(st.integers(1, 3))
    states, symbols = [], []
    for _ in range(n_seq):
        n = draw(st.integers(1, 3))
        states.append(draw(st.lists(st.integers(0, m - 1), min_size=n, max_size=n)))
        symbols.append(draw(st.lists(st.integers(0, nt - 1), min_size=n, max_size=n)))
    p = draw(st.sampled_from([None, 0.0, 0.25]))
    r = draw(st.sampled_from([0.0, 0.5]))
    model = hmm.estimate(states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r)
    obs = draw(st.lists(st.integers(0, nt - 1), min_size=1, max_size=4))
    return model, np.array(obs), m


@settings(max_examples=150, deadline=None)
@given(small_models(), st.sampled_from(["learned", "state1"]))
def test_posterior_matches_brute_force(case, start):
    model, obs, m = case
    G, total = brute_force(model, obs, start)
    if total == 0:
        with pytest.raises(DecodeError, match="probability zero"):
            hmm.posterior(model, obs, start=start)
        return
    post = hmm.posterior(model, obs, start=start)
    # different summation orders: equal to 1e-12 relative to probabilities <= 1
    np.testing.assert_allclose(full(post, m), G / total, rtol=0, atol=1e-12)
    assert post.log_likelihood == pytest.approx(np.log(total), rel=1e-12, abs=1e-12)


def test_hand_worked_two_branch_model():
    # 0 -> 1 and 0 -> 2, both emit symbol 1: half and half at step 1
    model = hmm.estimate([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2, pseudo_transition=0)
    post = hmm.posterior(model, [0, 1])
    np.testing.assert_array_equal(post.probabilities, [[1, 0, 0], [0, 0.5, 0.5]])
    assert post.log_likelihood == 0.0
    np.testing.assert_array_equal(post.unseen, [0, 0])


def test_huge_state_space_costs_only_the_seen_states():
    m = 10**12
    model = hmm.estimate([[5, 7, 9], [5, 8, 9]], [[0, 1, 2], [0, 1, 2]], m, 3)
    post = hmm.posterior(model, [0, 1, 2])
    assert post.probabilities.shape == (3, 4)
    # step 1: 7 and 8 are symmetric, each transition counted once from 5
    np.testing.assert_allclose(post.probabilities[1], [0, 0.5, 0.5, 0], atol=1e-15)
    np.testing.assert_allclose(post.probabilities.sum(axis=1), 1.0, rtol=1e-12)


def test_map_decoder_is_the_posterior_argmax():
    from ndlfd.learner import DECODERS

    model = hmm.estimate(
        [[0, 1, 3], [0, 2, 3], [0, 2, 3]], [[0, 1, 2]] * 3, 4, 3, pseudo_transition=0
    )
    states, logp = DECODERS.get("map")(model, np.array([0, 1, 2]), "learned")
    np.testing.assert_array_equal(states, [0, 2, 3])
    assert logp == pytest.approx(np.log(2 / 3))
    vit, _ = DECODERS.get("viterbi")(model, np.array([0, 1, 2]), "learned")
    np.testing.assert_array_equal(vit, [0, 2, 3])


def test_bad_input():
    model = hmm.estimate([[0, 1]], [[0, 1]], 2, 2)
    with pytest.raises(ValueError, match="at least one"):
        hmm.posterior(model, [])
    with pytest.raises(ValueError, match="DiscreteHMM"):
        hmm.posterior("model", [0])
    with pytest.raises(ValueError, match="start"):
        hmm.posterior(model, [0], start="first")
