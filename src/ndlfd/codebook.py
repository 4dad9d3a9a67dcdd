"""Discrete states and time symbols: the codebook (paper §2.4.1) and time bins.

A :class:`Codebook` cuts every normalized column into a number of levels: a
row of values becomes a *cell*, the tuple of its per-column level indices
(:meth:`Codebook.cells`). The learner's states are the cells its key points
visit, interned (:func:`intern_cells`): numbered ``0..n_visited-1`` in the
cells' lexicographic order, each id keeping its cell's indices, so any number
of columns at any levels gives states (27 columns at 20 levels are 20**27
possible cells, far past ``int64``; a fit visits a few thousand).

The paper numbers the tuple in mixed radix instead, first column most
significant (:meth:`Codebook.encode`); that number orders cells as the
lexicographic order does, so interned ids are the mixed-radix numbers' ranks
and every result that depends on the states' order (Viterbi's ties) is the
same. :meth:`Codebook.encode` and :meth:`Codebook.decode` are kept for
codebooks whose ``n_states`` fits in ``int64``. :class:`TimeBins` turns the
time vector of one demonstration into the observation symbols of the HMM.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence

import numpy as np
from numba import njit

from ._errors import ValidationError
from ._validation import (
    check_int_sequence,
    check_n_time_bins,
    check_points,
    check_times,
)
from .demonstration import unit_time

__all__ = ["Codebook", "TimeBins", "intern_cells", "lowest_unseen_cell"]

_INT64_MAX = int(np.iinfo(np.int64).max)


def _check_levels(levels) -> tuple[int, ...]:
    if isinstance(levels, np.ndarray):
        if levels.ndim != 1:
            raise ValidationError(
                "levels must be a sequence of integers >= 1, one per column; got an"
                f" array of shape {levels.shape}"
            )
        levels = levels.tolist()
    if isinstance(levels, (str, bytes)) or not isinstance(levels, Sequence):
        raise ValidationError(
            "levels must be a sequence of integers >= 1, one per column; got"
            f" {levels!r} of type {type(levels).__name__}"
        )
    if len(levels) == 0:
        raise ValidationError(
            "levels must be a sequence of integers >= 1, one per column; got an"
            " empty sequence"
        )
    out = []
    for k, value in enumerate(levels):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise ValidationError(
                f"levels[{k}] must be an integer >= 1; got {value!r} of type"
                f" {type(value).__name__}"
            )
        if int(value) < 1:
            raise ValidationError(f"levels[{k}] must be an integer >= 1; got {value!r}")
        if int(value) > _INT64_MAX:
            raise ValidationError(
                f"levels[{k}] must be at most {_INT64_MAX} (level indices are"
                f" int64); got {value!r}"
            )
        out.append(int(value))
    return tuple(out)


class Codebook:
    """Quantize normalized values into cells (and, where it fits, state numbers).

    Column ``k`` is cut into ``levels[k]`` equal levels of ``[0, 1]``: a value
    ``u`` becomes the level index ``q = floor(u * levels[k])`` clipped to
    ``0..levels[k]-1`` (so ``u = 1`` lands in the top level and values outside
    ``[0, 1]`` are clipped). The indices of one row are its cell
    (:meth:`cells`); the learner interns the cells it visits
    (:func:`intern_cells`), so any number of columns works.

    The paper's state number is the cell in mixed radix, first column most
    significant::

        state = ((q_0 * CB_1 + q_1) * CB_2 + q_2) ...

    computed in exact ``int64`` arithmetic by :meth:`encode` (and undone by
    :meth:`decode`, :meth:`to_levels`); those need ``n_states =
    prod(levels)`` to fit in ``int64`` and say so otherwise.

    Parameters
    ----------
    levels : sequence of int of length n_dims
        Levels per column, each >= 1.

    Attributes
    ----------
    levels : tuple of int
        The levels per column.
    n_dims : int
        Number of columns.
    n_states : int
        ``prod(levels)`` as a Python int (exact, of any size): the number of
        possible cells.
    fits_int64 : bool
        Whether ``n_states`` fits in ``int64`` (mixed-radix state numbers).

    Examples
    --------
    >>> cb = Codebook([2, 3])
    >>> cb.n_states
    6
    >>> cb.encode([[0.0, 0.0], [0.9, 0.5], [1.0, 1.0]])
    array([0, 4, 5])
    >>> cb.decode([4])
    array([[0.75, 0.5 ]])
    >>> cb.cells([[0.9, 0.5]])
    array([[1, 1]])
    >>> big = Codebook([20] * 27)
    >>> big.fits_int64, f"{big.n_states:.3g}"
    (False, '1.34e+35')
    """

    def __init__(self, levels) -> None:
        self.levels = _check_levels(levels)
        n = 1
        for cb in self.levels:
            n *= cb  # exact Python integer product
        self.n_states = n
        self.fits_int64 = n <= _INT64_MAX
        self.n_dims = len(self.levels)
        self._cb = np.array(self.levels, dtype=np.int64)

    def _need_int64(self, what: str) -> None:
        if not self.fits_int64:
            raise ValidationError(
                f"{what} numbers a cell in mixed radix, which needs the codebook's"
                f" {self.n_states:.3g} cells (levels {list(self.levels)}) to fit in"
                f" int64 (at most {_INT64_MAX}); use cells() and intern_cells(),"
                " which work for any number of columns"
            )

    @classmethod
    def from_groups(
        cls, levels_by_group: Mapping[str, int], column_groups: Sequence[str]
    ) -> Codebook:
        """Build a codebook from levels per physical group.

        Parameters
        ----------
        levels_by_group : mapping of str to int
            Levels for each group name (for example ``{"position": 20,
            "velocity": 10}``).
        column_groups : sequence of str of length n_dims
            The group of each column.

        Returns
        -------
        codebook : Codebook
            One level count per column, taken from its group.

        Examples
        --------
        >>> cb = Codebook.from_groups(
        ...     {"position": 20, "velocity": 10},
        ...     ["position", "position", "velocity", "velocity"],
        ... )
        >>> cb.levels, cb.n_states
        ((20, 20, 10, 10), 40000)
        """
        if not isinstance(levels_by_group, Mapping):
            raise ValidationError(
                "levels_by_group must be a mapping of group name to levels; got"
                f" {type(levels_by_group).__name__}"
            )
        if isinstance(column_groups, (str, bytes)) or not isinstance(
            column_groups, Sequence
        ):
            raise ValidationError(
                "column_groups must be a sequence of group names, one per column;"
                f" got {column_groups!r}"
            )
        groups = list(column_groups)
        missing = [g for g in dict.fromkeys(groups) if g not in levels_by_group]
        if missing:
            raise ValidationError(
                f"no codebook level given for group(s) {missing}; levels_by_group"
                f" has {sorted(map(str, levels_by_group))}"
            )
        unknown = [g for g in levels_by_group if g not in set(groups)]
        if unknown:
            raise ValidationError(
                f"levels_by_group names unknown group(s) {unknown}; the columns'"
                f" groups are {list(dict.fromkeys(groups))}"
            )
        levels = []
        for k, g in enumerate(groups):
            value = levels_by_group[g]
            if isinstance(value, bool) or not isinstance(value, numbers.Integral):
                raise ValidationError(
                    f"levels for group {g!r} must be an integer >= 1; got {value!r}"
                )
            if int(value) < 1:
                raise ValidationError(
                    f"levels for group {g!r} (column {k}) must be an integer >= 1;"
                    f" got {value!r}"
                )
            levels.append(int(value))
        return cls(levels)

    def __repr__(self) -> str:
        return f"Codebook(levels={list(self.levels)})"

    def _check_width(self, a: np.ndarray, name: str) -> None:
        if a.shape[1] != self.n_dims:
            raise ValidationError(
                f"{name} must have {self.n_dims} column(s), one per codebook level;"
                f" got shape {a.shape}"
            )

    def encode(self, U, *, return_n_clipped: bool = False):
        """Map normalized values to state numbers.

        Parameters
        ----------
        U : array-like of shape (n_points, n_dims)
            Normalized values, nominally in ``[0, 1]``.
        return_n_clipped : bool, default=False
            Also return how many values lay outside ``[0, 1]`` and were clipped.

        Returns
        -------
        states : ndarray of shape (n_points,), dtype int64
        n_clipped : int
            Only when ``return_n_clipped`` is true.

        Examples
        --------
        >>> Codebook([10]).encode([[0.05], [1.0], [1.7], [-0.2]], return_n_clipped=True)
        (array([0, 9, 9, 0]), 2)
        """
        self._need_int64("encode")
        return self._quantized(U, self.encode_checked, return_n_clipped)

    def _quantized(self, U, checked, return_n_clipped: bool):
        """``checked`` (encode or cells) of ``U`` once checked."""
        P = check_points(U, "U")
        self._check_width(P, "U")
        out, n_clipped = checked(P)
        return (out, n_clipped) if return_n_clipped else out

    def cells(self, U, *, return_n_clipped: bool = False):
        """Map normalized values to their cells: one level index per column.

        Parameters
        ----------
        U : array-like of shape (n_points, n_dims)
            Normalized values, nominally in ``[0, 1]``.
        return_n_clipped : bool, default=False
            Also return how many values lay outside ``[0, 1]`` and were clipped.

        Returns
        -------
        cells : ndarray of shape (n_points, n_dims), dtype int64
            Column ``k`` in ``0..levels[k]-1``.
        n_clipped : int
            Only when ``return_n_clipped`` is true.

        Examples
        --------
        >>> Codebook([10, 4]).cells([[0.05, 1.0], [1.7, 0.3]], return_n_clipped=True)
        (array([[0, 3],
               [9, 1]]), 1)
        """
        return self._quantized(U, self.cells_checked, return_n_clipped)

    def cells_checked(self, P: np.ndarray) -> tuple[np.ndarray, int]:
        """:meth:`cells` of values checked already, and the clipped count.

        ``P`` must be a finite float64 array of ``n_dims`` columns; nothing is
        checked again (the fit's key points).

        Parameters
        ----------
        P : ndarray of shape (n_points, n_dims), float64

        Returns
        -------
        cells : ndarray of shape (n_points, n_dims), dtype int64
        n_clipped : int

        Examples
        --------
        >>> Codebook([10]).cells_checked(np.array([[0.05], [1.7]]))
        (array([[0],
               [9]]), 1)
        """
        cells, n_clipped = _cell_rows(np.ascontiguousarray(P, np.float64), self._cb)
        return cells, int(n_clipped)

    def centres(self, cells) -> np.ndarray:
        """The normalized centres ``(q + 0.5) / levels`` of cells (eq. 9).

        Parameters
        ----------
        cells : array-like of shape (n_points, n_dims)
            Level indices, column ``k`` in ``0..levels[k]-1``.

        Returns
        -------
        U : ndarray of shape (n_points, n_dims), dtype float64

        Examples
        --------
        >>> Codebook([4, 2]).centres([[0, 1], [3, 0]])
        array([[0.125, 0.75 ],
               [0.875, 0.25 ]])
        """
        q = self._check_cells(cells)
        return (q + 0.5) / self._cb.astype(np.float64)

    def encode_checked(self, P: np.ndarray) -> tuple[np.ndarray, int]:
        """:meth:`encode` of values checked already, and the clipped count.

        For a caller's own normalized values (the fit's key points): ``P``
        must be a finite float64 array of ``n_dims`` columns; nothing is
        checked again.

        Parameters
        ----------
        P : ndarray of shape (n_points, n_dims), float64

        Returns
        -------
        states : ndarray of shape (n_points,), dtype int64
        n_clipped : int

        Examples
        --------
        >>> Codebook([10]).encode_checked(np.array([[0.05], [1.7]]))
        (array([0, 9]), 1)
        """
        self._need_int64("encode_checked")
        cells, n_clipped = self.cells_checked(P)
        return self._from_levels_unchecked(cells), n_clipped

    def _from_levels_unchecked(self, Q: np.ndarray) -> np.ndarray:
        s = Q[:, 0].copy()
        for k in range(1, self.n_dims):
            s *= self._cb[k]
            s += Q[:, k]
        return s

    def _check_states(self, states) -> np.ndarray:
        self._need_int64("a state number")
        return check_int_sequence(states, "states", low=0, high=self.n_states)

    def to_levels(self, states) -> np.ndarray:
        """Split state numbers into their per-column level digits.

        Parameters
        ----------
        states : array-like of shape (n_points,)
            State numbers in ``0..n_states-1``.

        Returns
        -------
        Q : ndarray of shape (n_points, n_dims), dtype int64

        Examples
        --------
        >>> Codebook([2, 3]).to_levels([0, 4, 5])
        array([[0, 0],
               [1, 1],
               [1, 2]])
        """
        s = self._check_states(states).copy()
        Q = np.empty((s.shape[0], self.n_dims), dtype=np.int64)
        for k in range(self.n_dims - 1, -1, -1):
            Q[:, k] = s % self._cb[k]
            s //= self._cb[k]
        return Q

    def _check_cells(self, Q, name: str = "cells") -> np.ndarray:
        a = np.asarray(Q)
        if a.dtype == object or a.dtype.kind not in "iuf":
            raise ValidationError(
                f"{name} must be an integer array of shape (n_points, {self.n_dims});"
                f" got an array of dtype {a.dtype}"
            )
        if a.ndim != 2:
            raise ValidationError(
                f"{name} must have shape (n_points, {self.n_dims}); got shape {a.shape}"
            )
        self._check_width(a, name)
        if a.dtype.kind == "f" and (
            not np.all(np.isfinite(a)) or np.any(a != np.round(a))
        ):
            raise ValidationError(
                f"{name} must hold whole numbers; got non-integer values"
            )
        q = np.ascontiguousarray(a, dtype=np.int64)
        bad = np.argwhere((q < 0) | (q >= self._cb))
        if bad.size:
            i, k = (int(v) for v in bad[0])
            raise ValidationError(
                f"{name}[:, {k}] must lie in 0..{self.levels[k] - 1}; got {name}[{i},"
                f" {k}] = {a[i, k]}"
            )
        return q

    def from_levels(self, Q) -> np.ndarray:
        """Combine per-column level digits (cells) into state numbers.

        Parameters
        ----------
        Q : array-like of shape (n_points, n_dims)
            Integer digits, column ``k`` in ``0..levels[k]-1``.

        Returns
        -------
        states : ndarray of shape (n_points,), dtype int64

        Examples
        --------
        >>> Codebook([2, 3]).from_levels([[1, 1], [1, 2]])
        array([4, 5])
        """
        self._need_int64("from_levels")
        return self._from_levels_unchecked(self._check_cells(Q, "Q"))

    def decode(self, states) -> np.ndarray:
        """Return the level centres ``(q + 0.5) / levels`` of state numbers.

        Parameters
        ----------
        states : array-like of shape (n_points,)
            State numbers in ``0..n_states-1``.

        Returns
        -------
        U : ndarray of shape (n_points, n_dims), dtype float64
            Normalized values at the centres of the levels.

        Examples
        --------
        >>> Codebook([4]).decode([0, 3])
        array([[0.125],
               [0.875]])
        """
        Q = self.to_levels(states)
        return (Q + 0.5) / self._cb.astype(np.float64)


@njit(cache=True, nogil=True)
def _cell_rows(P, cb):  # pragma: no cover - compiled
    # floor(u * CB) clipped to 0..CB-1 per column, and the count of values
    # outside [0, 1]: numpy's arithmetic in one pass
    n, d = P.shape
    cells = np.empty((n, d), dtype=np.int64)
    n_clipped = 0
    for i in range(n):
        for k in range(d):
            u = P[i, k]
            if u < 0.0 or u > 1.0:
                n_clipped += 1
            top = np.float64(cb[k]) - 1.0
            q = np.floor(u * np.float64(cb[k]))
            cells[i, k] = np.int64(min(max(q, 0.0), top))
    return cells, n_clipped


def intern_cells(cells) -> tuple[np.ndarray, np.ndarray]:
    """The distinct cells in lexicographic order, and each row's id among them.

    The order is the one the paper's mixed-radix numbers give (first column
    most significant), so ids are those numbers' ranks among the cells seen:
    an order-preserving renumbering. Rows are packed into one ``int64`` key
    per row by the columns' own ranges where that fits (fast), and sorted
    column by column otherwise; both give the same result.

    Parameters
    ----------
    cells : array-like of shape (n_rows, n_dims)
        Non-negative integer cells (:meth:`Codebook.cells`).

    Returns
    -------
    distinct : ndarray of shape (n_distinct, n_dims), dtype int64
        Sorted lexicographically, no two equal.
    ids : ndarray of shape (n_rows,), dtype int64
        ``distinct[ids] == cells``.

    Examples
    --------
    >>> distinct, ids = intern_cells([[1, 0], [0, 5], [1, 0], [0, 2]])
    >>> distinct
    array([[0, 2],
           [0, 5],
           [1, 0]])
    >>> ids
    array([2, 1, 2, 0])
    """
    q = np.ascontiguousarray(cells, dtype=np.int64)
    if q.ndim != 2:
        raise ValidationError(
            f"cells must have shape (n_rows, n_dims); got shape {q.shape}"
        )
    n, d = q.shape
    if n == 0:
        return q.copy(), np.zeros(0, dtype=np.int64)
    if q.min() < 0:
        raise ValidationError("cells must hold level indices >= 0; got a negative one")
    radix = q.max(axis=0) + 1
    size = 1
    for r in radix.tolist():
        size *= int(r)
    if size <= _INT64_MAX:  # one key per row, in the same order
        key = q[:, 0].copy()
        for k in range(1, d):
            key *= radix[k]
            key += q[:, k]
        _, first, ids = np.unique(key, return_index=True, return_inverse=True)
        return q[first], ids.reshape(-1).astype(np.int64)
    order = np.lexsort(q.T[::-1])
    sq = q[order]
    new = np.ones(n, dtype=bool)
    new[1:] = np.any(sq[1:] != sq[:-1], axis=1)
    ranks = np.cumsum(new) - 1
    ids = np.empty(n, dtype=np.int64)
    ids[order] = ranks
    return sq[new], ids


def lowest_unseen_cell(distinct, levels) -> np.ndarray | None:
    """The lexicographically lowest cell not in ``distinct`` (None: all seen).

    The cell the paper's numbering gives the lowest state number never seen in
    training (what a decoder returns for such a state).

    Parameters
    ----------
    distinct : ndarray of shape (n_distinct, n_dims)
        Sorted distinct cells (:func:`intern_cells`).
    levels : sequence of int of length n_dims

    Returns
    -------
    cell : ndarray of shape (n_dims,), dtype int64, or None

    Examples
    --------
    >>> lowest_unseen_cell(np.array([[0, 0], [0, 1], [1, 1]]), [2, 2])
    array([1, 0])
    """
    cb = [int(v) for v in levels]
    cell = [0] * len(cb)  # walk the cells in order beside the seen ones
    for row in np.asarray(distinct, dtype=np.int64).tolist():
        if row != cell:
            return np.array(cell, dtype=np.int64)
        for k in range(len(cb) - 1, -1, -1):  # the next cell in order
            cell[k] += 1
            if cell[k] < cb[k]:
                break
            cell[k] = 0
        else:
            return None  # every cell was seen
    return np.array(cell, dtype=np.int64)


@njit(cache=True, nogil=True)
def _bin_times(tau, n_bins):  # pragma: no cover - compiled
    # floor(tau * N_t) clipped to 0..N_t-1 (numpy's arithmetic, one pass)
    out = np.empty(tau.size, dtype=np.int64)
    top = np.float64(n_bins - 1)
    for i in range(tau.size):
        out[i] = np.int64(min(max(np.floor(tau[i] * n_bins), 0.0), top))
    return out


class TimeBins:
    """Cut one demonstration's normalized time into ``n_bins`` symbols.

    ``tau = (t - t[0]) / (t[-1] - t[0])`` (``tau = 0`` for a single sample) and the
    symbol is ``floor(tau * n_bins)`` clipped to ``n_bins - 1``.

    Parameters
    ----------
    n_bins : int
        Number of time symbols ``N_t``, in ``1..MAX_TIME_BINS`` (268,435,455: a
        generation works on every time bin at once).

    Examples
    --------
    >>> TimeBins(4).transform([0.0, 1.0, 2.0, 3.0, 4.0])
    array([0, 1, 2, 3, 3])
    """

    def __init__(self, n_bins: int) -> None:
        self.n_bins = check_n_time_bins(n_bins, "n_bins")

    def __repr__(self) -> str:
        return f"TimeBins(n_bins={self.n_bins})"

    def normalize(self, t) -> np.ndarray:
        """Map a strictly increasing time vector onto ``[0, 1]``.

        Parameters
        ----------
        t : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least one).

        Returns
        -------
        tau : ndarray of shape (n_samples,), dtype float64

        Examples
        --------
        >>> TimeBins(10).normalize([2.0, 3.0, 6.0])
        array([0.  , 0.25, 1.  ])
        """
        tt = check_times(t, name="t")
        if tt.size == 0:
            raise ValidationError("t must hold at least one time stamp; got length 0")
        return unit_time(tt)

    def transform(self, t) -> np.ndarray:
        """Return the time symbols of a time vector.

        Parameters
        ----------
        t : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least one).

        Returns
        -------
        symbols : ndarray of shape (n_samples,), dtype int64
            Values in ``0..n_bins-1``.

        Examples
        --------
        >>> TimeBins(3).transform([0.0, 0.5, 1.0])
        array([0, 1, 2])
        """
        return self.symbols(self.normalize(t))

    def symbols(self, tau) -> np.ndarray:
        """Time symbols of normalized times (:meth:`normalize`'s output).

        Parameters
        ----------
        tau : ndarray of shape (n_samples,)
            Normalized times, nominally in ``[0, 1]`` (not checked).

        Returns
        -------
        symbols : ndarray of shape (n_samples,), dtype int64
            ``floor(tau * n_bins)`` clipped to ``0..n_bins-1``.

        Examples
        --------
        >>> TimeBins(4).symbols(np.array([0.0, 0.3, 1.0]))
        array([0, 1, 3])
        """
        tau = np.ascontiguousarray(tau, dtype=np.float64)
        return _bin_times(tau, self.n_bins)
