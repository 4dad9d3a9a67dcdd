"""One place for input checks: every public doorway calls these.

Each check returns a clean array (float64 or int64, C-contiguous) or raises a
:class:`~ndlfd.ValidationError` whose message says what was expected and what
was got.
"""

from __future__ import annotations

import numbers

import numpy as np

from ._errors import ResourceLimitError, ValidationError

__all__ = [
    "MAX_TIME_BINS",
    "MAX_VALUES",
    "MAX_WORK_BYTES",
    "as_float_array",
    "check_int_sequence",
    "check_n_time_bins",
    "check_nonnegative_scalar",
    "check_points",
    "check_positive_int",
    "check_random_state",
    "check_times",
    "check_weights",
    "check_work_size",
    "first_nonfinite_row",
]


#: The largest work array (in bytes) one call allocates: 2 GiB. A call that
#: would need a larger one is refused with :class:`~ndlfd.ResourceLimitError`
#: before anything of that size is allocated (never a ``MemoryError`` from deep
#: inside). The bounds below follow from it; ``docs/robustness.md`` lists them.
MAX_WORK_BYTES = 2 * 2**30

#: The most values one input array may hold (points x dimensions, samples x
#: channels): its float64 copy is one work array.
MAX_VALUES = MAX_WORK_BYTES // 8

#: The most time bins (``n_time_bins``, ``TimeBins(n_bins)``): a generation
#: works on every bin at once (the blend decodes each bin on its segment
#: model, the band takes the posterior of each), 8 bytes per bin at the least.
MAX_TIME_BINS = MAX_WORK_BYTES // 8 - 1


def check_work_size(n_bytes: int, what: str, hint: str = "") -> None:
    """Refuse a call whose work array would exceed :data:`MAX_WORK_BYTES`.

    Call it before allocating, with the size computed in Python integers (no
    overflow).

    Parameters
    ----------
    n_bytes : int
        Bytes the call would allocate at once.
    what : str
        What would be allocated, for the message (e.g. "the posterior of 10
        steps over 5 seen states").
    hint : str, default=""
        What to do instead, appended to the message.

    Raises
    ------
    ResourceLimitError
        Stating the bound and the size got.

    Examples
    --------
    >>> check_work_size(8 * 10**6, "a small array")
    >>> check_work_size(2**40, "one TiB")
    Traceback (most recent call last):
    ...
    ndlfd._errors.ResourceLimitError: one TiB would need 1,048,576 MiB, above the ...
    """
    if int(n_bytes) > MAX_WORK_BYTES:
        raise ResourceLimitError(
            f"{what} would need {int(n_bytes) / 2**20:,.0f} MiB, above the bound"
            f" of {MAX_WORK_BYTES / 2**20:,.0f} MiB per work array"
            f" (ndlfd._validation.MAX_WORK_BYTES).{' ' + hint if hint else ''}"
        )


def _check_n_values(a: np.ndarray, name: str) -> None:
    """Refuse an array of more than :data:`MAX_VALUES` values before its copy."""
    if a.size > MAX_VALUES:
        raise ResourceLimitError(
            f"{name} must hold at most {MAX_VALUES:,} values (a 64-bit copy of at"
            f" most {MAX_WORK_BYTES / 2**30:g} GiB); got {a.size:,} values, shape"
            f" {a.shape}. Split the demonstration or downsample it first."
        )


def _describe(a: np.ndarray) -> str:
    return f"an array of shape {a.shape} and dtype {a.dtype}"


def as_float_array(values, name: str) -> np.ndarray:
    """Convert ``values`` to a float64 array or explain why it cannot be done.

    Booleans, strings, objects and complex numbers are refused rather than cast.
    """
    try:
        a = np.asarray(values)
    except (ValueError, TypeError) as exc:  # ragged nested lists
        raise ValidationError(
            f"{name} must be a rectangular numeric array; got {type(values).__name__}"
            f" that numpy cannot make rectangular ({exc})"
        ) from None
    if a.dtype == object:
        raise ValidationError(
            f"{name} must be a rectangular numeric array; got {_describe(a)}"
            " (ragged rows or non-numeric entries)"
        )
    if a.dtype.kind not in "iuf":
        raise ValidationError(
            f"{name} must hold real numbers (int or float); got {_describe(a)}"
        )
    _check_n_values(a, name)
    # ascontiguousarray makes a 0-d array 1-d: keep the shape, so a scalar is
    # refused where an array is expected instead of passing as one sample
    return np.ascontiguousarray(a, dtype=np.float64).reshape(a.shape)


