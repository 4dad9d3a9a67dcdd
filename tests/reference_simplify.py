"""Slow, obviously-correct Douglas–Peucker references for tests/test_simplify.py.

Written for clarity, not speed: recursion, plain numpy distances (projection,
``np.linalg.det`` for the paper formula). Near-ties are resolved with a small
tolerance ``tol`` so rounding in these plain formulas does not matter on the
integer-valued test data, whose distinct distances differ by far more.
"""

from __future__ import annotations

import numpy as np

EPS = np.finfo(np.float64).eps


def coincident(P, a, b):
    """Whether the endpoints count as coincident (the documented tolerance)."""
    scale = np.abs(P).max() if P.size else 0.0
    return np.linalg.norm(P[b] - P[a]) <= 8 * EPS * scale


def line_distances(P, a, b, times=None):
    v = P[a + 1 : b] - P[a]
    u = P[b] - P[a]
    if coincident(P, a, b):
        return np.linalg.norm(v, axis=1)
    t = v @ u / (u @ u)
    r = v - t[:, None] * u
    return np.linalg.norm(r, axis=1)


def segment_distances(P, a, b, times=None):
    v = P[a + 1 : b] - P[a]
    u = P[b] - P[a]
    if coincident(P, a, b):
        return np.linalg.norm(v, axis=1)
    t = np.clip(v @ u / (u @ u), 0.0, 1.0)
    return np.linalg.norm(v - t[:, None] * u, axis=1)


def sed_distances(P, a, b, times):
    s = (times[a + 1 : b] - times[a]) / (times[b] - times[a])
    chord = P[a] + s[:, None] * (P[b] - P[a])
    return np.linalg.norm(P[a + 1 : b] - chord, axis=1)


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


def paper_distances(P, a, b, times=None):
    d = P.shape[1]
    if d == 1:
        return line_distances(P, a, b)
    if coincident(P, a, b):
        return np.linalg.norm(P[a + 1 : b] - P[a], axis=1)
    base = np.linalg.norm(P[b] - P[a])
    return np.array(
        [
            abs(np.linalg.det(paper_matrix(P[a], P[i], P[b]))) / base
            for i in range(a + 1, b)
        ]
    )


DISTANCE_FUNCTIONS = {
    "line": line_distances,
    "segment": segment_distances,
    "sed": sed_distances,
    "paper": paper_distances,
}


def _tol(P):
    return 1e-9 * (1.0 + (np.abs(P).max() if P.size else 0.0))


def farthest(P, a, b, distance, times=None):
    """(index, distance) of the first point reaching the max (within tol)."""
    dist = DISTANCE_FUNCTIONS[distance](P, a, b, times)
    m = dist.max()
    j = int(np.flatnonzero(dist >= m - _tol(P))[0])
    return a + 1 + j, float(m)


def dp_reference(P, epsilon, distance="line", times=None, splits=None):
    """Recursive textbook Douglas–Peucker; returns sorted kept indices.

    ``splits``, if a list, receives ``(depth, a, b, far)`` for every split.
    """
    P = np.asarray(P, dtype=float)
    n = P.shape[0]
    if n == 1:
        return np.array([0])
    keep = {0, n - 1}

    def rec(a, b, depth):
        if b - a < 2:
            return
        i, m = farthest(P, a, b, distance, times)
        if m > epsilon + _tol(P):
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
