"""Compiled kernels of :mod:`ndlfd.demonstration`: velocity from position in one pass.

:func:`ndlfd.with_velocity` differentiates a demonstration's position with
:func:`numpy.gradient` over its real time stamps; on a short demonstration
that is a dozen small numpy calls. :func:`gradient` does the same arithmetic
(the same formulas, in the same order, so the result is the same bit for bit)
in one loop, and also says whether the time steps are steady (the cheap test
that lets ``with_velocity`` skip its jitter check). The kernels trust their
input (``t`` strictly increasing with at least two samples, ``P`` of one row
per sample, both float64); :mod:`ndlfd.demonstration` checks it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["gradient"]


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
