"""Discrete states and time symbols: the codebook (paper §2.4.1) and time bins.

A :class:`Codebook` cuts every normalized column into a number of levels and
numbers the tuple of per-column levels in mixed radix, first column most
significant, so that one ``int64`` names one state. :class:`TimeBins` turns the
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

__all__ = ["Codebook", "TimeBins"]

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
        out.append(int(value))
    return tuple(out)


class Codebook:
    """Quantize normalized values into mixed-radix integer states.

    Column ``k`` is cut into ``levels[k]`` equal levels of ``[0, 1]``: a value
    ``u`` becomes the digit ``q = floor(u * levels[k])`` clipped to
    ``0..levels[k]-1`` (so ``u = 1`` lands in the top level and values outside
    ``[0, 1]`` are clipped). The digits of one row form one state number in mixed
    radix, first column most significant::

        state = ((q_0 * CB_1 + q_1) * CB_2 + q_2) ...

    computed in exact ``int64`` arithmetic. The number of states
    ``n_states = prod(levels)`` must fit in ``int64``; a larger codebook is
    refused at construction.

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
        ``prod(levels)`` as a Python int.

    Examples
    --------
    >>> cb = Codebook([2, 3])
    >>> cb.n_states
    6
    >>> cb.encode([[0.0, 0.0], [0.9, 0.5], [1.0, 1.0]])
    array([0, 4, 5])
    >>> cb.decode([4])
    array([[0.75, 0.5 ]])
    """

    def __init__(self, levels) -> None:
        self.levels = _check_levels(levels)
        n = 1
        for cb in self.levels:
            n *= cb  # exact Python integer product
        if n > _INT64_MAX:
            raise ValidationError(
                f"a codebook with levels {list(self.levels)} has {n} states"
                f" (about {float(n):.3g}), which does not fit in int64 (at most"
                f" {_INT64_MAX}); use fewer levels or fewer columns"
            )
        self.n_states = n
        self.n_dims = len(self.levels)
        self._cb = np.array(self.levels, dtype=np.int64)

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
        P = check_points(U, "U")
        self._check_width(P, "U")
        states, n_clipped = self.encode_checked(P)
        return (states, n_clipped) if return_n_clipped else states

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
        states, n_clipped = _encode_rows(P, self._cb)
        return states, int(n_clipped)

    def _from_levels_unchecked(self, Q: np.ndarray) -> np.ndarray:
        s = Q[:, 0].copy()
        for k in range(1, self.n_dims):
            s *= self._cb[k]
            s += Q[:, k]
        return s

    def _check_states(self, states) -> np.ndarray:
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

    def from_levels(self, Q) -> np.ndarray:
        """Combine per-column level digits into state numbers.

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
        a = np.asarray(Q)
        if a.dtype == object or a.dtype.kind not in "iuf":
            raise ValidationError(
                f"Q must be an integer array of shape (n_points, {self.n_dims}); got"
                f" an array of dtype {a.dtype}"
            )
        if a.ndim != 2:
            raise ValidationError(
                f"Q must have shape (n_points, {self.n_dims}); got shape {a.shape}"
            )
        self._check_width(a, "Q")
        if a.dtype.kind == "f" and (
            not np.all(np.isfinite(a)) or np.any(a != np.round(a))
        ):
            raise ValidationError("Q must hold whole numbers; got non-integer values")
        q = np.ascontiguousarray(a, dtype=np.int64)
        bad = np.argwhere((q < 0) | (q >= self._cb))
        if bad.size:
            i, k = (int(v) for v in bad[0])
            raise ValidationError(
                f"Q[:, {k}] must lie in 0..{self.levels[k] - 1}; got Q[{i}, {k}] ="
                f" {a[i, k]}"
            )
        return self._from_levels_unchecked(q)

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
def _encode_rows(P, cb):  # pragma: no cover - compiled
    # floor(u * CB) clipped to 0..CB-1 per column, then mixed radix; and the
    # count of values outside [0, 1]: numpy's arithmetic in one pass
    n, d = P.shape
    states = np.empty(n, dtype=np.int64)
    n_clipped = 0
    for i in range(n):
        s = 0
        for k in range(d):
            u = P[i, k]
            if u < 0.0 or u > 1.0:
                n_clipped += 1
            top = np.float64(cb[k]) - 1.0
            q = np.floor(u * np.float64(cb[k]))
            q = min(max(q, 0.0), top)
            s = s * cb[k] + np.int64(q) if k else np.int64(q)
        states[i] = s
    return states, n_clipped


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
