"""Shared cases of the ndlfd.hmm tests: random training data, model equality."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from ndlfd.hmm import DiscreteHMM


@st.composite
def training(draw, max_m=8, max_nt=3, max_len=5):
    """(m, nt, states, symbols, p, r, obs, start) of a small random model."""
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


def same_model(a: DiscreteHMM, b: DiscreteHMM) -> None:
    """Assert two models have equal arrays and parameters."""
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
