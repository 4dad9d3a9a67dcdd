"""Route discovery judged on realistic robot data (``tests/route_corpus.py``).

Each set is fitted with ``KeypointHMM(**params)`` and an unconditioned dense
path of 300 samples over the median demonstration duration is generated.
Several true routes: the path follows one of them at ``tau_star`` and the
routes found are the true grouping. One true route: it is not split.
"""

import functools
import warnings

import numpy as np
import pytest

from ndlfd import KeypointHMM, NdlfdWarning
from route_corpus import CASES, ONE_ROUTE, SEPARATED, at_tau, route_error

#: Largest distance from the nearest route at ``tau_star``, in separations.
MAX_ROUTE_ERROR = 0.15
#: Samples of the generated path.
PATH_SAMPLES = 300
#: Samples per demonstration the corpus keeps to (fits stay fast).
MAX_DEMO_SAMPLES = 1500


def canonical(labels):
    """Labels renumbered by first appearance (a partition's one spelling)."""
    first = {}
    return np.array([first.setdefault(x, len(first)) for x in np.asarray(labels)])


@functools.cache
def fitted(name):
    """(route set, fitted model, generated path) of one case, made once."""
    rs = CASES[name]()
    with warnings.catch_warnings():
        # on purpose: the bag's stamps jitter like a real publisher's
        warnings.filterwarnings("ignore", "time stamps are jittery", NdlfdWarning)
        model = KeypointHMM(**rs.params).fit(rs.demos)
    duration = float(np.median([d.duration for d in rs.demos]))
    path = model.generate(np.linspace(0.0, duration, PATH_SAMPLES), dense=True)
    return rs, model, path


@pytest.mark.parametrize("name", list(CASES))
def test_the_corpus_is_what_it_claims(name):
    rs = CASES[name]()
    k = rs.n_routes
    np.testing.assert_array_equal(np.unique(rs.labels), np.arange(k))
    assert len(rs.labels) == len(rs.demos)
    assert max(d.n_samples for d in rs.demos) <= MAX_DEMO_SAMPLES
    assert rs.route_values.shape == (k, len(rs.columns))
    if name in ONE_ROUTE:
        assert k == 1
        assert rs.separation == np.inf
        return
    assert k >= 2
    # every demonstration is nearest its own route's mean at tau_star
    at = np.stack([at_tau(d, rs.columns, [rs.tau_star])[0] for d in rs.demos])
    nearest = np.linalg.norm(at[:, None, :] - rs.route_values, axis=2).argmin(axis=1)
    np.testing.assert_array_equal(nearest, rs.labels)
    # and the routes are the largest differences among the demonstrations
    spread = max(
        np.linalg.norm(at[rs.labels == r] - rs.route_values[r], axis=1).max()
        for r in range(k)
    )
    assert rs.separation > 4 * spread


@pytest.mark.parametrize("name", SEPARATED)
def test_the_path_follows_one_route(name):
    rs, _, path = fitted(name)
    err = route_error(rs, path)
    got = at_tau(path, rs.columns, [rs.tau_star])[0]
    assert err <= MAX_ROUTE_ERROR, (
        f"{name}: route error {err:.3f} (path {np.round(got, 3).tolist()} at"
        f" tau {rs.tau_star:.3f}; routes {np.round(rs.route_values, 3).tolist()},"
        f" separation {rs.separation:.3f})"
    )


@pytest.mark.parametrize("name", SEPARATED)
def test_the_routes_found_are_the_true_routes(name):
    rs, model, _ = fitted(name)
    found = model.routes_
    assert canonical(found).tolist() == canonical(rs.labels).tolist(), (
        f"{name}: found {found.tolist()}, true {rs.labels.tolist()}"
    )


@pytest.mark.parametrize("name", ONE_ROUTE)
def test_one_route_is_not_split(name):
    _, model, _ = fitted(name)
    found = model.routes_
    assert np.unique(found).size == 1, f"{name}: found {found.tolist()}"


@pytest.mark.parametrize("name", ["tf_bag", "pick_place_csv", "three_routes"])
def test_samples_each_follow_a_route(name):
    # `ndlfd sample -n 10` drew 2 of 10 between the routes before issue 26
    rs, model, _ = fitted(name)
    duration = float(np.median([d.duration for d in rs.demos]))
    t = np.linspace(0.0, duration, PATH_SAMPLES)
    errors = [route_error(rs, p) for p in model.sample(t, 20, random_state=0)]
    assert max(errors) <= MAX_ROUTE_ERROR, np.round(errors, 3).tolist()


@pytest.mark.parametrize("name", ["tf_bag", "pick_place_csv", "joint6"])
def test_the_band_of_a_route_is_its_demonstrations_spread(name):
    # before issue 26 the band was exactly 0 on most samples mid-swing and
    # spiked at key points: now it is the spread of the route's templates,
    # non-zero wherever they differ, and of the size of their spread
    rs, model, _ = fitted(name)
    duration = float(np.median([d.duration for d in rs.demos]))
    t = np.linspace(0.0, duration, PATH_SAMPLES)
    _, std = model.generate(t, dense=True, return_std=True)
    cols = [model.columns_.index(c.split(".")[-1]) for c in rs.columns]
    band = std[:, cols]
    assert np.all(band > 0)
    assert band.max() < 0.25 * rs.separation  # the route's, not between routes
