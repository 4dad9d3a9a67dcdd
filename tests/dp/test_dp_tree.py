"""Tests of ndlfd.dp._tree: the box tree's bounds and the pruned scans.

The pruned search must keep exactly the points the plain scan keeps (same
keys, first index on ties), and bound every point's distance from above.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.dp import _generic as G
from ndlfd.dp import _kernels as K
from ndlfd.dp import _simplify
from ndlfd.dp import _tree as T
from ndlfd.dp._simplify import simplify
from reference_simplify import DISTANCE_FUNCTIONS, dp_reference, zigzag

SETTINGS = settings(max_examples=40, deadline=None)
KINDS = {"line": T.TREE_LINE, "segment": T.TREE_SEGMENT, "sed": T.TREE_SED}


@st.composite
def paths(draw, min_n=2, max_n=700, max_d=6):
    """Integer walks, zigzags and plateaus, long enough for several leaves."""
    n = draw(st.integers(min_n, max_n))
    d = draw(st.integers(1, max_d))
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    shape = draw(st.sampled_from(["walk", "zigzag", "steps"]))
    if shape == "walk":
        P = np.cumsum(rng.integers(-2, 3, size=(n, d)), axis=0).astype(float)
    elif shape == "zigzag":
        P = np.zeros((n, d))
        z = zigzag(n)
        P[:, : min(d, 2)] = z[:, : min(d, 2)]
    else:  # plateaus: many exact ties
        P = np.repeat(rng.integers(-3, 4, size=(n // 7 + 1, d)), 7, axis=0)[:n]
        P = P.astype(float)
    times = np.cumsum(rng.integers(1, 4, size=n)).astype(float)
    return P, times


def always_tree(mp):
    """Every segment longer than 2 points goes through a tree built at once."""
    mp.setattr(_simplify, "TREE_MIN", 2)
    mp.setattr(_simplify, "TREE_BUDGET", 0)


@SETTINGS
@given(paths(), st.sampled_from(["line", "segment", "sed"]), st.data())
def test_node_bound_is_above_every_points_distance(case, mode, data):
    P, times = case
    n, d = P.shape
    a = data.draw(st.integers(0, n - 2))
    b = data.draw(st.integers(a + 1, n - 1))
    times = times if mode == "sed" else None
    job = _simplify._prepare(P, 0.0, mode, None, times, None)
    tree = T.make_tree(job.P, job.t, KINDS[mode], job.m, 1)
    T.fill_tree(job.P, tree[2], tree[3], tree[4])
    ws, stack, _ = T.tree_workspace(tree, d, n)
    T.tree_begin(tree, a, b, job.utol2, ws, stack, -1.0)
    _, _, bmin, bmax, offs, *_ = tree
    dist = DISTANCE_FUNCTIONS[mode](job.P, a, b, job.t)  # points a+1..b-1
    for lv in range(len(offs) - 1):
        span = T.LEAF << lv
        for j in range(offs[lv + 1] - offs[lv]):
            s0, e0 = j * span, min(n, (j + 1) * span)
            bound = T.node_bound(bmin, bmax, offs[lv] + j, ws, d, job.t, s0, e0)
            lo, hi = max(s0, a + 1), min(e0, b)
            if lo < hi:
                assert dist[lo - a - 1 : hi - a - 1].max() ** 2 <= bound


@SETTINGS
@given(paths(), st.sampled_from(["line", "segment", "sed"]), st.integers(0, 6))
def test_tree_scan_keeps_what_the_reference_keeps(case, mode, e):
    P, times = case
    eps = [0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0][e]
    kw = {"times": times} if mode == "sed" else {}
    with pytest.MonkeyPatch.context() as mp:
        always_tree(mp)
        got = simplify(P, eps, distance=mode, n_jobs=1, **kw)
    want = dp_reference(P, eps, mode, times=times if mode == "sed" else None)
    assert got.tolist() == want.tolist()


def test_tree_scan_equals_plain_scan_on_float_walks(monkeypatch):
    rng = np.random.default_rng(5)
    for d in (2, 3, 6, 13):
        P = np.cumsum(rng.normal(size=(20_000, d)), axis=0)
        t = np.cumsum(rng.uniform(0.5, 1.5, size=len(P)))
        for mode in ("line", "segment", "sed"):
            kw = {"times": t} if mode == "sed" else {}
            plain = simplify(P, 2.0, distance=mode, n_jobs=1, **kw)
            with monkeypatch.context() as mp:
                always_tree(mp)
                tree = simplify(P, 2.0, distance=mode, n_jobs=1, **kw)
            assert tree.tolist() == plain.tolist(), (d, mode)


@pytest.mark.parametrize("mode", ["line", "segment", "sed"])
def test_zigzag_builds_the_tree_and_scans_little(mode):
    # every corner kept: a plain scan costs n²/2 distance evaluations
    n = 60_000
    times = np.arange(n, dtype=float) if mode == "sed" else None
    job = _simplify._prepare(zigzag(n), 0.5, mode, None, times, None)
    keep = np.zeros(n, np.uint8)
    tree = _simplify._tree(job)
    args = (job.P, job.t, job.mode, job.eps2, job.utol2, keep, 0, n - 1, tree)
    work = G.dp_generic(*args)
    assert keep.all()
    assert work < n * n / 100  # a plain scan: n²/2


def test_the_tree_is_given_up_where_ties_keep_every_node():
    # a zigzag of constant height: every corner at the same distance, so no
    # bound can beat the first one and every point is scanned anyway
    tree = T.make_tree(np.zeros((5000, 2)), np.zeros(0), T.TREE_LINE, 1.0, 100)
    flags = np.array([1.0, 0.0, 0.0, 0.0])
    T.tree_done(tree, flags, 999, 1000)  # all scanned, but too few to judge
    assert flags[0] == 1.0
    flags = np.array([1.0, 0.0, 0.0, 0.0])
    for _ in range(3):
        T.tree_done(tree, flags, 50, 1000)  # pruned well: kept
    assert flags[0] == 1.0
    T.tree_done(tree, flags, 1000, 1000)  # 1150 of 4000 scanned
    assert flags[0] == 1.0
    T.tree_done(tree, flags, 2000, 2000)  # 3150 of 6000: given up
    assert flags[0] == -1.0


def test_a_flat_zigzag_keeps_every_corner_with_the_tree_given_up():
    n = 30_000
    P = np.column_stack([np.arange(n, dtype=float), (np.arange(n) % 2) * 1.0])
    assert simplify(P, 0.5, n_jobs=1).tolist() == list(range(n))
    assert simplify(P, 0.5, distance="segment").tolist() == list(range(n))


def _line_keys(P, a, b):
    """scan_line2's / scan_line3's keys of points a+1..b-1, in their order."""
    pa, u = P[a], P[b] - P[a]
    out = []
    for i in range(a + 1, b):
        dv = P[i] - pa
        if P.shape[1] == 2:
            c = dv[0] * u[1] - dv[1] * u[0]
            out.append(c * c)
        else:
            cx = dv[1] * u[2] - dv[2] * u[1]
            cy = dv[2] * u[0] - dv[0] * u[2]
            cz = dv[0] * u[1] - dv[1] * u[0]
            out.append(cx * cx + cy * cy + cz * cz)
    return np.array(out)


@SETTINGS
@given(paths(max_d=3, min_n=3), st.data(), st.floats(-1e3, 1e3), st.integers(0, 3))
def test_exact_key_bound_is_at_least_every_computed_key(case, data, shift, scale):
    """Bitwise: no computed 2-D / 3-D line key of a node's points exceeds its bound."""
    P, _ = case
    if P.shape[1] == 1:
        P = np.column_stack([P[:, 0], P[:, 0] * 0.5])
    P = P * [0.1, 1.0, 3.7, 1e-3][scale] + shift  # floats with rounding
    n, d = P.shape
    a = data.draw(st.integers(0, n - 3))
    b = data.draw(st.integers(a + 2, n - 1))
    tree = T.make_tree(P, np.zeros(0), T.TREE_LINE, float(np.abs(P).max()), 1)
    T.fill_tree(P, tree[2], tree[3], tree[4])
    ws, stack, _ = T.tree_workspace(tree, d, n)
    T.tree_begin(tree, a, b, 0.0, ws, stack, 0.0)
    keys = _line_keys(P, a, b)
    _, _, bmin, bmax, offs, *_ = tree
    for lv in range(len(offs) - 1):
        span = T.LEAF << lv
        for j in range(offs[lv + 1] - offs[lv]):
            lo, hi = max(j * span, a + 1), min(n, (j + 1) * span, b)
            if lo < hi:
                bound = T.exact_key_bound(bmin, bmax, offs[lv] + j, ws, d)
                assert keys[lo - a - 1 : hi - a - 1].max() <= bound


