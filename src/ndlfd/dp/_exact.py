"""Line and segment keys whose largest value over a box is known exactly.

The box tree (:mod:`ndlfd.dp._tree`) skips a node when no point in its box
can have a larger key than the best so far. Its general bounds are widened
for rounding, so they cannot skip a node whose points only *tie* with the
best: on a zigzag of constant height, whose corners all lie at the same
distance, every point is scanned for every split and a 1e6-point zigzag
costs ``n²/2`` distance evaluations.

A bound that holds bitwise needs a key that is monotone, in floating point,
in each coordinate of the point: then its largest value over a box is its
value at one corner, computed by the same operations. The line residual of
:mod:`ndlfd.dp._kernels`, ``r_k = U v_k - (v·u) u_k``, is not: ``v_k`` enters
both terms, and rounding can make ``r_k`` fall where it should rise. This
module computes the same residual in its *leave-one-out* form,

``r_k = C_k v_k - w_k u_k``, with ``C_k = Σ_{j≠k} u_j²`` and ``w_k = Σ_{j≠k} v_j u_j``,

equal to it in exact arithmetic (``C_k v_k - w_k u_k = U v_k - (v·u) u_k``).
``C_k >= 0`` does not depend on the point; ``w_k`` (a prefix sum plus a
suffix sum of the products ``v_j u_j``, each evaluated in one fixed order)
does not depend on ``v_k``. Rounding is monotone, so ``r_k`` is monotone in
every coordinate, and :func:`loo_key_bound` bounds the keys of a box exactly.

Computed plainly the form costs twice the plain residual; :func:`scan_loo`
first bounds each point's key by its plain residual and a bound of the
forms' difference, and computes the form only where that bound beats the
best so far. Even so, it costs 10-25 % more on a random walk, so the kernels
use it only where the tree needs it: on segments longer than
:data:`EXACT_MIN` points (the tree scans no shorter ones) that come from a
*lopsided* split (:func:`lopsided`: a zigzag's splits; the tree is filled
after enough of them), in every ``"segment"`` scan and every ``"line"`` scan
in 1-D and in 4 or more dimensions (2-D and 3-D line keys are cross
products, monotone already). Which form a segment gets depends on its
length and on how its parent was split, both given by the data, so the kept
points do not depend on the tree, the threads or the chunks.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "EXACT_MIN",
    "LOO_BLOCK",
    "LOO_FLOOR",
    "LOO_MANY",
    "LOO_SLACK",
    "loo_key",
    "loo_key_bound",
    "loo_keys_block",
    "loo_scales",
    "loo_workspace",
    "lopsided",
    "scan_loo",
    "scan_loo_range",
]

#: Segments from lopsided splits longer than this many points get the
#: leave-one-out keys; the tree (:func:`ndlfd.dp._tree.make_tree`) scans only
#: segments at least this long (``ndlfd.dp._simplify.TREE_MIN``).
EXACT_MIN = 4096

#: Points per block of :func:`scan_loo`.
LOO_BLOCK = 256


@njit(cache=True, nogil=True)
def lopsided(a, b, far):
    """Whether splitting ``(a, b)`` at ``far`` leaves a child under 1/16 of it.

    A zigzag makes only such splits, each child one point shorter; a random
    walk rarely (its farthest point is seldom near an end). The children of
    a lopsided split get the leave-one-out keys when long
    (:data:`EXACT_MIN`).
    """
    return min(far - a, b - far) * 16 < b - a


@njit(cache=True, nogil=True)
def loo_scales(u, C):
    """Fill ``C[k] = Σ_{j≠k} u_j²`` (prefix sum + suffix sum, in this order)."""
    d = u.shape[0]
    acc = 0.0
    for k in range(d):
        C[k] = acc
        acc += u[k] * u[k]
    acc = 0.0
    for k in range(d - 1, -1, -1):
        C[k] = C[k] + acc
        acc += u[k] * u[k]


@njit(cache=True, nogil=True)
def loo_workspace(d):
    """``(buf, bits, W, B, V)`` for :func:`scan_loo`.

    ``buf`` (length :data:`LOO_BLOCK`) takes the keys or their bounds and
    ``bits`` is its int64 view; ``W`` of shape ``(2, d)`` takes one point's
    products and sums, ``B`` of shape ``(2 d + 2, LOO_BLOCK)`` a block's;
    ``V`` of shape ``(4, d)`` holds ``P_a``, ``u``, ``P_b`` and ``C``.
    """
    buf = np.empty(LOO_BLOCK)
    W = np.empty((2, d))
    B = np.empty((2 * d + 2, LOO_BLOCK))
    return buf, buf.view(np.int64), W, B, np.empty((4, d))


@njit(cache=True, nogil=True)
def _end_key(cols, i, e, U):
    """The end key of point ``i``: ``Σ_k (x_k - e_k)²`` (``k`` ascending) · U²."""
    q = 0.0
    for k in range(len(cols)):
        r = cols[k][i] - e[k]
        q += r * r
    return q * (U * U)


@njit(cache=True, nogil=True)
def loo_key(cols, i, segment, U, V, W):
    """The leave-one-out key of point ``i`` (the definition; see the module).

    In this order: the products ``p_k = (x_k - xa_k) u_k`` and their prefix
    sums (``v·u`` is the last); with ``segment`` and ``v·u <= 0`` (``>= U``)
    the end key ``Σ_k (x_k - e_k)² · U²``; else the suffix sums added,
    ``r_k = C_k (x_k - xa_k) - w_k u_k`` and ``Σ_k r_k²``, ``k`` ascending.
    """
    d = len(cols)
    pa, u, pb, C = V[0], V[1], V[2], V[3]
    p, w = W[0], W[1]
    acc = 0.0
    for k in range(d):
        p[k] = (cols[k][i] - pa[k]) * u[k]
        w[k] = acc
        acc += p[k]
    if segment and (acc <= 0.0 or acc >= U):
        return _end_key(cols, i, pa if acc <= 0.0 else pb, U)
    acc = 0.0
    for k in range(d - 1, -1, -1):
        w[k] = w[k] + acc
        acc += p[k]
    q = 0.0
    for k in range(d):
        r = C[k] * (cols[k][i] - pa[k]) - w[k] * u[k]
        q += r * r
    return q


@njit(cache=True, nogil=True)
def loo_keys_block(cols, i0, m, segment, U, V, B, out):
    """:func:`loo_key` of points ``i0..i0+m-1`` into ``out``, column by column.

    The same operations in the same order per point, vectorized over the
    block (for blocks where many points are candidates: a zigzag's ties).
    """
    d = len(cols)
    pa, u, pb, C = V[0], V[1], V[2], V[3]
    prod, w, vu, suf = B[:d], B[d : 2 * d], B[2 * d], B[2 * d + 1]
    for j in range(m):
        vu[j] = 0.0
        suf[j] = 0.0
        out[j] = 0.0
    for k in range(d):  # products, and w_k = their prefix sum
        x = cols[k]
        pk = prod[k]
        wk = w[k]
        for j in range(m):
            p = (x[np.uint64(i0 + j)] - pa[k]) * u[k]
            pk[j] = p
            wk[j] = vu[j]
            vu[j] += p
    for k in range(d - 1, -1, -1):  # + the suffix sum
        pk = prod[k]
        wk = w[k]
        for j in range(m):
            wk[j] = wk[j] + suf[j]
            suf[j] += pk[j]
    for k in range(d):
        x = cols[k]
        wk = w[k]
        ck = C[k]
        for j in range(m):
            r = ck * (x[np.uint64(i0 + j)] - pa[k]) - wk[j] * u[k]
            out[j] += r * r
    if segment:  # past an end: the distance to it
        for j in range(m):
            if vu[j] <= 0.0 or vu[j] >= U:
                out[j] = _end_key(cols, i0 + j, pa if vu[j] <= 0.0 else pb, U)


@njit(cache=True, nogil=True, inline="always")
def _plain_bounds(cols, i0, m, U, slack, degenerate, rowwise, segment, B, out, V):
    """Each point's plain key plus the slack (or ``|v|²`` when degenerate).

    With ``segment``, a point past an end gets its end key (the same number
    as :func:`loo_key`'s: ``v·u`` is the same sum).
    """
    d = len(cols)
    pa, u, pb = V[0], V[1], V[2]
    vu, vv = B[2 * d], B[2 * d + 1]
    if rowwise and degenerate:
        for j in range(m):
            i = np.uint64(i0 + j)
            ss = 0.0
            for k in range(d):
                v = cols[k][i] - pa[k]
                ss += v * v
            out[j] = ss
        return
    # small d: each point's columns in registers, one flat loop per case with
    # no branch in it (so that it vectorizes), as in ndlfd.dp._kernels
    if rowwise and not segment:
        for j in range(m):
            i = np.uint64(i0 + j)
            s = 0.0
            ss = 0.0
            for k in range(d):
                v = cols[k][i] - pa[k]
                s += v * u[k]
                ss += v * v
            q = 0.0
            for k in range(d):
                r = U * (cols[k][i] - pa[k]) - s * u[k]
                q += r * r
            out[j] = q + (slack * ss + LOO_FLOOR)
        return
    if rowwise:
        UU = U * U
        for j in range(m):
            i = np.uint64(i0 + j)
            s = 0.0
            ss = 0.0
            for k in range(d):
                v = cols[k][i] - pa[k]
                s += v * u[k]
                ss += v * v
            q = 0.0
            qb = 0.0
            for k in range(d):
                r = U * (cols[k][i] - pa[k]) - s * u[k]
                q += r * r
                rb = cols[k][i] - pb[k]
                qb += rb * rb
            q = q + (slack * ss + LOO_FLOOR)
            if s <= 0.0:
                q = ss * UU  # the end key at P_a: the same sum as _end_key's
            if s >= U:
                q = qb * UU
            out[j] = q
        return
    for j in range(m):
        vu[j] = 0.0
        vv[j] = 0.0
        out[j] = 0.0
    for k in range(d):
        x = cols[k]
        for j in range(m):
            v = x[np.uint64(i0 + j)] - pa[k]
            vu[j] += v * u[k]
            vv[j] += v * v
    if degenerate:
        for j in range(m):
            out[j] = vv[j]
        return
    for k in range(d):
        x = cols[k]
        for j in range(m):
            r = U * (x[np.uint64(i0 + j)] - pa[k]) - vu[j] * u[k]
            out[j] += r * r
    for j in range(m):
        out[j] += slack * vv[j] + LOO_FLOOR
        if segment and (vu[j] <= 0.0 or vu[j] >= U):
            out[j] = _end_key(cols, i0 + j, pa if vu[j] <= 0.0 else pb, U)


#: ``(d + 4) * LOO_SLACK * eps * U² |v|²`` bounds the difference between the
#: plain key ``|U v - (v·u) u|²`` and :func:`loo_key` (both within
#: ``20 γ_{d+3} U² |v|²`` of the exact value; a factor 3 to spare for the
#: rounding of the bound and of its sum).
LOO_SLACK = 128.0

#: An absolute slack on top, far above what values near underflow can round
#: by (the doorway scales the data so that ``max|P|`` is within ``2**±64``).
LOO_FLOOR = 2.0**-600

#: A block with more candidates than this gets its keys column by column.
LOO_MANY = 16


@njit(cache=True, nogil=True)
def scan_loo(cols, segment, a, b, utol2, lo, hi, work):
    """Farthest point of ``(a, b)`` among ``lo..hi-1``, leave-one-out keys.

    ``cols`` holds the ``d`` columns (a tuple of 1-D arrays, or the
    transposed data of shape ``(d, n)``); ``segment`` picks the distance to
    the segment (endpoints past the ends) over the line. Returns ``(far, q,
    S)`` like the scans of :mod:`ndlfd.dp._kernels`: the first index with the
    largest :func:`loo_key`, ``S = U²`` (``1`` for coincident endpoints,
    keyed by the distance to ``P_a``). ``work`` is :func:`loo_workspace`'s.

    The leave-one-out form costs twice the plain residual, so each point
    first gets the plain key plus a bound of the two forms' difference
    (:data:`LOO_SLACK`); only a point whose bound beats the best so far gets
    its :func:`loo_key` (on a random walk, a few per segment); a block
    where more than :data:`LOO_MANY` points are candidates (a zigzag's ties)
    gets all its keys column by column (:func:`loo_keys_block`).
    """
    d = len(cols)
    buf, bits, W, B, V = work
    pa, u, pb, C = V[0], V[1], V[2], V[3]
    U = 0.0
    for k in range(d):
        pa[k] = cols[k][a]
        pb[k] = cols[k][b]
        u[k] = pb[k] - pa[k]
        U += u[k] * u[k]
    loo_scales(u, C)
    degenerate = U <= utol2
    UU = U * U
    S = 1.0 if degenerate else UU
    slack = (d + 4) * LOO_SLACK * 2.0**-53 * UU
    rowwise = d <= 8
    best_bits = np.int64(-1)  # bits order like the non-negative keys
    far = -1
    bestq = -1.0
    i0 = lo
    while i0 < hi:
        m = min(LOO_BLOCK, hi - i0)
        _plain_bounds(cols, i0, m, U, slack, degenerate, rowwise, segment, B, buf, V)
        bm = np.int64(-1)  # the block's largest bound (see ndlfd.dp._kernels)
        for j in range(m):
            v = bits[j]
            bm = v if v > bm else bm
        if bm <= best_bits:
            i0 += m
            continue
        if not degenerate:
            # the key of the largest bound first: a point whose bound is
            # below that key can neither beat nor tie it
            jm = 0
            while bits[jm] != bm:
                jm += 1
            km = loo_key(cols, i0 + jm, segment, U, V, W)
            many = 0
            for j in range(m):
                many += buf[j] >= km
            if many > LOO_MANY:
                loo_keys_block(cols, i0, m, segment, U, V, B, buf)
            else:
                for j in range(m):
                    if j != jm and buf[j] >= km and bits[j] > best_bits:
                        buf[j] = loo_key(cols, i0 + j, segment, U, V, W)
                buf[jm] = km  # what is left below km is a bound: it loses to km
        for j in range(m):
            if bits[j] > best_bits:
                best_bits = bits[j]
                bestq = buf[j]
                far = i0 + j
        i0 += m
    return far, bestq, S


@njit(cache=True, nogil=True)
def scan_loo_range(cols, segment, a, b, utol2, lo, hi):
    """:func:`scan_loo` of one chunk ``lo..hi-1``, with its own workspace."""
    return scan_loo(cols, segment, a, b, utol2, lo, hi, loo_workspace(len(cols)))


@njit(cache=True, nogil=True)
def _end_sq_bound(lo, hi, pe):
    """Largest ``(x - pe)²`` for ``x`` in ``[lo, hi]``, exactly as computed."""
    rl = lo - pe
    rh = hi - pe
    return max(rl * rl, rh * rh)


@njit(cache=True, nogil=True)
def loo_key_bound(bmin, bmax, node, ws, d, c0, U, segment):
    """The largest key :func:`scan_loo` can compute for a point of a box.

    The box is ``bmin[node, k] <= x_k <= bmax[node, k]``. ``ws`` holds the
    segment's ``P_a`` at ``0``, ``u`` at ``d``, ``P_b`` at ``3 d``, ``C``
    at ``c0`` (the layout of ``ndlfd.dp._tree``'s workspace), computed as
    :func:`scan_loo` computes them (``U > utol2``), and ``2 d`` values of
    scratch after ``C``.

    Every quantity of the key is monotone in each coordinate (rounding is
    monotone), so its extremes over the box are the same operations at box
    corners: ``v_k`` and the products ``v_k u_k`` at the ends of their
    ranges, the sums ``w_k`` (the same prefix and suffix order) of the
    smallest and of the largest products, ``r_k`` largest at the largest
    ``v_k`` and the ``w_k`` that makes ``w_k u_k`` smallest, and smallest the
    other way round. ``r_k²`` is at most the larger square of the two, and
    the key (a sum of non-negative terms, in the scan's order) at most the
    sum of these. With ``segment``, the range of ``v·u`` (the prefix sum of
    all ``d`` products) tells which of the line key and the two end keys
    (``|x - P_a|² U²``, ``|x - P_b|² U²``) a point of the box can take.
    The bound holds bitwise: a key of a point in the box never exceeds it.
    """
    sl = c0 + d  # the suffix sums of the smallest products, then the largest
    sh = c0 + 2 * d
    al = 0.0
    ah = 0.0
    for k in range(d - 1, -1, -1):
        p1 = (bmin[node, k] - ws[k]) * ws[d + k]
        p2 = (bmax[node, k] - ws[k]) * ws[d + k]
        ws[sl + k] = al
        ws[sh + k] = ah
        al += min(p1, p2)
        ah += max(p1, p2)
    al = 0.0  # now the prefix sums, w_k = prefix + suffix as the scan adds
    ah = 0.0
    q = 0.0
    for k in range(d):
        xa = ws[k]
        uk = ws[d + k]
        lo = bmin[node, k] - xa
        hi = bmax[node, k] - xa
        wl = al + ws[sl + k]
        wh = ah + ws[sh + k]
        up, down = (wl, wh) if uk >= 0.0 else (wh, wl)
        r_hi = ws[c0 + k] * hi - up * uk
        r_lo = ws[c0 + k] * lo - down * uk
        q += max(r_hi * r_hi, r_lo * r_lo)
        p1 = lo * uk
        p2 = hi * uk
        al += min(p1, p2)
        ah += max(p1, p2)
    if not segment:
        return q
    UU = U * U
    best = q if ah > 0.0 and al < U else 0.0  # (al, ah): the range of v·u
    if al <= 0.0:
        qa = 0.0
        for k in range(d):
            qa += _end_sq_bound(bmin[node, k], bmax[node, k], ws[k])
        best = max(best, qa * UU)
    if ah >= U:
        qb = 0.0
        for k in range(d):
            qb += _end_sq_bound(bmin[node, k], bmax[node, k], ws[3 * d + k])
        best = max(best, qb * UU)
    return best
