"""Each parameter reaches the stage it names (learner/_params.py).

Found by hand-made mutants (docs/robustness.md, "Options that changed
nothing"): a one-line change that ignored ``decoder`` or ``start`` in the
paper's decoding, or ``distance`` (and the time stamps of ``"sed"``) in the
fit's reduction, survived the suite. Each test below compares the learner
with the same stage computed directly from the public functions, on data
where the option's choices give different answers (checked first), so a
mutant that drops the option fails.
"""

import numpy as np
import pytest

import ndlfd
from ndlfd import Demonstration, KeypointHMM, ValidationError, hmm, synth
from ndlfd.learner._params import PARAM_NAMES, check_params
from ndlfd.learner._spec import prepare


def _reference_decode(model, symbols, decoder, start):
    """The paper's decoding from ndlfd.hmm: Viterbi, or the posterior argmax."""
    if decoder == "viterbi":
        return hmm.viterbi(model, symbols, start=start)[0]
    post = hmm.posterior(model, symbols, start=start)
    return post.states[np.argmax(post.probabilities, axis=1)]  # ties: lowest


def test_paper_decoding_follows_decoder_and_start():
    train, test = synth.make_dataset("square", n_demos=30, random_state=3)
    kw = dict(epsilon=0.05, n_time_bins=30, generation="paper", pseudo_transition=0.5)
    options = [(d, s) for d in ("viterbi", "map") for s in ("learned", "state1")]
    refs = {}
    for decoder, start in options:
        m = KeypointHMM(**kw, decoder=decoder, start=start).fit(train)
        key_t, symbols, _ = m.timing(test)
        refs[decoder, start] = _reference_decode(m.model_, symbols, decoder, start)
        got_t, states, _ = m.decode(test)
        np.testing.assert_array_equal(got_t, key_t)
        np.testing.assert_array_equal(states, refs[decoder, start])
    # the four choices decode differently here, so ignoring one is seen
    for i, a in enumerate(options):
        for b in options[i + 1 :]:
            assert not np.array_equal(refs[a], refs[b]), (a, b)


def _irregular_demos(n=6, seed=0):
    """2-D curves sampled at irregular times (SED differs from the index)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        s = np.linspace(0.0, 1.0, 150)
        t = 1.0 + rng.uniform(1.0, 3.0) * s**2  # slow, then fast: not the index
        P = np.column_stack([s, np.sin(3 * s)]) + rng.normal(0, 0.01, (150, 2))
        out.append(Demonstration.from_arrays(t, position=P))
    return out


def test_fit_reduction_follows_distance():
    train = _irregular_demos()
    eps = 0.02
    keys = {}
    for distance in ("line", "segment", "sed", "paper"):
        m = KeypointHMM(epsilon=eps, n_time_bins=20, distance=distance, n_jobs=1)
        m.fit(train)
        for k, demo in enumerate(train):
            d = prepare(demo, m.groups_)
            u = m.scaler_.transform(d, weighted=False)
            times = d.t if distance == "sed" else None
            ref = ndlfd.simplify(u, eps, distance=distance, times=times)
            np.testing.assert_array_equal(m.keypoints_[k], ref)
        keys[distance] = m.keypoints_
    # the distances keep different points here, and SED with the real time
    # stamps differs from SED over the sample index
    for a in keys:
        for b in keys:
            if a < b:
                assert any(
                    not np.array_equal(x, y)
                    for x, y in zip(keys[a], keys[b], strict=True)
                ), (a, b)
    d = prepare(train[0], m.groups_)
    u = m.scaler_.transform(d, weighted=False)
    index_time = np.arange(d.t.size, dtype=float)
    assert not np.array_equal(
        ndlfd.simplify(u, eps, distance="sed", times=d.t),
        ndlfd.simplify(u, eps, distance="sed", times=index_time),
    )


def test_check_params_refuses_each_bad_value_with_its_name():
    good = KeypointHMM().get_params()
    assert tuple(good) == PARAM_NAMES
    check_params(good)
    bad = {
        "epsilon": -1.0,
        "n_points": 1,
        "n_time_bins": 0,
        "distance": "nope",
        "normalization": "nope",
        "pseudo_transition": -1.0,
        "pseudo_emission": np.nan,
        "start": "nope",
        "generation": "nope",
        "decoder": "nope",
        "n_jobs": 0,
        "max_templates": 0,
        "match_window": 0.6,
        "weights": [1.0],
    }
    for name, value in bad.items():
        p = dict(good, **{name: value})
        with pytest.raises(ndlfd.NdlfdError, match=name):
            check_params(p)
    with pytest.raises(ValidationError, match="n_time_bins must be at most"):
        check_params(dict(good, n_time_bins=2**40))