def first_nonfinite_row(a: np.ndarray) -> int | None:
    """Index of the first row (or element of a 1-D array) with NaN or inf."""
    bad = ~np.isfinite(a)
    if not bad.any():  # the common case, without a per-row reduction
        return None
    if a.ndim > 1:
        bad = bad.reshape(a.shape[0], -1).any(axis=1)
    hits = np.flatnonzero(bad)
    return int(hits[0]) if hits.size else None


def check_points(points, name: str = "points", *, min_rows: int = 1) -> np.ndarray:
    """Return ``points`` as a finite float64 C-contiguous array of shape (n, d).

    Parameters
    ----------
    points : array-like of shape (n_points, n_dims)
        The values to check.
    name : str, default="points"
        The argument's name, used in messages.
    min_rows : int, default=1
        The smallest number of rows accepted.

    Returns
    -------
    P : ndarray of shape (n_points, n_dims), dtype float64

    Examples
    --------
    >>> check_points([[0, 1], [2, 3]]).dtype
    dtype('float64')
    >>> check_points([1.0, 2.0])
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: points must have shape (n_points, n_dims); got ...
    """
    P = as_float_array(points, name)
    if P.ndim != 2:
        hint = " For a 1-D signal pass np.column_stack([t, y])." if P.ndim == 1 else ""
        raise ValidationError(
            f"{name} must have shape (n_points, n_dims); got an array of shape"
            f" {P.shape}.{hint}"
        )
    if P.shape[1] < 1:
        raise ValidationError(
            f"{name} must have at least one column; got shape {P.shape}"
        )
    if P.shape[0] < min_rows:
        raise ValidationError(
            f"{name} must have at least {min_rows} row(s); got shape {P.shape}"
        )
    row = first_nonfinite_row(P)
    if row is not None:
        raise ValidationError(
            f"{name} must be finite; got {P[row].tolist()} (NaN or inf) at row {row}"
        )
    return P


