"""Two-valued channels: a gripper that was open or closed stays open or closed.

A gripper channel recorded as two values (0 and 1, or the two positions a
gripper driver reports) is part of the skill: the robot must close its hand at
the right moment, and a value between the two means nothing to it. The blend
averages the aligned demonstrations, so near a switch it gives values between
the two. :func:`snap_two_valued` puts every value of such a column back on the
nearer of its two recorded values: the generated switch falls where the
weighted average of the demonstrations crosses the middle, the (weighted)
median of their switch times.

Which columns are two-valued is read from the templates (the demonstrations
kept whole), once per model. Only the ``gripper`` group is treated so: a
position that happens to take two values stays continuous.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DISCRETE_GROUPS", "snap_physical", "snap_two_valued", "two_valued_columns"]

#: The groups whose columns stay on their recorded values when they hold two.
DISCRETE_GROUPS = ("gripper",)


def two_valued_columns(values: list, column_groups) -> dict[int, tuple[float, float]]:
    """The columns of :data:`DISCRETE_GROUPS` that take exactly two values.

    Parameters
    ----------
    values : list of ndarray of shape (n_j, n_columns)
        The templates' (normalized) values.
    column_groups : sequence of str
        The group of each column.

    Returns
    -------
    levels : dict of int to (float, float)
        Column index -> its two values, the smaller first.

    Examples
    --------
    >>> V = [np.array([[0.1, 0.0], [0.2, 1.0]]), np.array([[0.3, 1.0]])]
    >>> two_valued_columns(V, ("position", "gripper"))
    {1: (0.0, 1.0)}
    """
    out = {}
    for c, g in enumerate(column_groups):
        if g not in DISCRETE_GROUPS or not values:
            continue
        seen = np.unique(np.concatenate([v[:, c] for v in values]))
        if seen.size == 2:
            out[c] = (float(seen[0]), float(seen[1]))
    return out


def snap_two_valued(U: np.ndarray, levels: dict) -> np.ndarray:
    """Every value of the two-valued columns on the nearer of its two values.

    Parameters
    ----------
    U : ndarray of shape (n_rows, n_columns)
        Generated values (normalized), changed in place.
    levels : dict of int to (float, float)
        :func:`two_valued_columns`.

    Returns
    -------
    U : ndarray of shape (n_rows, n_columns)

    Examples
    --------
    >>> snap_two_valued(np.array([[0.2, 0.3], [0.4, 0.6]]), {1: (0.0, 1.0)})
    array([[0.2, 0. ],
           [0.4, 1. ]])
    """
    for c, (lo, hi) in levels.items():
        U[:, c] = np.where(U[:, c] >= 0.5 * (lo + hi), hi, lo)
    return U


def snap_physical(scaler, X: np.ndarray, levels: dict) -> np.ndarray:
    """Two-valued columns (a gripper) back on their values after the offsets.

    A requested start, goal, via point or prefix shifts every column by an
    offset faded over the path; a gripper column must stay open or closed,
    so it is snapped again (it takes the requested value until the fade is
    half done).

    Parameters
    ----------
    scaler : ndlfd.normalize.GroupScaler
        The model's (``scaler_``): the levels are normalized values.
    X : ndarray of shape (n_rows, n_columns)
        The path, physical units (changed in place).
    levels : dict of int to (float, float)
        :func:`two_valued_columns` of the model's templates.

    Returns
    -------
    X : ndarray of shape (n_rows, n_columns)
    """
    if not levels:
        return X
    cols = list(levels)
    U = snap_two_valued(scaler.transform(X, weighted=False), levels)
    X[:, cols] = scaler.inverse_transform(U, weighted=False)[:, cols]
    return X
