"""Compiled kernels of the fit's per-demonstration work, on plain arrays.

A fit touches every demonstration twice (:mod:`ndlfd.learner._passes`); on a
short demonstration the numpy calls of a pass cost more in overhead than in
arithmetic. These kernels do the same arithmetic in one loop each, with the
same results bit for bit as the numpy code they replaced (the tests compare
them on random demonstrations):

* :func:`column_extremes`: per-column minimum and maximum (pass 1);
* :func:`split_limbs`: values split into integer limbs, the exact centroid
  sums of :func:`ndlfd.learner._exact.to_limbs` (pass 2);
* :func:`group_sums`: the limbs of the key points of each codebook state
  added up (pass 2 and every merge of fit statistics);
* :func:`segment_rows`: every demonstration's segment state at every time
  bin, for the segment model (:mod:`ndlfd.learner._segments`).

The kernels trust their input (float64, C-contiguous, finite, at least one
row); the wrappers here and their callers check it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .._errors import ValidationError

__all__ = ["column_extremes", "group_sums", "segment_rows", "split_limbs"]


#: Values per lane group of :func:`_extremes`: the flat values run in tiles
#: of ``d * _LANES``, a loop the compiler vectorizes.
_LANES = 8


@njit(cache=True, nogil=True)
def _extremes(flat, d, lo, hi):  # pragma: no cover - compiled
    # flat: the rows of d values end to end; into lo and hi (given: returning
    # new arrays costs more than making them). Plain comparisons and loops
    # (no slices, no min/max) keep the compile time short.
    size = flat.size
    width = d * _LANES
    tiles = size // width
    for c in range(d):
        lo[c] = flat[c]
        hi[c] = flat[c]
    if tiles:  # per position in a tile, then per column
        L = np.empty(width)
        H = np.empty(width)
        for j in range(width):
            L[j] = flat[j]
            H[j] = flat[j]
        for b in range(1, tiles):
            at = b * width
            for j in range(width):
                x = flat[at + j]
                if x < L[j]:
                    L[j] = x
                if x > H[j]:
                    H[j] = x
        for j in range(width):
            c = j % d
            if L[j] < lo[c]:
                lo[c] = L[j]
            if H[j] > hi[c]:
                hi[c] = H[j]
    for k in range(tiles * width, size):
        c = k % d
        if flat[k] < lo[c]:
            lo[c] = flat[k]
        if flat[k] > hi[c]:
            hi[c] = flat[k]
    zero = False  # an extreme is 0: its sign is numpy's to choose
    for c in range(d):
        if lo[c] == 0.0 or hi[c] == 0.0:
            zero = True
    return zero


def column_extremes(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(X.min(axis=0), X.max(axis=0))`` of finite values, in one pass.

    When an extreme is zero, numpy's reduction decides whether it is ``0.0``
    or ``-0.0``; the result is then numpy's, so it is the same bit for bit.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_dims), float64
        Finite values, at least one row.

    Returns
    -------
    lo, hi : ndarray of shape (n_dims,)

    Examples
    --------
    >>> column_extremes(np.array([[1.0, 5.0], [-2.0, 7.0], [3.0, 6.0]]))
    (array([-2.,  5.]), array([3., 7.]))
    """
    X = np.ascontiguousarray(X, dtype=np.float64)
    lo, hi = np.empty(X.shape[1]), np.empty(X.shape[1])
    # read-only whether X is or not: one compiled version (writability is
    # part of numba's array type)
    flat = X.reshape(-1)
    flat.flags.writeable = False
    if _extremes(flat, X.shape[1], lo, hi):  # a zero: numpy's sign
        return X.min(axis=0), X.max(axis=0)
    return lo, hi


@njit(cache=True, nogil=True)
def _limbs(V, quanta, out):  # pragma: no cover - compiled
    # out (n_limbs, n, d) is made by the caller, as _segments' and
    # _group_sums' are: an array made in a kernel compiles numba's allocation
    # for its shape and dtype on a first run (the three kernels: 0.74 -> 0.43
    # s of CPU on an empty cache)
    n, d = V.shape
    n_limbs = quanta.shape[0]
    for i in range(n):
        for c in range(d):
            r = V[i, c]
            for k in range(n_limbs):
                q = quanta[k, c]
                a = np.trunc(r / q)
                out[k, i, c] = np.int64(a)
                r = r - a * q
    return out