@pytest.mark.parametrize("d", [2, 3])
def test_a_flat_zigzag_is_pruned_exactly_in_line_mode(d):
    """Constant height: every tie is pruned by the exact bounds, same points."""
    n = 60_000
    k = np.arange(n)
    cols = [k * 1.0, (k % 2) * 1.0, (k % 2) * 0.5][:d]
    P = np.column_stack(cols)
    job = _simplify._prepare(P, 0.5, "line", None, None, None)
    keep = np.zeros(n, np.uint8)
    tree = _simplify._tree(job)
    Pt = np.ascontiguousarray(job.P.T)
    z = Pt[2] if d == 3 else np.zeros(0)
    args = (d, Pt[0], Pt[1], z, np.zeros((d, 0)), job.t, job.mode)
    work = K.dp_line(*args, job.eps2, job.utol2, keep, 0, n - 1, tree)
    assert keep.all()
    assert work < n * n / 100  # a plain scan: n²/2
    # and against the plain scan on a shorter one, shifted off the integers
    m = 600  # the recursive reference: depth m
    Q = P[:m] * 0.37 + 1.3
    with pytest.MonkeyPatch.context() as mp:
        always_tree(mp)
        tree_kept = simplify(Q, 0.1, n_jobs=1)
    assert tree_kept.tolist() == dp_reference(Q, 0.1).tolist()


