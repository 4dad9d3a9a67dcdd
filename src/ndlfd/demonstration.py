"""The demonstration type: time stamps, values and the physical group of each column.

A :class:`Demonstration` is a small immutable container: a strictly increasing
time vector ``t`` of shape ``(n,)`` and a value array ``X`` of shape ``(n, d)``
whose columns are named (``columns``) and belong to *physical groups*
(``groups``): ``"position"``, ``"velocity"``, ``"orientation"``, ``"force"`` or a
user-named group. Group normalization (:class:`~ndlfd.normalize.GroupScaler`)
works per group, so the groups are what keeps a path's proportions.

Orientation is stored as unit quaternions, scalar-first ``(w, x, y, z)``, and is
sign-aligned on construction (see :mod:`ndlfd.orientation`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ._demo_kernels import gradient, window_derivative, with_room
from ._errors import ValidationError
from ._pose_groups import (
    default_columns,
    hand_group,
    is_orientation,
    is_position,
    pose_dims,
)
from ._poses import NO_FRAMES, check_frames
from ._registry import Registry
from ._repairs import repaired
from ._timing import speed_roughness, timing_jitter
from ._validation import (
    as_float_array,
    check_int_sequence,
    check_positive_int,
    check_times,
    first_nonfinite_row,
)
from .orientation import QUATERNION_ORDERS, check_quaternions, make_continuous

__all__ = [
    "JITTER_TOL",
    "SMOOTHERS",
    "WINDOW_STEPS",
    "Demonstration",
    "default_columns",
    "timing_jitter",
    "unit_time",
    "window_derivative",
    "with_velocity",
]

#: The groups that :meth:`Demonstration.from_arrays` knows by name, in the order
#: their columns are laid out.
KNOWN_GROUPS = ("position", "velocity", "orientation", "force")

_NAME_BAD = re.compile(r"[,\r\n#]")
_GROUP_OK = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")


def unit_time(t) -> np.ndarray:
    """Time stamps mapped onto ``[0, 1]``, first to last (all 0 if they span 0).

    The one time normalization of ndlfd: time bins, the blend, the metrics
    and the baselines all use it.

    Parameters
    ----------
    t : array-like of shape (n_samples,)
        Increasing time stamps (checked by the caller).

    Returns
    -------
    tau : ndarray of shape (n_samples,), dtype float64

    Examples
    --------
    >>> unit_time([2.0, 3.0, 6.0])
    array([0.  , 0.25, 1.  ])
    >>> unit_time([5.0])
    array([0.])
    """
    t = np.asarray(t, dtype=np.float64)
    span = t[-1] - t[0]
    return (t - t[0]) / span if span > 0 else np.zeros_like(t)


def _check_names(names, d: int, what: str) -> tuple[str, ...]:
    if type(names) not in (tuple, list) and (
        isinstance(names, str) or not isinstance(names, Sequence)
    ):
        raise ValidationError(
            f"{what} must be a sequence of str (one per column); got {names!r}"
        )
    names = tuple(names)
    if len(names) != d:
        raise ValidationError(
            f"{what} must have one entry per column of X ({d}); got {len(names)}"
        )
    for name in names:
        if not isinstance(name, str) or not name or name != name.strip():
            raise ValidationError(
                f"{what} must be non-empty str without surrounding spaces; got {name!r}"
            )
        if _NAME_BAD.search(name):
            raise ValidationError(
                f"{what} must not contain commas, newlines or '#'; got {name!r}"
            )
    return names


def _group_blocks(given: dict, columns, quaternion_order: str):
    """:meth:`Demonstration.from_arrays`'s groups as one array, names and groups."""
    blocks, names, groups, block_groups = [], [], [], []
    if columns is not None and not isinstance(columns, Mapping):
        flat = list(columns) if not isinstance(columns, str) else [columns]
        col_map = None
    else:
        flat = None
        col_map = dict(columns or {})
        unknown = sorted(set(col_map) - {g for g, v in given.items() if v is not None})
        if unknown:
            raise ValidationError(
                f"columns names groups that were not given: {unknown}"
            )
    for group, values in given.items():
        if values is None:
            continue
        a = as_float_array(values, group)
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2:
            raise ValidationError(
                f"{group} must have shape (n_samples, k) or (n_samples,); got"
                f" an array of shape {a.shape}"
            )
        if is_orientation(group):
            if a.shape[1] != 4:
                raise ValidationError(
                    f"{group} must have shape (n_samples, 4) (unit"
                    f" quaternions); got an array of shape {a.shape}"
                )
            a = check_quaternions(a, quaternion_order, name=group)
        blocks.append(a)
        block_groups.append(group)
        groups.extend([group] * a.shape[1])
        if col_map is not None:
            names.extend(col_map.get(group, default_columns(group, a.shape[1])))
    if not blocks:
        raise ValidationError(
            "from_arrays needs at least one group (position=, velocity=,"
            " orientation=, force= or a named group); got none"
        )
    rows = {b.shape[0] for b in blocks}
    if len(rows) != 1:
        shapes = {g: b.shape for g, b in zip(block_groups, blocks, strict=True)}
        raise ValidationError(
            f"every group must have the same number of rows; got shapes {shapes}"
        )
    X = np.hstack(blocks)
    return X, tuple(flat if flat is not None else names), tuple(groups)


