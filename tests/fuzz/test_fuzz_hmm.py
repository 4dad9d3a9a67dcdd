"""Fuzz every public function of ndlfd.hmm on arbitrary arrays.

``estimate``, ``merge``, ``viterbi``, ``posterior``, ``sample_paths`` and
``DiscreteHMM`` with its methods get sequences that are mostly valid and
sometimes not (NaN, inf, huge, negative, fractional, complex, bool, object,
ragged, empty, wrong dimension), sizes and pseudo-counts from the edge of
their range: each call gives a correct result (checked below) or one
:class:`ndlfd.NdlfdError`; never a numba typing error, a bare numpy error or
NaN in an output.
"""

import numpy as np
import pytest
from fuzz_helpers import BAD_OBJECTS, check_outcome
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ndlfd import hmm

FUZZ = settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)

#: entries that no state or symbol sequence may hold
BAD_ENTRIES = [-1, np.nan, np.inf, 1e300, 2.5, 2**63, 10**20]
#: sequences that are not 1-D integer arrays
BAD_SEQUENCES = [
    [],
    np.zeros(0, int),
    np.array([1 + 0j, 0]),
    np.array([True, False]),
    np.array([0, None], dtype=object),
    [[0, 1], [0]],
    "ab",
    np.zeros((1, 1, 1), int),
    np.int64(0),
]
#: sizes from the edge of the range, and not sizes
GOOD_SIZES = [1, 2, 5, 10**12, 2**63 - 1]
BAD_SIZES = [0, -1, 1.5, True, None, "3", 2**63]
#: pseudo-counts from the edge of the range, and not pseudo-counts
GOOD_PSEUDO = [0.0, 0.5, 1.0, 1e-300, 2.3e-308, 1e300, 1e307]
BAD_PSEUDO = [-1.0, np.nan, np.inf, "x", True, 5e-324, 1.7e308]


@st.composite
def sequence(draw, high, n=None):
    """A 1-D sequence in ``0..high-1`` as a list or an array of some dtype."""
    n = draw(st.integers(1, 6)) if n is None else n
    top = max(0, min(high, 6) - 1)
    seq = draw(st.lists(st.integers(0, top), min_size=n, max_size=n))
    dtype = draw(st.sampled_from([None, np.int64, np.int8, np.uint32, float]))
    return seq if dtype is None else np.array(seq, dtype=dtype)


def _corrupt(draw, case):
    """One thing of a valid case made bad."""
    m, nt, states, symbols, p, r = case
    what = draw(st.sampled_from(["size", "pseudo", "entry", "sequence", "length"]))
    if what == "size":
        if draw(st.booleans()):
            return draw(st.sampled_from(BAD_SIZES)), nt, states, symbols, p, r
        return m, draw(st.sampled_from(BAD_SIZES)), states, symbols, p, r
    if what == "pseudo":
        if draw(st.booleans()):
            return m, nt, states, symbols, draw(st.sampled_from(BAD_PSEUDO)), r
        return m, nt, states, symbols, p, draw(st.sampled_from(BAD_PSEUDO))
    k = draw(st.integers(0, len(states) - 1))
    which = draw(st.integers(0, 1))  # states or symbols
    seqs = [list(map(int, s)) for s in (states, symbols)[which]]
    if what == "entry":
        j = draw(st.integers(0, len(seqs[k]) - 1))
        seqs[k][j] = draw(st.sampled_from(BAD_ENTRIES))
    elif what == "sequence":
        seqs[k] = draw(st.sampled_from(BAD_SEQUENCES))
    else:
        seqs[k] = seqs[k] + [0]
    if which == 0:
        return m, nt, seqs, symbols, p, r
    return m, nt, states, seqs, p, r


@st.composite
def training(draw):
    """``(n_states, n_symbols, states, symbols, pseudo_t, pseudo_e)``.

    Valid three times in four; else one thing made bad.
    """
    m = draw(st.one_of(st.integers(1, 6), st.sampled_from(GOOD_SIZES)))
    nt = draw(st.one_of(st.integers(1, 4), st.sampled_from(GOOD_SIZES)))
    states, symbols = [], []
    for _ in range(draw(st.integers(1, 3))):
        n = draw(st.integers(1, 6))
        states.append(draw(sequence(m, n)))
        symbols.append(draw(sequence(nt, n)))
    p = draw(st.one_of(st.none(), st.sampled_from(GOOD_PSEUDO)))
    case = (m, nt, states, symbols, p, draw(st.sampled_from(GOOD_PSEUDO)))
    if draw(st.integers(0, 3)) == 0:
        case = _corrupt(draw, case)
    m, nt, states, symbols, p, r = case
    if len(states) == 1 and draw(st.booleans()):
        states, symbols = states[0], symbols[0]  # one demonstration as one array
    return m, nt, states, symbols, p, r


@st.composite
def query(draw):
    """Symbols to decode: mostly valid for a small model, sometimes not."""
    if draw(st.integers(0, 4)) == 0:
        return draw(st.sampled_from([*BAD_SEQUENCES, [0, -1], [0, np.nan], [0, 2**63]]))
    return draw(sequence(4))


def _check_path(model, symbols, path):
    assert path.dtype == np.int64 and path.shape == (len(symbols),)
    assert (path >= 0).all() and (path < model.n_states).all()


