"""Numba kernels behind :func:`ndlfd.simplify`: n-D Douglas–Peucker, no recursion.

The kernels trust their input (finite float64, C-contiguous, ``n >= 1``); the
checked doorway is :mod:`ndlfd.dp._simplify`.

Every distance is evaluated as a pair ``(q, S)`` with ``distance² = q / S``:

- ``q`` is a per-point *key* and ``S`` a per-segment *scale*, so within a
  segment the farthest point is the first index with the largest ``q`` and it
  is kept when ``q > epsilon² · S``. No square root and no division per point.
- For integer-valued data every ``q`` and ``S`` is an exact integer in floating
  point (while the values stay below 2**53), so ties and distances exactly
  equal to ``epsilon`` are decided exactly.

The keys, with ``v = P_i - P_a``, ``u = P_b - P_a``, ``U = |u|²``:

- ``"line"``: ``r = U v - (v·u) u`` (the residual of ``v`` after removing its
  component along ``u``, scaled by ``U``), ``q = |r|²``, ``S = U²``. Computing
  the residual vector and then its norm avoids the cancellation of
  ``|v|²|u|² - (v·u)²``: the absolute error of the distance stays at a few
  ulps of ``|v|``. In 2-D the key is the squared cross product
  ``(v_x u_y - v_y u_x)²`` with ``S = U`` (the same distance), and in 3-D the
  squared norm of the cross product ``|v × u|²`` with ``S = U``.
- ``"segment"``: the line's residual with the projection clamped to the
  segment, ``r = U v - w u`` with ``w = min(max(v·u, 0), U)``, ``q = |r|²``,
  ``S = U²`` (``U`` times the distance to the closest point of the segment,
  ``P_a + (w / U) u``). Between the ends (``0 < v·u < U``) it is the line's
  key, bit for bit; before ``P_a`` it is ``|U v|²``, past ``P_b``
  ``|U v - U u|²``: one ``min`` and one ``max`` per point more than the
  line's key, no selection. Like the line's, its error stays at a few ulps of
  ``|v|``, and it is an exact integer on integer data.
- ``"sed"``: ``D = t_b - t_a``, ``s = t_i - t_a``, ``q = |D v - s u|²``,
  ``S = D²``.
- ``"paper"``: ``q = det(A_d)²``, ``S = U``. Row operations reduce the paper's
  ``(d+1) × (d+1)`` determinant to a 3 × 3 one over the *last three* columns:
  ``det = v_a (u_b - u_c) + v_b (u_c - u_a) + v_c (u_a - u_b)`` with
  ``a, b, c = d-3, d-2, d-1`` (in 2-D it is the cross product, so it equals
  ``"line"``; in 1-D ``"paper"`` is defined as ``"line"``).
- Coincident endpoints (``U <= utol2``): distance to ``P_a``, ``q = |v|²``,
  ``S = 1`` (paper eq. 4). Not used by ``"sed"``, whose chord is defined by
  time even when its endpoints coincide.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._exact import EXACT_MIN, loo_workspace, lopsided, scan_loo, scan_loo_range
from ._tree import (
    tree_begin,
    tree_done,
    tree_keep,
    tree_next,
    tree_split,
    tree_workspace,
)

__all__ = [
    "MODE_LINE",
    "MODE_PAPER",
    "MODE_SED",
    "MODE_SEGMENT",
    "TREE_NONE_MAX",
    "dp_cols",
    "dp_line",
    "finite_maxabs",
    "scan_cols_range",
    "scan_line_range",
    "shifted_times",
    "transpose",
]

MODE_LINE = 0
MODE_SEGMENT = 1
MODE_SED = 2
MODE_PAPER = 3

#: The longest trajectory the ``dp_*`` kernels may be given ``tree=None``
#: for: none of its segments is longer than
#: :data:`~ndlfd.dp._exact.EXACT_MIN` points, so none would be scanned by
#: the exact keys, and the caller builds no tree for it
#: (``ndlfd.dp._simplify.TREE_MIN``). Given ``None``, numba prunes the tree's
#: and the exact keys' branches before typing, so the kernel compiles
#: without them: ``dp_cols`` (d = 4, with the kernels it calls) in 2.1 s
#: of CPU instead of 14.7 on a first run (``benchmarks/bench_firstrun.py``).
#: The points kept are the same: with no tree those branches are never
#: taken.
TREE_NONE_MAX = EXACT_MIN + 1


_ABS_MASK = np.int64(0x7FFFFFFFFFFFFFFF)
_EXP_ALL_ONES = np.int64(0x7FF0000000000000)


@njit(cache=True, nogil=True)
def _maxabs_bits(bits):
    """The largest ``bits[i]`` without its sign bit (``0`` for none)."""
    m = np.int64(0)
    for i in range(bits.shape[0]):
        v = bits[i] & _ABS_MASK
        m = v if v > m else m
    return m


def finite_maxabs(P):
    """``(all finite, max |P|)`` of a C-contiguous float64 array, one pass.

    Works on the bit patterns: ``|x|`` is the pattern without its sign bit,
    which orders like an int64, and ``x`` is NaN or inf exactly when that
    pattern is at least ``0x7FF0000000000000``. Both reductions are integer
    max reductions, which LLVM vectorizes. The patterns are numpy's view of
    ``P``: the kernel takes int64 values only, which compiles in a third of
    the time of reshaping and viewing in it (first run).
    """
    m = _maxabs_bits(P.reshape(-1).view(np.int64))
    return bool(m < _EXP_ALL_ONES), float(np.int64(m).view(np.float64))


@njit(cache=True, nogil=True)
def shifted_times(t, out):
    """``out = t - t[0]``, and whether ``t`` is finite and strictly increasing.

    One pass over ``t`` (length >= 1); a NaN anywhere makes it ``False``.
    """
    t0 = t[0]
    up = np.uint8(1)
    out[0] = 0.0
    for i in range(1, t.shape[0]):
        up &= t[i] > t[i - 1]
        out[i] = t[i] - t0
    return bool(up) and math.isfinite(t0) and math.isfinite(t[t.shape[0] - 1])


@njit(cache=True, nogil=True)
def transpose(P, out, lo, hi):
    """Copy rows ``lo..hi-1`` of ``P`` (n, d) into columns of ``out`` (d, n)."""
    d = P.shape[1]
    for i0 in range(lo, hi, 512):
        i1 = min(hi, i0 + 512)
        for k in range(d):
            for i in range(i0, i1):
                out[k, i] = P[i, k]


#: Points per block of the vectorized line-mode scans (a 2 KiB buffer).
BLOCK = 256

# The line-mode scans compute the keys of a block of points into ``buf`` in
# a vectorized loop, then take the block's max as an integer reduction over
# ``bits`` (an int64 view of ``buf``): keys are non-negative doubles, whose
# bit patterns order like int64, and LLVM vectorizes integer max reductions
# (not float ones without fast-math). The first index reaching a new max is
# looked up only when the max improves. Block indices are cast to uint64 so
# numba skips its negative-index wraparound and LLVM vectorizes the loops.
# The block max is written out in each scan: a helper function returning a
# tuple cost twice the time on trees with many short segments.


@njit(cache=True, nogil=True)
def scan_line2(x, y, a, b, utol2, lo, hi, buf, bits):
    """Farthest point of ``(a, b)`` among ``lo..hi-1``, 2-D line mode.

    Structure of arrays (``x``, ``y``), squared cross product with ``S = U``,
    no division or square root per point. ``buf`` is a workspace of length
    :data:`BLOCK` and ``bits`` its int64 view. Returns ``(far, q, S)``.
    """
    xa = x[a]
    ya = y[a]
    ux = x[b] - xa
    uy = y[b] - ya
    U = ux * ux + uy * uy
    degenerate = U <= utol2
    S = 1.0 if degenerate else U
    # the block loop: written out in each line-mode scan on purpose, one per
    # data layout (see the note on the line-mode scans above)
    best_bits = np.int64(-1)
    far = -1
    bestq = -1.0
    i0 = lo
    while i0 < hi:
        m = min(BLOCK, hi - i0)
        if degenerate:
            for j in range(m):
                i = np.uint64(i0 + j)
                dx = x[i] - xa
                dy = y[i] - ya
                buf[j] = dx * dx + dy * dy
        else:
            for j in range(m):
                i = np.uint64(i0 + j)
                c = (x[i] - xa) * uy - (y[i] - ya) * ux
                buf[j] = c * c
        # block max, written out in each scan on purpose (see the note on the
        # line-mode scans above: a helper returning a tuple cost twice the time)
        bm = np.int64(-1)
        for j in range(m):
            v = bits[j]
            bm = v if v > bm else bm
        if bm > best_bits:
            for j in range(m):
                if bits[j] == bm:
                    best_bits = bm
                    far = i0 + j
                    bestq = buf[j]
                    break
        i0 += m
    return far, bestq, S


@njit(cache=True, nogil=True)
def scan_line3(x, y, z, a, b, utol2, lo, hi, buf, bits):
    """Farthest point of ``(a, b)`` among ``lo..hi-1``, 3-D line mode.

    Squared norm of the cross product ``|v × u|²`` with ``S = U``.
    """
    xa = x[a]
    ya = y[a]
    za = z[a]
    ux = x[b] - xa
    uy = y[b] - ya
    uz = z[b] - za
    U = ux * ux + uy * uy + uz * uz
    degenerate = U <= utol2
    S = 1.0 if degenerate else U
    # the block loop: written out in each line-mode scan on purpose, one per
    # data layout (see the note on the line-mode scans above)
    best_bits = np.int64(-1)
    far = -1
    bestq = -1.0
    i0 = lo
    while i0 < hi:
        m = min(BLOCK, hi - i0)
        if degenerate:
            for j in range(m):
                i = np.uint64(i0 + j)
                dx = x[i] - xa
                dy = y[i] - ya
                dz = z[i] - za
                buf[j] = dx * dx + dy * dy + dz * dz
        else:
            for j in range(m):
                i = np.uint64(i0 + j)
                dx = x[i] - xa
                dy = y[i] - ya
                dz = z[i] - za
                cx = dy * uz - dz * uy
                cy = dz * ux - dx * uz
                cz = dx * uy - dy * ux
                buf[j] = cx * cx + cy * cy + cz * cz
        # block max, written out in each scan on purpose (see the note on the
        # line-mode scans above: a helper returning a tuple cost twice the time)
        bm = np.int64(-1)
        for j in range(m):
            v = bits[j]
            bm = v if v > bm else bm
        if bm > best_bits:
            for j in range(m):
                if bits[j] == bm:
                    best_bits = bm
                    far = i0 + j
                    bestq = buf[j]
                    break
        i0 += m
    return far, bestq, S


@njit(cache=True, nogil=True)
def scan_lineN(Pt, t, mode, a, b, utol2, lo, hi, buf, bits, vu, u, pa):
    """Farthest point of ``(a, b)`` among ``lo..hi-1``, any ``d``.

    ``mode`` as in :func:`scan_line_cols`. ``Pt`` is the transposed
    (column-major) data of shape ``(d, n)``; each block is processed column
    by column in vectorized loops. The keys are the same numbers as
    :func:`~ndlfd.dp._generic.scan_generic`'s (same operations, same order).
    ``buf`` (``bits`` its int64 view), ``vu`` are workspaces of length
    :data:`BLOCK`; ``u``, ``pa`` of length ``d``.
    """
    d = Pt.shape[0]
    U = 0.0
    for k in range(d):
        pa[k] = Pt[k, a]
        u[k] = Pt[k, b] - pa[k]
        U += u[k] * u[k]
    sed = mode == MODE_SED
    degenerate = U <= utol2 and not sed
    UU = U * U
    S = 1.0 if degenerate else UU
    ta = t[a] if sed else 0.0
    D = t[b] - ta if sed else 0.0
    if sed:
        S = D * D
    # the block loop: written out in each line-mode scan on purpose, one per
    # data layout (see the note on the line-mode scans above)
    best_bits = np.int64(-1)
    far = -1
    bestq = -1.0
    i0 = lo
    while i0 < hi:
        m = min(BLOCK, hi - i0)
        for j in range(m):
            buf[j] = 0.0
        if degenerate:
            for k in range(d):
                pk = pa[k]
                for j in range(m):
                    r = Pt[k, np.uint64(i0 + j)] - pk
                    buf[j] += r * r
        else:
            # r = A (x - xa) - c u with A = D, c = s (the time since t_a) for
            # "sed", A = U, c = v·u for the others; vu holds c
            if sed:
                A = D
                for j in range(m):
                    vu[j] = t[np.uint64(i0 + j)] - ta
            else:
                A = U
                for j in range(m):
                    vu[j] = 0.0
                # four columns per pass over the block, then one by one: the
                # sums in the same order, a quarter of the loads and stores
                k4 = 0
                while k4 + 4 <= d:
                    k = k4
                    p0, p1, p2, p3 = pa[k], pa[k + 1], pa[k + 2], pa[k + 3]
                    u0, u1, u2, u3 = u[k], u[k + 1], u[k + 2], u[k + 3]
                    for j in range(m):
                        i = np.uint64(i0 + j)
                        vu[j] = (
                            vu[j]
                            + (Pt[k, i] - p0) * u0
                            + (Pt[k + 1, i] - p1) * u1
                            + (Pt[k + 2, i] - p2) * u2
                            + (Pt[k + 3, i] - p3) * u3
                        )
                    k4 += 4
                for k in range(k4, d):
                    pk = pa[k]
                    uk = u[k]
                    for j in range(m):
                        vu[j] += (Pt[k, np.uint64(i0 + j)] - pk) * uk
                if mode == MODE_SEGMENT:  # the projection clamped to the segment
                    for j in range(m):
                        vu[j] = min(max(vu[j], 0.0), U)
            k4 = 0  # four columns per pass, as above
            while k4 + 4 <= d:
                k = k4
                p0, p1, p2, p3 = pa[k], pa[k + 1], pa[k + 2], pa[k + 3]
                u0, u1, u2, u3 = u[k], u[k + 1], u[k + 2], u[k + 3]
                for j in range(m):
                    i = np.uint64(i0 + j)
                    c = vu[j]
                    r0 = A * (Pt[k, i] - p0) - c * u0
                    r1 = A * (Pt[k + 1, i] - p1) - c * u1
                    r2 = A * (Pt[k + 2, i] - p2) - c * u2
                    r3 = A * (Pt[k + 3, i] - p3) - c * u3
                    buf[j] = buf[j] + r0 * r0 + r1 * r1 + r2 * r2 + r3 * r3
                k4 += 4
            for k in range(k4, d):
                pk = pa[k]
                uk = u[k]
                for j in range(m):
                    r = A * (Pt[k, np.uint64(i0 + j)] - pk) - vu[j] * uk
                    buf[j] += r * r
        # block max, written out in each scan on purpose (see the note on the
        # line-mode scans above: a helper returning a tuple cost twice the time)
        bm = np.int64(-1)
        for j in range(m):
            v = bits[j]
            bm = v if v > bm else bm
        if bm > best_bits:
            for j in range(m):
                if bits[j] == bm:
                    best_bits = bm
                    far = i0 + j
                    bestq = buf[j]
                    break
        i0 += m
    return far, bestq, S


@njit(cache=True, nogil=True)
def scan_line_cols(cols, t, mode, a, b, utol2, lo, hi, buf, bits, u, pa):
    """Farthest point of ``(a, b)`` among ``lo..hi-1``, small ``d``.

    ``mode`` is ``MODE_LINE``, ``MODE_SEGMENT`` or ``MODE_SED`` (``t`` the
    times, used by the latter only). ``cols`` is a tuple of ``d`` contiguous
    columns. Its length is part of the type, so numba compiles one version
    per ``d`` with the loops over the columns unrolled and the loop over
    points vectorized, with everything in registers. Same keys as
    :func:`~ndlfd.dp._generic.scan_generic` (same operations, same order).
    ``u``, ``pa`` are workspaces of length ``d``.
    """
    d = len(cols)
    U = 0.0
    for k in range(d):
        pa[k] = cols[k][a]
        u[k] = cols[k][b] - pa[k]
        U += u[k] * u[k]
    sed = mode == MODE_SED
    degenerate = U <= utol2 and not sed
    UU = U * U
    S = 1.0 if degenerate else UU
    ta = t[a] if sed else 0.0
    D = t[b] - ta if sed else 0.0
    if sed:
        S = D * D
    # the block loop: written out in each line-mode scan on purpose, one per
    # data layout (see the note on the line-mode scans above)
    best_bits = np.int64(-1)
    far = -1
    bestq = -1.0
    i0 = lo
    while i0 < hi:
        m = min(BLOCK, hi - i0)
        if degenerate:
            for j in range(m):
                i = np.uint64(i0 + j)
                q = 0.0
                for k in range(d):
                    r = cols[k][i] - pa[k]
                    q += r * r
                buf[j] = q
        elif sed:
            for j in range(m):
                i = np.uint64(i0 + j)
                s = t[i] - ta
                q = 0.0
                for k in range(d):
                    r = D * (cols[k][i] - pa[k]) - s * u[k]
                    q += r * r
                buf[j] = q
        elif mode == MODE_SEGMENT:
            # "segment" and "line" each have their own flat loop on purpose
            for j in range(m):
                i = np.uint64(i0 + j)
                vu = 0.0
                for k in range(d):
                    vu += (cols[k][i] - pa[k]) * u[k]
                w = min(max(vu, 0.0), U)  # the projection clamped to the segment
                q = 0.0
                for k in range(d):
                    r = U * (cols[k][i] - pa[k]) - w * u[k]
                    q += r * r
                buf[j] = q
        else:
            for j in range(m):
                i = np.uint64(i0 + j)
                vu = 0.0
                for k in range(d):
                    vu += (cols[k][i] - pa[k]) * u[k]
                q = 0.0
                for k in range(d):
                    r = U * (cols[k][i] - pa[k]) - vu * u[k]
                    q += r * r
                buf[j] = q
        # block max, written out in each scan on purpose (see the note on the
        # line-mode scans above: a helper returning a tuple cost twice the time)
        bm = np.int64(-1)
        for j in range(m):
            v = bits[j]
            bm = v if v > bm else bm
        if bm > best_bits:
            for j in range(m):
                if bits[j] == bm:
                    best_bits = bm
                    far = i0 + j
                    bestq = buf[j]
                    break
        i0 += m
    return far, bestq, S


@njit(cache=True, nogil=True)
def scan_cols_range(cols, t, mode, a, b, utol2, lo, hi, lop=False):
    """:func:`scan_line_cols` on one chunk ``lo..hi-1`` of segment ``(a, b)``.

    With ``lop`` (the segment comes from a lopsided split) and longer than
    :data:`~ndlfd.dp._exact.EXACT_MIN` points,
    :func:`~ndlfd.dp._exact.scan_loo` (``"line"`` and ``"segment"``), as
    :func:`dp_cols` does.
    """
    if lop and mode != MODE_SED and b - a > EXACT_MIN:
        return scan_loo_range(cols, mode == MODE_SEGMENT, a, b, utol2, lo, hi)
    buf = np.empty(BLOCK)
    d = len(cols)
    bits = buf.view(np.int64)
    u = np.empty(d)
    pa = np.empty(d)
    return scan_line_cols(cols, t, mode, a, b, utol2, lo, hi, buf, bits, u, pa)


@njit(cache=True, nogil=True)
def dp_cols(cols, t, mode, eps2, utol2, keep, a0, b0, tree, lop0=False):
    """Epsilon-mode Douglas–Peucker on ``[a0, b0]``, columns as a tuple.

    See :func:`scan_line_cols`; used for ``"line"`` from ``d = 4`` and for
    ``"segment"`` and ``"sed"`` from ``d = 1``, up to the last of
    ``ndlfd.dp._simplify.COLS_DIMS``. Segments longer than
    :data:`~ndlfd.dp._exact.EXACT_MIN` points from a lopsided split
    (:func:`~ndlfd.dp._exact.lopsided`; ``lop0`` for ``(a0, b0)``), but in
    ``"sed"``, are scanned by :func:`~ndlfd.dp._exact.scan_loo` (keys the
    tree bounds exactly). Explicit stack, no recursion; ``tree`` as in
    :func:`~ndlfd.dp._generic.dp_generic`: the tree tuple, or ``None`` for a
    trajectory of at most :data:`TREE_NONE_MAX` points.
    Returns the number of distance evaluations.
    """
    keep[a0] = 1
    keep[b0] = 1
    if b0 - a0 < 2:
        return 0
    d = len(cols)
    buf = np.empty(BLOCK)
    bits = buf.view(np.int64)
    u = np.empty(d)
    pa = np.empty(d)
    segment = mode == MODE_SEGMENT
    if tree is not None:  # pruned at compile time when tree is None
        lw = loo_workspace(d)
        ws, ts_stack, flags = tree_workspace(tree, d, keep.shape[0])
    stack = np.empty(2 * ((b0 - a0) // 2 + 2), np.int64)
    if tree is not None:  # each segment's lop flag: read by the tree's branch only
        lops = np.empty((b0 - a0) // 2 + 2, np.bool_)
        lops[0] = lop0
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
            loo = lops[sp] and mode != MODE_SED and b - a > EXACT_MIN
            if b - a > tree[7] and flags[0] > 0.0:
                # the tree loop: written out in each dp_* kernel, like the stack
                far, q, S, bd2 = -1, -1.0, 1.0, eps2
                w0 = work
                exact = loo or mode == MODE_SED
                ts = tree_begin(
                    tree, a, b, utol2, ws, ts_stack, eps2 if exact else -1.0
                )
                while True:
                    lo, hi, ts = tree_next(
                        tree, ws, ts_stack, ts, a + 1, b, bd2, q, far
                    )
                    if lo < 0:
                        break
                    if loo:
                        f, qq, SS = scan_loo(cols, segment, a, b, utol2, lo, hi, lw)
                    else:
                        f, qq, SS = scan_line_cols(
                            cols, t, mode, a, b, utol2, lo, hi, buf, bits, u, pa
                        )
                    far, q, S, bd2 = tree_keep(far, q, S, f, qq, SS, eps2)
                    work += hi - lo
                tree_done(tree, flags, work - w0, b - a - 1)
                plain = False
            elif loo:
                far, q, S = scan_loo(cols, segment, a, b, utol2, a + 1, b, lw)
                work += b - a - 1
                plain = False
        if plain:
            far, q, S = scan_line_cols(
                cols, t, mode, a, b, utol2, a + 1, b, buf, bits, u, pa
            )
            work += b - a - 1
        if q > eps2 * S:
            keep[far] = 1
            if tree is not None:  # pruned with the lop flags when tree is None
                if b - a > tree[7]:
                    tree_split(tree, flags, a, b, far)
                lop = lopsided(a, b, far)
            if far - a > 1:
                stack[2 * sp] = a
                stack[2 * sp + 1] = far
                if tree is not None:
                    lops[sp] = lop
                sp += 1
            if b - far > 1:
                stack[2 * sp] = far
                stack[2 * sp + 1] = b
                if tree is not None:
                    lops[sp] = lop
                sp += 1
    return work


@njit(cache=True, nogil=True)
def _scan_kind(kind, x, y, z, Pt, t, mode, a, b, utol2, lo, hi, buf, bits, vu, u, pa):
    """The line-mode scan of :func:`dp_line`'s ``kind``, with its workspaces."""
    if kind == 2:
        return scan_line2(x, y, a, b, utol2, lo, hi, buf, bits)
    if kind == 3:
        return scan_line3(x, y, z, a, b, utol2, lo, hi, buf, bits)
    return scan_lineN(Pt, t, mode, a, b, utol2, lo, hi, buf, bits, vu, u, pa)