@dataclass(frozen=True, eq=False, repr=False)
class Demonstration:
    """One demonstration: time stamps and grouped, named value columns.

    Parameters
    ----------
    t : array-like of shape (n_samples,)
        Finite, strictly increasing time stamps (seconds, or any unit).
    X : array-like of shape (n_samples, n_dims)
        Finite values, one column per channel.
    columns : sequence of str of length n_dims
        Unique column names (no commas, newlines or ``#``, so every
        demonstration can be written to CSV).
    groups : sequence of str of length n_dims
        The physical group of each column (a name made of letters, digits,
        ``_`` and ``-``). The columns of a group must be adjacent. A group named
        ``"orientation"`` must have 4 columns holding unit quaternions
        ``(w, x, y, z)``; they are sign-aligned on construction
        (:func:`~ndlfd.orientation.make_continuous`), so that invariant holds
        for every demonstration, including subsets made by :meth:`take`.
    frames : mapping of str to array-like, optional
        Task frames, constant over the demonstration (where the object or
        the place was): each a position of the position group's dimension,
        in 3-D optionally followed by a unit quaternion ``(w, x, y, z)``
        (:func:`ndlfd._poses.check_frames`). Kept by :meth:`take`,
        :meth:`select` and :meth:`with_group`.

    Attributes
    ----------
    t : ndarray of shape (n_samples,), read-only
    X : ndarray of shape (n_samples, n_dims), read-only
    columns : tuple of str
    groups : tuple of str
    frames : mapping of str to ndarray, read-only
        Empty without frames.

    Examples
    --------
    >>> demo = Demonstration.from_arrays(
    ...     [0.0, 0.5, 1.0], position=[[0, 0], [1, 0], [1, 1]]
    ... )
    >>> demo
    Demonstration(n_samples=3, duration=1, position=(x, y))
    >>> demo.get("position")[-1]
    array([1., 1.])
    >>> demo.take([0, 2]).X
    array([[0., 0.],
           [1., 1.]])
    """

    t: np.ndarray
    X: np.ndarray
    columns: tuple[str, ...]
    groups: tuple[str, ...]
    frames: Mapping[str, np.ndarray] | None = None

    def __post_init__(self) -> None:
        t = check_times(self.t, name="t")
        if t.shape[0] < 1:
            raise ValidationError("t must have at least one sample; got length 0")
        X = as_float_array(self.X, "X")
        if X.ndim != 2:
            hint = " For one column pass X[:, None]." if X.ndim == 1 else ""
            raise ValidationError(
                f"X must have shape (n_samples, n_dims); got an array of shape"
                f" {X.shape}.{hint}"
            )
        if X.shape[0] != t.shape[0]:
            raise ValidationError(
                f"X must have one row per time stamp ({t.shape[0]} rows); got"
                f" {X.shape[0]} rows"
            )
        if X.shape[1] < 1:
            raise ValidationError(
                f"X must have at least one column; got shape {X.shape}"
            )
        row = first_nonfinite_row(X)
        if row is not None:
            raise ValidationError(
                f"X must be finite; got {X[row].tolist()} (NaN or inf) at row {row}"
            )
        d = X.shape[1]
        columns = _check_names(self.columns, d, "columns")
        if len(set(columns)) != d:
            dup = next(c for c in columns if columns.count(c) > 1)
            raise ValidationError(f"columns must be unique; got {dup!r} twice")
        groups = _check_names(self.groups, d, "groups")
        for g in groups:
            if not _GROUP_OK.match(g):
                raise ValidationError(
                    "groups must be names made of letters, digits, '_' and '-'"
                    f" (starting with a letter or '_'); got {g!r}"
                )
        seen: list[str] = []
        for j, g in enumerate(groups):
            if seen and g == seen[-1]:
                continue
            if g in seen:
                first = groups.index(g)
                raise ValidationError(
                    f"the columns of a group must be adjacent; got group {g!r} at"
                    f" columns {first} and {j} with {seen[-1]!r} between them"
                )
            seen.append(g)
        X = np.array(X, dtype=np.float64, order="C", copy=True)
        for name in dict.fromkeys(g for g in groups if is_orientation(g)):
            idx = [j for j, g in enumerate(groups) if g == name]
            if len(idx) != 4:
                raise ValidationError(
                    f"the {name} group must have 4 columns (a unit quaternion"
                    f" w, x, y, z); got {len(idx)}"
                )
            Q = check_quaternions(X[:, idx], name=name)
            X[:, idx] = make_continuous(Q)
        t = np.array(t, dtype=np.float64, copy=True)
        t.flags.writeable = False
        X.flags.writeable = False
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "X", X)
        object.__setattr__(self, "columns", columns)
        object.__setattr__(self, "groups", groups)
        object.__setattr__(self, "frames", check_frames(self.frames, pose_dims(groups)))

    # ------------------------------------------------------------ construction
    @classmethod
    def from_arrays(
        cls,
        t,
        *,
        position=None,
        velocity=None,
        orientation=None,
        force=None,
        columns=None,
        quaternion_order: str = "wxyz",
        frames=None,
        **other_groups,
    ) -> Demonstration:
        """Build a demonstration from one array per group.

        Parameters
        ----------
        t : array-like of shape (n_samples,)
            Strictly increasing time stamps.
        position, velocity, force : array-like of shape (n_samples, k), optional
            Group values; a 1-D array is one column.
        orientation : array-like of shape (n_samples, 4), optional
            Unit quaternions in ``quaternion_order``; stored scalar-first and
            sign-aligned.
        columns : mapping of str to sequence of str, or sequence of str, optional
            Column names per group (missing groups get :func:`default_columns`),
            or all names in the final column order.
        quaternion_order : {"wxyz", "xyzw"}, default="wxyz"
            The order of ``orientation``'s components (``"xyzw"`` is scipy's).
        frames : mapping of str to array-like, optional
            Task frames, constant over the demonstration, e.g. ``{"object":
            [x, y, z, qw, qx, qy, qz]}`` (see the class's ``frames``).
        **other_groups : array-like of shape (n_samples, k)
            User-named groups, laid out after the known ones in the given order.

        Returns
        -------
        demo : Demonstration

        Examples
        --------
        >>> d = Demonstration.from_arrays(
        ...     [0, 1], position=[[0, 0], [1, 2]], grip=[0.0, 1.0]
        ... )
        >>> d.columns, d.groups
        (('x', 'y', 'grip0'), ('position', 'position', 'grip'))
        """
        QUATERNION_ORDERS.get(quaternion_order)
        given = {
            "position": position,
            "velocity": velocity,
            "orientation": orientation,
            "force": force,
        }
        given.update(other_groups)
        X, names, groups = _group_blocks(given, columns, quaternion_order)
        return cls(t, X, names, groups, frames)

    # ------------------------------------------------------------ properties
    @property
    def n_samples(self) -> int:
        """Number of samples (rows)."""
        return int(self.X.shape[0])

    @property
    def n_dims(self) -> int:
        """Number of value columns."""
        return int(self.X.shape[1])

    @property
    def group_names(self) -> tuple[str, ...]:
        """The distinct groups, in column order."""
        return tuple(dict.fromkeys(self.groups))

    @property
    def duration(self) -> float:
        """``t[-1] - t[0]`` (0 for a single sample)."""
        return float(self.t[-1] - self.t[0])

    def has_group(self, group: str) -> bool:
        """Whether the demonstration has a group of that name."""
        return group in self.groups

    # ------------------------------------------------------------ access
    def columns_of(self, group: str) -> np.ndarray:
        """Column indices of ``group``.

        Parameters
        ----------
        group : str
            A group of this demonstration.

        Returns
        -------
        indices : ndarray of shape (k,), dtype int64

        Raises
        ------
        ValidationError
            When the group is not in this demonstration (the message lists its
            groups).
        """
        if not isinstance(group, str) or group not in self.groups:
            raise ValidationError(
                f"unknown group {group!r}; this demonstration has groups:"
                f" {', '.join(repr(g) for g in self.group_names)}"
            )
        lo = self.groups.index(group)  # a group's columns are adjacent
        return np.arange(lo, lo + self.groups.count(group), dtype=np.int64)

    def get(self, group: str) -> np.ndarray:
        """Return the values of one group (a read-only view).

        Parameters
        ----------
        group : str
            A group of this demonstration.

        Returns
        -------
        values : ndarray of shape (n_samples, k)
        """
        idx = self.columns_of(group)
        return self.X[:, idx[0] : idx[-1] + 1]

    def select(self, *groups: str) -> Demonstration:
        """Keep only the given groups, in the order given.

        Examples
        --------
        >>> d = Demonstration.from_arrays([0, 1], position=[1, 2], velocity=[3, 4])
        >>> d.select("velocity", "position").columns
        ('vx', 'x')
        """
        if not groups:
            raise ValidationError("select needs at least one group; got none")
        if len(set(groups)) != len(groups):
            raise ValidationError(f"select got a group twice: {groups}")
        idx = np.concatenate([self.columns_of(g) for g in groups])
        return Demonstration(
            self.t,
            self.X[:, idx],
            tuple(self.columns[j] for j in idx),
            tuple(self.groups[j] for j in idx),
            self.frames,
        )

    def take(self, indices) -> Demonstration:
        """Keep only the given rows (for example the key points).

        Parameters
        ----------
        indices : array-like of shape (k,)
            Strictly increasing row indices in ``0..n_samples-1``, at least one.

        Returns
        -------
        demo : Demonstration
        """
        idx = check_int_sequence(indices, "indices", low=0, high=self.n_samples)
        if idx.size == 0:
            raise ValidationError("indices must select at least one row; got none")
        steps = np.flatnonzero(np.diff(idx) <= 0)
        if steps.size:
            i = int(steps[0]) + 1
            raise ValidationError(
                "indices must be strictly increasing; got indices"
                f"[{i}] = {idx[i]} after indices[{i - 1}] = {idx[i - 1]}"
            )
        return Demonstration(
            self.t[idx], self.X[idx], self.columns, self.groups, self.frames
        )

    def with_group(self, name: str, values, columns=None) -> Demonstration:
        """Append group ``name``, or replace it if present.

        A replaced group keeps its place among the columns.

        Parameters
        ----------
        name : str
            The group's name.
        values : array-like of shape (n_samples, k) or (n_samples,)
            Its values (orientation: unit quaternions, scalar-first).
        columns : sequence of str of length k, optional
            Column names; :func:`default_columns` by default.

        Returns
        -------
        demo : Demonstration

        Examples
        --------
        >>> d = Demonstration.from_arrays([0, 1], position=[[0, 0], [1, 1]])
        >>> d.with_group("force", [[0.0], [2.0]]).columns
        ('x', 'y', 'fx')
        """
        a = as_float_array(values, name if isinstance(name, str) else "values")
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2 or a.shape[0] != self.n_samples:
            raise ValidationError(
                f"values must have shape ({self.n_samples}, k) (one row per sample);"
                f" got an array of shape {a.shape}"
            )
        cols = default_columns(name, a.shape[1]) if columns is None else tuple(columns)
        return _with_block(self, name, a, cols)

    def with_frames(self, frames) -> Demonstration:
        """The same demonstration with these task frames (``None``: none).

        >>> d = Demonstration.from_arrays([0, 1], position=[[0, 0], [1, 1]])
        >>> d.with_frames({"object": [1.0, 0.5]}).frames["object"]
        array([1. , 0.5])
        """
        out = _assembled(self.t, self.X, self.columns, self.groups)
        object.__setattr__(out, "frames", check_frames(frames, pose_dims(self.groups)))
        return out

    # ------------------------------------------------------------ dunder
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Demonstration):
            return NotImplemented
        return (
            self.columns == other.columns
            and self.groups == other.groups
            and np.array_equal(self.t, other.t)
            and np.array_equal(self.X, other.X)
            and list(self.frames) == list(other.frames)
            and all(np.array_equal(v, other.frames[k]) for k, v in self.frames.items())
        )

    __hash__ = None  # type: ignore[assignment]

    def __len__(self) -> int:
        return self.n_samples

    def __repr__(self) -> str:
        parts = [f"n_samples={self.n_samples}", f"duration={self.duration:.6g}"]
        for g in self.group_names:
            cols = ", ".join(self.columns[j] for j in self.columns_of(g))
            parts.append(f"{g}=({cols})")
        if self.frames:
            parts.append(f"frames=({', '.join(self.frames)})")
        return f"Demonstration({', '.join(parts)})"


