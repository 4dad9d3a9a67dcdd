"""KeypointHMM.sample: routes in proportion, every sample on a route, reproducible."""

import numpy as np
import pytest
from scipy import stats

from ndlfd import NotFittedError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.learner._sampling import _seen_only
from ndlfd.synth import obstacle

T = np.linspace(0.0, 5.0, 400)
XS = np.linspace(-9.5, -0.5, 50)  # the course, away from the shared ends


@pytest.fixture(scope="module")
def uneven():
    demos = obstacle(9, 3)  # 9 above the obstacle, 3 below
    return demos, KeypointHMM().fit(demos)


def curve(P):
    """y along the course at XS."""
    order = np.argsort(P[:, 0])
    return np.interp(XS, P[order, 0], P[order, 1])


def spread(Y):
    """RMS over the course of the standard deviation across curves."""
    return float(np.sqrt(np.mean(Y.var(axis=0))))


def test_routes_in_proportion_and_every_sample_on_one(uneven):
    demos, model = uneven
    paths = model.sample(T, 200, random_state=0)
    assert len(paths) == 200
    D = np.array([curve(d.X) for d in demos])
    up, down = D[:9], D[9:]
    Y = np.array([curve(p.get("position")) for p in paths])
    major = Y[:, 25] > 0  # mid-course above the obstacle
    # every sample inside one route's tube along the whole course (the tube:
    # the route's demonstrations' envelope widened by 0.3; the routes are
    # 11 apart mid-course, so nothing between them passes)
    for y, on_up in zip(Y, major, strict=True):
        route = up if on_up else down
        assert np.all(y >= route.min(axis=0) - 0.3)
        assert np.all(y <= route.max(axis=0) + 0.3)
    # the major route in 75 % +- 10 % of the draws (9 of 12 demonstrations),
    # and a two-sided binomial test at level 0.001 (seed 0)
    k = int(major.sum())
    assert abs(k / 200 - 0.75) <= 0.10
    assert stats.binomtest(k, 200, 0.75).pvalue > 1e-3
    # variation within a route: not all alike, not wider than the
    # demonstrations' (measured: 0.65 of their spread, see _sampling)
    for Ys, Ds in ((Y[major], up), (Y[~major], down)):
        assert np.unique(Ys.round(6), axis=0).shape[0] > 1
        assert 0.2 * spread(Ds) < spread(Ys) <= spread(Ds)


def test_same_random_state_same_samples(uneven):
    _, model = uneven
    a = model.sample(T, 5, random_state=3)
    b = model.sample(T, 5, random_state=np.random.default_rng(3))
    for p, q in zip(a, b, strict=True):
        np.testing.assert_array_equal(p.X, q.X)
        np.testing.assert_array_equal(p.t, q.t)
    c = model.sample(T, 5, random_state=4)
    assert any(not np.array_equal(p.X, q.X) for p, q in zip(a, c, strict=True))


def test_sampling_leaves_generate_unchanged(uneven):
    _, model = uneven
    before = model.generate(T, dense=True)
    model.sample(T, 3, random_state=0)
    np.testing.assert_array_equal(model.generate(T, dense=True).X, before.X)


def test_a_start_on_the_minor_route_draws_the_minor_route():
    demos = obstacle(9, 3, lift=1.0)  # the routes start 2 apart
    model = KeypointHMM().fit(demos)
    low = {"position": [-10.0, -1.1]}
    paths = model.sample(T, 20, start=low, goal={"position": [0.0, 0.0]},
                         random_state=0)  # fmt: skip
    for p in paths:
        P = p.get("position")
        np.testing.assert_allclose(P[0], [-10.0, -1.1])
        np.testing.assert_allclose(P[-1], [0.0, 0.0], atol=1e-12)
        assert curve(P)[25] < -5


def test_key_points_when_not_dense(uneven):
    _, model = uneven
    (path,) = model.sample(T, dense=False, random_state=0)
    assert 2 <= path.t.size < T.size
    assert path.t[0] == T[0] and path.t[-1] == T[-1]


def test_errors(uneven):
    _, model = uneven
    with pytest.raises(NotFittedError, match="not fitted"):
        KeypointHMM().sample(T)
    with pytest.raises(ValidationError, match="n_samples"):
        model.sample(T, 0)
    with pytest.raises(ValidationError, match="random_state"):
        model.sample(T, random_state="seed")
    with pytest.raises(ValidationError, match="at least two"):
        model.sample([1.0])


def test_unseen_states_of_a_drawn_skeleton_keep_the_state_before():
    # with an emission pseudo-count the chain may pass through states never
    # seen (no centroid): those bins keep the seen state before them
    seen = np.array([2, 5, 9])
    np.testing.assert_array_equal(
        _seen_only(np.array([2, 0, 0, 5, 1, 9]), seen), [2, 2, 2, 5, 5, 9]
    )
    np.testing.assert_array_equal(_seen_only(np.array([0, 5, 0]), seen), [5, 5, 5])
    demos = obstacle(9, 3)
    model = KeypointHMM(pseudo_emission=0.5).fit(demos)
    for p in model.sample(T, 40, random_state=0):
        assert abs(curve(p.get("position"))[25]) > 5


def _prefix_of(demo, n):
    """The first ``n`` time stamps of ``T``, ``demo`` on the same normalized clock."""
    tau = demo.t / demo.t[-1]
    X = np.column_stack([np.interp(T[:n] / T[-1], tau, c) for c in demo.X.T])
    return Demonstration(T[:n], X, demo.columns, demo.groups)


@pytest.mark.parametrize(("who", "below"), [(10, True), (2, False)])
def test_samples_all_continue_an_observed_prefix(uneven, who, below):
    demos, model = uneven
    n = 120  # 30 % of the timing, on the minor (10) or major (2) route
    prefix = _prefix_of(demos[who], n)
    paths = model.sample(T, 30, dense=False, observed=prefix, random_state=5)
    rng = np.ptp(np.vstack([d.get("position") for d in demos]), axis=0)
    largest = np.abs(np.diff(prefix.X, axis=0)).max(axis=0)
    tails = []
    for p in paths:
        assert np.array_equal(p.t, T)  # every time stamp, even with dense=False
        P = p.get("position")
        np.testing.assert_array_equal(P[:n], prefix.X)
        # no jump: the step after the prefix within its largest + 0.5 % range
        assert np.all(np.abs(P[n] - P[n - 1]) <= largest + 0.005 * rng)
        assert (curve(P)[25] < -4.5) if below else (curve(P)[25] > 4.5)
        tails.append(P[n:])
    assert np.unique(np.round(tails, 6), axis=0).shape[0] > 1  # they vary
    again = model.sample(T, 30, observed=prefix, random_state=5)
    for p, q in zip(paths, again, strict=True):
        np.testing.assert_array_equal(p.X, q.X)
    other = model.sample(T, 30, observed=prefix, random_state=6)
    assert any(not np.array_equal(p.X, q.X) for p, q in zip(paths, other, strict=True))


def test_an_observed_prefix_with_a_start_or_via_is_refused(uneven):
    demos, model = uneven
    prefix = _prefix_of(demos[0], 50)
    with pytest.raises(ValidationError, match="cannot be combined with start or via"):
        model.sample(T, observed=prefix, start={"position": [-10.0, 0.0]})
    with pytest.raises(ValidationError, match="cannot be combined with start or via"):
        model.sample(T, observed=prefix, via=[(2.5, {"position": [-5.0, 5.0]})])
    with pytest.raises(ValidationError, match="first time stamps of the timing"):
        model.sample(T + 1.0, observed=prefix)
