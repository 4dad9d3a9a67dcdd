"""Compiled kernels of :mod:`ndlfd.demonstration`: velocity from position in one pass.

:func:`ndlfd.with_velocity` differentiates a demonstration's position with
:func:`numpy.gradient` over its real time stamps; on a short demonstration
that is a dozen small numpy calls. :func:`gradient` does the same arithmetic
(the same formulas, in the same order, so the result is the same bit for bit)
in one loop, and also says whether the time steps are steady (the cheap test
that lets ``with_velocity`` skip its jitter check); :func:`window_derivative`
is the derivative of jittery time stamps (a local straight-line fit);
:func:`with_room` copies a demonstration's values into a wider array whose
last columns :func:`gradient` then fills (the velocity group appended without
numpy's slow copy of short rows). The kernels trust their input (``t``
strictly increasing with at least two samples, ``P`` of one row per sample,
both float64); :mod:`ndlfd.demonstration` checks it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["gradient", "window_derivative", "with_room"]


def _read_only(a: np.ndarray) -> np.ndarray:
    """A read-only view of ``a`` (``a`` itself left as it is).

    Writability is part of numba's array type: a kernel given the caller's
    arrays as they come compiled a version per combination (``_gradient``
    up to five, ``_window_slopes`` four, in a run of the tests); given
    read-only views of its inputs, one.
    """
    view = a.view()
    view.flags.writeable = False
    return view


@njit(cache=True, nogil=True, error_model="numpy")
def _gradient(t, P, tol, V):  # pragma: no cover - compiled
    # V (any layout, for example the right columns of a wider array) gets the
    # derivative; the steps are never 0 (t strictly increasing), so numpy's
    # error model (no check of each division) changes no result
    n, d = P.shape
    lo = t[1] - t[0]
    hi = lo
    uniform = True
    for i in range(1, n - 1):
        step = t[i + 1] - t[i]
        uniform = uniform and step == t[1] - t[0]
        lo = min(lo, step)
        hi = max(hi, step)
    steady = n < 10 or hi - lo <= tol * lo
    if n == 2:  # numpy.gradient with edge_order=1
        dx = t[1] - t[0]
        for c in range(d):
            V[0, c] = (P[1, c] - P[0, c]) / dx
            V[1, c] = (P[1, c] - P[0, c]) / dx
        return steady
    if uniform:
        dx = t[1] - t[0]
        for i in range(1, n - 1):
            for c in range(d):
                V[i, c] = (P[i + 1, c] - P[i - 1, c]) / (2.0 * dx)
        a0, b0, c0 = -1.5 / dx, 2.0 / dx, -0.5 / dx
        a1, b1, c1 = 0.5 / dx, -2.0 / dx, 1.5 / dx
    else:
        # numpy's coefficient arrays first (a loop of divisions that
        # vectorizes), then its weighted sums
        A = np.empty(n)
        B = np.empty(n)
        C = np.empty(n)
        for i in range(1, n - 1):
            dx1 = t[i] - t[i - 1]
            dx2 = t[i + 1] - t[i]
            A[i] = -(dx2) / (dx1 * (dx1 + dx2))
            B[i] = (dx2 - dx1) / (dx1 * dx2)
            C[i] = dx1 / (dx2 * (dx1 + dx2))
        for c in range(d):
            for i in range(1, n - 1):
                V[i, c] = A[i] * P[i - 1, c] + B[i] * P[i, c] + C[i] * P[i + 1, c]
        dx1 = t[1] - t[0]
        dx2 = t[2] - t[1]
        a0 = -(2.0 * dx1 + dx2) / (dx1 * (dx1 + dx2))
        b0 = (dx1 + dx2) / (dx1 * dx2)
        c0 = -dx1 / (dx2 * (dx1 + dx2))
        dx1 = t[n - 2] - t[n - 3]
        dx2 = t[n - 1] - t[n - 2]
        a1 = (dx2) / (dx1 * (dx1 + dx2))
        b1 = -(dx2 + dx1) / (dx1 * dx2)
        c1 = (2.0 * dx2 + dx1) / (dx2 * (dx1 + dx2))
    for c in range(d):
        V[0, c] = a0 * P[0, c] + b0 * P[1, c] + c0 * P[2, c]
        V[n - 1, c] = a1 * P[n - 3, c] + b1 * P[n - 2, c] + c1 * P[n - 1, c]
    return steady


def gradient(
    t: np.ndarray, P: np.ndarray, tol: float, *, out: np.ndarray | None = None
) -> tuple[np.ndarray, bool]:
    """``numpy.gradient(P, t, axis=0)`` and whether the time steps are steady.

    Second-order differences (``edge_order=2``) from three samples on,
    first-order for two, bit for bit as :func:`numpy.gradient` computes
    them (uniform steps, all exactly equal, use its uniform formulas).

    Parameters
    ----------
    t : ndarray of shape (n_samples,), float64
        Strictly increasing time stamps (at least two; not checked).
    P : ndarray of shape (n_samples, n_dims), float64
        Values.
    tol : float
        The steps are *steady* when fewer than 10 samples are given or the
        largest step exceeds the smallest by at most ``tol`` times the smallest.
    out : ndarray of shape (n_samples, n_dims), float64, optional
        Where to write the derivative (a view, for example the last columns
        of :func:`with_room`'s array); a new array by default.

    Returns
    -------
    V : ndarray of shape (n_samples, n_dims)
        ``out`` when given.
    steady : bool

    Examples
    --------
    >>> V, steady = gradient(np.array([0.0, 1.0, 3.0]),
    ...                      np.array([[0.0], [2.0], [6.0]]), 0.1)
    >>> V.ravel(), steady
    (array([2., 2., 2.]), True)
    """
    P = _read_only(np.ascontiguousarray(P, dtype=np.float64))
    t = _read_only(np.ascontiguousarray(t, dtype=np.float64))
    V = np.empty(P.shape) if out is None else out
    steady = _gradient(t, P, float(tol), V)
    return V, bool(steady)


@njit(cache=True, nogil=True)
def _with_room(X, k):  # pragma: no cover - compiled
    n, d = X.shape
    W = np.empty((n, d + k))
    for i in range(n):
        for c in range(d):
            W[i, c] = X[i, c]
    return W


def with_room(X: np.ndarray, k: int) -> np.ndarray:
    """``X`` copied into the left columns of a new array ``k`` columns wider.

    For a group appended in place (:func:`gradient`'s ``out``): numpy copies
    rows of a few values slowly.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_dims), float64
    k : int
        Columns to add on the right (left uninitialized).

    Returns
    -------
    W : ndarray of shape (n_samples, n_dims + k)

    Examples
    --------
    >>> with_room(np.array([[1.0], [2.0]]), 1)[:, :1]
    array([[1.],
           [2.]])
    """
    return _with_room(_read_only(np.ascontiguousarray(X, dtype=np.float64)), int(k))


@njit(cache=True, nogil=True)
def _window_slopes(t, P, lo, hi):  # pragma: no cover - compiled
    n, d = P.shape
    V = np.empty((n, d))
    for i in range(n):
        a, b = lo[i], hi[i]
        k = b - a
        tm = 0.0
        for j in range(a, b):
            tm += t[j]
        tm /= k
        sxx = 0.0
        for j in range(a, b):
            sxx += (t[j] - tm) * (t[j] - tm)
        for c in range(d):
            pm = 0.0
            for j in range(a, b):
                pm += P[j, c]
            pm /= k
            sxy = 0.0
            for j in range(a, b):
                sxy += (t[j] - tm) * (P[j, c] - pm)
            V[i, c] = sxy / sxx
    return V


def window_derivative(t, P, half_width: float) -> np.ndarray:
    """Derivative by a local straight-line fit over a time window.

    At each sample the slope of the least-squares line through the samples
    within ``half_width`` seconds on either side (and at least the immediate
    neighbours) is the derivative: every sample in the window counts, so a
    jittery time stamp moves it little, where a difference of neighbours
    divides by the jittered step.

    Parameters
    ----------
    t : ndarray of shape (n_samples,)
        Strictly increasing time stamps (at least 2).
    P : ndarray of shape (n_samples, n_dims)
        Values.
    half_width : float
        Half the window, in the units of ``t``.

    Returns
    -------
    V : ndarray of shape (n_samples, n_dims)

    Examples
    --------
    >>> t = np.array([0.0, 1.0, 2.0, 3.0])
    >>> window_derivative(t, 3.0 * t[:, None] + 1.0, 1.0).ravel()
    array([3., 3., 3., 3.])
    """
    t = np.ascontiguousarray(t, dtype=np.float64)
    P = np.ascontiguousarray(P, dtype=np.float64)
    n = t.size
    idx = np.arange(n)
    lo = np.minimum(
        np.searchsorted(t, t - half_width, side="left"), np.maximum(idx - 1, 0)
    )
    hi = np.maximum(
        np.searchsorted(t, t + half_width, side="right"), np.minimum(idx + 2, n)
    )
    lo, hi = lo.astype(np.int64), hi.astype(np.int64)
    return _window_slopes(_read_only(t), _read_only(P), lo, hi)