# ---------------------------------------------------------------- velocity
SMOOTHERS: Registry[str] = Registry("smoothing")
SMOOTHERS.add("auto", "auto")
SMOOTHERS.add("none", "none")
SMOOTHERS.add("savgol", "savgol")
SMOOTHERS.add("window", "window")

#: Time stamps count as jittery when more than 10 % of consecutive steps
#: differ by more than this fraction of the median step *and* the speed
#: they imply jumps from step to step by more than this fraction of the
#: median speed (irregular but exact stamps of a smooth motion give a smooth
#: speed).
JITTER_TOL = 0.1


#: Half-width of the window fit in median time steps. On a minimum-jerk reach
#: logged with stamps jittered by +-amp steps, 2, 3, 4 and 6 steps gave a
#: largest error of 1.6, 0.65, 0.51 and 0.26 times amp times the peak speed
#: (20 seeds, amp 0.15-0.45); 4 keeps the curvature bias of fast motions small.
WINDOW_STEPS = 4.0


def _with_block(demo: Demonstration, name, a: np.ndarray, cols, X=None):
    """:meth:`Demonstration.with_group` of a 2-D block of one row per sample.

    ``X``, when given, is the new value array already assembled: ``demo.X``
    with ``a`` appended on the right (a new group).
    """
    if name in demo.groups:
        idx = demo.columns_of(name)
        lo, hi = int(idx[0]), int(idx[-1]) + 1
    else:
        lo = hi = demo.n_dims
    # finite: the block, or the whole assembled array (the rest is checked
    # already); a contiguous array is checked much faster than a strided view
    finite = a
    if X is None:
        X = np.concatenate([demo.X[:, :lo], a, demo.X[:, hi:]], axis=1)
    else:
        finite = X
    new_columns = demo.columns[:lo] + tuple(cols) + demo.columns[hi:]
    new_groups = demo.groups[:lo] + (name,) * a.shape[1] + demo.groups[hi:]
    checked = is_orientation(name) or (is_position(name) and demo.frames)
    if not checked and _valid_block(a, cols, name, new_columns, finite):
        out = _assembled(demo.t, X, new_columns, new_groups)
        object.__setattr__(out, "frames", demo.frames)
        return out
    return Demonstration(demo.t, X, new_columns, new_groups, demo.frames)