@njit(cache=True, nogil=True)
def scan_line_range(kind, x, y, z, Pt, t, mode, a, b, utol2, lo, hi, lop=False):
    """:func:`dp_line`'s scan of one chunk ``lo..hi-1`` of segment ``(a, b)``."""
    if lop and kind == 0 and mode != MODE_SED and b - a > EXACT_MIN:
        return scan_loo_range(Pt, mode == MODE_SEGMENT, a, b, utol2, lo, hi)
    buf = np.empty(BLOCK)
    bits = buf.view(np.int64)
    d = Pt.shape[0]
    vu, u, pa = np.empty(BLOCK), np.empty(d), np.empty(d)
    return _scan_kind(
        kind, x, y, z, Pt, t, mode, a, b, utol2, lo, hi, buf, bits, vu, u, pa
    )


@njit(cache=True, nogil=True)
def dp_line(kind, x, y, z, Pt, t, mode, eps2, utol2, keep, a0, b0, tree, lop0=False):
    """Epsilon-mode Douglas–Peucker on ``[a0, b0]``, column-major layouts.

    ``kind`` 2 and 3 use the structure-of-arrays columns ``x, y(, z)``
    (``"line"`` mode only); ``kind`` 0 uses the transposed data ``Pt`` of
    shape ``(d, n)`` in ``mode`` (``t`` the times, for ``"sed"``). Unused
    arrays may be empty. With ``kind`` 0, segments longer than
    :data:`~ndlfd.dp._exact.EXACT_MIN` points from a lopsided split (``lop0``
    for ``(a0, b0)``), but in ``"sed"``, are scanned by
    :func:`~ndlfd.dp._exact.scan_loo` (keys the tree bounds exactly).
    Explicit stack, no recursion; ``tree`` as in :func:`dp_cols`. Returns the
    number of distance evaluations.
    """
    keep[a0] = 1
    keep[b0] = 1
    if b0 - a0 < 2:
        return 0
    d = Pt.shape[0]
    buf = np.empty(BLOCK)
    bits = buf.view(np.int64)
    vu = np.empty(BLOCK)
    u = np.empty(d)
    pa = np.empty(d)
    segment = mode == MODE_SEGMENT
    if tree is not None:  # pruned at compile time when tree is None
        lw = loo_workspace(d)
        ws, ts_stack, flags = tree_workspace(tree, d, keep.shape[0])
    stack = np.empty(2 * ((b0 - a0) // 2 + 2), np.int64)
    if tree is not None:  # each segment's lop flag: read by the tree's branch only
        lops = np.empty((b0 - a0) // 2 + 2, np.bool_)
        lops[0] = lop0
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
            loo = lops[sp] and kind == 0 and mode != MODE_SED and b - a > EXACT_MIN
            if b - a > tree[7] and flags[0] > 0.0:
                # the tree loop: written out in each dp_* kernel, like the stack
                far, q, S, bd2 = -1, -1.0, 1.0, eps2
                w0 = work
                exact = kind in (2, 3) or loo or mode == MODE_SED
                ts = tree_begin(
                    tree, a, b, utol2, ws, ts_stack, eps2 if exact else -1.0
                )
                while True:
                    lo, hi, ts = tree_next(
                        tree, ws, ts_stack, ts, a + 1, b, bd2, q, far
                    )
                    if lo < 0:
                        break
                    if loo:
                        f, qq, SS = scan_loo(Pt, segment, a, b, utol2, lo, hi, lw)
                        far, q, S, bd2 = tree_keep(far, q, S, f, qq, SS, eps2)
                        work += hi - lo
                        continue
                    f, qq, SS = _scan_kind(
                        kind,
                        x,
                        y,
                        z,
                        Pt,
                        t,
                        mode,
                        a,
                        b,
                        utol2,
                        lo,
                        hi,
                        buf,
                        bits,
                        vu,
                        u,
                        pa,
                    )
                    far, q, S, bd2 = tree_keep(far, q, S, f, qq, SS, eps2)
                    work += hi - lo
                tree_done(tree, flags, work - w0, b - a - 1)
                plain = False
            elif loo:
                far, q, S = scan_loo(Pt, segment, a, b, utol2, a + 1, b, lw)
                work += b - a - 1
                plain = False
        if plain:
            # the scans called directly: through _scan_kind, 2-D ran 1.5x slower
            work += b - a - 1
            if kind == 2:
                far, q, S = scan_line2(x, y, a, b, utol2, a + 1, b, buf, bits)
            elif kind == 3:
                far, q, S = scan_line3(x, y, z, a, b, utol2, a + 1, b, buf, bits)
            else:
                far, q, S = scan_lineN(
                    Pt, t, mode, a, b, utol2, a + 1, b, buf, bits, vu, u, pa
                )
        if q > eps2 * S:
            keep[far] = 1
            if tree is not None:  # pruned with the lop flags when tree is None
                if b - a > tree[7]:
                    tree_split(tree, flags, a, b, far)
                lop = lopsided(a, b, far)
            if far - a > 1:
                stack[2 * sp] = a
                stack[2 * sp + 1] = far
                if tree is not None:
                    lops[sp] = lop
                sp += 1
            if b - far > 1:
                stack[2 * sp] = far
                stack[2 * sp + 1] = b
                if tree is not None:
                    lops[sp] = lop
                sp += 1
    return work
