"""Tests of ndlfd.dp._exact: the leave-one-out keys and their exact box bounds.

The keys must be the scaled squared distance (against plain numpy), the
scan must return the first index of their largest value (against brute
force, ties included), the plain-key filter must never drop a point that
could win (its slack bounds the two forms' difference), and the box bound
must hold bitwise for every point of the box.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.dp import _exact as E

SETTINGS = settings(max_examples=60, deadline=None)


def _setup(P, a, b):
    """The workspaces of a segment ``(a, b)``, filled as scan_loo fills them."""
    d = P.shape[1]
    buf, bits, W, B, V = E.loo_workspace(d)
    V[0], V[2] = P[a], P[b]
    U = 0.0
    for k in range(d):  # the scans' order
        V[1, k] = P[b, k] - P[a, k]
        U += V[1, k] * V[1, k]
    E.loo_scales(V[1], V[3])
    return buf, bits, W, B, V, U


def _box_bound(V, U, segment, box_lo, box_hi):
    """loo_key_bound of one box, with the workspace laid out as it expects."""
    d = V.shape[1]
    ws = np.full(7 * d, np.nan)  # P_a, u, -, P_b, C (at 4d), scratch
    ws[:d], ws[d : 2 * d], ws[3 * d : 4 * d], ws[4 * d : 5 * d] = V[0], V[1], V[2], V[3]
    box = (np.array([box_lo], float), np.array([box_hi], float))
    return E.loo_key_bound(*box, 0, ws, d, 4 * d, U, segment)


def _keys(P, a, b, segment):
    """loo_key of every point, one call each."""
    _, _, W, _, V, U = _setup(P, a, b)
    cols = tuple(np.ascontiguousarray(P.T))
    return np.array([E.loo_key(cols, i, segment, U, V, W) for i in range(len(P))])


@st.composite
def segments(draw, max_n=300):
    """Float points (walks, near-collinear lines, integer plateaus) and (a, b).

    A few dimensions only: each is compiled once per layout.
    """
    n = draw(st.integers(3, max_n))
    d = draw(st.sampled_from([1, 2, 3, 5, 9]))
    rng = np.random.default_rng(draw(st.integers(0, 2**31 - 1)))
    shape = draw(st.sampled_from(["walk", "line", "plateau"]))
    if shape == "walk":
        P = np.cumsum(rng.normal(size=(n, d)), axis=0)
    elif shape == "line":  # nearly collinear: keys tiny next to U² |v|²
        P = np.outer(np.arange(n), rng.normal(size=d)) + 1e-9 * rng.normal(size=(n, d))
    else:  # plateaus: many exact ties
        P = np.repeat(rng.integers(-3, 4, size=(n // 7 + 1, d)), 7, axis=0)[:n] * 1.0
    P = P * draw(st.sampled_from([1.0, 0.37, 1e-3, 3e4])) + draw(st.floats(-1e3, 1e3))
    a = draw(st.integers(0, n - 3))
    b = draw(st.integers(a + 2, n - 1))
    return np.ascontiguousarray(P), a, b


def test_loo_key_known_answers():
    # u along x (length 2): the point (1, 1, 1) is sqrt(2) from the line,
    # key U² · 2 = 32; past the ends, the squared distance to the end · U²
    P = np.array([[0.0, 0, 0], [1, 1, 1], [-1, 1, 0], [3, 0, 1], [2, 0, 0]])
    assert _keys(P, 0, 4, False)[1:4].tolist() == [32.0, 16.0, 16.0]
    assert _keys(P, 0, 4, True)[1:4].tolist() == [32.0, 32.0, 32.0]
    # 1-D: every point lies on the line
    Q = np.array([[0.0], [5.0], [-3.0], [1.0]])
    assert _keys(Q, 0, 3, False).tolist() == [0.0] * 4


def test_lopsided_known_answers():
    assert E.lopsided(0, 100, 1)  # a child of 1 point out of 100
    assert E.lopsided(0, 100, 99)
    assert not E.lopsided(0, 100, 7)  # 7 * 16 >= 100
    assert not E.lopsided(0, 100, 50)


@SETTINGS
@given(segments(), st.booleans())
def test_loo_key_is_the_scaled_squared_distance(case, segment):
    P, a, b = case
    v = P - P[a]
    u = P[b] - P[a]
    U = u @ u
    vu = v @ u
    w = np.clip(vu, 0.0, U) if segment else vu
    ref = ((U * v - np.outer(w, u)) ** 2).sum(axis=1)  # U² · distance²
    scale = U * U * (v * v).sum(axis=1) + 1e-300
    got = _keys(P, a, b, segment)
    assert np.all(np.abs(got - ref) <= 1e-12 * P.shape[1] * scale)


@SETTINGS
@given(segments(), st.booleans(), st.booleans())
def test_plain_bounds_are_above_every_loo_key(case, segment, rowwise):
    """The filter's bound: plain key + slack never falls below the key."""
    P, a, b = case
    n, d = P.shape
    buf, _, _, B, V, U = _setup(P, a, b)
    cols = tuple(np.ascontiguousarray(P.T))
    slack = (d + 4) * E.LOO_SLACK * 2.0**-53 * U * U
    keys = _keys(P, a, b, segment)
    for i0 in range(0, n, E.LOO_BLOCK):
        m = min(E.LOO_BLOCK, n - i0)
        E._plain_bounds(cols, i0, m, U, slack, False, rowwise, segment, B, buf, V)
        assert np.all(buf[:m] >= keys[i0 : i0 + m])


