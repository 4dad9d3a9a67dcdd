"""Counts of the supervised discrete HMM as plain arrays (see :mod:`ndlfd.hmm`).

:class:`Counts` holds everything the model is: the transition, emission and
first-state counts over the sorted seen states (CSR rows), the sizes and the
pseudo-counts. :func:`count` makes it from labelled sequences,
:func:`merge_counts` adds up several, and :class:`Table` gives the ratios
``(count + pseudo) / (total + width * pseudo)`` of one counted table. The model
class (:mod:`ndlfd.hmm._model`), the decoders (:mod:`ndlfd.hmm._decode`) and
the file format (:mod:`ndlfd.hmm._format`) all work on these arrays.
"""

from __future__ import annotations

import numbers
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from .._errors import ValidationError
from .._validation import (
    check_int_sequence,
    check_nonnegative_scalar,
    check_positive_int,
    check_work_size,
)

__all__ = [
    "Counts",
    "Table",
    "check_params",
    "count",
    "merge_counts",
    "row_sums",
    "safe_ratio",
]


def safe_ratio(num, den) -> np.ndarray:
    """``num / den`` with 0 where ``den == 0`` (then ``num`` is 0 as well).

    Parameters
    ----------
    num, den : array-like, broadcastable

    Returns
    -------
    ratio : ndarray of float64, of the broadcast shape

    Examples
    --------
    >>> safe_ratio([1.0, 0.0], [4.0, 0.0])
    array([0.25, 0.  ])
    """
    num = np.asarray(num, dtype=np.float64)
    den = np.asarray(den, dtype=np.float64)
    out = np.zeros(np.broadcast_shapes(num.shape, den.shape))
    np.divide(num, den, out=out, where=den != 0)
    return out