def _kernel_work(P, epsilon, mode, times=None):
    """``(work, keep)`` of the column-major kernel on the whole of ``P``."""
    n = P.shape[0]
    job = _simplify._prepare(P, epsilon, mode, None, times, None)
    keep = np.zeros(n, np.uint8)
    dp, _, args = _simplify._line_layout(job.P, job.t, job.mode)
    work = dp(*args, job.eps2, job.utol2, keep, 0, n - 1, _simplify._tree(job))
    return work, keep


def _flat_zigzag(n, d):
    """Constant height in every column but the first: every corner ties."""
    k = np.arange(n)
    return np.column_stack(
        [k * 1.0] + [(k % 2) * (0.5 + 0.25 * j) for j in range(d - 1)]
    )


@pytest.mark.parametrize(
    ("mode", "d"), [("segment", 2), ("segment", 5), ("line", 4), ("line", 9)]
)
def test_a_flat_zigzag_is_pruned_exactly_with_leave_one_out_keys(mode, d):
    """Segment mode, and line mode past 3-D: the ties are pruned, not scanned."""
    n = 40_000
    work, keep = _kernel_work(_flat_zigzag(n, d), 0.1, mode)
    assert keep.all()
    assert work < 4 * T.LEAF * n, work  # a few leaves a split; a plain scan: n²/2


@pytest.mark.parametrize(("mode", "d"), [("segment", 3), ("line", 6), ("line", 10)])
def test_leave_one_out_keys_keep_the_same_points_with_or_without_tree(
    mode, d, monkeypatch
):
    """Off the integers (rounding breaks the ties unevenly): the tree, the
    threads and the plain scan keep the same points; on integers, the
    textbook reference's."""
    n = 12_000
    P = _flat_zigzag(n, d) * 0.37 + 1.3
    P[:, 0] += np.random.default_rng(d).normal(scale=0.01, size=n)
    serial = simplify(P, 0.1, distance=mode, n_jobs=1)
    assert simplify(P, 0.1, distance=mode, n_jobs=2).tolist() == serial.tolist()
    with monkeypatch.context() as mp:
        mp.setattr(_simplify, "TREE_MIN", n)  # no tree
        assert simplify(P, 0.1, distance=mode, n_jobs=1).tolist() == serial.tolist()
    m = 4_500  # longer than EXACT_MIN, so the reference meets the new keys
    Q = _flat_zigzag(m, d)
    Q[::7, 1] += 0.25  # some corners higher: not all ties
    with monkeypatch.context():
        import sys

        monkeypatch.setattr(sys, "getrecursionlimit", sys.getrecursionlimit)
        old = sys.getrecursionlimit()
        sys.setrecursionlimit(max(old, 4 * m))
        try:
            ref = dp_reference(Q, 0.1, distance=mode)
        finally:
            sys.setrecursionlimit(old)
    assert simplify(Q, 0.1, distance=mode, n_jobs=1).tolist() == ref.tolist()


