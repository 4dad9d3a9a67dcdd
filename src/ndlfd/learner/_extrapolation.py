"""A start or goal far outside the demonstrations': a warning, not an error.

A requested start (goal) is compared with every demonstration's first (last)
sample, group by group, in units of how much those samples spread
(:func:`envelope_distance`); past :data:`FAR_SPREADS` the path is still made
as asked, with an :class:`~ndlfd._errors.ExtrapolationWarning` saying how far
it lies (:func:`warn_far_condition`, called by
:func:`~ndlfd.learner._conditioning.orient_condition` for ``generate`` and
``sample``).
"""

from __future__ import annotations

import warnings

import numpy as np

from .._errors import ExtrapolationWarning

__all__ = ["FAR_SPREADS", "SPREAD_FLOOR", "envelope_distance", "warn_far_condition"]

#: A requested start (goal) farther than this many spreads from the nearest
#: demonstration's start (goal) is warned about (:func:`warn_far_condition`).
#: For starts spread as a Gaussian, one column 3 standard deviations from
#: their mean comes about 3 times in 1,000; measured from the nearest start,
#: not the mean, the test is more lenient still. Past it the path no longer
#: interpolates the demonstrations but extrapolates them.
FAR_SPREADS = 3.0

#: The least spread of :func:`envelope_distance`, as a share of the group's
#: range over the demonstrations: one demonstration, or starts that coincide,
#: have a spread of 0, and any other start would be infinitely far.
SPREAD_FLOOR = 0.05


def envelope_distance(target, points, floor) -> tuple[float, int, np.ndarray]:
    """How far ``target`` lies from the nearest of ``points``, in their spread.

    The spread of each column is the standard deviation of ``points`` there
    (over the rows, ``ddof=0``), at least ``floor``; the distance to each
    point is the Euclidean norm of the difference divided column by column by
    the spread, and the nearest point's is returned.

    Parameters
    ----------
    target : array-like of shape (n_columns,)
    points : array-like of shape (n_points, n_columns)
        E.g. every demonstration's start, physical units.
    floor : float or array-like of shape (n_columns,)
        The least spread, > 0.

    Returns
    -------
    spreads : float
        The distance to the nearest point, in spreads.
    nearest : int
        Its row.
    spread : ndarray of shape (n_columns,)

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [2.0, 0.0]])  # spread 1 and 0 (floored)
    >>> d, i, s = envelope_distance([5.0, 0.5], pts, floor=0.25)
    >>> float(d), i, s.tolist()
    (3.605551275463989, 1, [1.0, 0.25])
    """
    P = np.asarray(points, dtype=np.float64)
    spread = np.maximum(P.std(axis=0), floor)
    d = np.linalg.norm((P - np.asarray(target, dtype=np.float64)) / spread, axis=1)
    i = int(np.argmin(d))
    return float(d[i]), i, spread


def warn_far_condition(cond, points, scaler, column_groups, what: str) -> None:
    """Warn of a start or goal far outside the demonstrations' starts or goals.

    For each group of ``cond``: its :func:`envelope_distance` to the
    demonstrations' first (start) or last (goal) samples, with a spread of at
    least :data:`SPREAD_FLOOR` of the group's range over the demonstrations
    (1 in its units if the group never changes). Past :data:`FAR_SPREADS`,
    an :class:`~ndlfd._errors.ExtrapolationWarning` names the group and its
    columns and gives the distance in spreads and in the data's units. The
    path is made as asked; the warning says it extrapolates.

    Parameters
    ----------
    cond : dict of str to ndarray, or None
        A checked start or goal, its orientation on the demonstrations' side
        (:func:`~ndlfd.learner._conditioning.orient_condition`).
    points : ndarray of shape (n_demos, n_columns) or None
        The demonstrations' first or last normalized samples (``None``, a
        model without them: no check).
    scaler : GroupScaler
        The fitted normalization.
    column_groups : sequence of str
    what : str
        ``"start"`` or ``"goal"``.

    Examples
    --------
    >>> from ndlfd import GroupScaler
    >>> sc = GroupScaler(("position",), mode="none").fit(np.array([[0.0], [1.0]]))
    >>> starts = np.array([[0.0], [0.1]])  # spread 0.05, the floor 0.05
    >>> warn_far_condition({"position": np.array([0.2])}, starts, sc,
    ...                    ("position",), "start")  # 2 spreads: no warning
    """
    if cond is None or points is None or len(points) == 0:
        return
    P = scaler.inverse_transform(points, weighted=False)
    names = getattr(scaler, "columns_", None)
    for g, v in cond.items():
        cols = [c for c, h in enumerate(column_groups) if h == g]
        span = scaler.group_max_[g] - scaler.group_min_[g]
        floor = SPREAD_FLOOR * (span if span > 0 else 1.0)
        spreads, i, spread = envelope_distance(v, P[:, cols], floor)
        if not spreads > FAR_SPREADS:
            continue
        label = ", ".join(names[c] for c in cols) if names else f"{len(cols)} columns"
        units = float(np.linalg.norm(v - P[i, cols]))
        warnings.warn(
            f"the {what} of {g} ({label}) = {_numbers(v)} is {spreads:.1f}"
            f" spreads from the nearest demonstration's {what} (demonstration"
            f" {i}, {_numbers(P[i, cols])}: {units:.3g} away in the data's"
            f" units); the demonstrations' {what}s spread {_numbers(spread)}"
            f" (standard deviation per column, at least {SPREAD_FLOOR:.0%} of"
            f" the group's range). Beyond {FAR_SPREADS:g} spreads the path"
            " extrapolates what was demonstrated",
            ExtrapolationWarning,
            stacklevel=2,
        )


def _numbers(values) -> str:
    """``(a, b, c)`` with 4 significant digits each."""
    return "(" + ", ".join(f"{float(x):.4g}" for x in values) + ")"
