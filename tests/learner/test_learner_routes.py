"""Routes: the path follows one route of the demonstrations, never runs between."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.learner._curves import frechet_matrix, route_curves
from ndlfd.learner._routes import (
    MIN_GAP,
    choose_route,
    route_columns,
    route_labels,
    route_probabilities,
    segment_paths,
    split_routes,
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
    np.testing.assert_array_equal(model.routes_, 0)
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


def _frechet_brute(A, B, band):
    """Discrete Fréchet by enumerating every monotone pairing within the band."""
    n, m = len(A), len(B)
    best = np.inf

    def walk(i, j, worst):
        nonlocal best
        if abs(i - j) > band:
            return
        worst = max(worst, float(np.linalg.norm(A[i] - B[j])))
        if worst >= best:
            return
        if i == n - 1 and j == m - 1:
            best = worst
            return
        for di, dj in ((1, 0), (0, 1), (1, 1)):
            if i + di < n and j + dj < m:
                walk(i + di, j + dj, worst)

    walk(0, 0, 0.0)
    return best


@given(st.integers(1, 6), st.integers(1, 3), st.integers(0, 2**16))
@settings(deadline=None)
def test_frechet_matrix_is_the_least_largest_pairing_brute_force(k, d, seed):
    # every monotone pairing enumerated, with and without the band; values
    # on a grid of 1/8 so both sides compute the same squares exactly
    rng = np.random.default_rng(seed)
    curves = rng.integers(-8, 9, (3, k, d)) / 8.0
    for share in (1.0, 0.25):
        band = max(1, int(np.ceil(share * k)))
        D = frechet_matrix(curves, band=share)
        for i in range(3):
            for j in range(3):
                want = 0.0 if i == j else _frechet_brute(curves[i], curves[j], band)
                assert D[i, j] == pytest.approx(want, rel=1e-12, abs=1e-15)
        # the same to other curves, and the same on two threads
        np.testing.assert_array_equal(frechet_matrix(curves, curves, band=share), D)
        big = rng.normal(size=(40, k, d))
        np.testing.assert_array_equal(
            frechet_matrix(big, n_jobs=1, band=share),
            frechet_matrix(big, n_jobs=2, band=share),
        )


def test_frechet_ignores_pace_and_counts_a_detour_in_full():
    tau = np.linspace(0.0, 1.0, 400)
    line = np.column_stack([tau, 0 * tau])
    slow = np.column_stack([tau**1.5, 0 * tau])  # the same line, another pace
    detour = np.column_stack([tau, 0.2 * (np.abs(tau - 0.5) < 0.06)])  # 12 %
    C = route_curves([line, slow, detour], [tau] * 3, np.array([0, 1]))
    D = frechet_matrix(C)
    assert D[0, 1] < 0.02
    assert D[0, 2] == pytest.approx(0.2, abs=0.01)


def test_route_curves_give_a_rest_few_points():
    # a 3 s rest then a 1 s reach: the reach keeps more than half the points
    t = np.linspace(0.0, 4.0, 2000)
    s = np.clip(t - 3.0, 0.0, 1.0)
    rng = np.random.default_rng(0)
    U = np.column_stack([s, 0 * s]) + rng.normal(0, 0.002, (t.size, 2))
    curve = route_curves([U], [t / 4.0], np.array([0, 1]), 64)[0]
    moving = np.sum((curve[:, 0] > 0.02) & (curve[:, 0] < 0.98))
    assert moving > 32


def test_route_columns_default_and_named():
    np.testing.assert_array_equal(
        route_columns(("position",) * 2 + ("velocity",) * 2 + ("gripper",)), [0, 1]
    )
    cg = ("joints",) * 3 + ("gripper", "velocity")
    np.testing.assert_array_equal(route_columns(cg), [0, 1, 2])
    np.testing.assert_array_equal(route_columns(cg, ["gripper"]), [3])
    np.testing.assert_array_equal(route_columns(("orientation",) * 4), [0, 1, 2, 3])


_TAU = np.linspace(0.0, 1.0, 32)


def _bumps(heights, width=1.0):
    """Curves over a bump of each height (the routes' shape, 2-D)."""
    bump = np.exp(-(((_TAU - 0.5) / (0.15 * width)) ** 2))
    return np.stack([np.column_stack([_TAU, h * bump]) for h in heights])


@st.composite
def separated_groups(draw):
    k = draw(st.integers(1, 4))
    sizes = draw(st.lists(st.integers(2, 6), min_size=k, max_size=k))
    seed = draw(st.integers(0, 2**16))
    return sizes, seed


def _renumbered(truth):
    _, first = np.unique(truth, return_index=True)
    renumber = {g: r for r, g in enumerate(truth[np.sort(first)])}
    return np.array([renumber[g] for g in truth])


@given(separated_groups(), st.sampled_from([1.0, 0.3]))
@settings(max_examples=100, deadline=None)
def test_split_routes_find_well_separated_groups(case, width):
    # bumps whose heights come in groups 0.3 apart, each spread over 0.02,
    # wide or brief (30 % of the width): each group one route, numbered by
    # its first member; n_routes=k gives the same
    sizes, seed = case
    rng = np.random.default_rng(seed)
    h = np.concatenate([0.3 * g + rng.uniform(0, 0.02, n) for g, n in enumerate(sizes)])
    truth = np.repeat(np.arange(len(sizes)), sizes)
    order = rng.permutation(h.size)
    h, truth = h[order], truth[order]
    curves = _bumps(h, width)
    np.testing.assert_array_equal(split_routes(curves), _renumbered(truth))
    got = split_routes(curves, n_routes=len(sizes))
    np.testing.assert_array_equal(got, _renumbered(truth))


@pytest.mark.parametrize("heights", [[0.3, 0.31, -0.3], [0.3, -0.3], [0.0, 0.2, 0.205]])
def test_split_routes_two_against_one_and_one_against_one(heights):
    # three curves or fewer: no floor, a gap of MIN_GAP makes two routes
    labels = split_routes(_bumps(heights))
    assert np.unique(labels).size == 2


def test_split_routes_keep_an_even_spread_one_route():
    # bump heights spread evenly, wide or narrow: no gap stands out. Random
    # spreads of noiseless bumps are split now and then (docs/routes.md:
    # 6-19 % of draws of 5-20 curves), so this is a known answer, not a
    # property; the route corpus (test_learner_route_corpus) holds the
    # realistic continuous sets.
    for n in (5, 8, 12, 20):
        for half in (0.05, 0.3, 0.6):
            h = np.linspace(-half, half, n)
            np.testing.assert_array_equal(split_routes(_bumps(h)), 0)


def test_split_routes_nested_routes_and_small_gaps():
    # three routes side by side: 0.1 apart, 0.005 wide
    h = np.r_[0.0, 0.004, 0.002, 0.1, 0.104, 0.2, 0.203, 0.201]
    np.testing.assert_array_equal(split_routes(_bumps(h)), [0, 0, 0, 1, 1, 2, 2, 2])
    # below MIN_GAP: one route, however tight
    y = h * (0.9 * MIN_GAP / 0.1)
    np.testing.assert_array_equal(split_routes(_bumps(y)), 0)


def test_route_labels_of_demonstrations_that_are_no_template():
    tau = np.linspace(0.0, 1.0, 50)
    bump = np.sin(np.pi * tau)
    V = [np.column_stack([tau, s * bump]) for s in (0.3, 0.31, -0.3, -0.29)]
    amps = (0.3, 0.31, -0.3, -0.29, 0.28, -0.33)
    seg = np.stack([np.column_stack([tau, s * bump]) for s in amps])

    def segment_curves(rows):
        return seg[rows]

    curves = route_curves(V, [tau] * 4, np.array([0, 1]))
    labels = route_labels(curves, np.arange(4), 6, segment_curves)
    np.testing.assert_array_equal(labels, [0, 0, 1, 1, 0, 1])


def test_route_options_of_the_model():
    demos = obstacle(5, 4)
    truth = np.r_[np.zeros(5), np.ones(4)]
    np.testing.assert_array_equal(KeypointHMM().fit(demos).routes_, truth)
    np.testing.assert_array_equal(KeypointHMM(n_routes=1).fit(demos).routes_, 0)
    three = KeypointHMM(n_routes=3).fit(demos).routes_
    assert np.unique(three).size == 3
    # every route of three within one true route
    assert all(np.unique(truth[three == r]).size == 1 for r in range(3))
    with pytest.raises(ValidationError, match="route_groups names none"):
        KeypointHMM(route_groups=["force"]).fit(demos)
    with pytest.raises(ValidationError, match="n_routes=10 is more than the 9"):
        KeypointHMM(n_routes=10).fit(demos)
    with pytest.raises(ValidationError, match="route_groups must be"):
        KeypointHMM(route_groups="position").fit(demos)


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