@pytest.mark.parametrize("d", [1, 2, 6])
def test_a_flat_zigzag_is_pruned_exactly_in_sed_mode(d):
    """The doorway takes the drift out, the exact sed bounds skip the ties."""
    n = 40_000
    P = _flat_zigzag(n, d + 1)[:, 1:] if d == 1 else _flat_zigzag(n, d)
    times = np.arange(n, dtype=float)
    work, keep = _kernel_work(P, 0.1, "sed", times)
    assert keep.all()
    assert work < 4 * T.LEAF * n, work  # a few leaves a split; a plain scan: n²/2
    # the same points as the plain scans, and on a short one the reference's
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_simplify, "TREE_MIN", n)  # no tree
        assert simplify(P, 0.1, distance="sed", times=times).tolist() == list(range(n))
    m = 600
    Q = P[:m].copy()
    Q[::5] += 0.5  # some corners higher: not all ties
    with pytest.MonkeyPatch.context() as mp:
        always_tree(mp)
        got = simplify(Q, 0.1, distance="sed", times=times[:m], n_jobs=1)
    assert got.tolist() == dp_reference(Q, 0.1, "sed", times[:m]).tolist()


@SETTINGS
@given(paths(max_d=4), st.data())
def test_detrending_keeps_every_sed_distance(case, data):
    """sed distances are the same before and after the drift is taken out."""
    P, times = case
    job = _simplify._prepare(P, 0.0, "sed", None, times, None)
    t = job.t
    a = data.draw(st.integers(0, P.shape[0] - 1))
    b = data.draw(st.integers(a, P.shape[0] - 1))
    if b - a < 2:
        return
    before = DISTANCE_FUNCTIONS["sed"](P, a, b, times)
    after = DISTANCE_FUNCTIONS["sed"](job.P, a, b, t)
    assert np.allclose(before, after, rtol=1e-12, atol=1e-9 * (1 + np.abs(P).max()))
    # integer data stay exact: the drift removed is a short dyadic number
    assert np.array_equal(np.round(job.P * 2.0**30), job.P * 2.0**30)


@pytest.mark.parametrize("d", [2, 3])
def test_a_flat_zigzag_is_pruned_exactly_in_paper_mode(d):
    """The paper's determinant: a tree of exact bounds only, the same points."""
    n = 40_000
    P = np.column_stack([_flat_zigzag(n, 2), np.zeros((n, d - 2))])
    job = _simplify._prepare(P, 0.1, "paper", None, None, None)
    keep = np.zeros(n, np.uint8)
    args = (job.P, job.t, job.mode, job.eps2, job.utol2, keep, 0, n - 1)
    work = G.dp_generic(*args, _simplify._tree(job))
    assert work < 4 * T.LEAF * n, work  # a few leaves a split; a plain scan: n²/2
    plain = np.zeros(n, np.uint8)
    G.dp_generic(*args[:5], plain, 0, n - 1, T.make_tree(job.P, job.t, None, 1, 1))
    assert keep.tolist() == plain.tolist()
    m = 600
    with pytest.MonkeyPatch.context() as mp:
        always_tree(mp)
        got = simplify(P[:m], 0.1, distance="paper", n_jobs=1)
    assert got.tolist() == dp_reference(P[:m], 0.1, "paper").tolist()


@pytest.mark.parametrize("mode", ["line", "segment", "sed", "paper"])
def test_a_zigzag_whose_corners_grow_is_pruned_too(mode):
    """The farthest corner next to the segment's far end: found first."""
    n = 40_000
    i = np.arange(n, dtype=float)
    P = np.column_stack([i, np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * (i + 1)])
    times = i if mode == "sed" else None
    job = _simplify._prepare(P, 0.5, mode, None, times, None)
    keep = np.zeros(n, np.uint8)
    args = (job.P, job.t, job.mode, job.eps2, job.utol2, keep, 0, n - 1)
    work = G.dp_generic(*args, _simplify._tree(job))
    assert keep.all()
    assert work < 4 * T.LEAF * n, work  # a plain scan: n²/2
