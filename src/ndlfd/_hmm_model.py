"""Counts and estimation of the supervised discrete HMM (see :mod:`ndlfd.hmm`).

:class:`DiscreteHMM` holds the sparse counts over the states seen in training
and builds the log tables the decoders use; :func:`estimate` and :func:`merge`
make one. Decoding lives in :mod:`ndlfd._hmm_decode`, the file format in
:mod:`ndlfd._hmm_format`.
"""

from __future__ import annotations

import numbers
import os

import numpy as np
import scipy.sparse as sp

from ._errors import ModelFormatError, NotFittedError, ValidationError
from ._fileformat import load_npz, save_npz
from ._registry import Registry
from ._validation import (
    check_int_sequence,
    check_nonnegative_scalar,
    check_positive_int,
)

__all__ = ["DENSE_LIMIT_BYTES", "DiscreteHMM", "estimate", "merge"]

#: Largest dense matrix (in bytes) that ``dense=True`` accessors build: 256 MiB.
DENSE_LIMIT_BYTES = 256 * 2**20

_STARTS: Registry[str] = Registry("start")
_STARTS.add("learned", "learned")
_STARTS.add("state1", "state1")

_NEG_INF = -np.inf


# ----------------------------------------------------------------------------- input


def _is_scalar_int_like(x) -> bool:
    return isinstance(x, numbers.Number) or (isinstance(x, np.ndarray) and x.ndim == 0)


def _as_sequences(values, name: str, high: int) -> list[np.ndarray]:
    """One array → one sequence; a list of arrays (or a 2-D array) → many."""
    if isinstance(values, np.ndarray):
        if values.ndim == 1:
            seqs = [values]
        elif values.ndim == 2:
            seqs = list(values)
        else:
            raise ValidationError(
                f"{name} must be a 1-D integer array or a list of them (one per"
                f" demonstration); got an array of shape {values.shape}"
            )
    elif isinstance(values, (list, tuple)):
        if len(values) == 0:
            raise ValidationError(
                f"{name} must hold at least one sequence; got an empty {name}"
            )
        if all(_is_scalar_int_like(v) for v in values):
            seqs = [np.asarray(values)]
        else:
            seqs = list(values)
    else:
        raise ValidationError(
            f"{name} must be a 1-D integer array or a list of them (one per"
            f" demonstration); got {type(values).__name__}"
        )
    if len(seqs) == 0:
        raise ValidationError(
            f"{name} must hold at least one sequence; got an array of shape"
            f" {np.shape(values)}"
        )
    out = []
    for k, s in enumerate(seqs):
        a = check_int_sequence(s, f"{name}[{k}]", low=0, high=high)
        if a.size == 0:
            raise ValidationError(
                f"{name}[{k}] is empty; every demonstration needs at least one"
                " element (empty sequences are refused, not skipped)"
            )
        out.append(a)
    return out


def _count_pairs(a: np.ndarray, b: np.ndarray, n_rows: int, weights=None):
    """CSR (indptr, columns, counts) of the multiset of pairs ``(a, b)``.

    With ``weights``, each pair counts its weight (integer counts to add up).
    """
    order = np.lexsort((b, a))
    a2 = a[order]
    b2 = b[order]
    n = a2.shape[0]
    new = np.ones(n, dtype=bool)
    if n > 1:
        new[1:] = (a2[1:] != a2[:-1]) | (b2[1:] != b2[:-1])
    first = np.flatnonzero(new)
    rows = a2[first]
    cols = np.ascontiguousarray(b2[first], dtype=np.int64)
    if weights is None:
        counts = np.diff(np.append(first, n)).astype(np.int64)
    else:
        w = np.asarray(weights, dtype=np.int64)[order]
        counts = np.add.reduceat(w, first) if n else np.zeros(0, np.int64)
    indptr = np.zeros(n_rows + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n_rows), out=indptr[1:])
    return indptr, cols, counts


def _safe_ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """``num / den`` with 0 where ``den == 0`` (then ``num`` is 0 as well)."""
    num = np.asarray(num, dtype=np.float64)
    den = np.asarray(den, dtype=np.float64)
    out = np.zeros(np.broadcast_shapes(num.shape, den.shape))
    np.divide(num, den, out=out, where=den != 0)
    return out


