"""Compiled kernels of :mod:`ndlfd.demonstration`: velocity from position in one pass.

:func:`ndlfd.with_velocity` differentiates a demonstration's position with
:func:`numpy.gradient` over its real time stamps; on a short demonstration
that is a dozen small numpy calls. :func:`gradient` does the same arithmetic
(the same formulas, in the same order, so the result is the same bit for bit)
in one loop, and also says whether the time steps are steady (the cheap test
that lets ``with_velocity`` skip its jitter check); :func:`window_derivative`
is the derivative of jittery time stamps (a local straight-line fit). The
kernels trust their input (``t`` strictly increasing with at least two
samples, ``P`` of one row per sample, both float64); :mod:`ndlfd.demonstration`
checks it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["gradient", "window_derivative"]


@njit(cache=True, nogil=True)
def _gradient(t, P, tol):  # pragma: no cover - compiled
    n, d = P.shape
    V = np.empty((n, d))
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
        return V, steady
    if uniform:
        dx = t[1] - t[0]
        for i in range(1, n - 1):
            for c in range(d):
                V[i, c] = (P[i + 1, c] - P[i - 1, c]) / (2.0 * dx)
        a0, b0, c0 = -1.5 / dx, 2.0 / dx, -0.5 / dx
        a1, b1, c1 = 0.5 / dx, -2.0 / dx, 1.5 / dx
    else:
        for i in range(1, n - 1):
            dx1 = t[i] - t[i - 1]
            dx2 = t[i + 1] - t[i]
            a = -(dx2) / (dx1 * (dx1 + dx2))
            b = (dx2 - dx1) / (dx1 * dx2)
            cc = dx1 / (dx2 * (dx1 + dx2))
            for c in range(d):
                V[i, c] = a * P[i - 1, c] + b * P[i, c] + cc * P[i + 1, c]
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
    return V, steady


def gradient(t: np.ndarray, P: np.ndarray, tol: float) -> tuple[np.ndarray, bool]:
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

    Returns
    -------
    V : ndarray of shape (n_samples, n_dims)
    steady : bool

    Examples
    --------
    >>> V, steady = gradient(np.array([0.0, 1.0, 3.0]),
    ...                      np.array([[0.0], [2.0], [6.0]]), 0.1)
    >>> V.ravel(), steady
    (array([2., 2., 2.]), True)
    """
    V, steady = _gradient(
        np.ascontiguousarray(t, dtype=np.float64),
        np.ascontiguousarray(P, dtype=np.float64),
        float(tol),
    )
    return V, bool(steady)


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
    return _window_slopes(t, P, lo.astype(np.int64), hi.astype(np.int64))