@FUZZ
@given(
    case=training(),
    query=query(),
    start=st.sampled_from(["learned", "state1", "learned", "nope"]),
    n_samples=st.sampled_from([1, 3, 1, 0, 2.0]),
    seen=st.booleans(),
)
def test_fuzz_hmm_estimate_and_decoders(case, query, start, n_samples, seen):
    m, nt, states, symbols, p, r = case
    if seen and isinstance(symbols, list) and len(symbols) > 1:
        query = symbols[-1]  # a training sequence: decodable unless bad
    model = check_outcome(
        hmm.estimate, states, symbols, m, nt, pseudo_transition=p, pseudo_emission=r
    )
    if model is None:
        return
    assert model.n_sequences_ >= 1 and model.states_.size >= 1
    assert (np.diff(model.states_) > 0).all() and model.states_[-1] < m
    out = check_outcome(hmm.viterbi, model, query, start=start)
    if out is not None:
        path, logp = out
        _check_path(model, query, path)
        assert logp <= 1e-9
        assert np.array_equal(model.decode(query, start=start)[0], path)
    post = check_outcome(hmm.posterior, model, query, start=start)
    if post is not None:
        assert post.probabilities.shape == (len(query), model.states_.size)
        total = post.probabilities.sum(axis=1) + post.unseen
        np.testing.assert_allclose(total, 1.0, rtol=1e-9)
        assert (post.probabilities >= 0).all() and post.log_likelihood <= 1e-9
        assert out is not None  # what posterior decodes, viterbi decodes
    elif out is not None and min(x for x in (p or 1.0, r or 1.0)) > 1e-100:
        # and back, unless a pseudo-count near zero underflows the forward
        # pass (viterbi works in log space)
        pytest.fail("viterbi decoded what posterior refused")
    paths = check_outcome(
        hmm.sample_paths, model, query, n_samples, start=start, random_state=0
    )
    if paths is not None:
        assert paths.shape == (n_samples, len(query))
        for path in paths:
            _check_path(model, query, path)


@FUZZ
@given(case=training(), probe=query(), dense=st.booleans())
def test_fuzz_hmm_model_methods(case, probe, dense):
    m, nt, states, symbols, p, r = case
    model = check_outcome(
        hmm.DiscreteHMM(m, nt, pseudo_transition=p, pseudo_emission=r).fit,
        states,
        symbols,
    )
    if model is None:
        return
    A = check_outcome(model.transition_matrix, dense=dense)
    B = check_outcome(model.emission_matrix, dense=dense)
    pi = check_outcome(model.initial_distribution) if dense else None
    # sparse always; dense refused exactly above the documented limit
    limit = hmm.DENSE_LIMIT_BYTES
    for M, width in ((A, m), (B, nt), (pi, 1))[: 3 if dense else 2]:
        assert (M is None) == (dense * 8 * m * width > limit), (M, m, width)
    for M in (A, B) if dense else ():
        if M is not None:  # each row a distribution, or zero (no pseudo-count)
            rows = M.sum(axis=1)
            assert np.all(np.isclose(rows, 1.0) | (rows == 0)), rows
    if not dense:
        assert np.isfinite(A.data).all() and np.isfinite(B.data).all()
        assert (A.data >= 0).all() and (B.data >= 0).all()
    if pi is not None:
        assert np.isclose(pi.sum(), 1.0) or pi.sum() == 0
    for fn in (model.transition_baseline, model.emission_baseline):
        base = check_outcome(fn, probe)
        if base is not None:
            assert base.shape == (len(probe),) and (base >= 0).all()
    again = check_outcome(hmm.DiscreteHMM.from_arrays, model.to_arrays("x/"), "x/")
    assert again is not None and np.array_equal(again.states_, model.states_)


@FUZZ
@given(cases=st.lists(training(), min_size=1, max_size=3), extra=st.booleans())
def test_fuzz_hmm_merge(cases, extra):
    models = [
        check_outcome(hmm.estimate, s, o, m, nt, pseudo_transition=p, pseudo_emission=r)
        for m, nt, s, o, p, r in cases
    ]
    models = [mod for mod in models if mod is not None]
    if extra:
        models.append(hmm.DiscreteHMM(3, 2))  # not fitted
    merged = check_outcome(hmm.merge, models)
    if merged is not None:
        assert merged.n_sequences_ == sum(mod.n_sequences_ for mod in models)
        tot = sum(int(mod.emission_totals_.sum()) for mod in models)
        assert int(merged.emission_totals_.sum()) == tot


@pytest.mark.parametrize("bad", [*BAD_OBJECTS, *BAD_SEQUENCES], ids=repr)
def test_fuzz_hmm_wrong_types(bad):
    model = hmm.estimate([[0, 1]], [[0, 1]], 2, 2)
    for call in (
        lambda: hmm.estimate(bad, [0], 2, 2),
        lambda: hmm.estimate([0], bad, 2, 2),
        lambda: hmm.estimate([0], [0], bad, 2),
        lambda: hmm.estimate([0], [0], 2, 2, pseudo_transition=bad),
        lambda: hmm.viterbi(model, bad),
        lambda: hmm.viterbi(bad, [0]),
        lambda: hmm.viterbi(model, [0], start=bad),
        lambda: hmm.posterior(model, bad),
        lambda: hmm.sample_paths(model, bad),
        lambda: hmm.sample_paths(model, [0], bad),
        lambda: hmm.sample_paths(model, [0], random_state=bad),
        lambda: hmm.merge(bad),
        lambda: hmm.merge([model, bad]),
        lambda: model.transition_baseline(bad),
        lambda: hmm.DiscreteHMM.from_arrays({"sizes": bad}),
        lambda: hmm.DiscreteHMM.from_arrays(bad),
        lambda: hmm.DiscreteHMM.from_arrays(model.to_arrays(), bad),
    ):
        check_outcome(call)  # None is valid for some: a result is fine
