"""Distances between two paths: DTW, discrete Fréchet, time-aligned RMSE, endpoint.

All functions take two paths of shape ``(n, d)`` and ``(k, d)`` (the same ``d``)
and compare them with the Euclidean distance between points. The dynamic
programmes run in ``O(n k)`` time and ``O(k)`` memory in a compiled kernel.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ._errors import ValidationError
from ._validation import check_points, check_times

__all__ = [
    "discrete_frechet",
    "dtw_distance",
    "endpoint_error",
    "path_difference",
    "time_aligned_rmse",
]


def _pair(a, b) -> tuple[np.ndarray, np.ndarray]:
    A = check_points(a, "a")
    B = check_points(b, "b")
    if A.shape[1] != B.shape[1]:
        raise ValidationError(
            f"a and b must have the same number of columns; got {A.shape[1]} and"
            f" {B.shape[1]}"
        )
    return A, B


@njit(cache=True, nogil=True)
def _dtw_kernel(A, B):  # pragma: no cover - compiled
    n, k = A.shape[0], B.shape[0]
    prev = np.full(k + 1, np.inf)
    cur = np.full(k + 1, np.inf)
    prev[0] = 0.0
    for i in range(1, n + 1):
        cur[0] = np.inf
        for j in range(1, k + 1):
            s = 0.0
            for c in range(A.shape[1]):
                diff = A[i - 1, c] - B[j - 1, c]
                s += diff * diff
            best = prev[j - 1]
            if prev[j] < best:
                best = prev[j]
            if cur[j - 1] < best:
                best = cur[j - 1]
            cur[j] = np.sqrt(s) + best
        prev, cur = cur, prev
    return prev[k]


@njit(cache=True, nogil=True)
def _frechet_kernel(A, B):  # pragma: no cover - compiled
    n, k = A.shape[0], B.shape[0]
    prev = np.empty(k)
    cur = np.empty(k)
    for i in range(n):
        for j in range(k):
            s = 0.0
            for c in range(A.shape[1]):
                diff = A[i, c] - B[j, c]
                s += diff * diff
            d = np.sqrt(s)
            if i == 0 and j == 0:
                best = d
            elif i == 0:
                best = cur[j - 1]
            elif j == 0:
                best = prev[0]
            else:
                best = min(prev[j], prev[j - 1], cur[j - 1])
            cur[j] = max(best, d)
        prev, cur = cur, prev
    return prev[k - 1]


def dtw_distance(a, b, *, normalize: bool = False) -> float:
    """Dynamic time warping distance between two paths.

    The sum of Euclidean point distances along the cheapest monotone alignment
    (steps ``(1, 0)``, ``(0, 1)`` and ``(1, 1)``).

    Parameters
    ----------
    a : array-like of shape (n_a, n_dims)
        First path.
    b : array-like of shape (n_b, n_dims)
        Second path.
    normalize : bool, default=False
        Divide by ``n_a + n_b`` so paths of different lengths compare fairly.

    Returns
    -------
    distance : float

    Examples
    --------
    >>> dtw_distance([[0, 0], [1, 0], [2, 0]], [[0, 0], [2, 0]])
    1.0
    """
    A, B = _pair(a, b)
    d = float(_dtw_kernel(A, B))
    return d / (A.shape[0] + B.shape[0]) if normalize else d


def discrete_frechet(a, b) -> float:
    """Discrete Fréchet distance between two paths (Eiter & Mannila, 1994).

    Parameters
    ----------
    a : array-like of shape (n_a, n_dims)
        First path.
    b : array-like of shape (n_b, n_dims)
        Second path.

    Returns
    -------
    distance : float
        The smallest, over monotone couplings of the two point sequences, of the
        largest distance between coupled points.

    Examples
    --------
    >>> discrete_frechet([[0, 0], [1, 0], [2, 0]], [[0, 1], [2, 1]])
    1.4142135623730951
    """
    A, B = _pair(a, b)
    return float(_frechet_kernel(A, B))


def time_aligned_rmse(t_a, a, t_b, b) -> float:
    """Root-mean-square error of ``b`` against ``a`` at ``a``'s normalized times.

    Both time vectors are mapped to ``[0, 1]`` (first to last sample), ``b`` is
    linearly interpolated at ``a``'s normalized times, and the RMS of the
    Euclidean point errors is returned.

    Parameters
    ----------
    t_a : array-like of shape (n_a,)
        Time stamps of ``a`` (strictly increasing).
    a : array-like of shape (n_a, n_dims)
        The reference path.
    t_b : array-like of shape (n_b,)
        Time stamps of ``b`` (strictly increasing).
    b : array-like of shape (n_b, n_dims)
        The path to evaluate.

    Returns
    -------
    rmse : float

    Examples
    --------
    >>> time_aligned_rmse([0, 1, 2], [[0.0], [1.0], [2.0]], [0, 4], [[1.0], [3.0]])
    1.0
    """
    A, B = _pair(a, b)
    ta = _unit_time(check_times(t_a, A.shape[0], "t_a"))
    tb = _unit_time(check_times(t_b, B.shape[0], "t_b"))
    Bi = np.column_stack([np.interp(ta, tb, B[:, c]) for c in range(B.shape[1])])
    return float(np.sqrt(np.mean(np.sum((Bi - A) ** 2, axis=1))))


def _unit_time(t: np.ndarray) -> np.ndarray:
    span = t[-1] - t[0]
    return (t - t[0]) / span if span > 0 else np.zeros_like(t)


def endpoint_error(a, b) -> float:
    """Euclidean distance between the last points of two paths.

    Parameters
    ----------
    a : array-like of shape (n_a, n_dims)
        First path.
    b : array-like of shape (n_b, n_dims)
        Second path.

    Returns
    -------
    error : float

    Examples
    --------
    >>> endpoint_error([[0, 0], [3, 4]], [[9, 9], [0, 0]])
    5.0
    """
    A, B = _pair(a, b)
    return float(np.linalg.norm(A[-1] - B[-1]))


def path_difference(t_a, a, t_b, b, *, scale=None) -> float:
    """Difference between two paths in percent of a scale (ndlfd's "difference %").

    The paper (Fig. 6) reports a "difference" between generated paths without
    defining it. ndlfd defines it as ``100 * time_aligned_rmse(a, b) / scale``,
    where ``scale`` defaults to the diagonal of ``a``'s bounding box (the length
    of the vector of per-column ranges), so the number reads as "the paths are
    on average this many percent of the motion's extent apart".

    Parameters
    ----------
    t_a, a, t_b, b
        As in :func:`time_aligned_rmse`.
    scale : float, optional
        The length that counts as 100 %.

    Returns
    -------
    difference : float
        In percent.

    Examples
    --------
    >>> path_difference([0, 1], [[0.0, 0.0], [3.0, 4.0]], [0, 1], [[0.5, 0], [3.5, 4]])
    10.0
    """
    A = check_points(a, "a")
    if scale is None:
        scale = float(np.linalg.norm(A.max(axis=0) - A.min(axis=0)))
    if not np.isfinite(scale) or scale <= 0:
        raise ValidationError(
            f"scale must be a finite number > 0; got {scale!r} (a path that does"
            " not move needs an explicit scale)"
        )
    return 100.0 * time_aligned_rmse(t_a, A, t_b, b) / scale
