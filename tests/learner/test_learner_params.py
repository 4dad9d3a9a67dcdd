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


def _route_weights(model):
    """The log weights of the route an unconditioned generate follows."""
    from ndlfd.learner._generation import demo_log_weights
    from ndlfd.learner._routes import choose_route

    logw, routes = demo_log_weights(model, None, None, {})
    return np.where(routes == choose_route(routes, logw), logw, -np.inf)


def test_blend_route_model_follows_pseudo_transition():
    """The route's segment model, against ``segment_model`` of its demonstrations.

    On two routes (9 over an obstacle, 3 under it) the route model holds the
    major route's demonstrations only, so it is built at generation time
    (``route_model``) and must carry ``pseudo_transition``: a mutant that
    drops it fails (docs/robustness.md, "Options that changed nothing").
    """
    from ndlfd.learner._cache import ModelCache
    from ndlfd.learner._generation import decode_route
    from ndlfd.learner._segments import segment_model

    demos = synth.obstacle(9, 3)
    arrays = {}
    for pseudo in (0.0, 0.5):
        kw = dict(n_time_bins=40, pseudo_transition=pseudo, pseudo_emission=0.1)
        m = KeypointHMM(**kw, n_jobs=1).fit(demos)
        logw = _route_weights(m)
        on_route = np.flatnonzero(np.isfinite(logw))
        assert 0 < on_route.size < len(demos)  # a route model of its own
        got, states, _ = decode_route(m, logw, ModelCache())
        want = segment_model(
            m.fit_stats_,
            on_route,
            m.codebook_.n_states,
            m.n_time_bins,
            pseudo_transition=pseudo,
            pseudo_emission=0.1,
        )
        got_a, want_a = got.to_arrays(), want.to_arrays()
        assert got_a.keys() == want_a.keys()
        for k in want_a:
            np.testing.assert_array_equal(got_a[k], want_a[k], err_msg=k)
        ref = _reference_decode(want, np.arange(m.n_time_bins), "viterbi", "learned")
        np.testing.assert_array_equal(states, ref)
        arrays[pseudo] = want_a
    # pseudo_transition changes the model here, so ignoring it is seen
    assert any(not np.array_equal(arrays[0.0][k], arrays[0.5][k]) for k in arrays[0.0])


def test_blend_skeleton_follows_decoder_and_start():
    """The blend's skeleton: the segment model decoded by ``ndlfd.hmm``.

    Compared with Viterbi or the posterior argmax, from the learned start or
    state 1, on data where each choice changes the skeleton (checked), so
    a mutant that drops ``decoder`` or ``start`` in the blend fails.
    """
    from ndlfd.learner._cache import ModelCache
    from ndlfd.learner._generation import decode_route

    train, _ = synth.make_dataset("square", n_demos=30, random_state=3)
    kw = dict(epsilon=0.05, n_time_bins=30, pseudo_transition=0.5, n_jobs=1)
    refs = {}
    for decoder in ("viterbi", "map"):
        for start in ("learned", "state1"):
            m = KeypointHMM(**kw, decoder=decoder, start=start).fit(train)
            logw = _route_weights(m)
            model, states, _ = decode_route(m, logw, ModelCache())
            ref = _reference_decode(model, np.arange(m.n_time_bins), decoder, start)
            np.testing.assert_array_equal(states, ref)
            refs[decoder, start] = ref

    def differ(a, b):
        return not np.array_equal(refs[a], refs[b])

    assert differ(("viterbi", "learned"), ("map", "learned")) or differ(
        ("viterbi", "state1"), ("map", "state1")
    ), "the decoders decode alike here"
    assert differ(("viterbi", "learned"), ("viterbi", "state1")) or differ(
        ("map", "learned"), ("map", "state1")
    ), "the starts decode alike here"


def test_band_follows_start():
    """``return_std``'s band follows the model's ``start``.

    The band is the spread of the templates aligned to the skeleton decoded
    with ``start`` (:func:`ndlfd.learner._blend.spread`); the reference
    recomputes it from that model's own plan; on the paper's curve the two
    starts decode different skeletons, so the choice must show.
    """
    from ndlfd.learner._blend import spread
    from ndlfd.learner._generation import make_plan

    train, _ = synth.make_dataset("curve", n_demos=20, random_state=4)
    t = np.linspace(0.0, 1.0, 60)
    bands = {}
    for start in ("learned", "state1"):
        m = KeypointHMM(epsilon=0.05, n_time_bins=25, start=start, n_jobs=1).fit(train)
        _, std = m.generate(t, dense=True, return_std=True)
        plan = make_plan(m, t, None, None, m._cache)
        tq = (t - t[0]) / (t[-1] - t[0])
        templates = (plan.values, plan.taus, plan.index, plan.weights, plan.knots)
        want = m.scaler_.inverse_scale(spread(*templates, tq))
        np.testing.assert_allclose(std, want, rtol=1e-12, atol=1e-15)
        bands[start] = want
    assert not np.allclose(bands["learned"], bands["state1"])  # the choice shows


def test_sample_follows_start():
    """``sample`` draws its skeletons with the model's ``start``.

    Two models that differ only in ``start`` (the fit does not use it): the
    draws of ``ndlfd.hmm.sample_paths`` on their segment model differ between
    the two starts (checked), so over a few seeds some of their samples must
    differ too; a mutant that drops ``start`` in ``sample`` makes every one
    equal. (Most draws end on the same skeleton: only the first bins differ.)
    """
    train, _ = synth.make_dataset("square", n_demos=30, random_state=3)
    kw = dict(epsilon=0.05, n_time_bins=30, pseudo_transition=0.5, n_jobs=1)
    models = {s: KeypointHMM(**kw, start=s).fit(train) for s in ("learned", "state1")}
    seg = models["learned"].segment_model_
    bins = np.arange(models["learned"].n_time_bins)
    ref = {
        s: np.asarray(hmm.sample_paths(seg, bins, 20, start=s, random_state=0))
        for s in ("learned", "state1")
    }
    assert not np.array_equal(ref["learned"], ref["state1"])  # start matters here
    t = np.linspace(0.0, 1.0, 80)
    differing = 0
    for seed in range(5):
        a = models["learned"].sample(t, 20, random_state=seed)
        b = models["state1"].sample(t, 20, random_state=seed)
        differing += sum(
            not np.array_equal(x.X, y.X) for x, y in zip(a, b, strict=True)
        )
    assert differing > 0
