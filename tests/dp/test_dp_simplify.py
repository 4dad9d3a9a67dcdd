"""Tests of ndlfd.dp._simplify against the slow references of reference_simplify."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from ndlfd._errors import OptionError, ValidationError
from ndlfd._validation import check_times
from ndlfd.dp import _simplify
from ndlfd.dp._simplify import DISTANCES, simplify, simplify_many
from reference_simplify import (
    DISTANCE_FUNCTIONS,
    budget_reference,
    dp_reference,
    greedy_order,
    line_distances,
    paper_matrix,
    zigzag,
)

MODES = ["line", "segment", "sed", "paper"]
# dyadic tolerances: eps² is exact, so "distance == eps" is decided exactly
EPSILONS = [0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0]
SETTINGS = settings(max_examples=60, deadline=None)


@st.composite
def integer_paths(draw, max_n=40, max_d=8, min_n=1):
    """Small integer-valued paths: duplicates, collinear runs, closed loops."""
    n = draw(st.integers(min_n, max_n))
    d = draw(st.integers(1, max_d))
    r = draw(st.sampled_from([1, 3, 10]))
    P = draw(arrays(np.float64, (n, d), elements=st.integers(-r, r).map(float)))
    if n > 1 and draw(st.booleans()):
        P[-1] = P[0]  # coincident endpoints
    if draw(st.booleans()):  # repeated rows
        reps = draw(arrays(np.int64, (n,), elements=st.integers(1, 3)))
        P = np.repeat(P, reps, axis=0)[:max_n]
    return P


def integer_times(draw, n):
    steps = draw(arrays(np.float64, (n,), elements=st.integers(1, 3).map(float)))
    return np.cumsum(steps)


@st.composite
def cases(draw, modes=MODES):
    # every kernel family: 2-D, 3-D, column tuples (1-8), transposed (9-16)
    P = draw(integer_paths(max_d=16))
    mode = draw(st.sampled_from(modes))
    times = integer_times(draw, P.shape[0]) if mode == "sed" else None
    return P, mode, times


# ---------------------------------------------------------------- known answers


def test_segment_example_from_the_spec():
    P = [[0, 0], [5, 0], [10, 0], [5, 0.01], [1, 0]]
    assert simplify(P, 1).tolist() == [0, 4]
    assert simplify(P, 1, distance="segment").tolist() == [0, 2, 4]


def test_hand_worked_2d_example():
    # chord 0-4 is y = 0: distances 2, 1, 3 -> point 3 is kept at eps = 1.
    # chord 0-3 is y = x: points 1 and 2 both at 1/sqrt(2) (a tie).
    P = [[0, 0], [1, 2], [2, 1], [3, 3], [4, 0]]
    assert simplify(P, 1).tolist() == [0, 3, 4]
    assert simplify(P, 0.8).tolist() == [0, 3, 4]
    # eps = 0.7 < 1/sqrt(2): the tie goes to the first index, 1; then the
    # chord 1-3 has point 2 at 3/sqrt(5) = 1.34 > 0.7.
    assert simplify(P, 0.7).tolist() == [0, 1, 2, 3, 4]
    # budget: 3 first (distance 3), then the first of the tie, 1
    assert simplify(P, n_points=3).tolist() == [0, 3, 4]
    assert simplify(P, n_points=4).tolist() == [0, 1, 3, 4]


def test_strictly_greater_than_epsilon():
    P = [[0, 0], [1, 1], [2, 0]]
    assert simplify(P, 1.0).tolist() == [0, 2]
    assert simplify(P, 0.999).tolist() == [0, 1, 2]


def test_one_and_two_points():
    for mode in MODES:
        times = [0.0, 1.0] if mode == "sed" else None
        t1 = [0.0] if mode == "sed" else None
        assert simplify([[3.0, 4.0]], 0.1, distance=mode, times=t1).tolist() == [0]
        assert simplify([[3.0], [4.0]], 0, distance=mode, times=times).tolist() == [
            0,
            1,
        ]
    assert simplify([[1.0, 2.0]], n_points=5).tolist() == [0]
    assert simplify([[1.0], [2.0]], n_points=1).tolist() == [0, 1]
    out = simplify([[3.0, 4.0]], 0.1)
    assert out.dtype == np.int64


def test_coincident_endpoints_use_distance_to_first_point():
    P = [[0, 0], [1, 0], [3, 0], [0, 2], [0, 0]]
    # distances to P_0: 1, 3, 2
    assert simplify(P, 2.5).tolist() == [0, 2, 4]
    assert simplify(P, 3.0).tolist() == [0, 4]


def test_one_dimensional_line_keeps_only_turning_structure():
    # in 1-D the "line" through two distinct values is the whole axis
    P = np.array([[0.0], [5.0], [-3.0], [2.0]])
    assert simplify(P, 0).tolist() == [0, 3]
    assert simplify(P, 0, distance="paper").tolist() == [0, 3]
    # coincident endpoints: distances to P_0 are 5, 3
    Q = np.array([[0.0], [5.0], [-3.0], [0.0]])
    assert simplify(Q, 4).tolist() == [0, 1, 3]


def test_paper_formula_is_not_a_distance_in_3d():
    p1, pi, pn = np.zeros(3), np.array([0.0, 1.0, 1.0]), np.array([1.0, 0.0, 0.0])
    det = abs(np.linalg.det(paper_matrix(p1, pi, pn)))
    assert det == pytest.approx(0.0)  # but the true distance is sqrt(2)
    P = np.array([p1, pi, pn])
    assert simplify(P, 0.5, distance="paper").tolist() == [0, 2]
    assert simplify(P, 0.5, distance="line").tolist() == [0, 1, 2]


def test_sed_compares_with_the_chord_at_the_same_time():
    # the middle point lies on the line but far from where the chord is at t=1
    P = [[0.0, 0.0], [9.0, 0.0], [10.0, 0.0]]
    assert simplify(P, 1, distance="line").tolist() == [0, 2]
    assert simplify(P, 1, distance="sed", times=[0, 1, 2]).tolist() == [0, 1, 2]
    assert simplify(P, 1, distance="sed", times=[0, 9, 10]).tolist() == [0, 2]


@pytest.mark.parametrize("d", range(1, 17))
def test_segment_past_the_ends_known_answer_in_every_kernel(d):
    # chord (0, 0)-(4, 0). Point 1, (-3, 4), lies before P_a: 5 from the
    # segment (4 from the line). Then chord (-3, 4)-(4, 0), u = (7, -4),
    # |u|² = 65: point 2, (7, 0), has v·u = 10·7 + 4·4 = 86 > 65, past P_b,
    # so it is |(7, 0) - (4, 0)| = 3 from the segment (12 / sqrt(65) = 1.49
    # from the line). The two columns sit in two of d columns (every kernel
    # family); in 1-D only the x column: distances 3 (before P_a) and 3.
    P2 = np.array([[0.0, 0.0], [-3.0, 4.0], [7.0, 0.0], [4.0, 0.0]])
    cols = np.random.default_rng(d).choice(d, size=min(d, 2), replace=False)
    P = np.zeros((4, d))
    P[:, cols] = P2[:, : cols.size]
    seg = {"distance": "segment"}
    if d == 1:
        assert simplify(P, 2.9, **seg).tolist() == [0, 1, 2, 3]
        assert simplify(P, 3.0, **seg).tolist() == [0, 3]
        return
    assert simplify(P, 4.5).tolist() == [0, 3]
    assert simplify(P, 4.5, **seg).tolist() == [0, 1, 3]
    assert simplify(P, 2.9, **seg).tolist() == [0, 1, 2, 3]
    assert simplify(P, 3.0, **seg).tolist() == [0, 1, 3]
    assert simplify(P, 5.0, **seg).tolist() == [0, 3]


def test_registry_lists_the_modes():
    assert DISTANCES.names == tuple(MODES)


# ------------------------------------------------------------ property tests


@SETTINGS
@given(cases(), st.sampled_from(EPSILONS))
def test_matches_reference(case, eps):
    P, mode, times = case
    got = simplify(P, eps, distance=mode, times=times)
    want = dp_reference(P, eps, mode, times)
    assert got.dtype == np.int64
    assert got.tolist() == want.tolist()
    n = P.shape[0]
    assert got[0] == 0 and got[-1] == n - 1
    mask = simplify(P, eps, distance=mode, times=times, return_mask=True)
    assert mask.dtype == np.bool_ and mask.shape == (n,)
    assert np.flatnonzero(mask).tolist() == got.tolist()


@SETTINGS
@given(cases(), st.integers(1, 45))
def test_budget_matches_reference(case, k):
    P, mode, times = case
    got = simplify(P, n_points=k, distance=mode, times=times)
    want = budget_reference(P, k, mode, times)
    assert got.tolist() == want.tolist()
    assert len(got) == min(max(k, 2), P.shape[0])
    mask = simplify(P, n_points=k, distance=mode, times=times, return_mask=True)
    assert np.flatnonzero(mask).tolist() == got.tolist()


@SETTINGS
@given(cases(), st.sampled_from(EPSILONS))
def test_epsilon_result_is_a_prefix_of_the_budget_order(case, eps):
    P, mode, times = case
    by_eps = simplify(P, eps, distance=mode, times=times)
    by_budget = simplify(P, n_points=len(by_eps), distance=mode, times=times)
    assert by_eps.tolist() == by_budget.tolist()


def test_a_budget_can_match_no_epsilon():
    # chord 0-3 is y = 0: point 1 at distance 2 is farthest (point 2 at 1.5).
    # After the split, chord 1-3 shows point 2 at about 2.55 > 2. A budget of
    # 3 points stops between the two; no epsilon can (any eps < 2 keeps both).
    P = np.array([[0.0, 0.0], [1.0, 2.0], [5.0, -1.5], [10.0, 0.0]])
    assert line_distances(P, 0, 3).tolist() == [2.0, 1.5]
    assert line_distances(P, 1, 3)[0] > 2.5
    assert greedy_order(P) == [1, 2]
    budget3 = simplify(P, n_points=3).tolist()
    assert budget3 == [0, 1, 3]
    eps_results = {tuple(simplify(P, e).tolist()) for e in np.linspace(0, 5, 2001)}
    assert eps_results == {(0, 1, 2, 3), (0, 3)}


@SETTINGS
@given(cases(), st.sampled_from(EPSILONS), st.sampled_from(EPSILONS))
def test_monotone_in_epsilon(case, e1, e2):
    P, mode, times = case
    lo, hi = min(e1, e2), max(e1, e2)
    small = set(simplify(P, lo, distance=mode, times=times).tolist())
    large = set(simplify(P, hi, distance=mode, times=times).tolist())
    assert large <= small


@SETTINGS
@st.composite
def overshooting_paths(draw):
    """Integer paths that run back and forth along a line, past both ends.

    Positions along a random integer direction (some before the first point
    and past the last) plus small integer offsets: many points whose closest
    point of a chord is one of its ends, in every dimension 1..16.
    """
    n = draw(st.integers(3, 60))
    d = draw(st.integers(1, 16))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    direction = rng.integers(-2, 3, size=d)
    direction[rng.integers(d)] = 3
    along = rng.integers(-8, 9, size=n)
    along[[0, -1]] = draw(st.sampled_from([(0, 4), (-2, 6), (3, 3), (0, 1)]))
    side = rng.integers(-2, 3, size=(n, d)) * (rng.random((n, 1)) < 0.5)
    return (along[:, None] * direction + side).astype(float)


@SETTINGS
@given(overshooting_paths(), st.sampled_from(EPSILONS))
def test_segment_mode_past_the_ends_matches_reference(P, eps):
    # the clamped projection: points before P_a and past P_b are measured
    # from that end, in every kernel family (integer keys: exact)
    got = simplify(P, eps, distance="segment", n_jobs=1)
    assert got.tolist() == dp_reference(P, eps, "segment").tolist()


@given(integer_paths(), st.sampled_from(EPSILONS))
def test_line_dropped_points_are_within_epsilon(P, eps):
    kept = simplify(P, eps)
    for a, b in itertools.pairwise(kept):
        if b - a > 1:
            assert line_distances(P, a, b).max() <= eps + 1e-9


@SETTINGS
@given(integer_paths(max_d=2), st.sampled_from(EPSILONS))
def test_paper_equals_line_in_2d(P, eps):
    assume(P.shape[1] == 2)
    assert simplify(P, eps, distance="paper").tolist() == simplify(P, eps).tolist()
    assert (
        simplify(P, n_points=7, distance="paper").tolist()
        == simplify(P, n_points=7).tolist()
    )


@SETTINGS
@given(
    st.integers(2, 40),
    st.integers(1, 8),
    st.integers(0, 2**32 - 1),
    st.floats(0.05, 0.95),
)
def test_line_invariant_to_rotation_and_translation(n, d, seed, frac):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(n, d))
    Q, _ = np.linalg.qr(rng.normal(size=(d, d)))
    shift = rng.normal(size=d) * 10
    splits = []
    dp_reference(P, -1.0, splits=splits)  # every node distance of the tree
    node_d = [line_distances(P, a, b)[i - a - 1] for _, a, b, i in splits if b - a > 1]
    eps = frac * (max(node_d) if node_d else 1.0)
    # The rotated data are other floats, and their distances are rounded
    # differently: compare only where that cannot matter, with every node
    # distance 1e-6 away from eps and every farthest point 1e-9 ahead of the
    # runner-up of its segment (a stated margin, far above the rounding).
    assume(all(abs(x - eps) > 1e-6 for x in node_d))
    for _, a, b, _ in splits:
        top2 = np.sort(line_distances(P, a, b))[-2:]
        assume(top2.size < 2 or top2[1] - top2[0] > 1e-9)
    base = simplify(P, eps)
    assert base.tolist() == dp_reference(P, eps).tolist()
    assert simplify(P @ Q.T + shift, eps).tolist() == base.tolist()


# weights that keep weighted integer data exact (multiples of 1/4, or integers)
WEIGHTS = [0.0, 0.25, 0.5, 1.0, 2.0, 3.0]


@SETTINGS
@given(cases(), st.sampled_from(EPSILONS), st.data())
def test_weights_measure_in_the_weighted_metric(case, eps, data):
    P, mode, times = case
    d = P.shape[1]
    w = data.draw(arrays(np.float64, (d,), elements=st.sampled_from(WEIGHTS)))
    got = simplify(P, eps, distance=mode, weights=w, times=times)
    want = dp_reference(P, eps, mode, times, weights=w)
    assert got.tolist() == want.tolist()


def test_weights_known_answer():
    # unweighted, point 1 is 2 from the chord y = 0 and point 2 is 1.5 from it
    P = np.array([[0.0, 0.0], [1.0, 2.0], [5.0, -1.5], [10.0, 0.0]])
    assert simplify(P, 1.9).tolist() == [0, 1, 2, 3]
    # y weighted by 1/2: distances 1 and 0.75 from the same chord
    assert simplify(P, 1.0, weights=[1.0, 0.5]).tolist() == [0, 3]
    assert simplify(P, 0.99, weights=[1.0, 0.5]).tolist() == [0, 1, 2, 3]
    # x weighted by 0, y by 3: the chord 0-3 has length 0 in the weighted
    # metric (coincident endpoints), so point 1 is 3 * 2 = 6 from P_0; then
    # the chord 1-3 runs along y and point 2 lies on it.
    assert simplify(P, 5.9, weights=[0.0, 3.0]).tolist() == [0, 1, 3]
    assert simplify(P, 6.0, weights=[0.0, 3.0]).tolist() == [0, 3]


@pytest.mark.parametrize("d", [1, 2, 3, 4, 6, 8, 9, 10, 11, 16])
@pytest.mark.parametrize("mode", MODES)
def test_long_integer_walks_cross_block_boundaries(d, mode):
    # several blocks of the vectorized scans, many exact ties across blocks
    rng = np.random.default_rng(d)
    n = 300 if mode == "paper" else 700  # the paper reference is slow
    P = np.cumsum(rng.integers(-1, 2, size=(n, d)), axis=0).astype(float)
    times = np.cumsum(rng.integers(1, 3, size=n)).astype(float)
    t = times if mode == "sed" else None
    for eps in (0.0, 1.0, 2.5):
        got = simplify(P, eps, distance=mode, times=t)
        assert got.tolist() == dp_reference(P, eps, mode, t).tolist()
    if mode == "line":
        got = simplify(P, n_points=40, distance=mode, times=t)
        assert got.tolist() == budget_reference(P, 40, mode, t).tolist()


@st.composite
def block_crossing_paths(draw, d):
    """Integer paths over several 256-point blocks of the scans, full of ties.

    Walks folded into a small box (so distances repeat), points drawn from
    {-1, 0, 1}^d, and a folded 2-D walk placed in two of d columns (the others
    zero, so ties stay as common as in 2-D), in every dimension family of the
    line kernels (2-D, 3-D, column tuples for 4-10, transposed data for 1 and
    11+). Drawn from a seed: drawing thousands of values one by one is slow.
    """
    n = draw(st.integers(300, 1600))
    kind = draw(st.sampled_from(["box", "grid", "flat"]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if kind == "grid":
        return rng.integers(-1, 2, size=(n, d)).astype(float)
    walk = np.cumsum(rng.integers(-1, 2, size=(n, d if kind == "box" else 2)), axis=0)
    walk = np.abs((walk + 2) % 8 - 4).astype(float)
    if kind == "box":
        return walk
    P = np.zeros((n, d))
    cols = rng.choice(d, size=min(d, 2), replace=False)
    P[:, cols] = walk[:, : cols.size]
    return P


@pytest.mark.parametrize("d", [1, 2, 3, 4, 6, 9, 10, 11, 16])
@settings(max_examples=8, deadline=None)
@given(
    data=st.data(),
    eps=st.sampled_from([0.5, 1.0, 1.5, 2.5]),
    mode=st.sampled_from(["line", "segment", "sed"]),
)
def test_ties_across_blocks_go_to_the_first_index(d, data, eps, mode):
    # equal distances in different blocks of a scan: the first index wins
    P = data.draw(block_crossing_paths(d), label="P")
    # integer times (a step of 1 or 2): "sed" keys stay exact integers too
    t = np.cumsum(np.arange(len(P)) % 3 // 2 + 1.0) if mode == "sed" else None
    got = simplify(P, eps, distance=mode, times=t, n_jobs=1)
    assert got.tolist() == dp_reference(P, eps, mode, t).tolist()


def _loop(n, d, radius, centre, angle, rng):
    """A closed loop of n points (n odd) on a circle in a random plane of R^d.

    Point (n - 1) / 2 is the only point farthest from P_0 (the antipode).
    """
    basis, _ = np.linalg.qr(rng.normal(size=(d, 2)))
    theta = angle + 2 * np.pi * np.arange(n) / (n - 1)
    P = centre + radius * (np.cos(theta)[:, None] * basis[:, 0])
    P += radius * (np.sin(theta)[:, None] * basis[:, 1])
    P[-1] = P[0]
    return P


@SETTINGS
@given(
    st.integers(2, 10).map(lambda h: 2 * h + 1),
    st.integers(2, 6),
    st.integers(0, 2**32 - 1),
    st.integers(-3, 3),
    st.sampled_from(["line", "segment"]),
)
def test_loops_closed_up_to_ulps_keep_their_far_point(n, d, seed, ulps, mode):
    # endpoints a few ulps apart are coincident (|u| <= 8 eps max|P|): the
    # loop is measured from P_0, and the antipode is its first key point. Were
    # the one-ulp gap taken as a direction, the "line" through the endpoints
    # would be noise and the far point could lie on it.
    rng = np.random.default_rng(seed)
    radius = 2.0 ** rng.integers(-20, 20)
    centre = rng.normal(size=d) * radius * rng.choice([0.0, 1.0, 10.0])
    P = _loop(n, d, radius, centre, rng.uniform(0, 2 * np.pi), rng)
    k = int(np.argmax(np.abs(P[0])))
    P[-1, k] = P[0, k] + ulps * np.spacing(P[0, k])
    mid = (n - 1) // 2
    # the arcs are within the radius of their chords (the diameter)
    assert simplify(P, 1.5 * radius, distance=mode).tolist() == [0, mid, n - 1]
    assert simplify(P, n_points=3, distance=mode).tolist() == [0, mid, n - 1]
    assert dp_reference(P, 1.5 * radius, mode).tolist() == [0, mid, n - 1]


@SETTINGS
@given(
    st.integers(3, 40),
    st.integers(2, 5),
    st.sampled_from(MODES),
    st.integers(0, 2**32 - 1),
    st.floats(0.05, 0.95),
)
def test_float_paths_with_revisits_match_reference(n, d, mode, seed, frac):
    # float data that come back to where they were: exact copies of earlier
    # points (exact ties, which go to the first index) and an end a few ulps
    # from the start (coincident endpoints)
    rng = np.random.default_rng(seed)
    scale = 2.0 ** rng.integers(-30, 30)
    P = rng.normal(size=(n, d)) * scale
    for i in rng.choice(np.arange(1, n), size=rng.integers(0, n // 3 + 1)):
        P[i] = P[rng.integers(0, i)]
    k = int(rng.integers(0, d))
    P[-1] = P[0]
    P[-1, k] += int(rng.integers(-3, 4)) * np.spacing(P[0, k])
    times = np.cumsum(rng.uniform(0.5, 2.0, n)) if mode == "sed" else None
    splits = []
    dp_reference(P, -1.0, mode, times, splits=splits)
    dist = DISTANCE_FUNCTIONS[mode]
    node_d = [dist(P, a, b, times)[i - a - 1] for _, a, b, i in splits]
    eps = frac * max(node_d, default=scale)
    # floats are rounded differently here and in the kernels: compare where
    # rounding cannot decide (stated margins), exact ties being exact copies
    assume(all(abs(x - eps) > 1e-6 * scale for x in node_d))
    for _, a, b, _ in splits:
        top2 = np.sort(dist(P, a, b, times))[-2:]
        lead = top2[-1] - top2[0]
        assume(top2.size < 2 or lead == 0 or lead > 1e-9 * scale)
    got = simplify(P, eps, distance=mode, times=times)
    assert got.tolist() == dp_reference(P, eps, mode, times).tolist()


def test_loop_one_ulp_open_known_answer():
    # unit circle from 45 degrees, end moved one ulp along x: measured from
    # the x direction the bottom point (0, -1) would be 1.71 away and the
    # antipode only 1.41; measured from P_0 (coincident endpoints) the
    # antipode is the farthest, at distance 2.
    theta = np.pi / 4 + 2 * np.pi * np.arange(9) / 8
    P = np.column_stack([np.cos(theta), np.sin(theta)])
    P[-1] = P[0]
    P[-1, 0] = np.nextafter(P[0, 0], 2.0)
    for mode in ("line", "segment", "paper"):
        assert simplify(P, 1.5, distance=mode).tolist() == [0, 4, 8]
        assert simplify(P, n_points=3, distance=mode).tolist() == [0, 4, 8]


# -------------------------------------------------------------- worst case


def test_zigzag_reference_splits_at_depth_n():
    n = 40
    splits = []
    kept = dp_reference(zigzag(n), 0.5, splits=splits)
    assert len(kept) == n
    assert max(depth for depth, *_ in splits) == n - 3
    assert simplify(zigzag(n), 0.5).tolist() == kept.tolist()
    assert simplify(zigzag(n), 0.5, distance="segment").tolist() == kept.tolist()


@pytest.mark.parametrize("d", [2, 3, 5])
def test_zigzag_deep_split_without_recursion(d):
    n = 100_000 if d == 2 else 20_000
    P = np.zeros((n, d))
    P[:, :2] = zigzag(n)
    kept = simplify(P, 0.5)
    assert len(kept) == n


# ------------------------------------------------------------- many / threads


def test_simplify_many_equals_a_loop():
    rng = np.random.default_rng(1)
    demos = [np.cumsum(rng.normal(size=(m, 3)), axis=0) for m in (1, 2, 50, 300, 7)]
    for kw in ({"epsilon": 0.5}, {"n_points": 6}, {"epsilon": 1.0, "n_jobs": 1}):
        want = [
            simplify(p, **{k: v for k, v in kw.items() if k != "n_jobs"}) for p in demos
        ]
        got = simplify_many(demos, **kw)
        assert [g.tolist() for g in got] == [w.tolist() for w in want]
    times = [np.arange(len(p), dtype=float) for p in demos]
    got = simplify_many(demos, 0.5, distance="sed", times=times, return_mask=True)
    for g, p, t in zip(got, demos, times, strict=True):
        want = simplify(p, 0.5, distance="sed", times=t, return_mask=True)
        assert g.tolist() == want.tolist()


def test_simplify_many_errors_name_the_trajectory():
    with pytest.raises(ValidationError, match=r"trajectories\[1\] must be finite"):
        simplify_many([[[0, 0], [1, 1]], [[0, 0], [np.nan, 1]]], 0.1)
    with pytest.raises(ValidationError, match="one time vector per trajectory"):
        simplify_many([[[0, 0], [1, 1]]], 0.1, distance="sed", times=[])
    with pytest.raises(ValidationError, match=r"sequence of .* got one array"):
        simplify_many(np.zeros((3, 2)), 0.1)
    with pytest.raises(ValidationError, match="n_jobs must be an integer >= 1"):
        simplify_many([[[0, 0]]], 0.1, n_jobs=0)
    with pytest.raises(ValidationError, match=r"times\[1\] must be strictly"):
        simplify_many(
            [[[0, 0], [1, 1]], [[0, 0], [1, 1]]],
            0.1,
            distance="sed",
            times=[[0, 1], [1, 1]],
        )


@pytest.mark.parametrize("mode", MODES)
def test_n_jobs_is_checked_in_every_mode(mode):
    times = [0, 1, 2] if mode == "sed" else None
    with pytest.raises(ValidationError, match="n_jobs must be an integer >= 1; got 0"):
        simplify([[0, 0], [1, 1], [2, 0]], 0.1, distance=mode, times=times, n_jobs=0)


# ------------------------------------------------------------------ errors


@pytest.mark.parametrize(
    ("points", "match"),
    [
        ([[0, 0], [np.nan, 1], [2, 2]], r"must be finite; got \[nan, 1.0\].* row 1"),
        ([[0, 0], [1, 1], [np.inf, 2]], r"must be finite.*row 2"),
        ([1.0, 2.0, 3.0], r"np.column_stack\(\[t, y\]\)"),
        (np.zeros((2, 2, 2)), r"shape \(n_points, n_dims\); got .* \(2, 2, 2\)"),
        ([["a", "b"]], r"real numbers .* got .*dtype <U1"),
        (np.zeros((0, 2)), r"at least 1 row"),
        (np.zeros((3, 0)), r"at least one column"),
    ],
)
def test_bad_points(points, match):
    with pytest.raises(ValidationError, match=match):
        simplify(points, 0.1)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"epsilon": -1}, ValidationError, "epsilon must be a finite number >= 0"),
        ({"epsilon": np.nan}, ValidationError, "epsilon must be a finite number"),
        ({"epsilon": "1"}, ValidationError, "epsilon must be .* got '1'"),
        ({}, ValidationError, "exactly one of epsilon .* got neither"),
        ({"epsilon": 1, "n_points": 3}, ValidationError, "exactly one .* got both"),
        ({"n_points": 0}, ValidationError, "n_points must be an integer >= 1"),
        ({"n_points": 2.5}, ValidationError, "n_points must be an integer"),
        (
            {"epsilon": 1, "weights": [1.0]},
            ValidationError,
            r"weights must have one entry per column \(length 2\); got shape",
        ),
        (
            {"epsilon": 1, "weights": [1.0, -1.0]},
            ValidationError,
            r"weights must be finite and >= 0; got weights\[1\] = -1",
        ),
        (
            {"epsilon": 1, "distance": "sed"},
            ValidationError,
            "distance='sed' needs times .* got times=None",
        ),
        (
            {"epsilon": 1, "distance": "sed", "times": [0, 2, 1]},
            ValidationError,
            "times must be strictly increasing",
        ),
        (
            {"epsilon": 1, "distance": "sed", "times": [0, 1]},
            ValidationError,
            r"times must have one entry per point \(length 3\); got length 2",
        ),
        (
            {"epsilon": 1, "times": [0, 1, 2]},
            ValidationError,
            "times are only used by distance='sed'; got times with distance='line'",
        ),
        (
            {"epsilon": 1, "distance": "hausdorff"},
            OptionError,
            "unknown distance 'hausdorff'; expected one of: 'line', 'segment'",
        ),
    ],
)
def test_bad_options(kwargs, error, match):
    with pytest.raises(error, match=match):
        simplify([[0, 0], [1, 1], [2, 0]], **kwargs)


@settings(max_examples=80, deadline=None)
@given(
    st.lists(
        st.one_of(
            st.floats(-1e3, 1e3),
            st.sampled_from([np.nan, np.inf, -np.inf, 0.0, 1.0]),
        ),
        min_size=1,
        max_size=12,
    ),
    st.booleans(),
)
def test_times_fast_path_agrees_with_check_times(values, sort):
    # the compiled check-and-shift of "sed" times: the shifted times of
    # check_times when it accepts them, its own error when it does not
    t = np.array(sorted(values) if sort else values)
    try:
        want = check_times(t, len(t))
    except ValidationError as exc:
        with pytest.raises(ValidationError) as got:
            _simplify._shifted_times(t, len(t), "times")
        assert str(got.value) == str(exc)
    else:
        got = _simplify._shifted_times(t, len(t), "times")
        assert got.tobytes() == (want - want[0]).tobytes()


def test_extreme_scales_are_exact():
    P = np.array([[0, 0], [1, 2], [2, 1], [3, 3], [4, 0]], dtype=float)
    for s in (2.0**-300, 2.0**300):
        assert simplify(P * s, 0.7 * s).tolist() == [0, 1, 2, 3, 4]
        assert simplify(P * s, 1 * s).tolist() == [0, 3, 4]
        for mode in ("segment", "paper"):
            assert simplify(P * s, 1 * s, distance=mode).tolist() == [0, 3, 4]


# ----------------------------------------------------------------- parallel


@pytest.mark.parametrize("mode", ["line", "segment", "sed"])
@pytest.mark.parametrize("d", [2, 3, 5, 13])
def test_parallel_equals_serial_on_a_long_random_walk(d, mode):
    rng = np.random.default_rng(d)
    P = np.cumsum(rng.normal(size=(150_000, d)), axis=0)
    t = np.cumsum(rng.uniform(0.5, 1.5, size=len(P))) if mode == "sed" else None
    eps = 3.5 * np.sqrt(d)  # a step's length grows like sqrt(d)
    serial = simplify(P, eps, distance=mode, times=t, n_jobs=1)
    assert 100 < len(serial) < len(P) // 10
    for n_jobs in (2, 3):
        got = simplify(P, eps, distance=mode, times=t, n_jobs=n_jobs)
        assert got.tolist() == serial.tolist()


@SETTINGS
@given(
    integer_paths(min_n=3),
    st.sampled_from(EPSILONS),
    st.integers(2, 4),
    st.sampled_from(["line", "segment", "sed"]),
)
def test_parallel_chunked_scans_keep_the_first_maximum(
    monkeypatch_module, P, eps, n_jobs, mode
):
    # tiny thresholds so that even short integer paths, full of ties, go
    # through the chunked scans and the thread pool
    t = np.arange(len(P), dtype=float) if mode == "sed" else None
    got = simplify(P, eps, distance=mode, times=t, n_jobs=n_jobs)
    assert got.tolist() == dp_reference(P, eps, mode, t).tolist()


@pytest.fixture(scope="module")
def monkeypatch_module():
    mp = pytest.MonkeyPatch()
    mp.setattr(_simplify, "CHUNK_MIN", 2)
    mp.setattr(_simplify, "SPLIT_MIN", 2)
    yield mp
    mp.undo()
