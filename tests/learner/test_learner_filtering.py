"""A prefix's route by forward filtering, against enumerating every state path."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.learner._filtering import (
    bin_observations,
    observation_noise,
    path_log_likelihoods,
)
from ndlfd.synth import obstacle


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.0, 1.0), min_size=1, max_size=12),
    st.integers(1, 6),
    st.integers(0, 2**31),
)
def test_bin_observations_against_a_loop(taus, n_bins, seed):
    tau = np.sort(np.array(taus))
    U = np.random.default_rng(seed).normal(size=(tau.size, 2))
    got = bin_observations(U, tau, n_bins)
    bins = [min(int(np.floor(x * n_bins)), n_bins - 1) for x in tau]
    assert got.shape == (bins[-1] + 1, 2)
    for b in range(bins[-1] + 1):
        rows = [i for i, x in enumerate(bins) if x == b]
        if rows:
            np.testing.assert_allclose(got[b], U[rows].mean(axis=0))
        else:
            assert np.isnan(got[b]).all()


@pytest.fixture(scope="module")
def tiny():
    """Two routes, 3 position levels a side (9 states), 4 time bins."""
    demos = obstacle(3, 2, n_samples=40)
    model = KeypointHMM(
        levels={"position": 3}, n_time_bins=4, derive_velocity=False
    ).fit(demos)
    return demos, model


def _centroid_at(model, j, b):
    """Demonstration j's segment centroid at bin b: its last key point's state."""
    stats = model.fit_stats_
    end = int(np.cumsum(stats.n_keys)[j])
    kb = np.asarray(stats.key_bins)[end - stats.n_keys[j] : end]
    ks = np.asarray(stats.key_states)[end - stats.n_keys[j] : end]
    s = ks[np.flatnonzero(kb <= b)[-1]]
    return model.centroids_[np.searchsorted(model.centroid_states_, s)]


def test_observation_noise_is_the_templates_residual_at_least_a_cell(tiny):
    _, model = tiny
    var = observation_noise(model, {})
    floor = (1.0 / 3.0) ** 2 / 12.0
    assert var.shape == (2,) and np.all(var >= floor)
    # a slow recomputation: each template's bin means against the centroid of
    # the state of its last key point at or before the bin
    nt = model.n_time_bins
    sq, count = np.zeros(2), 0
    for k, j in enumerate(model.template_indices_):
        U, tau = model.train_values_[k], model.train_tau_[k]
        bins = np.minimum(np.floor(tau * nt).astype(int), nt - 1)
        for b in range(nt):
            if np.any(bins == b):
                sq += (U[bins == b].mean(axis=0) - _centroid_at(model, j, b)) ** 2
                count += 1
    np.testing.assert_allclose(var, np.maximum(sq / count, floor))


@pytest.mark.parametrize(("who", "fraction"), [(0, 0.5), (4, 0.9), (2, 0.05)])
def test_path_log_likelihoods_against_a_loop(tiny, who, fraction):
    demos, model = tiny
    d = demos[who]
    n = max(int(fraction * d.t.size), 1)
    U = model.scaler_.transform(d.X[:n], weighted=False)
    tau = model.time_bins_.normalize(d.t)[:n]
    cache = {}
    got = path_log_likelihoods(model, U, tau, cache)
    var = observation_noise(model, cache)
    nt = model.n_time_bins
    bins = np.minimum(np.floor(tau * nt).astype(int), nt - 1)
    want = np.zeros(len(demos))
    for j in range(len(demos)):
        for b in np.unique(bins):
            r = U[bins == b].mean(axis=0) - _centroid_at(model, j, b)
            want[j] -= 0.5 * np.sum(r * r / var)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    # past the shared start, a path of its own route fits best (3 levels a
    # side are too coarse to tell demonstrations of one route apart)
    assert (np.argmax(got) >= 3) == (who >= 3) or fraction < 0.1


def test_a_prefix_decides_the_route_that_generate_and_sample_follow():
    demos = obstacle(9, 3)
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 200)
    for who, sign in ((10, -1.0), (2, 1.0)):  # the minor route, the major one
        d = demos[who]
        times = d.t[0] + (d.t[-1] - d.t[0]) * np.linspace(0.0, 1.0, t.size)
        X = np.column_stack([np.interp(times, d.t, c) for c in d.X.T])
        prefix = Demonstration(times[:40], X[:40], d.columns, d.groups)
        path = model.generate(times, observed=prefix).get("position")
        mid = path[np.argmin(np.abs(path[:, 0] + 5.0)), 1]
        assert sign * mid == pytest.approx(5.5, abs=0.5)
        for s in model.sample(times, 5, observed=prefix, random_state=1):
            P = s.get("position")
            assert sign * P[np.argmin(np.abs(P[:, 0] + 5.0)), 1] > 4.0
