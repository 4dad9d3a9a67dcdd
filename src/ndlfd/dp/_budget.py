"""Budget-mode Douglas–Peucker: a target number of key points (``n_points=``).

The most significant points first: a max-heap of segments keyed by their
farthest point's distance, scanned by :func:`ndlfd.dp._generic.scan_generic`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ._generic import scan_generic

__all__ = ["dp_budget"]


@njit(cache=True, nogil=True)
def _heap_better(key, far, i, j):
    # larger distance first; equal distances: smaller index first
    return key[i] > key[j] or (key[i] == key[j] and far[i] < far[j])


@njit(cache=True, nogil=True)
def _heap_swap(key, far, sa, sb, i, j):
    key[i], key[j] = key[j], key[i]
    far[i], far[j] = far[j], far[i]
    sa[i], sa[j] = sa[j], sa[i]
    sb[i], sb[j] = sb[j], sb[i]


@njit(cache=True, nogil=True)
def dp_budget(P, t, mode, k, utol2, keep):
    """Budget-mode Douglas–Peucker: greedy global-farthest splitting.

    Keeps ``min(max(k, 2), n)`` points: the endpoints, then repeatedly the
    farthest point (``distance² = q / S``) of the segment whose farthest point
    is farthest; equal distances go to the smaller index. A binary max-heap of
    segments, no recursion. Returns the number of kept points.
    """
    n = P.shape[0]
    keep[0] = 1
    keep[n - 1] = 1
    count = 1 if n == 1 else 2
    if n < 3 or count >= k:
        return count
    u = np.empty(P.shape[1])
    cap = n // 2 + 2
    key = np.empty(cap)
    far = np.empty(cap, np.int64)
    sa = np.empty(cap, np.int64)
    sb = np.empty(cap, np.int64)
    f, q, S = scan_generic(P, t, 0, n - 1, mode, utol2, 1, n - 1, u)
    key[0] = q / S
    far[0] = f
    sa[0] = 0
    sb[0] = n - 1
    size = 1
    while count < k and size > 0:
        a = sa[0]
        b = sb[0]
        m = far[0]
        keep[m] = 1
        count += 1
        # pop the root
        size -= 1
        _heap_swap(key, far, sa, sb, 0, size)
        i = 0
        while True:
            c = 2 * i + 1
            if c >= size:
                break
            if c + 1 < size and _heap_better(key, far, c + 1, c):
                c += 1
            if _heap_better(key, far, c, i):
                _heap_swap(key, far, sa, sb, c, i)
                i = c
            else:
                break
        # push the children that have interior points
        for side in range(2):
            lo = a if side == 0 else m
            hi = m if side == 0 else b
            if hi - lo < 2:
                continue
            f, q, S = scan_generic(P, t, lo, hi, mode, utol2, lo + 1, hi, u)
            j = size
            key[j] = q / S
            far[j] = f
            sa[j] = lo
            sb[j] = hi
            size += 1
            while j > 0:
                p = (j - 1) // 2
                if _heap_better(key, far, j, p):
                    _heap_swap(key, far, sa, sb, j, p)
                    j = p
                else:
                    break
    return count
