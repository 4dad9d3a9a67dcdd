"""Compiled kernels behind :mod:`ndlfd.hmm`.

The kernels trust their input (the checked wrappers in :mod:`ndlfd.hmm` build it)
and only add and compare log-probabilities: every logarithm is computed with numpy
beforehand so that ties are bit-exact against a dense numpy reference.

State space of the kernels. The ``S`` seen states are numbered ``0..S-1`` in the
order of their global ids (``gid[0..S-1]``). Slot ``S`` stands for the whole class
of states never seen in training: they all have identical rows of ``A`` and ``B``
and identical incoming probabilities, hence identical Viterbi scores, and the class
is represented by its lowest global id ``gid[S]``.

The argmax with ties to the lowest global id (``s > best or (s == best and
gid[i] < best_g)``) is written out in each loop of :func:`viterbi_sparse` on
purpose: those are the kernel's inner loops, kept flat.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["sample_backward", "viterbi_sparse"]


#: The largest global id: no state's id is above it (the argmax's start).
_BIG = np.iinfo(np.int64).max


@njit(cache=True, nogil=True)
def viterbi_sparse(
    obs,
    gid,
    has_unseen,
    in_indptr,
    in_src,
    in_logp,
    row_base,
    unseen_trans,
    em_indptr,
    em_state,
    em_logp,
    em_base,
    unseen_emit,
    emit_all,
    start_base,
    start_idx,
    start_logp,
):
    """Exact Viterbi over the sparse-counts-plus-row-baseline structure.

    Parameters
    ----------
    obs : ndarray of shape (T,), int64
        Symbols, each in ``0..n_symbols-1``.
    gid : ndarray of shape (S + 1,), int64
        Global id of each kernel slot; ``gid[S]`` is the lowest unseen id.
    has_unseen : bool
        Whether unseen states exist (slot ``S`` is usable).
    in_indptr, in_src, in_logp : ndarray
        Counted transitions grouped by destination slot: for destination ``j``,
        entries ``in_indptr[j]:in_indptr[j+1]`` hold the source slot and
        ``log((C + p) / (n_src + m p))``.
    row_base : ndarray of shape (S,), float64
        ``log(p / (n_i + m p))`` per seen source (``-inf`` when ``p == 0``).
    unseen_trans : float
        ``log(p / (m p))``, the transition log-probability out of an unseen state
        (``-inf`` when ``p == 0``).
    em_indptr, em_state, em_logp : ndarray
        Counted emissions grouped by symbol: for symbol ``o``, entries
        ``em_indptr[o]:em_indptr[o+1]`` hold the seen slot (increasing) and
        ``log((E + r) / (e_j + N_t r))``.
    em_base : ndarray of shape (S,), float64
        ``log(r / (e_j + N_t r))`` per seen state (``-inf`` when ``r == 0``).
    unseen_emit : float
        ``log(r / (N_t r))`` (``-inf`` when ``r == 0``).
    emit_all : bool
        ``r > 0``: every state can emit every symbol.
    start_base : float
        Log start probability of every slot not listed in ``start_idx``.
    start_idx, start_logp : ndarray
        Seen slots with a counted start probability and its logarithm.

    Returns
    -------
    path : ndarray of shape (T,), int64
        Kernel slots of the best path (map through ``gid``).
    log_probability : float
    fail_step : int
        ``-1`` on success, else the first step at which no state is reachable.
    """
    T = obs.shape[0]
    S = gid.shape[0] - 1
    NEG = -np.inf
    big = _BIG
    # Arrays filled by loops, not np.full or .copy(), and the offsets below
    # computed here, not by a kernel of their own: each of those compiled
    # apart on a first run (1.5 -> 1.3 s of CPU for this kernel).
    # off[t]: where step t's candidates start in the back-pointers
    off = np.empty(T + 1, dtype=np.int64)
    off[0] = 0
    for t in range(T):
        if emit_all:
            c = S + (1 if has_unseen else 0)
        else:
            c = em_indptr[obs[t] + 1] - em_indptr[obs[t]]
        off[t + 1] = off[t] + c
    # local candidate indices (< n_seen + 2 < 2**31): 4 bytes each
    bp = np.empty(off[T], dtype=np.int32)
    prev = np.empty(S + 1)
    cur = np.empty(S + 1)
    start = np.empty(S + 1)
    for i in range(S + 1):
        prev[i] = NEG
        cur[i] = NEG
        start[i] = start_base
    path = np.zeros(T, dtype=np.int64)

    # emission scratch for emit_all: em_cur[j] = log B[j, o] for the current o
    em_cur = np.empty(em_base.shape[0])
    for i in range(em_base.shape[0]):
        em_cur[i] = em_base[i]

    # step 0
    for e in range(start_idx.shape[0]):
        start[start_idx[e]] = start_logp[e]
    o = obs[0]
    # Step 0 and the steps below each write out the emission scratch update
    # and the emission lookup, and each loop its tie-breaking argmax: unrolled
    # on purpose, these are the kernel's inner loops, kept flat (no helper
    # call per candidate).
    if emit_all:
        for e in range(em_indptr[o], em_indptr[o + 1]):
            em_cur[em_state[e]] = em_logp[e]
    n0 = off[1] - off[0]
    any_finite = False
    for k in range(n0):
        j = k if emit_all else em_state[em_indptr[o] + k]
        if emit_all:
            lb = em_cur[j] if j < S else unseen_emit
        else:
            lb = em_logp[em_indptr[o] + k]
        s = start[j] + lb
        cur[j] = s
        bp[k] = -1
        if s > NEG:
            any_finite = True
    if emit_all:
        for e in range(em_indptr[o], em_indptr[o + 1]):
            em_cur[em_state[e]] = em_base[em_state[e]]
    if not any_finite:
        return path, NEG, 0

    for t in range(1, T):
        # swap: prev <- cur (step t-1); cur must be all -inf
        tmp = prev
        prev = cur
        cur = tmp
        o_prev = obs[t - 1]
        o = obs[t]
        n_prev = off[t] - off[t - 1]
        # (b) best predecessor under the pseudo-count alone, over all active slots
        best_b = NEG
        best_b_g = big
        best_b_l = -1
        for k in range(n_prev):
            i = k if emit_all else em_state[em_indptr[o_prev] + k]
            d = prev[i]
            if d == NEG:
                continue
            if i < S:
                s = d + row_base[i]
            else:
                s = d + unseen_trans
            if s == NEG:
                continue
            # argmax, ties to the lowest global id: unrolled on purpose (above)
            if s > best_b or (s == best_b and gid[i] < best_b_g):
                best_b = s
                best_b_g = gid[i]
                best_b_l = i
        # as at step 0, written out on purpose
        if emit_all:
            for e in range(em_indptr[o], em_indptr[o + 1]):
                em_cur[em_state[e]] = em_logp[e]
        n_cur = off[t + 1] - off[t]
        any_finite = False
        for k in range(n_cur):
            j = k if emit_all else em_state[em_indptr[o] + k]
            best = best_b
            bg = best_b_g
            bl = best_b_l
            if j < S:
                # (a) counted transitions into j
                for e in range(in_indptr[j], in_indptr[j + 1]):
                    i = in_src[e]
                    d = prev[i]
                    if d == NEG:
                        continue
                    s = d + in_logp[e]
                    # argmax, ties to the lowest global id: unrolled on purpose
                    if s > best or (s == best and gid[i] < bg):
                        best = s
                        bg = gid[i]
                        bl = i
            bp[off[t] + k] = bl
            if best == NEG:
                cur[j] = NEG
                continue
            if emit_all:
                lb = em_cur[j] if j < S else unseen_emit
            else:
                lb = em_logp[em_indptr[o] + k]
            s = best + lb
            cur[j] = s
            if s > NEG:
                any_finite = True
        if emit_all:
            for e in range(em_indptr[o], em_indptr[o + 1]):
                em_cur[em_state[e]] = em_base[em_state[e]]
        # clean step t-1 out of prev so it is all -inf again
        for k in range(n_prev):
            prev[k if emit_all else em_state[em_indptr[o_prev] + k]] = NEG
        if not any_finite:
            return path, NEG, t

    # final state: best score, ties to the lowest global id (the argmax
    # unrolled on purpose, as in the loops above)
    o = obs[T - 1]
    n_last = off[T] - off[T - 1]
    best = NEG
    bg = big
    bk = -1
    for k in range(n_last):
        j = k if emit_all else em_state[em_indptr[o] + k]
        s = cur[j]
        if s == NEG:
            continue
        if s > best or (s == best and gid[j] < bg):
            best = s
            bg = gid[j]
            bk = k
    # backtrack through positions within each step's candidate list
    k = bk
    for t in range(T - 1, -1, -1):
        o = obs[t]
        j = k if emit_all else em_state[em_indptr[o] + k]
        path[t] = j
        if t == 0:
            break
        i = bp[off[t] + k]
        # position of slot i among the candidates of step t-1
        o_prev = obs[t - 1]
        if emit_all:
            k = i
        else:
            lo = em_indptr[o_prev]
            hi = em_indptr[o_prev + 1]
            while lo < hi:
                mid = (lo + hi) // 2
                if em_state[mid] < i:
                    lo = mid + 1
                else:
                    hi = mid
            k = lo - em_indptr[o_prev]
    return path, best, -1


@njit(cache=True, nogil=True)
def _first_above(cum, x):
    """First index whose cumulative weight exceeds ``x``.

    Past the end (rounding), the last index with a positive weight.
    """
    lo, hi = 0, cum.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if cum[mid] > x:
            hi = mid
        else:
            lo = mid + 1
    if lo < cum.shape[0]:
        return lo
    k = cum.shape[0] - 1
    while k > 0 and cum[k] <= cum[k - 1]:
        k -= 1
    return k


@njit(cache=True, nogil=True)
def sample_backward(alpha, W, last, col_indptr, col_rows, col_vals, u):
    """Backward sampling of FFBS over the seen states and the unseen class.

    Slot ``S`` (``alpha.shape[1]``) is the unseen class, as in
    :func:`viterbi_sparse`.

    Parameters
    ----------
    alpha : ndarray of shape (T, S)
        Filtered probabilities of the seen states.
    W : ndarray of shape (T, S + 1)
        Per step the cumulative baseline weights ``alpha_t(i) b_i`` of the
        seen states, then the unseen class's ``alpha_t(u) / m``.
    last : ndarray of shape (S + 1,)
        Cumulative filtered probabilities at the last step (unseen class last).
    col_indptr, col_rows, col_vals : ndarray
        The counted part ``K`` of the transitions by column (CSC over the seen
        states): the rows with a counted transition into each state and
        ``K[i, j]``.
    u : ndarray of shape (n_samples, T)
        Uniforms in ``[0, 1)``, one per drawn state.

    Returns
    -------
    idx : ndarray of shape (n_samples, T), int64
        Slots ``0..S``.
    """
    n, T = u.shape
    S = alpha.shape[1]
    out = np.empty((n, T), dtype=np.int64)
    for s in range(n):
        j = _first_above(last, u[s, T - 1] * last[S])
        out[s, T - 1] = j
        for t in range(T - 2, -1, -1):
            c = 0.0
            lo, hi = 0, 0
            if j < S:
                lo, hi = col_indptr[j], col_indptr[j + 1]
                for k in range(lo, hi):
                    c += alpha[t, col_rows[k]] * col_vals[k]
            flow = W[t, S]
            x = u[s, t] * (c + flow)
            if c > 0.0 and (x < c or not flow > 0.0):
                # a counted transition into j: scan its predecessors
                acc = 0.0
                j_new = -1
                for k in range(lo, hi):
                    w = alpha[t, col_rows[k]] * col_vals[k]
                    if w > 0.0:
                        acc += w
                        j_new = col_rows[k]
                        if acc > x:
                            break
                j = j_new
            else:
                j = _first_above(W[t], x - c)
            out[s, t] = j
    return out
