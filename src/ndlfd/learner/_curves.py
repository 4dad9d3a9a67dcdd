"""Route curves: demonstrations as comparable curves, and the distances between them.

What :mod:`ndlfd.learner._routes` judges routes on:

* :func:`route_curves`: each template as a curve of :data:`ROUTE_POINTS`
  points on the route columns (normalized units), averaged over short windows
  of time, then spaced half by time and half by the distance travelled (so a
  rest takes few points and a brief detour keeps some);
* :func:`open_end_frechet`: a growing prefix against them (any beginning of
  each curve), for replanning (:mod:`ndlfd.learner._prefix_route`);
* :func:`frechet_matrix`: their discrete Fréchet distances (the least, over
  monotone pairings of their points, of the largest distance of a pair:
  pace-free, and where two curves differ most), compiled and on threads;
"""

from __future__ import annotations

import math
import os

import numpy as np
from numba import njit

from .._parallel import thread_pool

__all__ = [
    "BAND",
    "ROUTE_POINTS",
    "frechet_matrix",
    "open_end_frechet",
    "route_curves",
]

#: Points of a template's route curve (:func:`route_curves`).
ROUTE_POINTS = 64

#: How far (a share of its points) a Fréchet pairing may run one curve ahead
#: of the other (:func:`frechet_matrix`).
BAND = 0.25

#: Time windows a template is averaged over before its curve is spaced.
_WINDOWS = 128


def _window_means(U: np.ndarray, tau: np.ndarray, n: int) -> np.ndarray:
    """The mean of the samples in each of ``n`` equal windows of time (filled)."""
    if U.shape[0] <= 2 * n:
        return U
    w = np.clip((tau * n).astype(np.int64), 0, n - 1)
    counts = np.bincount(w, minlength=n).astype(np.float64)
    sums = np.stack([np.bincount(w, weights=c, minlength=n) for c in U.T], axis=1)
    has = counts > 0
    centres = (np.arange(n) + 0.5) / n
    means = sums[has] / counts[has, None]
    return np.stack([np.interp(centres, centres[has], c) for c in means.T], axis=1)


def route_curves(values, taus, cols, n_points: int = ROUTE_POINTS) -> np.ndarray:
    """Each template as a curve of ``n_points`` points on the route columns.

    The samples are averaged over :data:`_WINDOWS` windows of time (when
    there are more than twice as many), then the curve is resampled evenly
    in ``(time + distance travelled) / 2``: the distance counts only the
    steps above the tenth percentile of a step (what noise at rest adds).

    Parameters
    ----------
    values : list of ndarray of shape (n_j, n_columns)
        The templates' normalized values.
    taus : list of ndarray of shape (n_j,)
        Their normalized times.
    cols : ndarray of int
        :func:`route_columns`.
    n_points : int, default=:data:`ROUTE_POINTS`

    Returns
    -------
    curves : ndarray of shape (n_templates, n_points, len(cols))

    Examples
    --------
    A line at constant speed is spaced evenly:

    >>> tau = np.linspace(0.0, 1.0, 11)
    >>> route_curves([tau[:, None]], [tau], np.array([0]), 3)[0, :, 0]
    array([0. , 0.5, 1. ])
    """
    out = np.empty((len(values), n_points, len(cols)))
    grid = np.linspace(0.0, 1.0, n_points)
    for k, (U, tau) in enumerate(zip(values, taus, strict=True)):
        M = _window_means(np.asarray(U, dtype=np.float64)[:, cols], tau, _WINDOWS)
        if M.shape[0] == 1:
            out[k] = M[0]
            continue
        big = float(np.abs(M).max())  # scaled first: steps of 1e300 square to inf
        step = np.sqrt(
            np.sum((np.diff(M / big if big > 0 else M, axis=0)) ** 2, axis=1)
        )
        step = np.maximum(step - np.quantile(step, 0.1), 0.0)
        length = np.r_[0.0, np.cumsum(step)]
        clock = np.linspace(0.0, 1.0, M.shape[0])
        u = clock if length[-1] <= 0 else 0.5 * (clock + length / length[-1])
        out[k] = np.stack([np.interp(grid, u, c) for c in M.T], axis=1)
    return out


@njit(cache=True, nogil=True)
def _frechet_row(A, i, B, lo, hi, prev, cur):  # pragma: no cover - compiled
    """Row ``i`` of the discrete Fréchet table (squared), columns ``lo..hi-1``.

    ``prev`` holds row ``i - 1``, ``cur`` receives row ``i`` (cells outside
    ``lo..hi-1`` must be ``inf``); returns the row's least value.
    """
    low = np.inf
    for j in range(lo, hi):
        s = 0.0
        for c in range(A.shape[1]):
            diff = A[i, c] - B[j, c]
            s += diff * diff
        if i == 0 and j == 0:
            best = s
        elif i == 0:
            best = cur[j - 1]
        elif j == 0:
            best = prev[0]
        else:
            best = min(prev[j], prev[j - 1], cur[j - 1])
        v = max(best, s)
        cur[j] = v
        low = min(low, v)
    return low


@njit(cache=True, nogil=True)
def _open_end_rows(P, curves, out):  # pragma: no cover - compiled
    """Open-end Fréchet of ``P[:i+1]`` to each curve, for every ``i`` (squared)."""
    k = curves.shape[1]
    prev = np.empty(k)
    cur = np.empty(k)
    for t in range(curves.shape[0]):
        for i in range(P.shape[0]):
            out[t, i] = _frechet_row(P, i, curves[t], 0, k, prev, cur)
            prev, cur = cur, prev
    return out