def _valid_block(a: np.ndarray, cols, name, columns, finite) -> bool:
    """Whether a new group's block passes every check of the constructor.

    ``finite`` holds the block's values (and possibly checked ones).
    """
    try:
        _check_names(cols, a.shape[1], "columns")
    except ValidationError:
        return False
    return (
        isinstance(name, str)
        and _GROUP_OK.fullmatch(name) is not None  # no newline: a valid name too
        and len(set(columns)) == len(columns)
        and bool(np.isfinite(finite).all())
    )


def _assembled(t, X, columns, groups) -> Demonstration:
    """A demonstration of checked parts, without checking them again.

    For :meth:`Demonstration.with_group` once :func:`_valid_block` passed: the
    rest is a checked demonstration's, and the group is appended or stays in
    place (so its columns stay adjacent).
    """
    out = object.__new__(Demonstration)
    X.flags.writeable = False
    for name, value in (("t", t), ("X", X), ("columns", columns), ("groups", groups)):
        object.__setattr__(out, name, value)
    object.__setattr__(out, "frames", NO_FRAMES)
    return out


def with_velocity(
    demo: Demonstration,
    *,
    smoothing: str | None = None,
    window_length: int = 7,
    polyorder: int = 2,
    half_width: float | None = None,
    overwrite: bool = False,
    hand: str = "",
) -> Demonstration:
    """Add a velocity group derived from the position group and the real time stamps.

    Velocity is ``numpy.gradient(P, t, axis=0, edge_order=2)``: second-order
    central differences for non-uniform steps inside, second-order one-sided
    differences at both ends. With two samples the one velocity the data can
    show, ``(P[1] - P[0]) / (t[1] - t[0])``, is given to both samples
    (``edge_order=1``); a single sample has no velocity and is refused.

    Time stamps logged with jitter make neighbouring differences useless (a
    step that is 1 % of the usual one multiplies the error by 100). By default
    (``smoothing=None``, ``"auto"``) the stamps are checked: when more than
    10 % of consecutive steps differ by more than :data:`JITTER_TOL` of the
    median step (:func:`timing_jitter`) and the speed those steps imply jumps
    from step to step by more than that fraction of the median speed (stamps
    that are irregular but exact, of a smooth motion, give a smooth speed and
    keep the exact derivative), the velocity is the slope
    of a local straight-line fit over a time window instead
    (:func:`window_derivative`, ``half_width`` = :data:`WINDOW_STEPS` median
    steps unless given), and one :class:`~ndlfd.NdlfdWarning` says so.
    ``"window"`` always uses the window fit; ``"none"`` always
    ``numpy.gradient``.

    With ``smoothing="savgol"`` the position is first smoothed with
    :func:`scipy.signal.savgol_filter` (``window_length``, ``polyorder``,
    ``mode="interp"``), then differentiated with the real ``t`` as above. The
    Savitzky–Golay filter treats the samples as equally spaced, so with
    strongly non-uniform sampling the smoothing (not the derivative) is an
    approximation.

    Parameters
    ----------
    demo : Demonstration
        Must have a ``"position"`` group.
    smoothing : {None, "auto", "none", "window", "savgol"}, default=None
        How to differentiate (``None`` is ``"auto"``): see above.
    window_length : int, default=7
        Savitzky–Golay window (odd, > polyorder, <= n_samples).
    polyorder : int, default=2
        Savitzky–Golay polynomial order.
    half_width : float, optional
        Half the window of the ``"window"`` fit, in seconds;
        :data:`WINDOW_STEPS` median time steps by default.
    overwrite : bool, default=False
        When the demonstration already has a velocity group it is returned
        unchanged unless ``overwrite=True``, which recomputes the velocity in
        place of the old one.
    hand : str, default=""
        Whose velocity: ``""`` the ``position`` group's (``velocity``), a
        hand's name that of its ``<hand>_position`` (``<hand>_velocity``,
        columns ``<hand>_vx, ...``).

    Returns
    -------
    demo : Demonstration
        With a ``"velocity"`` group named after the position columns (``vx, vy,
        vz`` or ``v0, v1, ...``).

    Examples
    --------
    >>> d = Demonstration.from_arrays([0.0, 1.0, 3.0], position=[0.0, 2.0, 6.0])
    >>> with_velocity(d).get("velocity").ravel()
    array([2., 2., 2.])
    """
    mode = SMOOTHERS.get("auto" if smoothing is None else smoothing)
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )
    pos_group, vel_group = hand_group(hand, "position"), hand_group(hand, "velocity")
    if vel_group in demo.groups and not overwrite:
        return demo
    P = demo.get(pos_group)  # read-only; smoothing makes a new array
    n = demo.n_samples
    if n < 2:
        raise ValidationError(
            "velocity needs at least 2 samples to be derived from position; got 1"
        )
    if mode == "savgol":
        window_length = check_positive_int(window_length, "window_length")
        polyorder = check_positive_int(polyorder, "polyorder", minimum=0)
        if window_length % 2 == 0 or window_length <= polyorder or window_length > n:
            raise ValidationError(
                "window_length must be odd, greater than polyorder"
                f" ({polyorder}) and at most n_samples ({n}); got {window_length}"
            )
        from scipy.signal import savgol_filter  # lazy: scipy.signal is slow to import

        P = savgol_filter(P, window_length, polyorder, axis=0, mode="interp")
    V = wide = None
    if mode in ("auto", "none"):
        # numpy.gradient's arithmetic in one compiled pass, written straight
        # into the new columns of the wider array when velocity is appended;
        # steps within JITTER_TOL of the smallest cannot be jittery: skip the
        # percentiles
        if vel_group not in demo.groups:
            wide = with_room(demo.X, P.shape[1])
        out = None if wide is None else wide[:, demo.n_dims :]
        V, steady = gradient(demo.t, P, JITTER_TOL, out=out)
    if mode == "auto":
        jitter = 0.0 if steady else timing_jitter(demo.t)
        if jitter > JITTER_TOL and speed_roughness(P, demo.t) > JITTER_TOL:
            mode = "window"
        if mode == "window":
            repaired(
                "jitter",
                1,
                f"time stamps are jittery (consecutive steps differ by up to"
                f" {100 * jitter:.0f} % of the median step in 90 % of cases, more"
                f" than {100 * JITTER_TOL:.0f} %): velocity is derived by a local"
                " straight-line fit over a time window, not from neighbouring"
                " samples",
                stacklevel=2,
            )
    if mode == "window":
        wide = None  # the velocity of the window fit replaces the gradient's
        if half_width is None:
            half_width = WINDOW_STEPS * float(np.median(np.diff(demo.t)))
        elif not (np.isfinite(half_width) and half_width > 0):
            raise ValidationError(f"half_width must be > 0 seconds; got {half_width!r}")
        V = window_derivative(demo.t, P, half_width)
    elif V is None:
        V, _ = gradient(demo.t, P, JITTER_TOL)
    names = default_columns(vel_group, V.shape[1])
    taken = set(demo.columns)
    if vel_group in demo.groups:  # overwritten: its own names are free
        taken -= {demo.columns[j] for j in demo.columns_of(vel_group)}
    if taken.intersection(names):
        names = tuple(f"{vel_group}.{c}" for c in names)
    return _with_block(demo, vel_group, V, names, wide)
