"""Group normalization (paper §2.2): one range per physical group.

:class:`GroupScaler` maps every column of a group with the *same* minimum and
maximum, taken over all the group's columns and all training demonstrations:
``u = (x - min_g) / (max_g - min_g)``. A path twice as long in X as in Y stays
so after normalization, which per-column scaling would destroy (the paper's
Fig. 2b counter-example, available here as ``mode="per-dimension"``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numba import njit

from ._errors import NotFittedError, ValidationError
from ._registry import Registry
from ._validation import check_points
from .demonstration import Demonstration

__all__ = ["SCALING_MODES", "GroupScaler"]


def _group_ranges(mins, maxs, groups):
    """Per column, the min and max over all columns of the same group."""
    lo, hi = mins.copy(), maxs.copy()
    for g in dict.fromkeys(groups):
        idx = [j for j, h in enumerate(groups) if h == g]
        lo[idx] = mins[idx].min()
        hi[idx] = maxs[idx].max()
    return lo, hi


def _per_column(mins, maxs, groups):
    return mins.copy(), maxs.copy()


def _identity(mins, maxs, groups):
    return np.zeros_like(mins), np.ones_like(maxs)


#: ``mode`` → function (column mins, column maxs, column groups) → the
#: (min, max) actually used for each column.
SCALING_MODES = Registry("mode")
SCALING_MODES.add("group", _group_ranges)
SCALING_MODES.add("per-dimension", _per_column)
SCALING_MODES.add("none", _identity)


# ---------------------------------------------------------------------- input
def _as_list(data, what):
    """Return (list of 2-D arrays, column groups or None, columns or None)."""
    if not _is_collection(data):
        data = [data]
    if len(data) == 0:
        raise ValidationError(f"{what} must hold at least one demonstration")
    arrays, groups, columns = [], None, None
    for i, item in enumerate(data):
        if isinstance(item, Demonstration):
            if i == 0:
                groups, columns = item.groups, item.columns
            elif columns is None:
                raise ValidationError(
                    f"{what} mixes arrays and Demonstrations; got a"
                    f" Demonstration at {what}[{i}]"
                )
            elif (item.groups, item.columns) != (groups, columns):
                raise ValidationError(
                    f"{what}[{i}] has columns {item.columns} in groups"
                    f" {item.groups}; expected the columns of {what}[0]:"
                    f" {columns} in groups {groups}"
                )
            arrays.append(np.asarray(item.X))
        else:
            if columns is not None:
                raise ValidationError(
                    f"{what} mixes Demonstrations and arrays; got"
                    f" {type(item).__name__} at {what}[{i}]"
                )
            name = f"{what}[{i}]" if len(data) > 1 else what
            arrays.append(check_points(item, name))
    d = arrays[0].shape[1]
    for i, a in enumerate(arrays):
        if a.shape[1] != d:
            raise ValidationError(
                f"every demonstration must have the same number of columns"
                f" ({d}, as {what}[0]); got {a.shape[1]} in {what}[{i}]"
            )
    return arrays, groups, columns


def _check_groups(param, data_groups, d):
    if param is None:
        if data_groups is None:
            raise ValidationError(
                "groups must be given (one group name per column) when fitting"
                " plain arrays; got groups=None. Pass e.g."
                f" GroupScaler(groups={['position'] * d!r}) or fit Demonstrations"
            )
        return tuple(data_groups)
    if isinstance(param, str) or not isinstance(param, Sequence):
        raise ValidationError(
            f"groups must be a sequence of group names, one per column; got {param!r}"
        )
    groups = tuple(param)
    if len(groups) != d or not all(isinstance(g, str) and g for g in groups):
        raise ValidationError(
            f"groups must name the group of each of the {d} columns; got {param!r}"
        )
    if data_groups is not None and tuple(data_groups) != groups:
        raise ValidationError(
            f"groups={groups} disagrees with the demonstrations' groups"
            f" {tuple(data_groups)}"
        )
    return groups


def _check_weights(w, groups):
    d = len(groups)
    if w is None:
        return np.ones(d)
    if isinstance(w, Mapping):
        unknown = [g for g in w if g not in groups]
        if unknown:
            raise ValidationError(
                f"weights name unknown group(s) {unknown}; the groups are"
                f" {list(dict.fromkeys(groups))}"
            )
        values = np.array([w.get(g, 1.0) for g in groups], dtype=object)
    else:
        if isinstance(w, str) or not isinstance(w, (Sequence, np.ndarray)):
            raise ValidationError(
                "weights must be a mapping group -> weight or one weight per"
                f" column; got {w!r}"
            )
        values = np.asarray(w, dtype=object)
        if values.shape != (d,):
            raise ValidationError(
                f"weights must have one entry per column (length {d}); got"
                f" shape {values.shape}"
            )
    out = np.empty(d)
    for j, v in enumerate(values):
        ok = isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(
            v, bool
        )
        if not ok or not np.isfinite(v) or v < 0:
            raise ValidationError(
                "weights must be finite numbers >= 0; got"
                f" {v!r} for column {j} (group {groups[j]!r})"
            )
        out[j] = float(v)
    return out


def _checked_ranges(data_min, data_max, column_groups, columns):
    """Stored ranges, groups and names of :meth:`GroupScaler.from_ranges`, checked."""
    lo = check_points(
        np.atleast_1d(np.asarray(data_min, dtype=float))[None], "data_min"
    )[0]
    hi = check_points(
        np.atleast_1d(np.asarray(data_max, dtype=float))[None], "data_max"
    )[0]
    d = lo.shape[0]
    if hi.shape != (d,):
        raise ValidationError(
            f"data_max must have shape ({d},) like data_min; got {hi.shape}"
        )
    bad = np.flatnonzero(hi < lo)
    if bad.size:
        j = int(bad[0])
        raise ValidationError(
            f"data_max must be >= data_min; got {float(hi[j])!r} < {float(lo[j])!r}"
            f" in column {j}"
        )
    groups = tuple(column_groups) if not isinstance(column_groups, str) else ()
    if len(groups) != d or not all(isinstance(g, str) and g for g in groups):
        raise ValidationError(
            f"column_groups must name the group of each of the {d} columns; got"
            f" {column_groups!r}"
        )
    if columns is not None:
        columns = tuple(columns)
        if len(columns) != d:
            raise ValidationError(f"columns must have {d} names; got {len(columns)}")
    return lo, hi, groups, columns


class GroupScaler:
    """Scale each physical group to [0, 1] with one range per group.

    Parameters
    ----------
    groups : sequence of str of length n_dims, optional
        The group of each column. ``None`` (default) takes the groups from the
        :class:`~ndlfd.demonstration.Demonstration` objects passed to :meth:`fit`; it is
        required when fitting plain arrays. When both are given they must agree.
    mode : {"group", "per-dimension", "none"}, default="group"
        ``"group"``: per group one global min and max over all its columns and
        all demonstrations (the paper's magnitude normalization).
        ``"per-dimension"``: each column its own range. ``"none"``: identity
        (min 0, max 1), weights still apply.
    weights : mapping of str to float, or sequence of float, optional
        Non-negative multipliers applied after normalization: per group (groups
        not named get 1) or per column. Used to make a group count more or less
        in the key-point reduction. :meth:`inverse_transform` divides them out;
        a zero weight cannot be divided out, so a column with weight 0 is
        inverse-mapped to its minimum ``data_min_`` (documented, tested).

    Attributes
    ----------
    n_features_in_ : int
        Number of columns seen in :meth:`fit`.
    column_groups_ : tuple of str
        The group of each column.
    columns_ : tuple of str or None
        Column names when fitted on demonstrations (checked at transform time).
    group_names_ : tuple of str
        The distinct groups, in column order.
    data_min_, data_max_ : ndarray of shape (n_features_in_,)
        The range actually used for each column (in group mode all columns of a
        group share the group's range; in ``"none"`` mode 0 and 1).
    data_range_ : ndarray of shape (n_features_in_,)
        ``data_max_ - data_min_``; 0 for a constant group, which is then mapped
        to ``x - min`` (so to 0) instead of being divided by zero.
    group_min_, group_max_ : dict of str to float
        Per group the smallest and largest value seen over all its columns and
        demonstrations (in group mode, the range used).
    column_weights_ : ndarray of shape (n_features_in_,)
        The weight of each column (1.0 when no weights).
    n_samples_seen_ : int
        Total number of rows seen in :meth:`fit`.

    Examples
    --------
    >>> import numpy as np
    >>> X = np.array([[0.0, 0.0], [20.0, 10.0]])   # 20 long in x, 10 in y
    >>> GroupScaler(["position", "position"]).fit_transform(X)
    array([[0. , 0. ],
           [1. , 0.5]])
    >>> GroupScaler(["position", "position"], mode="per-dimension").fit_transform(X)
    array([[0., 0.],
           [1., 1.]])
    """

    def __init__(self, groups=None, mode="group", weights=None):
        self.groups = groups
        self.mode = mode
        self.weights = weights

    # ------------------------------------------------------------------ fit
    def fit(self, demos, y=None) -> GroupScaler:
        """Learn each column's range from one or many demonstrations.

        Parameters
        ----------
        demos : Demonstration, list of Demonstration, ndarray of shape (n, d)\
 or list of such arrays
            Training data; lists may be ragged in length but not in columns.
        y : None
            Ignored (scikit-learn convention).

        Returns
        -------
        self : GroupScaler
        """
        SCALING_MODES.get(self.mode)
        arrays, data_groups, columns = _as_list(demos, "demos")
        d = arrays[0].shape[1]
        groups = _check_groups(self.groups, data_groups, d)
        weights = _check_weights(self.weights, groups)
        mins = np.min([a.min(axis=0) for a in arrays], axis=0)
        maxs = np.max([a.max(axis=0) for a in arrays], axis=0)
        n_samples = int(sum(a.shape[0] for a in arrays))
        self._set_fitted(mins, maxs, groups, columns, weights, n_samples)
        return self

    def _set_fitted(self, mins, maxs, groups, columns, weights, n_samples) -> None:
        """The fitted attributes from the data's column extremes (fit's end)."""
        lo, hi = SCALING_MODES.get(self.mode)(mins, maxs, groups)
        gmin, gmax = _group_ranges(mins, maxs, groups)
        self._set_ranges(lo, hi, groups, columns, weights, n_samples, gmin, gmax)

    def _set_ranges(self, lo, hi, groups, columns, weights, n_samples, gmin, gmax):
        """The fitted attributes: ranges used, data extremes per group, counts."""
        self.n_features_in_ = len(groups)
        self.column_groups_ = groups
        self.columns_ = columns
        self.group_names_ = tuple(dict.fromkeys(groups))
        self.group_min_ = {g: float(gmin[groups.index(g)]) for g in self.group_names_}
        self.group_max_ = {g: float(gmax[groups.index(g)]) for g in self.group_names_}
        self.data_min_ = lo
        self.data_max_ = hi
        self.data_range_ = hi - lo
        self.column_weights_ = weights
        self.n_samples_seen_ = n_samples
        # A range below the smallest normal float is a zero range: dividing by
        # a subnormal number overflows for any value a little outside it.
        tiny = np.finfo(np.float64).tiny
        self._range_divisor = np.where(self.data_range_ > tiny, self.data_range_, 1.0)

    @classmethod
    def from_data_ranges(
        cls,
        mins,
        maxs,
        column_groups,
        *,
        n_samples: int,
        columns=None,
        mode: str = "group",
        weights=None,
    ) -> GroupScaler:
        """The scaler :meth:`fit` makes of data with these column extremes.

        A fit needs only each column's smallest and largest value and the
        number of rows, so data seen in parts (the two passes of
        :meth:`ndlfd.KeypointHMM.fit`) give exactly the scaler of one fit.

        Parameters
        ----------
        mins, maxs : array-like of shape (n_dims,)
            Each column's smallest and largest value over the data.
        column_groups : sequence of str of length n_dims
            The group of each column.
        n_samples : int
            Rows of the data (``n_samples_seen_``).
        columns : sequence of str of length n_dims, optional
            Column names, checked when transforming Demonstrations.
        mode, weights
            As in the constructor.

        Returns
        -------
        scaler : GroupScaler
            Fitted, equal in every attribute to ``GroupScaler(column_groups,
            mode, weights).fit(data)``.

        Examples
        --------
        >>> X = np.array([[0.0, 0.0], [20.0, 10.0]])
        >>> s = GroupScaler.from_data_ranges([0.0, 0.0], [20.0, 10.0],
        ...                                  ["p", "p"], n_samples=2)
        >>> s.transform(X), s.group_max_, s.n_samples_seen_
        (array([[0. , 0. ],
               [1. , 0.5]]), {'p': 20.0}, 2)
        """
        self = cls(groups=None, mode=mode, weights=weights)
        groups = tuple(column_groups)
        mins = np.asarray(mins, dtype=np.float64)
        maxs = np.asarray(maxs, dtype=np.float64)
        columns = None if columns is None else tuple(columns)
        weights = _check_weights(self.weights, groups)
        self._set_fitted(mins, maxs, groups, columns, weights, int(n_samples))
        return self

    @classmethod
    def from_ranges(
        cls,
        data_min,
        data_max,
        column_groups,
        *,
        columns=None,
        mode: str = "group",
        weights=None,
        group_min=None,
        group_max=None,
        n_samples_seen: int = 0,
    ) -> GroupScaler:
        """Rebuild a fitted scaler from stored per-column ranges (for loading models).

        Parameters
        ----------
        data_min, data_max : array-like of shape (n_dims,)
            The ranges actually used (``data_min_`` / ``data_max_`` of a fitted
            scaler), ``data_min <= data_max``.
        column_groups : sequence of str of length n_dims
            The group of each column.
        columns : sequence of str of length n_dims, optional
            Column names, checked when transforming Demonstrations.
        mode, weights
            As in the constructor; stored as the parameters.
        group_min, group_max : mapping of str to float, optional
            The data's extremes per group (``group_min_`` / ``group_max_`` of
            the fitted scaler); by default the group-wise extremes of the
            given ranges.
        n_samples_seen : int, default=0
            Rows the fitted scaler saw.

        Returns
        -------
        scaler : GroupScaler
            Fitted: transforms exactly like the scaler the ranges came from.

        Examples
        --------
        >>> s = GroupScaler.from_ranges([0.0, 0.0], [10.0, 10.0], ["p", "p"])
        >>> s.transform([[5.0, 10.0]])
        array([[0.5, 1. ]])
        """
        SCALING_MODES.get(mode)
        lo, hi, groups, columns = _checked_ranges(
            data_min, data_max, column_groups, columns
        )
        self = cls(groups=None, mode=mode, weights=weights)
        gmin, gmax = _group_ranges(lo, hi, groups)
        weights = _check_weights(self.weights, groups)
        n = int(n_samples_seen)
        self._set_ranges(lo.copy(), hi.copy(), groups, columns, weights, n, gmin, gmax)
        names = self.group_names_
        for given, have in ((group_min, self.group_min_), (group_max, self.group_max_)):
            if given is not None:
                if set(given) != set(names):
                    raise ValidationError(
                        f"group_min and group_max must name the groups {names};"
                        f" got {tuple(given)}"
                    )
                have.update((g, float(given[g])) for g in names)
        return self

    # ------------------------------------------------------------------ use
    def _check_fitted(self):
        if not hasattr(self, "data_min_"):
            raise NotFittedError(
                "this GroupScaler is not fitted yet; call fit(demos) before"
                " transform or inverse_transform"
            )

    def _prepare(self, X, what):
        """Return (list of arrays, was_single) checked against the fitted columns."""
        self._check_fitted()
        single = not _is_collection(X)
        items = [X] if single else list(X)
        arrays = []
        for i, item in enumerate(items):
            name = what if single else f"{what}[{i}]"
            if isinstance(item, Demonstration):
                if self.columns_ is not None and item.columns != self.columns_:
                    raise ValidationError(
                        f"{name} has columns {item.columns}; expected the fitted"
                        f" columns {self.columns_} (use demo.select(...) to pick"
                        " the fitted groups)"
                    )
                if item.groups != self.column_groups_:
                    raise ValidationError(
                        f"{name} has column groups {item.groups}; expected the"
                        f" fitted groups {self.column_groups_}"
                    )
                arrays.append(np.asarray(item.X))
            else:
                a = check_points(item, name)
                if a.shape[1] != self.n_features_in_:
                    raise ValidationError(
                        f"{name} must have {self.n_features_in_} columns (as in"
                        f" fit); got shape {a.shape}"
                    )
                arrays.append(a)
        return arrays, single

    def _divisor(self):
        """The ranges divided by: a zero range counts as 1 (see ``_set_ranges``)."""
        return self._range_divisor

    def inverse_scale(self, D) -> np.ndarray:
        """Map normalized differences or spreads to physical units (no offset).

        ``D * data_range_`` (a zero range counts as 1, as in :meth:`transform`),
        unweighted: for a standard deviation or a step, not a position.

        Parameters
        ----------
        D : array-like of shape (n_samples, n_features_in_)

        Returns
        -------
        ndarray of shape (n_samples, n_features_in_)

        Examples
        --------
        >>> s = GroupScaler.from_ranges([0.0, 5.0], [10.0, 5.0], ["p", "q"])
        >>> s.inverse_scale([[0.5, 0.5]])
        array([[5. , 0.5]])
        """
        self._check_fitted()
        return np.asarray(D, dtype=np.float64) * self._divisor()

    def transform(self, X, *, weighted: bool = True):
        """Normalize: ``u = (x - data_min_) / data_range_ * column_weights_``.

        Values outside the fitted range are kept (they map below 0 or above
        the weight), never clipped.

        Parameters
        ----------
        X : Demonstration, ndarray of shape (n_samples, n_features_in_), or list
            A Demonstration must have the fitted columns and groups. A list gives
            a list.
        weighted : bool, default=True
            Apply ``column_weights_``; ``False`` gives the plain [0, 1] values
            (for example for a codebook).

        Returns
        -------
        U : ndarray of shape (n_samples, n_features_in_), or list of them
        """
        arrays, single = self._prepare(X, "X")
        div, w = self._divisor(), self.column_weights_
        out = [_scale_rows(a, self.data_min_, div, w, weighted) for a in arrays]
        return out[0] if single else out

    def inverse_transform(self, U, *, weighted: bool = True):
        """Map normalized values back to physical units.

        Parameters
        ----------
        U : ndarray of shape (n_samples, n_features_in_), or list of them
            Normalized values as produced by :meth:`transform` with the same
            ``weighted``.
        weighted : bool, default=True
            Whether ``U`` carries the column weights. A column of weight 0 is
            mapped back to its ``data_min_`` (its values cannot be recovered).

        Returns
        -------
        X : ndarray of shape (n_samples, n_features_in_), or list of them
        """
        arrays, single = self._prepare(U, "U")
        div = self._divisor()
        out = []
        for a in arrays:
            if weighted:
                w = self.column_weights_
                a = np.divide(a, w, out=np.zeros_like(a), where=w > 0)
            out.append(a * div + self.data_min_)
        return out[0] if single else out

    def fit_transform(self, demos, y=None, *, weighted: bool = True):
        """Fit to ``demos`` and return their normalized values.

        Returns
        -------
        U : ndarray of shape (n_samples, n_features_in_), or list of them
            A list when ``demos`` is a list.
        """
        return self.fit(demos).transform(demos, weighted=weighted)

    def get_params(self, deep: bool = True) -> dict:
        """Return the constructor parameters (scikit-learn convention)."""
        return {"groups": self.groups, "mode": self.mode, "weights": self.weights}

    def set_params(self, **params) -> GroupScaler:
        """Set constructor parameters (scikit-learn convention)."""
        for key, value in params.items():
            if key not in ("groups", "mode", "weights"):
                raise ValidationError(
                    f"unknown parameter {key!r} for GroupScaler; expected groups,"
                    " mode or weights"
                )
            setattr(self, key, value)
        return self

    def __repr__(self) -> str:
        return (
            f"GroupScaler(groups={self.groups!r}, mode={self.mode!r},"
            f" weights={self.weights!r})"
        )


#: Values per lane group of :func:`_scale_rows`: the parameters are tiled to
#: ``d * _LANES`` so that the loop over a tile runs on vector registers.
_LANES = 8


@njit(cache=True, nogil=True, error_model="numpy")
def _scale_flat(flat, d, lo, div, w, weighted, res):  # pragma: no cover - compiled
    # res = (x - lo) / div * w element by element (w = 1 unweighted), over
    # rows of d values end to end: numpy's arithmetic in one pass. The values
    # run in tiles of d * _LANES with the parameters tiled alike, a loop the
    # compiler vectorizes (division included, as numpy's error model lets it:
    # div is never 0 here); each element gets the same three correctly
    # rounded operations, so the result is numpy's bit for bit.
    width = d * _LANES
    L = np.empty(width)
    D = np.empty(width)
    M = np.empty(width)
    for j in range(width):
        L[j] = lo[j % d]
        D[j] = div[j % d]
        M[j] = w[j % d] if weighted else 1.0
    tiles = flat.size // width
    for b in range(tiles):
        at = b * width
        for j in range(width):
            res[at + j] = (flat[at + j] - L[j]) / D[j] * M[j]
    rest = tiles * width  # a multiple of d: the tiles' parameters fit the rest
    for k in range(rest, flat.size):
        res[k] = (flat[k] - L[k - rest]) / D[k - rest] * M[k - rest]


def _scale_rows(X, lo, div, w, weighted: bool) -> np.ndarray:
    """``(X - lo) / div * w`` (``w`` = 1 when not ``weighted``), compiled."""
    X = np.ascontiguousarray(X)
    out = np.empty(X.shape)
    # read-only whether X is or not: one compiled version (writability is
    # part of numba's array type; the fitted lo, div, w are writable)
    flat = X.reshape(-1)
    flat.flags.writeable = False
    _scale_flat(flat, X.shape[1], lo, div, w, weighted, out.reshape(-1))
    return out


def _is_collection(X) -> bool:
    """Whether ``X`` is a list of demonstrations/arrays rather than one of them."""
    if not isinstance(X, (list, tuple)) or len(X) == 0:
        return isinstance(X, (list, tuple))  # [] is an (empty) collection
    first = X[0]
    if isinstance(first, Demonstration):
        return True
    if isinstance(first, np.ndarray):
        return first.ndim == 2
    try:
        inner = first[0]
    except (IndexError, TypeError, KeyError):
        return False
    return isinstance(inner, (Sequence, np.ndarray)) and not isinstance(inner, str)
