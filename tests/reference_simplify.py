"""Slow, obviously-correct Douglas–Peucker references for tests/dp/test_dp_simplify.py.

Written for clarity, not speed: recursion, plain numpy distances (projection,
``np.linalg.det`` for the paper formula). Near-ties are resolved with a small
tolerance ``tol`` (1e-9 of the data's largest coordinate) so rounding in these
plain formulas does not matter on the integer-valued test data, whose distinct
distances differ by far more; float data are compared only where the distances
keep a stated margin from each other and from epsilon.
"""

from __future__ import annotations

import numpy as np

EPS = np.finfo(np.float64).eps


def _w2(P, weights):
    """Squared column weights (ones when there are none)."""
    return np.ones(P.shape[1]) if weights is None else np.asarray(weights) ** 2


def _inner(x, y, w2):
    """Weighted inner product along the last axis: sum_k w_k² x_k y_k.

    The weighted distance is measured in this metric, never by scaling the
    columns of the data first (which is how the fast code does it).
    """
    return np.sum(x * y * w2, axis=-1)


def _norm(x, w2):
    return np.sqrt(_inner(x, x, w2))


def coincident(P, a, b, weights=None):
    """Whether the endpoints count as coincident (the documented tolerance).

    With weights the scale is the largest weighted coordinate,
    ``max_k w_k max_i |P_ik|``.
    """
    w = np.ones(P.shape[1]) if weights is None else np.asarray(weights, float)
    scale = (np.abs(P).max(axis=0) * w).max() if P.size else 0.0
    return _norm(P[b] - P[a], _w2(P, weights)) <= 8 * EPS * scale


def line_distances(P, a, b, times=None, weights=None):
    w2 = _w2(P, weights)
    v = P[a + 1 : b] - P[a]
    u = P[b] - P[a]
    if coincident(P, a, b, weights):
        return _norm(v, w2)
    t = _inner(v, u, w2) / _inner(u, u, w2)
    r = v - t[:, None] * u
    return _norm(r, w2)


def segment_distances(P, a, b, times=None, weights=None):
    w2 = _w2(P, weights)
    v = P[a + 1 : b] - P[a]
    u = P[b] - P[a]
    if coincident(P, a, b, weights):
        return _norm(v, w2)
    t = np.clip(_inner(v, u, w2) / _inner(u, u, w2), 0.0, 1.0)
    return _norm(v - t[:, None] * u, w2)


def sed_distances(P, a, b, times, weights=None):
    s = (times[a + 1 : b] - times[a]) / (times[b] - times[a])
    chord = P[a] + s[:, None] * (P[b] - P[a])
    return _norm(P[a + 1 : b] - chord, _w2(P, weights))


def paper_matrix(p1, pi, pn):
    """The paper's (d+1) x (d+1) matrix A_d (eq. 5), for d >= 2."""
    d = p1.shape[0]
    A = np.zeros((d + 1, d + 1))
    A[0] = np.r_[1.0, p1]
    A[1] = np.r_[1.0, pi]
    A[2] = np.r_[1.0, pn]
    for k in range(1, d - 1):  # completion rows k = 1..d-2
        A[2 + k, k:] = 1.0
    return A


def paper_distances(P, a, b, times=None, weights=None):
    """The paper's formula; with weights, on the weighted coordinates w_k P_ik.

    The formula is defined on coordinates, not by a metric, so weighting it
    means weighting the coordinates of the three points in A_d.
    """
    d = P.shape[1]
    if d == 1:
        return line_distances(P, a, b, weights=weights)
    if coincident(P, a, b, weights):
        return _norm(P[a + 1 : b] - P[a], _w2(P, weights))
    w = np.ones(d) if weights is None else np.asarray(weights, float)
    base = _norm(P[b] - P[a], _w2(P, weights))
    return np.array(
        [
            abs(np.linalg.det(paper_matrix(w * P[a], w * P[i], w * P[b]))) / base
            for i in range(a + 1, b)
        ]
    )


DISTANCE_FUNCTIONS = {
    "line": line_distances,
    "segment": segment_distances,
    "sed": sed_distances,
    "paper": paper_distances,
}


def _tol(P, weights=None):
    """Near-tie tolerance, relative to the data's scale (so scale-invariant)."""
    w = 1.0 if weights is None else max(1.0, float(np.max(weights)))
    return 1e-9 * w * (np.abs(P).max() if P.size else 0.0)


def farthest(P, a, b, distance, times=None, weights=None):
    """(index, distance) of the first point reaching the max (within tol)."""
    dist = DISTANCE_FUNCTIONS[distance](P, a, b, times, weights=weights)
    m = dist.max()
    j = int(np.flatnonzero(dist >= m - _tol(P, weights))[0])
    return a + 1 + j, float(m)


def dp_reference(P, epsilon, distance="line", times=None, splits=None, weights=None):
    """Recursive textbook Douglas–Peucker; returns sorted kept indices.

    ``splits``, if a list, receives ``(depth, a, b, far)`` for every split.
    ``weights`` measures every distance in the weighted metric (see _inner).
    """
    P = np.asarray(P, dtype=float)
    n = P.shape[0]
    if n == 1:
        return np.array([0])
    keep = {0, n - 1}

    def rec(a, b, depth):
        if b - a < 2:
            return
        i, m = farthest(P, a, b, distance, times, weights)
        if m > epsilon + _tol(P, weights):
            keep.add(i)
            if splits is not None:
                splits.append((depth, a, b, i))
            rec(a, i, depth + 1)
            rec(i, b, depth + 1)

    rec(0, n - 1, 0)
    return np.array(sorted(keep))


def budget_reference(P, n_points, distance="line", times=None):
    """Greedy global-farthest splitting, by scanning every open segment."""
    P = np.asarray(P, dtype=float)
    n = P.shape[0]
    if n == 1:
        return np.array([0])
    keep = {0, n - 1}
    segments = [(0, n - 1)] if n > 2 else []
    target = min(max(n_points, 2), n)
    while len(keep) < target:
        cands = [(a, b, *farthest(P, a, b, distance, times)) for a, b in segments]
        top = max(c[3] for c in cands)
        best = min((c for c in cands if c[3] >= top - _tol(P)), key=lambda c: c[2])
        a, b, i, _ = best
        keep.add(i)
        segments.remove((a, b))
        segments += [(lo, hi) for lo, hi in ((a, i), (i, b)) if hi - lo >= 2]
    return np.array(sorted(keep))


def greedy_order(P, distance="line", times=None):
    """Interior indices in the order the budget rule adds them."""
    P = np.asarray(P, dtype=float)
    n = P.shape[0]
    order = []
    prev = set(budget_reference(P, 2, distance, times).tolist())
    for k in range(3, n + 1):
        cur = set(budget_reference(P, k, distance, times).tolist())
        order.append((cur - prev).pop())
        prev = cur
    return order


def zigzag(n):
    """A worst case: every split peels one point off the end of a segment.

    ``x = i`` and ``y = ±(n - i)`` alternating, so the point next to the
    segment's first endpoint is always farthest from the chord.
    """
    i = np.arange(n, dtype=float)
    y = np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * (n - i)
    return np.column_stack([i, y])
