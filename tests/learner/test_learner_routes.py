"""Routes: the path follows one route of the demonstrations, never runs between."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.learner._routes import (
    choose_route,
    route_labels,
    route_probabilities,
    segment_paths,
)
from ndlfd.learner._segments import segment_states
from ndlfd.synth import obstacle


def _mid_y(path):
    P = path.get("position")
    return float(P[np.argmin(np.abs(P[:, 0] + 5.0)), 1])


@pytest.mark.parametrize(("n_up", "n_down"), [(7, 5), (9, 3), (3, 9), (5, 7)])
def test_the_path_follows_the_route_most_demonstrations_take(n_up, n_down):
    # a blend of every demonstration crosses mid-course near y = 0, through
    # the obstacle both routes avoid
    demos = obstacle(n_up, n_down)
    model = KeypointHMM().fit(demos)
    path = model.generate(np.linspace(0.0, 5.0, 200), dense=True)
    major = 1.0 if n_up > n_down else -1.0
    assert major * _mid_y(path) == pytest.approx(5.5, abs=0.3)
    # on the route the whole way: every sample within the major route's tube
    P = path.get("position")
    ys = np.stack([np.interp(P[:, 0], d.X[:, 0], d.X[:, 1]) for d in demos])
    route = ys[:n_up] if major > 0 else ys[n_up:]
    assert np.all(P[:, 1] >= route.min(axis=0) - 0.3)
    assert np.all(P[:, 1] <= route.max(axis=0) + 0.3)


def test_a_start_on_the_minor_route_follows_the_minor_route():
    demos = obstacle(9, 3, lift=1.0)  # the routes start 2 apart
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 200)
    assert _mid_y(model.generate(t, dense=True)) > 5
    low = {"position": [-10.0, -1.1]}
    assert _mid_y(model.generate(t, dense=True, start=low)) < -5
    high = {"position": [-10.0, 1.1]}
    assert _mid_y(model.generate(t, dense=True, start=high)) > 5


def test_demonstrations_of_one_route_are_one_route():
    # spread evenly about one course: all one route, all blended
    rng = np.random.default_rng(3)
    s = np.linspace(0.0, 1.0, 100)
    demos = [
        Demonstration(s, np.column_stack([s, np.sin(3 * s) + off]), ["x", "y"],
                      ["position"] * 2)
        for off in np.linspace(-0.2, 0.2, 8) + rng.normal(0, 0.01, 8)
    ]  # fmt: skip
    model = KeypointHMM().fit(demos)
    paths = segment_paths(model.fit_stats_, model.centroid_states_, 50)
    labels = route_labels(paths, model.template_indices_, model.centroids_)
    np.testing.assert_array_equal(labels, 0)
    # the path is their average: near the middle course, not one of them
    y = model.generate(s, dense=True).get("position")[:, 1]
    assert np.abs(y - np.sin(3 * s)).max() < 0.1


# ----------------------------------------------------------- the parts, exact


@st.composite
def key_sequences(draw):
    n_bins = draw(st.integers(1, 12))
    n_demos = draw(st.integers(1, 6))
    bins, states, n_keys = [], [], []
    for _ in range(n_demos):
        k = draw(st.integers(1, 6))
        b = sorted(draw(st.lists(st.integers(0, n_bins - 1), min_size=k, max_size=k)))
        b[0] = 0
        bins += b
        states += draw(st.lists(st.integers(0, 9), min_size=k, max_size=k))
        n_keys.append(k)
    return n_bins, np.array(n_keys), np.array(bins), np.array(states)


class _Stats:
    def __init__(self, n_keys, key_bins, key_states):
        self.n_keys, self.key_bins, self.key_states = n_keys, key_bins, key_states


@given(key_sequences())
@settings(max_examples=200)
def test_segment_paths_are_each_demonstrations_segment_states(case):
    n_bins, n_keys, bins, states = case
    seen = np.unique(states)
    paths = segment_paths(_Stats(n_keys, bins, states), seen, n_bins)
    ends = np.cumsum(n_keys)
    for j, (lo, hi) in enumerate(zip(ends - n_keys, ends, strict=True)):
        expected = segment_states(bins[lo:hi], states[lo:hi], n_bins)
        np.testing.assert_array_equal(seen[paths[j]], expected)


@st.composite
def separated_groups(draw):
    k = draw(st.integers(1, 4))
    sizes = draw(st.lists(st.integers(2, 6), min_size=k, max_size=k))
    n_bins = draw(st.integers(1, 5))
    seed = draw(st.integers(0, 2**16))
    return sizes, n_bins, seed


@given(separated_groups())
@settings(max_examples=100)
def test_route_labels_find_well_separated_groups(case):
    # each group a chain of curves 1 +- 0.1 apart (per bin), the groups 100
    # apart: each group is one route, numbered by its first template
    sizes, n_bins, seed = case
    rng = np.random.default_rng(seed)
    centroids, paths, truth = [], [], []
    for g, size in enumerate(sizes):
        for i in range(size):
            row = []
            for _ in range(n_bins):
                centroids.append([100.0 * g + i + rng.uniform(-0.05, 0.05), 0.0])
                row.append(len(centroids) - 1)
            paths.append(row)
            truth.append(g)
    order = rng.permutation(len(paths))
    paths = np.array(paths, dtype=np.int32)[order]
    truth = np.array(truth)[order]
    labels = route_labels(paths, np.arange(len(paths)), np.array(centroids))
    _, first = np.unique(truth, return_index=True)
    renumber = {g: r for r, g in enumerate(truth[np.sort(first)])}
    np.testing.assert_array_equal(labels, [renumber[g] for g in truth])


def test_demonstrations_that_are_no_template_take_their_nearest_templates_route():
    C = np.array([[0.0], [0.2], [9.0], [9.3], [0.1], [9.1]])
    paths = np.array([[0], [1], [2], [3], [4], [5]], dtype=np.int32)
    labels = route_labels(paths, np.array([0, 1, 2, 3]), C)
    np.testing.assert_array_equal(labels, [0, 0, 1, 1, 0, 1])


@given(st.lists(st.integers(0, 3), min_size=1, max_size=12), st.integers(0, 99))
def test_choose_route_is_the_heaviest_brute_force(labels, seed):
    labels = np.array(labels)
    logw = np.random.default_rng(seed).normal(0, 2, labels.size)
    w = np.exp(logw - logw.max())
    totals = {r: w[labels == r].sum() for r in np.unique(labels)}
    best = max(totals.values())
    # ties (within rounding) go to the lowest route number
    expected = min(r for r, v in totals.items() if v >= best * (1 - 1e-12))
    assert choose_route(labels, logw) == expected


def test_segment_paths_refuses_work_past_the_bound_before_allocating():
    """Demonstrations × time bins beyond MAX_WORK_BYTES: one error, no array."""
    from types import SimpleNamespace

    from ndlfd import ResourceLimitError
    from ndlfd._validation import MAX_WORK_BYTES

    n_demos, n_bins = 2**12, MAX_WORK_BYTES // (8 * 2**12) + 1
    stats = SimpleNamespace(
        n_keys=np.ones(n_demos, dtype=np.int64),
        key_bins=np.zeros(n_demos, dtype=np.int64),
        key_states=np.zeros(n_demos, dtype=np.int64),
    )
    with pytest.raises(ResourceLimitError, match="time bins"):
        segment_paths(stats, np.array([0]), n_bins)
    # one bin fewer fits the bound; checked on the bound itself, not by allocating
    assert 8 * n_demos * (n_bins - 1) <= MAX_WORK_BYTES


def test_route_probabilities():
    np.testing.assert_allclose(
        route_probabilities(np.array([0, 1, 1, 0]), np.log([1.0, 1.0, 2.0, 4.0])),
        [5 / 8, 3 / 8],
    )