def open_end_frechet(P: np.ndarray, curves: np.ndarray) -> np.ndarray:
    """Open-end discrete Fréchet distances of a growing prefix to curves.

    Parameters
    ----------
    P : ndarray of shape (m, n_dims)
        The prefix's points.
    curves : ndarray of shape (n_curves, n_points, n_dims)

    Returns
    -------
    distances : ndarray of shape (n_curves, m)
        ``distances[t, i]``: the least, over monotone pairings of ``P[:i+1]``
        with any beginning of curve ``t``, of the largest distance of a pair.
        It never falls as ``i`` grows.

    Examples
    --------
    A prefix along the start of a line is 0 from it, however far the line
    goes on; a prefix that turns away is as far as it turns:

    >>> line = np.array([[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]])
    >>> open_end_frechet(np.array([[0.0, 0.0], [1.0, 0.0]]), line)
    array([[0., 0.]])
    >>> open_end_frechet(np.array([[0.0, 0.0], [1.0, 0.5]]), line)
    array([[0. , 0.5]])
    """
    P = np.ascontiguousarray(P, dtype=np.float64)
    curves = np.ascontiguousarray(curves, dtype=np.float64)
    out = np.empty((curves.shape[0], P.shape[0]))
    return np.sqrt(_open_end_rows(P, curves, out))


@njit(cache=True, nogil=True)
def _frechet_rows(curves, others, lo, hi, lower, band, out):  # pragma: no cover
    """Fréchet distances of curves ``lo..hi-1`` to every other (or to ``others``).

    Into ``out`` (``(hi - lo, m)``, zeros). Each distance is the table of
    :func:`_frechet_row` (squared) filled row by row within ``band`` points
    of the diagonal, written out here in one flat loop: with the row and the
    distance as functions of their own, and the output made here, it
    compiled in twice the time (0.95 s of CPU instead of 0.44 on a first
    run).
    """
    m, k = others.shape[0], others.shape[1]
    n, d = curves.shape[1], curves.shape[2]
    prev = np.empty(k)
    cur = np.empty(k)
    for i in range(lo, hi):
        for o in range(i + 1 if lower else 0, m):
            for r in range(n):
                for j in range(k):
                    cur[j] = np.inf
                for j in range(max(0, r - band), min(k, r + band + 1)):
                    s = 0.0
                    for c in range(d):
                        diff = curves[i, r, c] - others[o, j, c]
                        s += diff * diff
                    if r == 0 and j == 0:
                        best = s
                    elif r == 0:
                        best = cur[j - 1]
                    elif j == 0:
                        best = prev[0]
                    else:
                        best = min(prev[j], prev[j - 1], cur[j - 1])
                    cur[j] = max(best, s)
                prev, cur = cur, prev
            out[i - lo, o] = math.sqrt(prev[k - 1])
    return out


def frechet_matrix(
    curves: np.ndarray,
    others: np.ndarray | None = None,
    n_jobs=None,
    band: float = BAND,
) -> np.ndarray:
    """Discrete Fréchet distances between curves of one length.

    The pairings run neither curve more than ``band`` of its points ahead of
    the other (the curves are spaced alike, :func:`route_curves`);
    each distance is computed alone, so the result does not depend on
    ``n_jobs``.

    Parameters
    ----------
    curves : ndarray of shape (n, n_points, n_dims)
    others : ndarray of shape (m, n_points, n_dims), optional
        Distances of each curve to these instead of to each other.
    n_jobs : int, optional
        Threads (``None``: one per CPU).
    band : float, default=:data:`BAND`
        A share of the points (1: every monotone pairing).

    Returns
    -------
    distances : ndarray of shape (n, n) (symmetric, zero diagonal) or (n, m)

    Examples
    --------
    A curve and the same curve run at another pace are 0 apart; a detour
    counts in full:

    >>> a = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> slow = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> detour = np.array([[0.0, 0.0], [1.0, 0.3], [1.0, 0.0], [2.0, 0.0]])
    >>> frechet_matrix(a[None], np.stack([slow, detour]))
    array([[0. , 0.3]])
    """
    curves = np.ascontiguousarray(curves, dtype=np.float64)
    lower = others is None
    others = curves if lower else np.ascontiguousarray(others, dtype=np.float64)
    band = max(1, int(np.ceil(band * curves.shape[1])))
    n = curves.shape[0]
    workers = max(1, min(n_jobs or os.cpu_count() or 1, n // 16))
    cuts = np.linspace(0, n, workers + 1).astype(np.int64)
    if lower:  # the upper triangle: rows of equal work, not equal count
        cuts = np.round(n - np.sqrt(np.linspace(1.0, 0.0, workers + 1)) * n)
        cuts = cuts.astype(np.int64)

    def rows(k):
        out = np.zeros((cuts[k + 1] - cuts[k], others.shape[0]))
        return _frechet_rows(curves, others, cuts[k], cuts[k + 1], lower, band, out)

    if workers == 1:
        D = rows(0)
    else:
        D = np.concatenate(list(thread_pool(workers).map(rows, range(workers))))
    return D + D.T if lower else D