def _log(x) -> np.ndarray:
    """Natural log with ``log(0) = -inf`` and no warning."""
    with np.errstate(divide="ignore"):
        return np.log(np.asarray(x, dtype=np.float64))


def _log_table(indptr, cols, counts, totals, pseudo, width, n_cols):
    """Log-probabilities of one counted table (CSR over the seen states).

    Each counted entry ``(i, c)`` gets the log of the ratio
    ``log((count + pseudo) / (totals[i] + width * pseudo))`` (one float formula
    for bit-exact ties); each row the baseline ``log(pseudo / (totals[i] +
    width * pseudo))`` of its uncounted entries (``-inf`` when ``pseudo == 0``);
    an unseen row ``log(1 / width)``.

    Returns
    -------
    logp : ndarray, per entry in CSR order
    row_base : ndarray of shape (n_rows,)
    unseen : float
    col_indptr, col_rows, col_logp : ndarray
        The same entries grouped by column (CSC), rows ascending in a column.
    """
    rows = np.repeat(np.arange(totals.shape[0], dtype=np.int64), np.diff(indptr))
    wp = width * pseudo
    logp = _log((counts + pseudo) / (totals[rows] + wp))
    if pseudo > 0:
        row_base = _log(pseudo / (totals + wp))
        unseen = float(_log(np.array([pseudo / wp]))[0])
    else:
        row_base = np.full(totals.shape[0], _NEG_INF)
        unseen = _NEG_INF
    order = np.lexsort((rows, cols))
    col_indptr = np.zeros(n_cols + 1, dtype=np.int64)
    np.cumsum(np.bincount(cols, minlength=n_cols), out=col_indptr[1:])
    return (
        logp,
        row_base,
        unseen,
        col_indptr,
        np.ascontiguousarray(rows[order]),
        np.ascontiguousarray(logp[order]),
    )


def _check_dense_size(n_entries: int, what: str) -> None:
    nbytes = n_entries * 8
    if nbytes > DENSE_LIMIT_BYTES:
        raise ValidationError(
            f"a dense {what} would need {nbytes / 2**20:.1f} MiB, above the"
            f" {DENSE_LIMIT_BYTES / 2**20:.0f} MiB limit; use dense=False (sparse"
            " counts plus a per-row baseline)"
        )


# ----------------------------------------------------------------------------- model