def split_limbs(V: np.ndarray, quanta: np.ndarray) -> np.ndarray:
    """Integer limbs ``a_k = trunc(r_k / q_k)``, ``r_{k+1} = r_k - a_k q_k``.

    Parameters
    ----------
    V : ndarray of shape (n, n_dims), float64
        Values (``|v| <= 2**E`` per column, see
        :func:`~ndlfd.learner._exact.scale_exponents`).
    quanta : ndarray of shape (n_limbs, n_dims), float64
        The powers of two ``q_k`` of each column.

    Returns
    -------
    limbs : ndarray of shape (n_limbs, n, n_dims), dtype int64

    Examples
    --------
    >>> split_limbs(np.array([[0.75]]), np.array([[0.5], [0.25]]))[:, 0, 0]
    array([1, 1])
    """
    V = np.ascontiguousarray(V, dtype=np.float64)
    quanta = np.ascontiguousarray(quanta, dtype=np.float64)
    out = np.empty((quanta.shape[0], *V.shape), dtype=np.int64)
    return _limbs(V, quanta, out)


@njit(cache=True, nogil=True)
def _segments(key_bins, key_states, starts, ends, out):  # pragma: no cover
    for r in range(starts.size):
        p, last = starts[r], ends[r] - 1
        for b in range(out.shape[1]):
            while p < last and key_bins[p + 1] <= b:
                p += 1
            out[r, b] = key_states[p]
    return out


def segment_rows(key_bins, key_states, starts, ends, n_bins: int) -> np.ndarray:
    """Per demonstration, the state of its last key point at or before each bin.

    Demonstration ``r`` holds the key points ``starts[r]:ends[r]`` (at least
    one) of the flat arrays; its bins are non-decreasing. Before its first key
    point's bin a demonstration is in its first key point's state.

    Parameters
    ----------
    key_bins, key_states : ndarray of shape (n_keys,), dtype int64
        Time bin and codebook state of every key point.
    starts, ends : ndarray of shape (n_demos,), dtype int64
    n_bins : int

    Returns
    -------
    states : ndarray of shape (n_demos, n_bins), dtype int64

    Examples
    --------
    >>> segment_rows(np.array([0, 2, 2, 4, 0, 1]), np.array([7, 8, 9, 5, 1, 2]),
    ...              np.array([0, 4]), np.array([4, 6]), 5)
    array([[7, 7, 9, 9, 5],
           [1, 2, 2, 2, 2]])
    """
    i64 = np.int64
    starts = np.ascontiguousarray(starts, dtype=i64)
    ends = np.ascontiguousarray(ends, dtype=i64)
    key_states = np.ascontiguousarray(key_states, dtype=i64)
    if np.any(ends <= starts) or np.any(starts < 0) or np.any(ends > key_states.size):
        raise ValidationError(
            "every demonstration needs at least one key point within the"
            f" {key_states.size} given; got starts {starts} and ends {ends}"
        )
    out = np.empty((starts.size, int(n_bins)), dtype=i64)
    key_bins = np.ascontiguousarray(key_bins, dtype=i64)
    return _segments(key_bins, key_states, starts, ends, out)


@njit(cache=True, nogil=True)
def _group_sums(limbs, order, starts, out):  # pragma: no cover - compiled
    n_limbs, n, d = limbs.shape
    for g in range(starts.size):
        end = starts[g + 1] if g + 1 < starts.size else n
        for j in range(starts[g], end):
            r = order[j]
            for k in range(n_limbs):
                for c in range(d):
                    out[k, g, c] += limbs[k, r, c]
    return out


def group_sums(limbs, order, starts) -> np.ndarray:
    """Sums of runs of rows: ``np.add.reduceat(limbs[:, order], starts, axis=1)``.

    Integer sums, so exactly what numpy gives.

    Parameters
    ----------
    limbs : ndarray of shape (n_limbs, n, n_dims), dtype int64
    order : ndarray of shape (n,), dtype int64
        The rows in run order (a permutation of ``0..n-1``).
    starts : ndarray of shape (n_runs,), dtype int64
        Where each run starts in ``order``: strictly increasing, the first 0.

    Returns
    -------
    sums : ndarray of shape (n_limbs, n_runs, n_dims), dtype int64

    Examples
    --------
    >>> L = np.arange(6).reshape(1, 3, 2)
    >>> group_sums(L, np.array([2, 0, 1]), np.array([0, 1]))[0]
    array([[4, 5],
           [2, 4]])
    """
    i64 = np.int64
    limbs = np.ascontiguousarray(limbs, dtype=i64)
    starts = np.ascontiguousarray(starts, dtype=i64)
    out = np.zeros((limbs.shape[0], starts.size, limbs.shape[2]), dtype=i64)
    return _group_sums(limbs, np.ascontiguousarray(order, dtype=i64), starts, out)