def row_sums(indptr: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Sum of each CSR row's integer values.

    Parameters
    ----------
    indptr : ndarray of shape (n_rows + 1,), int64
    values : ndarray of shape (n_entries,), int64

    Returns
    -------
    sums : ndarray of shape (n_rows,), int64

    Examples
    --------
    >>> row_sums(np.array([0, 2, 2, 3]), np.array([1, 4, 2]))
    array([5, 0, 2])
    """
    csum = np.zeros(values.shape[0] + 1, dtype=np.int64)
    np.cumsum(values, out=csum[1:])
    return csum[indptr[1:]] - csum[indptr[:-1]]


class Table(NamedTuple):
    """One counted table of the model (``C`` or ``E``) and its smoothing.

    Row ``i`` (a seen state) has the entries ``indptr[i]:indptr[i + 1]`` of
    ``columns`` and ``counts``; its probabilities are ``(count + pseudo) /
    (totals[i] + width * pseudo)`` on a counted entry and the baseline
    ``pseudo / (totals[i] + width * pseudo)`` elsewhere.

    Attributes
    ----------
    indptr : ndarray of shape (n_seen + 1,), int64
    columns : ndarray of shape (n_entries,), int64
        Seen-state positions (transitions) or symbols (emissions), increasing
        in each row.
    counts : ndarray of shape (n_entries,), int64
    totals : ndarray of shape (n_seen,), int64
        Row sums of ``counts``.
    pseudo : float
        The pseudo-count (``p`` or ``r``).
    width : int
        Number of columns of the full matrix (``n_states`` or ``n_symbols``).
    """

    indptr: np.ndarray
    columns: np.ndarray
    counts: np.ndarray
    totals: np.ndarray
    pseudo: float
    width: int

    def csr(self, n_cols: int, values=None) -> sp.csr_array:
        """The table as a CSR array of shape (n_seen, n_cols): ``values`` or counts."""
        data = self.counts if values is None else values
        shape = (self.totals.shape[0], n_cols)
        return sp.csr_array((data, self.columns, self.indptr), shape=shape)

    def rows(self) -> np.ndarray:
        """Row (seen-state position) of each entry, shape (n_entries,), int64."""
        n_rows = self.totals.shape[0]
        return np.repeat(np.arange(n_rows, dtype=np.int64), np.diff(self.indptr))

    def denominators(self) -> np.ndarray:
        """``totals + width * pseudo`` per row, shape (n_seen,), float64."""
        return self.totals + self.width * self.pseudo

    def baseline(self) -> np.ndarray:
        """``pseudo / (total + width * pseudo)`` per row, shape (n_seen,)."""
        den = self.denominators()
        return safe_ratio(np.full(den.shape, self.pseudo), den)

    def unseen_baseline(self) -> float:
        """``pseudo / (width * pseudo)``, the row of a state never seen (or 0)."""
        return float(safe_ratio(self.pseudo, 0.0 + self.width * self.pseudo))

    def counted(self, rows: np.ndarray, *, smoothed: bool = False) -> np.ndarray:
        """``count / (total + width * pseudo)`` per entry, shape (n_entries,).

        With ``smoothed``, ``(count + pseudo) / (...)``: the full probability
        of a counted entry. ``rows`` is :meth:`rows`.
        """
        num = self.counts + self.pseudo if smoothed else self.counts
        return safe_ratio(num, self.denominators()[rows])


class Counts(NamedTuple):
    """The counts of a supervised discrete HMM and its pseudo-counts.

    Attributes
    ----------
    n_states : int
        ``m``.
    n_symbols : int
        ``N_t``.
    pseudo_transition : float
        ``p`` in use (``1 / m`` when the parameter was ``None``).
    pseudo_emission : float
        ``r``.
    n_sequences : int
        ``D``, the number of training sequences.
    states : ndarray of shape (n_seen,), int64
        Sorted distinct states seen in training; rows below follow this order.
    transition_indptr, transition_targets, transition_counts : ndarray, int64
        ``C`` as CSR over the seen states (targets are seen-state positions).
    emission_indptr, emission_symbols, emission_counts : ndarray, int64
        ``E`` as CSR, seen states by symbols.
    start_counts : ndarray of shape (n_seen,), int64
        ``F``: how many sequences start in each seen state.
    """

    n_states: int
    n_symbols: int
    pseudo_transition: float
    pseudo_emission: float
    n_sequences: int
    states: np.ndarray
    transition_indptr: np.ndarray
    transition_targets: np.ndarray
    transition_counts: np.ndarray
    emission_indptr: np.ndarray
    emission_symbols: np.ndarray
    emission_counts: np.ndarray
    start_counts: np.ndarray

    def transitions(self) -> Table:
        """The transition table: ``A = (C + p) / (n_i + m p)``."""
        return Table(
            self.transition_indptr,
            self.transition_targets,
            self.transition_counts,
            row_sums(self.transition_indptr, self.transition_counts),
            self.pseudo_transition,
            self.n_states,
        )

    def emissions(self) -> Table:
        """The emission table: ``B = (E + r) / (e_i + N_t r)``."""
        return Table(
            self.emission_indptr,
            self.emission_symbols,
            self.emission_counts,
            row_sums(self.emission_indptr, self.emission_counts),
            self.pseudo_emission,
            self.n_symbols,
        )

    def lowest_unseen_state(self) -> int | None:
        """Lowest state id never seen in training, ``None`` if all were seen."""
        n_seen = self.states.shape[0]
        if n_seen == self.n_states:
            return None
        mism = np.flatnonzero(self.states != np.arange(n_seen))
        return int(mism[0]) if mism.size else n_seen


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


# ----------------------------------------------------------------------------- counting


def check_params(
    n_states, n_symbols, pseudo_transition, pseudo_emission
) -> tuple[int, int, float, float]:
    """The sizes and pseudo-counts of a model, checked.

    Returns
    -------
    m, n_t : int
    p, r : float
        ``p`` is ``1 / m`` when ``pseudo_transition`` is ``None``.

    Raises
    ------
    ValidationError
        A value out of its range, or a pseudo-count so large that a
        denominator ``width * pseudo`` overflows.
    """
    m = check_positive_int(n_states, "n_states")
    if m > np.iinfo(np.int64).max:
        raise ValidationError(f"n_states must fit in int64; got {m}")
    nt = check_positive_int(n_symbols, "n_symbols")
    if nt > np.iinfo(np.int64).max:
        raise ValidationError(f"n_symbols must fit in int64; got {nt}")
    if pseudo_transition is None:
        p = 1.0 / m
    else:
        p = check_nonnegative_scalar(pseudo_transition, "pseudo_transition")
    r = check_nonnegative_scalar(pseudo_emission, "pseudo_emission")
    for name, pseudo, width, wname in (
        ("pseudo_transition", p, m, "n_states"),
        ("pseudo_emission", r, nt, "n_symbols"),
    ):  # every row's denominator total + width * pseudo must stay finite
        if 0 < pseudo < np.finfo(float).tiny:
            raise ValidationError(
                f"{name} must be 0 or at least {np.finfo(float).tiny:.3g} (a"
                f" normal float64); got {pseudo!r}"
            )
        if not np.isfinite(float(width) * pseudo * 2.0):
            raise ValidationError(
                f"{name} * {wname} must stay below {np.finfo(float).max / 2:.3g};"
                f" got {pseudo!r} * {width} (use a smaller pseudo-count)"
            )
    return m, nt, p, r


def count(
    states,
    symbols,
    n_states: int,
    n_symbols: int,
    pseudo_transition: float | None = None,
    pseudo_emission: float = 0.0,
) -> Counts:
    """Count transitions, emissions and first states of labelled sequences.

    Transitions are counted between consecutive states *within* each sequence.
    Sizes and pseudo-counts are checked first (:func:`check_params`), then the
    sequences.

    Parameters
    ----------
    states : array-like of shape (n_steps,) or list of them
        State sequences, one per demonstration, ids in ``0..n_states-1``; a
        2-D array is one sequence per row. Empty sequences are refused.
    symbols : array-like of shape (n_steps,) or list of them
        Symbol sequences of the same structure and lengths.
    n_states, n_symbols : int
        ``m`` and ``N_t``.
    pseudo_transition : float or None, default=None
        ``p``; ``None`` means ``1 / n_states``.
    pseudo_emission : float, default=0.0
        ``r``.

    Returns
    -------
    Counts

    Examples
    --------
    >>> c = count([[0, 2, 2], [2]], [[0, 1, 1], [1]], 3, 2, 0.0, 0.0)
    >>> c.states, c.transition_counts, c.start_counts
    (array([0, 2]), array([1, 1]), array([1, 1]))
    """
    m, nt, p, r = check_params(n_states, n_symbols, pseudo_transition, pseudo_emission)
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
    n_total = int(lengths.sum())
    check_work_size(
        8 * n_total, f"counting {len(seq_s)} sequence(s) of {n_total:,} steps in all"
    )
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
    return Counts(
        m, nt, p, r, len(seq_s),
        seen.astype(np.int64), t_indptr, t_dst, t_cnt, e_indptr, e_sym, e_cnt,
        f_cnt,
    )  # fmt: skip


def merge_counts(parts) -> Counts:
    """Add up the counts of separate groups of sequences.

    Parameters
    ----------
    parts : sequence of Counts
        At least one, all with the same sizes and pseudo-counts (the caller
        checks; the result takes them from the first).

    Returns
    -------
    Counts
        Exactly what :func:`count` gives on all the sequences at once.

    Examples
    --------
    >>> a = count([[0, 1]], [[0, 0]], 3, 1, 0.0, 0.0)
    >>> b = count([[2, 1]], [[0, 0]], 3, 1, 0.0, 0.0)
    >>> both = merge_counts([a, b])
    >>> both.states, both.emission_counts, both.n_sequences
    (array([0, 1, 2]), array([1, 2, 1]), 2)
    """
    parts = list(parts)
    seen = np.unique(np.concatenate([c.states for c in parts]))
    n_seen = seen.shape[0]
    t_src, t_dst, t_w, e_src, e_sym, e_w, f_loc, f_w = ([] for _ in range(8))
    for c in parts:
        loc = np.searchsorted(seen, c.states)
        t_src.append(np.repeat(loc, np.diff(c.transition_indptr)))
        t_dst.append(loc[c.transition_targets])
        t_w.append(c.transition_counts)
        e_src.append(np.repeat(loc, np.diff(c.emission_indptr)))
        e_sym.append(c.emission_symbols)
        e_w.append(c.emission_counts)
        f_loc.append(loc)
        f_w.append(c.start_counts)
    cat = np.concatenate
    t_indptr, t_dst_, t_cnt = _count_pairs(cat(t_src), cat(t_dst), n_seen, cat(t_w))
    e_indptr, e_sym_, e_cnt = _count_pairs(cat(e_src), cat(e_sym), n_seen, cat(e_w))
    f_cnt = np.bincount(cat(f_loc), weights=cat(f_w), minlength=n_seen)
    return Counts(
        *parts[0][:4], sum(c.n_sequences for c in parts), seen.astype(np.int64),
        t_indptr, t_dst_, t_cnt, e_indptr, e_sym_, e_cnt, f_cnt.astype(np.int64),
    )  # fmt: skip