class DiscreteHMM:
    """A supervised discrete HMM stored as sparse counts over the seen states.

    Use :func:`estimate` (or ``DiscreteHMM(...).fit(states, symbols)``) to build
    one and :func:`viterbi` (or :meth:`decode`) to decode symbols.

    Parameters
    ----------
    n_states : int
        Number of states ``m`` (may be huge, up to the int64 range).
    n_symbols : int
        Number of symbols ``N_t``.
    pseudo_transition : float or None, default=None
        Transition pseudo-count ``p``; ``None`` means ``1 / n_states``.
    pseudo_emission : float, default=0.0
        Emission pseudo-count ``r``.

    Attributes
    ----------
    states_ : ndarray of shape (n_seen,), dtype int64
        Sorted distinct states seen in training. Rows and columns of the count
        matrices below follow this order.
    transition_counts_ : scipy.sparse.csr_array of shape (n_seen, n_seen)
        ``C`` restricted to the seen states.
    emission_counts_ : scipy.sparse.csr_array of shape (n_seen, n_symbols)
        ``E`` restricted to the seen states.
    start_counts_ : ndarray of shape (n_seen,), dtype int64
        ``F``: how many demonstrations start in each seen state.
    transition_totals_ : ndarray of shape (n_seen,), dtype int64
        ``n_i``, transitions out of each seen state.
    emission_totals_ : ndarray of shape (n_seen,), dtype int64
        ``e_i``, occurrences of each seen state.
    n_sequences_ : int
        ``D``, the number of training sequences.
    pseudo_transition_ : float
        The transition pseudo-count in use (``1 / n_states`` when the parameter is
        ``None``).
    lowest_unseen_state_ : int or None
        Lowest state id never seen in training (``None`` if all were seen); it
        represents every unseen state in decoded paths.

    Examples
    --------
    >>> hmm = DiscreteHMM(4, 2, pseudo_transition=0).fit([[0, 1, 2], [0, 2]],
    ...                                                 [[0, 0, 1], [0, 1]])
    >>> hmm.states_
    array([0, 1, 2])
    >>> hmm.transition_matrix(dense=True)[0]
    array([0. , 0.5, 0.5, 0. ])
    >>> path, logp = hmm.decode([0, 1])
    >>> path, round(float(np.exp(logp)), 3)
    (array([0, 2]), 0.5)
    """

    def __init__(
        self,
        n_states: int,
        n_symbols: int,
        *,
        pseudo_transition: float | None = None,
        pseudo_emission: float = 0.0,
    ) -> None:
        self.n_states = n_states
        self.n_symbols = n_symbols
        self.pseudo_transition = pseudo_transition
        self.pseudo_emission = pseudo_emission

    def __repr__(self) -> str:
        return (
            f"DiscreteHMM(n_states={self.n_states}, n_symbols={self.n_symbols},"
            f" pseudo_transition={self.pseudo_transition!r},"
            f" pseudo_emission={self.pseudo_emission!r})"
        )

    # -- parameters ----------------------------------------------------------------

    def _checked_params(self) -> tuple[int, int, float, float]:
        m = check_positive_int(self.n_states, "n_states")
        if m > np.iinfo(np.int64).max:
            raise ValidationError(f"n_states must fit in int64; got {m}")
        nt = check_positive_int(self.n_symbols, "n_symbols")
        if self.pseudo_transition is None:
            p = 1.0 / m
        else:
            p = check_nonnegative_scalar(self.pseudo_transition, "pseudo_transition")
        r = check_nonnegative_scalar(self.pseudo_emission, "pseudo_emission")
        return m, nt, p, r

    # -- fitting -------------------------------------------------------------------

    def fit(self, states, symbols) -> DiscreteHMM:
        """Count transitions, emissions and first states of training sequences.

        Parameters
        ----------
        states : array-like of shape (n_steps,) or list of them
            State sequences, one per demonstration, each in ``0..n_states-1``.
            A single 1-D array is one demonstration; a 2-D array is one
            demonstration per row. Empty sequences are refused.
        symbols : array-like of shape (n_steps,) or list of them
            Symbol sequences of the same structure and lengths, in
            ``0..n_symbols-1``.

        Returns
        -------
        self : DiscreteHMM

        Examples
        --------
        >>> hmm = DiscreteHMM(3, 1).fit([0, 1, 1], [0, 0, 0])
        >>> hmm.transition_totals_, hmm.emission_totals_
        (array([1, 1]), array([1, 2]))
        """
        m, nt, p, r = self._checked_params()
        seq_s = _as_sequences(states, "states", m)
        seq_o = _as_sequences(symbols, "symbols", nt)
        if len(seq_s) != len(seq_o):
            raise ValidationError(
                "states and symbols must hold the same number of sequences; got"
                f" {len(seq_s)} state and {len(seq_o)} symbol sequence(s)"
            )
        for k, (a, b) in enumerate(zip(seq_s, seq_o, strict=True)):
            if a.shape[0] != b.shape[0]:
                raise ValidationError(
                    f"states[{k}] and symbols[{k}] must have the same length; got"
                    f" {a.shape[0]} and {b.shape[0]}"
                )
        lengths = np.array([a.shape[0] for a in seq_s], dtype=np.int64)
        all_s = np.concatenate(seq_s)
        all_o = np.concatenate(seq_o)
        seen, loc = np.unique(all_s, return_inverse=True)
        loc = loc.reshape(-1).astype(np.int64)
        n_seen = seen.shape[0]
        ends = np.cumsum(lengths)
        firsts = ends - lengths
        not_last = np.ones(all_s.shape[0], dtype=bool)
        not_last[ends - 1] = False
        src_pos = np.flatnonzero(not_last)
        t_indptr, t_dst, t_cnt = _count_pairs(loc[src_pos], loc[src_pos + 1], n_seen)
        e_indptr, e_sym, e_cnt = _count_pairs(loc, all_o, n_seen)
        f_cnt = np.bincount(loc[firsts], minlength=n_seen).astype(np.int64)
        self._set_fitted(
            m, nt, p, r, seen.astype(np.int64), t_indptr, t_dst, t_cnt,
            e_indptr, e_sym, e_cnt, f_cnt, len(seq_s),
        )  # fmt: skip
        return self

    def _set_fitted(
        self, m, nt, p, r, seen, t_indptr, t_dst, t_cnt, e_indptr, e_sym, e_cnt,
        f_cnt, n_seq,
    ) -> None:  # fmt: skip
        self._raw = {
            "states": seen,
            "transition_indptr": t_indptr,
            "transition_targets": t_dst,
            "transition_counts": t_cnt,
            "emission_indptr": e_indptr,
            "emission_symbols": e_sym,
            "emission_counts": e_cnt,
            "start_counts": f_cnt,
        }
        self._m, self._nt, self._p, self._r = m, nt, p, r
        n_seen = seen.shape[0]
        self.states_ = seen
        self.n_sequences_ = int(n_seq)
        self.pseudo_transition_ = float(p)
        self.transition_totals_ = _row_sums(t_indptr, t_cnt)
        self.emission_totals_ = _row_sums(e_indptr, e_cnt)
        self.start_counts_ = f_cnt
        self.transition_counts_ = sp.csr_array(
            (t_cnt, t_dst, t_indptr), shape=(n_seen, n_seen)
        )
        self.emission_counts_ = sp.csr_array(
            (e_cnt, e_sym, e_indptr), shape=(n_seen, nt)
        )
        mism = np.flatnonzero(seen != np.arange(n_seen))
        if n_seen == m:
            self.lowest_unseen_state_ = None
        else:
            self.lowest_unseen_state_ = int(mism[0]) if mism.size else n_seen
        self._tables = None

    def _check_fitted(self) -> None:
        if not hasattr(self, "_raw"):
            raise NotFittedError(
                "this DiscreteHMM is not fitted yet; call fit(states, symbols) or"
                " ndlfd.hmm.estimate(...) first"
            )

    # -- log tables for the kernel ------------------------------------------------

    def _kernel_tables(self) -> dict:
        if self._tables is not None:
            return self._tables
        raw = self._raw
        m, nt, p, r = self._m, self._nt, self._p, self._r
        seen = raw["states"]
        n_seen = seen.shape[0]
        n = self.transition_totals_.astype(np.float64)
        e = self.emission_totals_.astype(np.float64)
        t_indptr = raw["transition_indptr"]
        t_dst = raw["transition_targets"]
        la, row_base, unseen_trans, in_indptr, in_src, in_logp = _log_table(
            t_indptr, t_dst, raw["transition_counts"], n, p, m, n_seen
        )
        mp = m * p
        _, em_base, unseen_emit, em_indptr, em_state, em_logp = _log_table(
            raw["emission_indptr"],
            raw["emission_symbols"],
            raw["emission_counts"],
            e,
            r,
            nt,
            nt,
        )

        has_unseen = self.lowest_unseen_state_ is not None
        gid = np.empty(n_seen + 1, dtype=np.int64)
        gid[:n_seen] = seen
        gid[n_seen] = self.lowest_unseen_state_ if has_unseen else m

        # start="learned": pi[j] = (F[j] + p) / (D + m p)
        f = self.start_counts_
        d = float(self.n_sequences_)
        s_idx = np.flatnonzero(f).astype(np.int64)
        s_logp = _log((f[s_idx] + p) / (d + mp))
        s_base = float(_log(np.array([p / (d + mp)]))[0]) if p > 0 else _NEG_INF
        # start="state1": row 0 of A
        if n_seen and seen[0] == 0:
            lo, hi = t_indptr[0], t_indptr[1]
            s1 = (float(row_base[0]), t_dst[lo:hi].copy(), la[lo:hi].copy())
        else:
            s1 = (unseen_trans, np.empty(0, np.int64), np.empty(0, np.float64))
        self._tables = {
            "gid": gid,
            "has_unseen": has_unseen,
            "in_indptr": in_indptr,
            "in_src": in_src,
            "in_logp": in_logp,
            "row_base": row_base,
            "unseen_trans": unseen_trans,
            "em_indptr": em_indptr,
            "em_state": em_state,
            "em_logp": em_logp,
            "em_base": em_base,
            "unseen_emit": unseen_emit,
            "emit_all": r > 0,
            "start": {
                "learned": (s_base, s_idx, s_logp),
                "state1": s1,
            },
        }
        return self._tables

    # -- decoding ------------------------------------------------------------------

    def decode(self, symbols, *, start: str = "learned") -> tuple[np.ndarray, float]:
        """Most likely state path for ``symbols`` (see :func:`viterbi`).

        Parameters
        ----------
        symbols : array-like of shape (n_steps,)
            Symbols in ``0..n_symbols-1``.
        start : {"learned", "state1"}, default="learned"
            Start distribution (see :func:`viterbi`).

        Returns
        -------
        path : ndarray of shape (n_steps,), dtype int64
        log_probability : float

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 1]], 2, 2)
        >>> hmm.decode([0, 1])[0]
        array([0, 1])
        """
        from ._hmm_decode import viterbi

        return viterbi(self, symbols, start=start)

    # -- probabilities -------------------------------------------------------------

    def _rows_of(self, states) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s = check_int_sequence(states, "states", low=0, high=self._m)
        pos = np.searchsorted(self.states_, s)
        pos_c = np.minimum(pos, self.states_.shape[0] - 1)
        is_seen = self.states_[pos_c] == s
        return s, pos_c, is_seen

    def transition_baseline(self, states) -> np.ndarray:
        """Per-row constant ``b_i = p / (n_i + m p)`` of the transition matrix.

        Every entry ``A[i, j]`` without a counted transition equals ``b_i``
        (0 when ``p == 0``).

        Parameters
        ----------
        states : array-like of shape (n,)
            State ids ``i`` (rows of ``A``).

        Returns
        -------
        baseline : ndarray of shape (n,), dtype float64

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 0]], 4, 1)   # p = 1/4
        >>> hmm.transition_baseline([0, 3])
        array([0.125, 0.25 ])
        """
        self._check_fitted()
        return self._baseline(states, self.transition_totals_, self._p, self._m)

    def emission_baseline(self, states) -> np.ndarray:
        """Per-row constant ``r / (e_i + N_t r)`` of the emission matrix.

        Parameters
        ----------
        states : array-like of shape (n,)
            State ids ``i`` (rows of ``B``).

        Returns
        -------
        baseline : ndarray of shape (n,), dtype float64

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 0]], 4, 2, pseudo_emission=1.0)
        >>> hmm.emission_baseline([0, 3])
        array([0.33333333, 0.5       ])
        """
        self._check_fitted()
        return self._baseline(states, self.emission_totals_, self._r, self._nt)

    def _baseline(self, states, totals, pseudo, width) -> np.ndarray:
        """``pseudo / (total_i + width * pseudo)`` per state (total 0 if unseen)."""
        _, pos, is_seen = self._rows_of(states)
        n = np.where(is_seen, totals[pos], 0).astype(np.float64)
        return _safe_ratio(np.full(n.shape, pseudo), n + width * pseudo)

    def transition_matrix(self, dense: bool = False):
        """The transition matrix ``A`` (sparse count part, or dense on request).

        ``A`` is dense in truth when ``p > 0``, so the sparse form is its count
        part: ``A[i, j] = K[i, j] + b_i`` with ``K[i, j] = C[i, j] / (n_i + m p)``
        and ``b_i`` from :meth:`transition_baseline`. When ``p == 0`` the baseline
        is 0 and ``K`` *is* ``A``. The sparse form never allocates anything of
        size ``m``.

        Parameters
        ----------
        dense : bool, default=False
            Return the full ``(m, m)`` array built with
            ``(C + p) / (n_i + m p)``; refused above :data:`DENSE_LIMIT_BYTES`.

        Returns
        -------
        K : scipy.sparse.coo_array of shape (n_states, n_states)
            When ``dense`` is false (call ``.tocsr()`` for row access).
        A : ndarray of shape (n_states, n_states)
            When ``dense`` is true.

        Examples
        --------
        >>> hmm = estimate([[0, 1, 1]], [[0, 0, 0]], 2, 1, pseudo_transition=0)
        >>> hmm.transition_matrix().toarray()
        array([[0., 1.],
               [0., 1.]])
        """
        self._check_fitted()
        m, p = self._m, self._p
        raw = self._raw
        seen = self.states_
        n = self.transition_totals_.astype(np.float64)
        t_src = np.repeat(np.arange(seen.shape[0]), np.diff(raw["transition_indptr"]))
        rows = seen[t_src]
        cols = seen[raw["transition_targets"]]
        cnt = raw["transition_counts"]
        if not dense:
            vals = _safe_ratio(cnt, n[t_src] + m * p)
            return sp.coo_array((vals, (rows, cols)), shape=(m, m))
        _check_dense_size(m * m, f"transition matrix ({m} x {m})")
        A = np.empty((m, m))
        A[:] = _safe_ratio(p, 0.0 + m * p)
        A[seen, :] = _safe_ratio(np.full(n.shape, p), n + m * p)[:, None]
        A[rows, cols] = _safe_ratio(cnt + p, n[t_src] + m * p)
        return A

    def emission_matrix(self, dense: bool = False):
        """The emission matrix ``B`` (sparse count part, or dense on request).

        As for :meth:`transition_matrix`: ``B[i, k] = K[i, k] + c_i`` with
        ``K[i, k] = E[i, k] / (e_i + N_t r)`` and ``c_i`` from
        :meth:`emission_baseline`; with ``r == 0`` (the default) ``K`` is ``B``.

        Parameters
        ----------
        dense : bool, default=False
            Return the full ``(m, N_t)`` array built with
            ``(E + r) / (e_i + N_t r)``; refused above :data:`DENSE_LIMIT_BYTES`.

        Returns
        -------
        K : scipy.sparse.coo_array of shape (n_states, n_symbols)
            When ``dense`` is false.
        B : ndarray of shape (n_states, n_symbols)
            When ``dense`` is true.

        Examples
        --------
        >>> hmm = estimate([[0, 1, 1]], [[0, 0, 1]], 2, 2)
        >>> hmm.emission_matrix(dense=True)
        array([[1. , 0. ],
               [0.5, 0.5]])
        """
        self._check_fitted()
        m, nt, r = self._m, self._nt, self._r
        raw = self._raw
        seen = self.states_
        e = self.emission_totals_.astype(np.float64)
        e_src = np.repeat(np.arange(seen.shape[0]), np.diff(raw["emission_indptr"]))
        rows = seen[e_src]
        cols = raw["emission_symbols"]
        cnt = raw["emission_counts"]
        if not dense:
            vals = _safe_ratio(cnt, e[e_src] + nt * r)
            return sp.coo_array((vals, (rows, cols)), shape=(m, nt))
        _check_dense_size(m * nt, f"emission matrix ({m} x {nt})")
        B = np.empty((m, nt))
        B[:] = _safe_ratio(r, 0.0 + nt * r)
        B[seen, :] = _safe_ratio(np.full(e.shape, r), e + nt * r)[:, None]
        B[rows, cols] = _safe_ratio(cnt + r, e[e_src] + nt * r)
        return B

    def initial_distribution(self) -> np.ndarray:
        """The learned start distribution ``pi[j] = (F[j] + p) / (D + m p)``.

        Returns
        -------
        pi : ndarray of shape (n_states,)
            Dense; refused above :data:`DENSE_LIMIT_BYTES`.

        Examples
        --------
        Two demonstrations start in state 0 (``F = (2, 0)``, ``D = 2``) and the
        default ``p = 1/m = 1/2``: ``pi = (2.5 / 3, 0.5 / 3)``.

        >>> estimate([[0, 1], [0, 0]], [[0, 0], [0, 0]], 2, 1).initial_distribution()
        array([0.83333333, 0.16666667])
        """
        self._check_fitted()
        m, p = self._m, self._p
        _check_dense_size(m, f"initial distribution ({m},)")
        d = float(self.n_sequences_)
        pi = np.empty(m)
        pi[:] = p / (d + m * p)
        pi[self.states_] = (self.start_counts_ + p) / (d + m * p)
        return pi

    # -- persistence ---------------------------------------------------------------

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The model as plain numeric arrays (for embedding in another file).

        Parameters
        ----------
        prefix : str, default=""
            Prepended to every key.

        Returns
        -------
        arrays : dict of str to ndarray

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 1]], 2, 2)
        >>> sorted(hmm.to_arrays("hmm/"))[:2]
        ['hmm/emission_counts', 'hmm/emission_indptr']
        """
        self._check_fitted()
        out = {prefix + k: v.copy() for k, v in self._raw.items()}
        out[prefix + "sizes"] = np.array(
            [self._m, self._nt, self.n_sequences_], dtype=np.int64
        )
        p_param = np.nan if self.pseudo_transition is None else self._p
        out[prefix + "pseudo"] = np.array([p_param, self._r], dtype=np.float64)
        return out

    @classmethod
    def from_arrays(cls, arrays, prefix: str = "") -> DiscreteHMM:
        """Rebuild a model from :meth:`to_arrays` output, validating everything.

        Parameters
        ----------
        arrays : mapping of str to ndarray
            May hold other keys; only those starting with ``prefix`` are read.
        prefix : str, default=""
            The prefix given to :meth:`to_arrays`.

        Returns
        -------
        model : DiscreteHMM

        Raises
        ------
        ModelFormatError
            If an array is missing or inconsistent (shape, dtype, range, counts).

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 1]], 2, 2)
        >>> DiscreteHMM.from_arrays(hmm.to_arrays()).decode([0, 1])[0]
        array([0, 1])
        """
        from ._hmm_format import model_from_arrays

        return model_from_arrays(cls, arrays, prefix)

    def save(self, path: str | os.PathLike) -> None:
        """Write the model to an ``.npz`` file (kind ``DiscreteHMM``, version 1).

        Parameters
        ----------
        path : str or path-like
            Destination; written atomically.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "hmm.npz"
        >>> estimate([[0, 1]], [[0, 1]], 2, 2).save(f)
        >>> DiscreteHMM.load(f).states_
        array([0, 1])
        """
        from ._hmm_format import FORMAT_KIND, FORMAT_VERSION

        self._check_fitted()
        save_npz(
            path,
            self.to_arrays(),
            kind=FORMAT_KIND,
            version=FORMAT_VERSION,
            metadata={
                "n_states": self._m,
                "n_symbols": self._nt,
                "n_seen_states": int(self.states_.shape[0]),
            },
        )

    @classmethod
    def load(cls, path: str | os.PathLike) -> DiscreteHMM:
        """Read a model written by :meth:`save`.

        Parameters
        ----------
        path : str or path-like
            The file.

        Returns
        -------
        model : DiscreteHMM

        Raises
        ------
        ModelFormatError
            For a foreign, truncated, tampered or other-version file.
        """
        from ._hmm_format import FORMAT_KIND, FORMAT_VERSION, model_from_arrays

        arrays, _ = load_npz(path, kind=FORMAT_KIND, version=FORMAT_VERSION)
        try:
            return model_from_arrays(cls, arrays, "")
        except ModelFormatError as exc:
            raise ModelFormatError(f"{path}: {exc}") from None


def _row_sums(indptr: np.ndarray, values: np.ndarray) -> np.ndarray:
    csum = np.zeros(values.shape[0] + 1, dtype=np.int64)
    np.cumsum(values, out=csum[1:])
    return csum[indptr[1:]] - csum[indptr[:-1]]


# ----------------------------------------------------------------------------- API


def estimate(
    states,
    symbols,
    n_states: int,
    n_symbols: int,
    *,
    pseudo_transition: float | None = None,
    pseudo_emission: float = 0.0,
) -> DiscreteHMM:
    """Estimate a discrete HMM from labelled sequences (MATLAB ``hmmestimate``).

    Parameters
    ----------
    states : array-like of shape (n_steps,) or list of them
        State sequences (one per demonstration), ids in ``0..n_states-1``.
    symbols : array-like of shape (n_steps,) or list of them
        Symbol sequences of the same lengths, ids in ``0..n_symbols-1``.
    n_states : int
        Number of states ``m`` (may be far larger than the states seen).
    n_symbols : int
        Number of symbols ``N_t``.
    pseudo_transition : float or None, default=None
        ``p`` in ``A[i, j] = (C[i, j] + p) / (n_i + m p)``; ``None`` means
        ``1 / n_states``.
    pseudo_emission : float, default=0.0
        ``r`` in ``B[i, k] = (E[i, k] + r) / (e_i + N_t r)``.

    Returns
    -------
    model : DiscreteHMM
        Fitted; its memory follows the number of distinct states seen.

    Examples
    --------
    >>> hmm = estimate([[3, 5, 5], [3, 5]], [[0, 1, 2], [0, 2]], 10**12, 3)
    >>> hmm.states_, hmm.n_sequences_
    (array([3, 5]), 2)
    >>> hmm.decode([0, 1, 2])[0]
    array([3, 5, 5])
    """
    return DiscreteHMM(
        n_states,
        n_symbols,
        pseudo_transition=pseudo_transition,
        pseudo_emission=pseudo_emission,
    ).fit(states, symbols)


def merge(models) -> DiscreteHMM:
    """Combine HMMs estimated on separate groups of demonstrations.

    Transition, emission and first-state counts are per demonstration and add
    up, so estimating on chunks of the demonstrations (in other threads,
    processes or machines, e.g. with Dask) and merging gives exactly the model
    that :func:`estimate` gives on all of them at once.

    Parameters
    ----------
    models : sequence of DiscreteHMM
        Fitted models with the same ``n_states``, ``n_symbols`` and
        pseudo-counts.

    Returns
    -------
    model : DiscreteHMM

    Examples
    --------
    >>> a = estimate([[0, 1, 1]], [[0, 1, 2]], 4, 3)
    >>> b = estimate([[0, 2, 1]], [[0, 1, 2]], 4, 3)
    >>> both = estimate([[0, 1, 1], [0, 2, 1]], [[0, 1, 2], [0, 1, 2]], 4, 3)
    >>> merged = merge([a, b])
    >>> merged.states_, merged.n_sequences_
    (array([0, 1, 2]), 2)
    >>> (merged.transition_counts_ != both.transition_counts_).nnz
    0
    """
    models = list(models) if not isinstance(models, DiscreteHMM) else [models]
    if not models:
        raise ValidationError("merge needs at least one fitted DiscreteHMM; got none")
    for k, mod in enumerate(models):
        if not isinstance(mod, DiscreteHMM):
            raise ValidationError(
                f"models[{k}] must be a DiscreteHMM; got {type(mod).__name__}"
            )
        mod._check_fitted()
    first = models[0]
    key = (first._m, first._nt, first._p, first._r)
    for k, mod in enumerate(models[1:], start=1):
        other = (mod._m, mod._nt, mod._p, mod._r)
        if other != key:
            raise ValidationError(
                "models must share n_states, n_symbols and pseudo-counts; models[0]"
                f" has {key} and models[{k}] has {other}"
            )
    m, nt, p, r = key
    seen = np.unique(np.concatenate([mod.states_ for mod in models]))
    n_seen = seen.shape[0]
    t_src, t_dst, t_w, e_src, e_sym, e_w, f_loc, f_w = ([] for _ in range(8))
    for mod in models:
        raw = mod._raw
        loc = np.searchsorted(seen, mod.states_)
        rows = np.repeat(loc, np.diff(raw["transition_indptr"]))
        t_src.append(rows)
        t_dst.append(loc[raw["transition_targets"]])
        t_w.append(raw["transition_counts"])
        e_src.append(np.repeat(loc, np.diff(raw["emission_indptr"])))
        e_sym.append(raw["emission_symbols"])
        e_w.append(raw["emission_counts"])
        f_loc.append(loc)
        f_w.append(raw["start_counts"])
    cat = np.concatenate
    t_indptr, t_dst_, t_cnt = _count_pairs(cat(t_src), cat(t_dst), n_seen, cat(t_w))
    e_indptr, e_sym_, e_cnt = _count_pairs(cat(e_src), cat(e_sym), n_seen, cat(e_w))
    f_cnt = np.bincount(cat(f_loc), weights=cat(f_w), minlength=n_seen)
    out = DiscreteHMM(
        first.n_states,
        first.n_symbols,
        pseudo_transition=first.pseudo_transition,
        pseudo_emission=first.pseudo_emission,
    )
    out._set_fitted(
        m, nt, p, r, seen.astype(np.int64), t_indptr, t_dst_, t_cnt,
        e_indptr, e_sym_, e_cnt, f_cnt.astype(np.int64),
        sum(mod.n_sequences_ for mod in models),
    )  # fmt: skip
    return out
