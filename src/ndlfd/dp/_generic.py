"""The any-mode Douglas–Peucker kernel: row-major data, every distance mode.

:func:`scan_generic` computes the keys of :mod:`ndlfd.dp._kernels` (see its
docstring for each mode's key and scale) for any ``d``, point by point on
the row-major data, including the paper's determinant (``"paper"``), which
only it computes. :func:`dp_generic` runs the epsilon-mode Douglas–Peucker
with it: ``distance="paper"`` uses it, and the budget mode
(:mod:`ndlfd.dp._budget`) scans with :func:`scan_generic`. The faster
column-major kernels of the other modes are in :mod:`ndlfd.dp._kernels`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ._kernels import MODE_PAPER, MODE_SED, MODE_SEGMENT
from ._tree import (
    tree_begin,
    tree_done,
    tree_keep,
    tree_next,
    tree_split,
    tree_workspace,
)

__all__ = ["dp_generic", "scan_generic"]


@njit(cache=True, nogil=True)
def scan_generic(P, t, a, b, mode, utol2, lo, hi, u):
    """Farthest point of segment ``(a, b)`` among indices ``lo..hi-1``.

    Returns ``(far, q, S)``: the first index with the largest key ``q`` and
    the segment scale ``S`` (``distance² = q / S``). ``u`` is a workspace of
    length ``d``. ``far`` is ``-1`` (and ``q`` is ``-1``) when ``lo >= hi``.
    """
    d = P.shape[1]
    best = -1.0
    far = -1
    # Each mode has its own flat loop over the points, with the key and the
    # argmax written out in it: unrolled on purpose, so that no mode test or
    # helper call runs per point.
    if mode == MODE_SED:
        ta = t[a]
        D = t[b] - ta
        for k in range(d):
            u[k] = P[b, k] - P[a, k]
        for i in range(lo, hi):
            s = t[i] - ta
            q = 0.0
            for k in range(d):
                r = D * (P[i, k] - P[a, k]) - s * u[k]
                q += r * r
            if q > best:
                best = q
                far = i
        return far, best, D * D
    U = 0.0
    for k in range(d):
        u[k] = P[b, k] - P[a, k]
        U += u[k] * u[k]
    if U <= utol2:
        for i in range(lo, hi):
            q = 0.0
            for k in range(d):
                r = P[i, k] - P[a, k]
                q += r * r
            if q > best:
                best = q
                far = i
        return far, best, 1.0
    if mode == MODE_PAPER and d >= 2:
        if d == 2:
            w0 = u[1]
            w1 = -u[0]
            for i in range(lo, hi):
                c = (P[i, 0] - P[a, 0]) * w0 + (P[i, 1] - P[a, 1]) * w1
                q = c * c
                if q > best:
                    best = q
                    far = i
            return far, best, U
        ka = d - 3
        wa = u[ka + 1] - u[ka + 2]
        wb = u[ka + 2] - u[ka]
        wc = u[ka] - u[ka + 1]
        for i in range(lo, hi):
            c = (
                (P[i, ka] - P[a, ka]) * wa
                + (P[i, ka + 1] - P[a, ka + 1]) * wb
                + (P[i, ka + 2] - P[a, ka + 2]) * wc
            )
            q = c * c
            if q > best:
                best = q
                far = i
        return far, best, U
    UU = U * U
    segment = mode == MODE_SEGMENT
    for i in range(lo, hi):
        vu = 0.0
        for k in range(d):
            vu += (P[i, k] - P[a, k]) * u[k]
        if segment:  # the projection clamped to the segment
            vu = min(max(vu, 0.0), U)
        q = 0.0
        for k in range(d):
            r = U * (P[i, k] - P[a, k]) - vu * u[k]
            q += r * r
        if q > best:
            best = q
            far = i
    return far, best, UU


@njit(cache=True, nogil=True)
def dp_generic(P, t, mode, eps2, utol2, keep, a0, b0, tree):
    """Epsilon-mode Douglas–Peucker on ``P[a0..b0]`` for any mode and ``d``.

    Marks kept interior indices in ``keep`` (uint8, length ``n``); the
    endpoints ``a0`` and ``b0`` are marked too. Explicit stack, no recursion.
    Segments longer than ``tree[7]`` points are scanned through the box tree
    ``tree`` (:func:`ndlfd.dp._tree.make_tree`) once it is filled (by
    :func:`ndlfd.dp._tree.tree_split` after lopsided splits, unless it
    was filled before). ``tree=None`` (a trajectory of at most
    :data:`ndlfd.dp._kernels.TREE_NONE_MAX` points) compiles a version
    without the tree. Returns the number of distance evaluations.
    """
    keep[a0] = 1
    keep[b0] = 1
    if b0 - a0 < 2:
        return 0
    u = np.empty(P.shape[1])
    if tree is not None:  # pruned at compile time when tree is None
        ws, ts_stack, flags = tree_workspace(tree, P.shape[1], P.shape[0])
    stack = np.empty(2 * ((b0 - a0) // 2 + 2), np.int64)
    # The explicit-stack loop is written out in each dp_* kernel on purpose:
    # the scans take different arguments, and this way each kernel calls its
    # scan directly, with no dispatch per segment in the hot loop.
    stack[0] = a0
    stack[1] = b0
    sp = 1
    work = 0
    while sp > 0:
        sp -= 1
        a = stack[2 * sp]
        b = stack[2 * sp + 1]
        plain = True
        if tree is not None:
            if b - a > tree[7] and flags[0] > 0.0:
                # the tree loop: written out in each dp_* kernel, like the stack
                far, q, S, bd2 = -1, -1.0, 1.0, eps2
                w0 = work
                # the sed and paper keys are bounded exactly (ndlfd.dp._tree)
                exact = eps2 if mode in (MODE_SED, MODE_PAPER) else -1.0
                ts = tree_begin(tree, a, b, utol2, ws, ts_stack, exact)
                while True:
                    lo, hi, ts = tree_next(
                        tree, ws, ts_stack, ts, a + 1, b, bd2, q, far
                    )
                    if lo < 0:
                        break
                    f, qq, SS = scan_generic(P, t, a, b, mode, utol2, lo, hi, u)
                    far, q, S, bd2 = tree_keep(far, q, S, f, qq, SS, eps2)
                    work += hi - lo
                tree_done(tree, flags, work - w0, b - a - 1)
                plain = False
        if plain:
            far, q, S = scan_generic(P, t, a, b, mode, utol2, a + 1, b, u)
            work += b - a - 1
        if q > eps2 * S:
            keep[far] = 1
            if tree is not None:
                if b - a > tree[7]:
                    tree_split(tree, flags, a, b, far)
            if far - a > 1:
                stack[2 * sp] = a
                stack[2 * sp + 1] = far
                sp += 1
            if b - far > 1:
                stack[2 * sp] = far
                stack[2 * sp + 1] = b
                sp += 1
    return work