def check_times(times, n: int | None = None, name: str = "times") -> np.ndarray:
    """Return ``times`` as a finite, strictly increasing float64 vector.

    Parameters
    ----------
    times : array-like of shape (n_samples,)
        Time stamps.
    n : int, optional
        The required length.
    name : str, default="times"
        The argument's name, used in messages.

    Returns
    -------
    t : ndarray of shape (n_samples,), dtype float64

    Examples
    --------
    >>> check_times([0.0, 0.5, 0.4])
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: times must be strictly increasing; got times[2] = ...
    """
    t = as_float_array(times, name)
    if t.ndim != 1:
        raise ValidationError(
            f"{name} must have shape (n_samples,); got an array of shape {t.shape}"
        )
    if n is not None and t.shape[0] != n:
        raise ValidationError(
            f"{name} must have one entry per point (length {n}); got length"
            f" {t.shape[0]}"
        )
    row = first_nonfinite_row(t)
    if row is not None:
        raise ValidationError(f"{name} must be finite; got {t[row]} at index {row}")
    if t.size > 1:
        steps = np.diff(t)
        bad = np.flatnonzero(steps <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            raise ValidationError(
                f"{name} must be strictly increasing; got {name}[{i}] = {t[i]:g}"
                f" after {name}[{i - 1}] = {t[i - 1]:g}"
            )
    return t


def check_nonnegative_scalar(value, name: str) -> float:
    """Return ``value`` as a finite float >= 0 or raise :class:`ValidationError`.

    Examples
    --------
    >>> check_nonnegative_scalar(0.5, "epsilon")
    0.5
    >>> check_nonnegative_scalar(-1, "epsilon")
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: epsilon must be a finite number >= 0; got -1
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValidationError(
            f"{name} must be a finite number >= 0; got {value!r}"
            f" of type {type(value).__name__}"
        )
    v = float(value)
    if not np.isfinite(v) or v < 0:
        raise ValidationError(f"{name} must be a finite number >= 0; got {value!r}")
    return v


def check_positive_int(
    value, name: str, *, minimum: int = 1, maximum: int | None = None, why: str = ""
) -> int:
    """Return ``value`` as an ``int`` >= ``minimum`` or raise an error.

    With ``maximum``, a larger value raises :class:`~ndlfd.ResourceLimitError`
    stating the bound and ``why`` it holds.

    Examples
    --------
    >>> check_positive_int(3, "n_points")
    3
    >>> check_positive_int(2.5, "n_points")
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: n_points must be an integer >= 1; got 2.5
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValidationError(f"{name} must be an integer >= {minimum}; got {value!r}")
    if int(value) < minimum:
        raise ValidationError(f"{name} must be an integer >= {minimum}; got {value!r}")
    if maximum is not None and int(value) > maximum:
        because = f" ({why})" if why else ""
        raise ResourceLimitError(
            f"{name} must be at most {maximum:,}{because}; got {int(value):,}"
        )
    return int(value)


def check_n_time_bins(value, name: str = "n_time_bins") -> int:
    """Return a number of time bins in ``1..MAX_TIME_BINS``.

    Examples
    --------
    >>> check_n_time_bins(50, "n_time_bins")
    50
    >>> check_n_time_bins(2**40, "n_time_bins")
    Traceback (most recent call last):
    ...
    ndlfd._errors.ResourceLimitError: n_time_bins must be at most 268,435,455 ...
    """
    why = "a generation works on every time bin at once, 8 bytes per bin"
    return check_positive_int(value, name, maximum=MAX_TIME_BINS, why=why)


def check_weights(weights, n: int, name: str = "weights") -> np.ndarray:
    """Return non-negative finite per-column weights of length ``n``.

    Examples
    --------
    >>> check_weights([1, 2], 3)
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: weights must have one entry per column ...
    """
    w = as_float_array(weights, name)
    if w.ndim != 1 or w.shape[0] != n:
        raise ValidationError(
            f"{name} must have one entry per column (length {n}); got shape {w.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(w) | (w < 0))
    if bad.size:
        i = int(bad[0])
        raise ValidationError(
            f"{name} must be finite and >= 0; got {name}[{i}] = {w[i]}"
        )
    return w


def check_int_sequence(values, name: str, *, low: int, high: int) -> np.ndarray:
    """Return a 1-D int64 array whose entries lie in ``low..high-1``.

    Floats that hold whole numbers are accepted; anything else is refused.

    Examples
    --------
    >>> check_int_sequence([0, 2, 1], "states", low=0, high=3)
    array([0, 2, 1])
    >>> check_int_sequence([0, 3], "states", low=0, high=3)
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: states must lie in 0..2; got states[1] = 3
    """
    try:
        a = np.asarray(values)
    except (ValueError, TypeError) as exc:  # ragged nested lists
        raise ValidationError(
            f"{name} must be a 1-D array of integers; got {type(values).__name__}"
            f" that numpy cannot make rectangular ({exc})"
        ) from None
    if a.dtype == object or a.dtype.kind not in "iuf":
        raise ValidationError(
            f"{name} must be a 1-D array of integers; got {_describe(a)}"
        )
    if a.ndim != 1:
        raise ValidationError(
            f"{name} must be a 1-D array of integers; got shape {a.shape}"
        )
    _check_n_values(a, name)
    if a.dtype.kind == "f":
        if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise ValidationError(
                f"{name} must hold whole numbers; got non-integer values"
            )
    high = min(high, 2**63)  # int64 ids, whatever the bound (n_states of any size)
    if a.size and (a.min() < low or a.max() >= high):  # before a cast that wraps
        i = int(np.flatnonzero((a < low) | (a >= high))[0])
        raise ValidationError(
            f"{name} must lie in {low}..{high - 1}; got {name}[{i}] = {a[i]}"
        )
    return np.ascontiguousarray(a, dtype=np.int64)


def check_random_state(seed) -> np.random.Generator:
    """Turn ``None``, an int or a Generator into a :class:`numpy.random.Generator`.

    Examples
    --------
    >>> a = check_random_state(0).integers(10, size=3)
    >>> b = check_random_state(0).integers(10, size=3)
    >>> bool((a == b).all())
    True
    """
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or (
        isinstance(seed, numbers.Integral) and not isinstance(seed, bool)
    ):
        return np.random.default_rng(seed)
    if isinstance(seed, np.random.RandomState):
        return np.random.default_rng(seed.randint(0, 2**31 - 1))
    raise ValidationError(
        f"random_state must be None, an int or a numpy Generator; got {seed!r}"
    )
