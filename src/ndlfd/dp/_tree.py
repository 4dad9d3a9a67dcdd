"""Exact pruning of Douglas–Peucker scans with a tree of bounding boxes.

A segment's farthest point is the *first* index with the largest key (see
:mod:`ndlfd.dp._kernels`). On long segments most points cannot be it: a
1e6-point zigzag whose every corner is kept splits one point off per step,
and a plain scan pays ``n²/2`` distance evaluations for it.

The points are grouped into blocks of consecutive indices (:data:`LEAF`
points), and blocks into a binary tree; every node holds the axis-aligned
bounding box of its points (:func:`fill_tree`). For one segment, the walk
(:func:`tree_begin`, :func:`tree_next`) visits the nodes overlapping the
segment's interior depth first, left to right, computes an upper bound of the
distance of any point in the node's box, and skips the node when that bound
cannot beat the best key found so far (or the tolerance). The caller scans the
leaves that are left with its usual kernel, so every key it compares is the
same number as in a plain scan, and ties still go to the first index: leaves
come in index order, a pruned node holds no key larger than the best so far,
and an equal key at a later index would lose anyway.

Bounds (``v = p - P_a``, ``u = P_b - P_a``, box center ``c``, half widths
``h``, ``dist`` 1-Lipschitz in ``p``):

- line: ``dist(c) + min(Σ_k h_k |M e_k|, |h|)`` with ``M`` the projection
  orthogonal to ``u`` (``|M e_k|² = 1 - u_k²/|u|²``);
- segment: the line's bound ``B`` and the overshoot ``o`` of the projection
  ``w = v·u / |u|²`` past ``[0, 1]`` over the box (``w(c) ± Σ_k h_k |u_k| /
  |u|²``): ``sqrt(B² + (o |u|)²)``;
- sed: the distance of ``c`` to the chord at the box's middle time ``+ |h|
  + (half time span) |u| / (t_b - t_a)``;
- coincident endpoints: ``|c - P_a| + |h|``;
- ``"paper"``: none (its determinant is no distance); only its exact bound
  below prunes.

Every bound is then widened by a relative ``1e-8`` and an absolute ``1e-8 R``
(``R = 4 max|P| sqrt(d)``, a bound of ``|v|`` and ``|u|``): many orders of
magnitude above the rounding of the kernels' keys (a few ulps of ``|v|``), so
a pruned node never holds a point whose computed key would have won.

Widened bounds cannot skip a node whose points *tie* with the best so far.
For the ``"line"`` and ``"segment"`` scans of long segments from lopsided
splits (a zigzag's), :func:`exact_key_bound` bounds the scan's own computed
keys exactly (rounding is monotone; in 2-D and 3-D ``"line"`` keys are cross
products, elsewhere the leave-one-out keys of :mod:`ndlfd.dp._exact`), so
such a node is skipped too: a 1e6-point zigzag of constant height no longer
costs ``n²/2``. So are the ``"sed"`` keys (each term is monotone in one
coordinate and the time; the doorway removes the path's mean drift first,
so that the boxes of a path that moves with time stay tight) and the
paper's determinant (a linear form of two or three coordinates).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._exact import EXACT_MIN, loo_key_bound, loo_scales, lopsided

__all__ = [
    "LEAF",
    "TREE_LINE",
    "TREE_PAPER",
    "TREE_POINT",
    "TREE_SED",
    "TREE_SEGMENT",
    "exact_key_bound",
    "fill_tree",
    "make_tree",
    "node_bound",
    "tree_begin",
    "tree_done",
    "tree_keep",
    "tree_levels",
    "tree_next",
    "tree_split",
    "tree_workspace",
]

#: Points per leaf block of the tree.
LEAF = 128

#: Bound kinds of :func:`tree_begin`.
TREE_LINE = 0
TREE_SEGMENT = 1
TREE_SED = 2
TREE_POINT = 3
TREE_PAPER = 4

_WIDEN = 1e-8


def tree_levels(n):
    """``offs``: level ``l`` (0 = leaves) holds the nodes ``offs[l]..offs[l+1]-1``.

    Node ``j`` of level ``l`` covers the rows ``j · LEAF · 2**l`` up to the
    next node's first row (or ``n``).
    """
    sizes = [max(1, -(-n // LEAF))]
    while sizes[-1] > 1:
        sizes.append((sizes[-1] + 1) // 2)
    return np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)


@njit(cache=True, nogil=True)
def fill_tree(P, bmin, bmax, offs):
    """Fill the bounding boxes ``bmin[node] .. bmax[node]`` (shape ``(d,)``).

    Every entry is written once, with its final value: kernels on other
    threads that share the tree and have filled it already may read it
    meanwhile (see :func:`tree_split`).
    """
    n, d = P.shape
    for j in range(offs[1]):
        s = j * LEAF
        e = min(n, s + LEAF)
        for k in range(d):
            lo = P[s, k]
            hi = P[s, k]
            for i in range(s + 1, e):
                x = P[i, k]
                lo = min(lo, x)
                hi = max(hi, x)
            bmin[j, k] = lo
            bmax[j, k] = hi
    for lv in range(1, offs.shape[0] - 1):
        for j in range(offs[lv + 1] - offs[lv]):
            node = offs[lv] + j
            c0 = offs[lv - 1] + 2 * j
            c1 = min(c0 + 1, offs[lv] - 1)
            for k in range(d):
                bmin[node, k] = min(bmin[c0, k], bmin[c1, k])
                bmax[node, k] = max(bmax[c0, k], bmax[c1, k])


def make_tree(P, t, kind, m, tree_min, budget=0):
    """The tree tuple the kernels take.

    ``(P, t, bmin, bmax, offs, kind, m, tree_min, budget)``. The boxes are
    allocated here and filled by a kernel (:func:`tree_split`) once the work
    spent on long lopsided splits passes ``budget`` point evaluations (``0``:
    at its start); then segments longer than ``tree_min`` points are scanned
    through the tree. ``kind=None`` never fills one.
    """
    n, d = P.shape
    if kind is None:
        e = np.zeros((0, d))
        return (P, t, e, e, np.zeros(2, np.int64), 0, float(m), n, -1)
    offs = tree_levels(n)
    bmin, bmax = np.empty((offs[-1], d)), np.empty((offs[-1], d))
    return (P, t, bmin, bmax, offs, int(kind), float(m), int(tree_min), int(budget))


@njit(cache=True, nogil=True)
def tree_workspace(tree, d, n):
    """``(ws, stack, flags)``: the walk's workspaces, and the kernel's flags.

    ``flags[0] > 0`` once this kernel call has filled the tree (at once when
    the budget is 0) and ``< 0`` once it gave up on it (:func:`tree_done`),
    ``flags[1]`` is the work of its lopsided splits, ``flags[2:4]`` the points
    scanned through the tree and the segments' lengths.
    """
    levels = max(1, math.ceil(math.log2(max(2, n) / LEAF)) + 2)
    flags = np.zeros(4)
    if tree[8] == 0 and tree[2].shape[0] > 0:
        fill_tree(tree[0], tree[2], tree[3], tree[4])
        flags[0] = 1.0
    depth = 4 * (levels + 4)  # the walk's stack: (level, node) pairs
    return np.zeros(8 * d + 10), np.empty(depth, np.int64), flags


@njit(cache=True, nogil=True)
def tree_split(tree, flags, a, b, far):
    """Account for the split of ``(a, b)`` at ``far``.

    A split of a segment longer than ``tree_min`` that leaves a child of
    less than a sixteenth of it is lopsided: a zigzag makes only such splits,
    each one point shorter, and scanning them plainly costs ``n²/2``. Their
    work is summed in ``flags[1]``; past the budget this kernel call fills
    the tree and sets ``flags[0]``. Kernels on other threads may fill the
    same tree at the same time: each writes the same final values.
    """
    P, _, bmin, bmax, offs, _, _, tree_min, budget = tree
    if flags[0] != 0.0 or budget < 0 or b - a <= tree_min:
        return
    if not lopsided(a, b, far):
        return
    flags[1] += b - a
    if flags[1] > budget:
        fill_tree(P, bmin, bmax, offs)
        flags[0] = 1.0


# workspace layout: ws[0:d] = P_a, ws[d:2d] = u, ws[2d:3d] = |M e_k|,
# ws[3d:4d] = P_b, ws[4d:5d] = scratch; then the scalars at 5d + these; then
# the leave-one-out scales C at 5d + 10 and scratch of 2d after them
_U, _KIND, _DT, _UN, _R, _TA, _N, _EXACT, _QEPS, _PROBE = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9

# ws[5d + _EXACT]: which keys exact_key_bound bounds (0: none)
_EXACT_CROSS = 1.0  # the 2-D and 3-D line scans' cross products
_EXACT_LOO = 2.0  # the leave-one-out line keys (ndlfd.dp._exact)
_EXACT_LOO_SEGMENT = 3.0  # the same, with the segment's end keys
_EXACT_SED = 4.0  # the "sed" keys
_EXACT_PAPER = 5.0  # the paper's determinant


@njit(cache=True, nogil=True)
def _paper_weights(ws, d):
    """The paper determinant's weights of its columns, at ``ws[5d + 10 + k]``.

    As ``scan_generic`` computes them: in 2-D ``(u_1, -u_0)``, else, over the
    last three columns ``a, b, c``, ``(u_b - u_c, u_c - u_a, u_a - u_b)``.
    """
    c0 = 5 * d + 10
    if d == 2:
        ws[c0] = ws[d + 1]
        ws[c0 + 1] = -ws[d]
        return
    ka = d - 3
    ua, ub, uc = ws[d + ka], ws[d + ka + 1], ws[d + ka + 2]
    ws[c0 + ka] = ub - uc
    ws[c0 + ka + 1] = uc - ua
    ws[c0 + ka + 2] = ua - ub


@njit(cache=True, nogil=True)
def tree_begin(tree, a, b, utol2, ws, stack, exact_eps2):
    """Start the walk for segment ``(a, b)``; returns the stack size.

    ``tree`` is :func:`make_tree`'s tuple, filled; ``ws`` and ``stack`` come
    from :func:`tree_workspace`. Coincident endpoints (``|u|² <= utol2``, except
    for ``"sed"``) are bounded by the distance to ``P_a``. ``exact_eps2 >= 0``
    (the tolerance squared) turns on the exact bounds of the scan's own keys
    (:func:`exact_key_bound`): the caller passes it when its keys are
    ``scan_line2``'s or ``scan_line3``'s (2-D and 3-D ``"line"``),
    :func:`~ndlfd.dp._exact.scan_loo`'s (other ``"line"`` and ``"segment"``
    scans of long segments from lopsided splits), a ``"sed"`` scan's or the
    paper determinant's, else ``-1``. The walk starts with the leaf of the
    last interior point (see :func:`tree_next`).
    """
    P, t, _, _, offs, kind, m, _, _ = tree
    d = P.shape[1]
    U = 0.0
    for k in range(d):
        ws[k] = P[a, k]
        ws[3 * d + k] = P[b, k]
        uk = P[b, k] - P[a, k]
        ws[d + k] = uk
        U += uk * uk
    for k in range(d):
        uk = ws[d + k]
        ws[2 * d + k] = math.sqrt(max(0.0, 1.0 - uk * uk / U)) if U > 0.0 else 1.0
    s = 5 * d
    ws[s + _U] = U
    ws[s + _KIND] = TREE_POINT if kind != TREE_SED and U <= utol2 else kind
    if kind == TREE_SED:
        dt = t[b] - t[a]
        ws[s + _DT] = dt
        ws[s + _UN] = math.sqrt(U) / dt
        ws[s + _TA] = t[a]
    ws[s + _R] = 4.0 * m * math.sqrt(d)
    ws[s + _N] = P.shape[0]
    ws[s + _EXACT] = 0.0
    on = exact_eps2 >= 0.0 and U > utol2 and kind in (TREE_LINE, TREE_SEGMENT)
    if on and d in (2, 3) and kind == TREE_LINE:
        S = U  # the scan's S (summed in the same order) and q > eps2 * S
        ws[s + _EXACT] = _EXACT_CROSS
        ws[s + _QEPS] = exact_eps2 * S
    elif exact_eps2 >= 0.0 and kind == TREE_PAPER and U > utol2 and d >= 2:
        _paper_weights(ws, d)
        ws[s + _EXACT] = _EXACT_PAPER
        ws[s + _QEPS] = exact_eps2 * U  # the scan's S = U
    elif exact_eps2 >= 0.0 and kind == TREE_SED:
        S = ws[s + _DT] * ws[s + _DT]  # the scans' S = D * D
        ws[s + _EXACT] = _EXACT_SED
        ws[s + _QEPS] = exact_eps2 * S
    elif on and b - a > EXACT_MIN:
        loo_scales(ws[d : 2 * d], ws[5 * d + 10 : 6 * d + 10])
        S = U * U
        segment = kind == TREE_SEGMENT
        ws[s + _EXACT] = _EXACT_LOO_SEGMENT if segment else _EXACT_LOO
        ws[s + _QEPS] = exact_eps2 * S
    stack[0] = offs.shape[0] - 2  # the root: its level, then its index
    stack[1] = 0
    # on top, the leaf of the last interior point, taken first: a zigzag's
    # farthest point lies next to one end, and the walk goes left to right
    stack[2] = 0
    stack[3] = (b - 1) // LEAF
    ws[s + _PROBE] = stack[3] + 0.5  # .5: not taken yet
    return 2


@njit(cache=True, nogil=True)
def node_bound(bmin, bmax, node, ws, d, t, s0, e0):
    """Widened upper bound of the squared distance of the points of ``node``.

    ``node`` is a row of ``bmin``/``bmax`` covering the rows ``s0..e0-1``
    (their times bound the ``"sed"`` chord); ``ws`` is set up by
    :func:`tree_begin`. Compare with ``key / S`` of the kernels.
    """
    s = 5 * d
    U = ws[s + _U]
    kind = int(ws[s + _KIND])
    sc = 4 * d
    cc = 0.0  # |c - P_a|²
    hh = 0.0  # |h|²
    cu = 0.0  # (c - P_a)·u
    hm = 0.0  # Σ h_k |M e_k|
    hu = 0.0  # Σ h_k |u_k|
    for k in range(d):
        lo = bmin[node, k]
        hi = bmax[node, k]
        c = 0.5 * (lo + hi) - ws[k]
        h = 0.5 * (hi - lo)
        ws[sc + k] = c
        cc += c * c
        hh += h * h
        cu += c * ws[d + k]
        hm += h * ws[2 * d + k]
        hu += h * abs(ws[d + k])
    hn = math.sqrt(hh)
    if kind == TREE_PAPER:  # not a distance: only its exact bound prunes
        return math.inf
    if kind == TREE_POINT:
        dist = math.sqrt(cc) + hn
    elif kind == TREE_SED:
        # the chord is at P_a + (t - t_a) / (t_b - t_a) · u at time t
        tc = (0.5 * (t[s0] + t[e0 - 1]) - ws[s + _TA]) / ws[s + _DT]
        rr = 0.0
        for k in range(d):
            r = ws[sc + k] - tc * ws[d + k]
            rr += r * r
        dist = math.sqrt(rr) + hn + 0.5 * (t[e0 - 1] - t[s0]) * ws[s + _UN]
    else:
        w = cu / U if U > 0.0 else 0.0
        rr = 0.0
        for k in range(d):
            r = ws[sc + k] - w * ws[d + k]
            rr += r * r
        dist = math.sqrt(rr) + min(hm, hn)
        if kind == TREE_SEGMENT:
            # squared distance to the segment = to the line + the overshoot
            # of the projection past an endpoint, bounded over the box
            dw = hu / U if U > 0.0 else 0.0
            over = max(0.0, dw - w, w + dw - 1.0) * math.sqrt(U)
            dist = math.sqrt(dist * dist + over * over)
    dist = dist * (1.0 + _WIDEN) + _WIDEN * ws[s + _R]
    return dist * dist * (1.0 + _WIDEN)


@njit(cache=True, nogil=True)
def _cross_sq_bound(p0, p1, pa, s, q0, q1, qa, r):
    """Largest ``c * c`` of ``c = (p - pa) * s - (q - qa) * r`` on a box.

    ``p`` in ``[p0, p1]``, ``q`` in ``[q0, q1]``. Rounding is monotone, so the
    computed ``c`` is monotone in ``p`` (non-decreasing when ``s >= 0``) and in
    ``q`` (non-increasing when ``r >= 0``): its extremes over the box are the
    same expression at two corners, exactly, in floating point.
    """
    ph, pl = (p1, p0) if s >= 0.0 else (p0, p1)
    ql, qh = (q0, q1) if r >= 0.0 else (q1, q0)
    hi = (ph - pa) * s - (ql - qa) * r
    lo = (pl - pa) * s - (qh - qa) * r
    return max(hi * hi, lo * lo)


@njit(cache=True, nogil=True)
def exact_key_bound(bmin, bmax, node, ws, d, t0=0.0, t1=0.0):
    """The largest key the scan can compute for a point of ``node``'s box.

    The leave-one-out keys of long segments are bounded by
    :func:`~ndlfd.dp._exact.loo_key_bound`. The ``"sed"`` keys are sums over
    ``k`` of ``r_k²``, ``r_k = D (x_k - xa_k) - s u_k`` (``s = t - t_a``,
    ``D = t_b - t_a``; the times of the node's rows lie in ``[t0, t1]``),
    each ``r_k`` of the form :func:`_cross_sq_bound` bounds. The paper's
    determinant (``"paper"``, ``d >= 2``) is a sum of ``(x_k - xa_k) w_k``
    over two or three columns, largest and smallest at corners. The keys of
    ``scan_line2`` /
    ``scan_line3`` (2-D and 3-D ``"line"``) are squared cross products,
    ``c = (x - xa) * uy - (y - ya) * ux`` in 2-D and the sum
    ``cx² + cy² + cz²`` of three such components in 3-D, evaluated in this
    order. Each component's square is bounded exactly by
    :func:`_cross_sq_bound`, and a sum of rounded non-negative terms is
    monotone in each term, so the bound holds bitwise, with no widening. Ties
    at a later index never win, so a node whose bound is at most the best key
    so far can be skipped even when its points tie with it (a zigzag of
    constant height).
    """
    exact = ws[5 * d + _EXACT]
    if exact == _EXACT_PAPER:
        # c = sum of (x_k - xa_k) w_k over its 2 or 3 columns, in order
        k0 = 0 if d == 2 else d - 3
        hi = 0.0
        lo = 0.0
        for k in range(k0, d):
            w = ws[5 * d + 10 + k]
            p1 = (bmin[node, k] - ws[k]) * w
            p2 = (bmax[node, k] - ws[k]) * w
            hi = max(p1, p2) if k == k0 else hi + max(p1, p2)
            lo = min(p1, p2) if k == k0 else lo + min(p1, p2)
        return max(hi * hi, lo * lo)
    if exact == _EXACT_SED:
        D = ws[5 * d + _DT]
        ta = ws[5 * d + _TA]
        q = 0.0
        for k in range(d):  # the scans' order
            lo, hi = bmin[node, k], bmax[node, k]
            q += _cross_sq_bound(lo, hi, ws[k], D, t0, t1, ta, ws[d + k])
        return q
    if exact != _EXACT_CROSS:
        segment = exact == _EXACT_LOO_SEGMENT
        U = ws[5 * d + _U]
        return loo_key_bound(bmin, bmax, node, ws, d, 5 * d + 10, U, segment)
    x0 = bmin[node, 0]
    x1 = bmax[node, 0]
    y0 = bmin[node, 1]
    y1 = bmax[node, 1]
    if d == 2:
        xa, ya, ux, uy = ws[0], ws[1], ws[2], ws[3]
        return _cross_sq_bound(x0, x1, xa, uy, y0, y1, ya, ux)
    z0 = bmin[node, 2]
    z1 = bmax[node, 2]
    xa, ya, za, ux, uy, uz = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5]
    cx = _cross_sq_bound(y0, y1, ya, uz, z0, z1, za, uy)  # dy * uz - dz * uy
    cy = _cross_sq_bound(z0, z1, za, ux, x0, x1, xa, uz)  # dz * ux - dx * uz
    cz = _cross_sq_bound(x0, x1, xa, uy, y0, y1, ya, ux)  # dx * uy - dy * ux
    return cx + cy + cz


@njit(cache=True, nogil=True)
def tree_next(tree, ws, stack, sp, lo, hi, best_d2, best_key, best_far):
    """The next leaf range to scan for the interior ``lo..hi-1``.

    Returns ``(lo', hi', sp)``: a sub-range of ``lo..hi-1`` whose leaf may
    hold a point with squared distance above ``best_d2`` (the larger of
    ``epsilon²`` and the best so far); ``(-1, -1, 0)`` when none is left.
    With the exact bounds on (:func:`tree_begin`), a node is skipped instead
    when no key of its points can exceed ``epsilon² S`` or the best key so
    far, ``best_key`` (``-1`` before any) at ``best_far``, nor equal it at an
    index before ``best_far`` (ties go to the first index).

    The leaf of the segment's last interior point comes first, then the
    walk goes depth first, left to right: a zigzag's farthest point lies
    next to one end of the segment, either one, and once it is found the
    rest is skipped. :func:`tree_keep` keeps the first index of the largest
    key whatever the order of the leaves.
    """
    _, t, bmin, bmax, offs, _, _, _, _ = tree
    d = bmin.shape[1]
    n = int(ws[5 * d + _N])
    exact = ws[5 * d + _EXACT] > 0.0
    qeps = ws[5 * d + _QEPS]
    while sp > 0:
        sp -= 1
        lv = stack[2 * sp]
        j = stack[2 * sp + 1]
        span = LEAF << lv
        s0 = j * span
        e0 = min(n, s0 + span)
        if e0 <= lo or s0 >= hi:
            continue
        if lv == 0 and j + 0.5 == ws[5 * d + _PROBE]:
            ws[5 * d + _PROBE] = j  # the probe, taken now
        elif lv == 0 and j == ws[5 * d + _PROBE]:
            continue  # taken first
        node = offs[lv] + j
        # the widened bound first (cheap), then the exact one (skips ties)
        if node_bound(bmin, bmax, node, ws, d, t, s0, e0) <= best_d2:
            continue
        if exact:
            t0, t1 = (t[s0], t[e0 - 1]) if t.shape[0] > 0 else (0.0, 0.0)
            bound = exact_key_bound(bmin, bmax, node, ws, d, t0, t1)
            if bound <= qeps or bound < best_key:
                continue
            if bound == best_key and max(s0, lo) > best_far:
                continue
        if lv == 0:
            return max(s0, lo), min(e0, hi), sp
        c = 2 * j
        if c + 1 < offs[lv] - offs[lv - 1]:
            stack[2 * sp] = lv - 1
            stack[2 * sp + 1] = c + 1
            sp += 1
        stack[2 * sp] = lv - 1
        stack[2 * sp + 1] = c
        sp += 1
    return -1, -1, 0


@njit(cache=True, nogil=True)
def tree_done(tree, flags, scanned, length):
    """Account for a segment of ``length`` points scanned through the tree.

    Where the bounds cannot prune (exact ties: a zigzag of constant height
    has every corner at the same distance, and an equal key at a later
    index never wins, so no node can be skipped) the tree only adds the cost
    of its bounds; once the segments through it sum to 16 ``tree_min`` and
    more than half of their points were scanned, this kernel call stops
    using it (``flags[0] = -1``).
    """
    flags[2] += scanned
    flags[3] += length
    if flags[3] >= 16 * tree[7] and flags[2] > 0.5 * flags[3]:
        flags[0] = -1.0


@njit(cache=True, nogil=True)
def tree_keep(far, q, S, f, qq, SS, eps2):
    """Fold a leaf's ``(f, qq, SS)`` into the best ``(far, q, S)`` so far.

    Returns ``(far, q, S, best_d2)``. The leaves come in any order
    (:func:`tree_next`): a leaf wins with a larger key, or the same key at
    an earlier index, so the first index of the maximum is kept.
    """
    if qq > q or (qq == q and 0 <= f < far):
        far, q, S = f, qq, SS
    return far, q, S, max(eps2, q / S)
