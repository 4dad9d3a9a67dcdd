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
    MAX_VALUES,
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


def _is_int_vector(a) -> bool:
    return type(a) is np.ndarray and a.ndim == 1 and a.dtype.kind in "iu"


def _flat_sequences(values, name: str, high: int) -> tuple[np.ndarray, np.ndarray]:
    """The sequences of ``values`` end to end (int64) and the length of each.

    What :func:`_as_sequences` accepts, checked the same way. A 2-D integer
    array or a list of 1-D integer arrays (the learner's many short sequences)
    is checked at once; only when that check fails does each sequence get its
    own check, for an error that names it.
    """
    fast = None
    if isinstance(values, np.ndarray):
        if values.ndim == 2 and values.dtype.kind in "iu" and values.size:
            fast = values.reshape(-1), np.full(values.shape[0], values.shape[1])
    elif isinstance(values, (list, tuple)) and len(values) > 1:
        if all(_is_int_vector(v) for v in values):
            lengths = np.fromiter((v.size for v in values), np.int64, len(values))
            if lengths.all() and lengths.sum() <= MAX_VALUES:
                fast = np.concatenate(values), lengths
    if fast is not None:
        flat, lengths = fast
        if flat.size <= MAX_VALUES and flat.min() >= 0 and flat.max() < high:
            return np.ascontiguousarray(flat, dtype=np.int64), lengths.astype(np.int64)
    seqs = _as_sequences(values, name, high)  # each checked: the error names it
    lengths = np.array([a.shape[0] for a in seqs], dtype=np.int64)
    return np.concatenate(seqs), lengths


def _count_pairs(a: np.ndarray, b: np.ndarray, n_rows: int, weights=None, n_cols=None):
    """CSR (indptr, columns, counts) of the multiset of pairs ``(a, b)``.

    With ``weights``, each pair counts its weight (integer counts to add up).
    With ``n_cols`` (``0 <= b < n_cols``) and no weights, the pairs are sorted
    as one key ``a * n_cols + b`` when it fits in int64 (:func:`_key_pairs`):
    the same counts, several times faster than sorting the pairs.
    """
    if weights is None and n_cols is not None and n_rows * n_cols < 2**62:
        return _key_pairs(a, b, n_rows, n_cols)
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


def _key_pairs(a: np.ndarray, b: np.ndarray, n_rows: int, n_cols: int):
    """:func:`_count_pairs` of unweighted pairs with ``n_rows * n_cols < 2**62``."""
    key = np.sort(np.asarray(a, dtype=np.int64) * n_cols + b)
    n = key.shape[0]
    new = np.ones(n, dtype=bool)
    if n > 1:
        np.not_equal(key[1:], key[:-1], out=new[1:])
    first = np.flatnonzero(new)
    rows, cols = np.divmod(key[first], n_cols)
    counts = np.diff(np.append(first, n)).astype(np.int64)
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
    m = check_positive_int(n_states, "n_states")  # any size: ids are int64
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
    all_s, lengths = _flat_sequences(states, "states", m)
    all_o, o_lengths = _flat_sequences(symbols, "symbols", nt)
    if lengths.size != o_lengths.size:
        raise ValidationError(
            "states and symbols must hold the same number of sequences; got"
            f" {lengths.size} state and {o_lengths.size} symbol sequence(s)"
        )
    differ = np.flatnonzero(lengths != o_lengths)
    if differ.size:
        k = int(differ[0])
        raise ValidationError(
            f"states[{k}] and symbols[{k}] must have the same length; got"
            f" {lengths[k]} and {o_lengths[k]}"
        )
    n_total = int(lengths.sum())
    check_work_size(
        8 * n_total,
        f"counting {lengths.size} sequence(s) of {n_total:,} steps in all",
    )
    seen, loc = np.unique(all_s, return_inverse=True)
    loc = loc.reshape(-1).astype(np.int64)
    n_seen = seen.shape[0]
    ends = np.cumsum(lengths)
    firsts = ends - lengths
    not_last = np.ones(all_s.shape[0], dtype=bool)
    not_last[ends - 1] = False
    src_pos = np.flatnonzero(not_last)
    t_indptr, t_dst, t_cnt = _count_pairs(
        loc[src_pos], loc[src_pos + 1], n_seen, n_cols=n_seen
    )
    e_indptr, e_sym, e_cnt = _count_pairs(loc, all_o, n_seen, n_cols=nt)
    f_cnt = np.bincount(loc[firsts], minlength=n_seen).astype(np.int64)
    return Counts(
        m, nt, p, r, lengths.size,
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