@SETTINGS
@given(segments(), st.booleans(), st.booleans(), st.data())
def test_scan_loo_finds_the_first_largest_key(case, segment, layout, data):
    P, a, b = case
    lo = data.draw(st.integers(a + 1, b - 1))
    hi = data.draw(st.integers(lo + 1, b))
    buf, bits, W, B, V, U = _setup(P, a, b)
    if U == 0.0:  # coincident ends: see the next test
        return
    Pt = np.ascontiguousarray(P.T)
    cols = tuple(Pt) if layout else Pt
    work = (buf, bits, W, B, V)
    far, q, S = E.scan_loo(cols, segment, a, b, 0.0, lo, hi, work)
    keys = _keys(P, a, b, segment)[lo:hi]
    assert far == lo + int(np.argmax(keys))  # argmax: the first on ties
    assert q == keys.max()
    assert S == U * U


def test_scan_loo_takes_coincident_ends_as_a_point():
    P = np.array([[0.0, 0.0], [3.0, 4.0], [-3.0, 4.0], [1.0, 1.0], [0.0, 0.0]])
    cols = tuple(np.ascontiguousarray(P.T))
    far, q, S = E.scan_loo_range(cols, False, 0, 4, 1e-20, 1, 4)
    assert (far, q, S) == (1, 25.0, 1.0)  # the first of two points 5 away


@SETTINGS
@given(segments(), st.booleans(), st.data())
def test_loo_key_bound_holds_bitwise(case, segment, data):
    """No key of a point in the box exceeds the bound; a point box is tight."""
    P, a, b = case
    n = P.shape[0]
    _, _, _, _, V, U = _setup(P, a, b)
    if U == 0.0:
        return
    lo = data.draw(st.integers(0, n - 1))
    hi = data.draw(st.integers(lo + 1, n))
    bound = _box_bound(V, U, segment, P[lo:hi].min(axis=0), P[lo:hi].max(axis=0))
    keys = _keys(P, a, b, segment)
    assert keys[lo:hi].max() <= bound
    assert _box_bound(V, U, segment, P[lo], P[lo]) == keys[lo]


@pytest.mark.parametrize("segment", [False, True])
def test_a_flat_box_is_bounded_by_the_tie(segment):
    # a horizontal chord over a zigzag of constant height: every corner
    # ties, and the box of many corners is bounded by the tie exactly
    k = np.arange(1000.0)
    P = np.column_stack([k, k % 2, (k % 2) * 0.5, np.zeros(1000)])
    _, _, _, _, V, U = _setup(P, 0, 998)
    keys = _keys(P, 0, 998, segment)
    box = P[100:400]
    bound = _box_bound(V, U, segment, box.min(axis=0), box.max(axis=0))
    assert bound == keys[101] == keys[100:400].max()
