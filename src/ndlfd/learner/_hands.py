"""What generation does for every hand: its quaternions and its velocity.

Each orientation group (every hand's, :mod:`ndlfd._pose_groups`) is read as
one quaternion block and renormalized after every step that moves it; each
hand's velocity, when learned, is the derivative of its generated positions.
"""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from .._pose_groups import hands, orientation_blocks
from ..orientation import normalize_quaternions

__all__ = ["derive_velocity", "quat_columns", "renormalized"]


def quat_columns(column_groups):
    """Every orientation group's 4 columns, one group after another (or None)."""
    cols = [j for b in orientation_blocks(column_groups) for j in b]
    return cols or None


def renormalized(X: np.ndarray, column_groups) -> np.ndarray:
    """``X`` with every orientation group's rows made unit quaternions.

    Examples
    --------
    >>> groups = ("orientation",) * 4 + ("g",)
    >>> renormalized(np.array([[0.0, 2.0, 0.0, 0.0, 5.0]]), groups)
    array([[0., 1., 0., 0., 5.]])
    """
    blocks = orientation_blocks(column_groups)
    if not blocks:
        return X
    X = X.copy()
    for cols in blocks:
        X[:, cols] = normalize_quaternions(X[:, cols], zero="identity")
    return X


def derive_velocity(X, tq, key_tau, all_t, column_groups) -> np.ndarray:
    """Velocity columns as the derivative of the generated positions.

    ``X`` holds the dense rows (at ``all_t``) followed by the key rows (at
    normalized times ``key_tau``), whose velocity is interpolated from the
    dense derivative.
    """
    n = all_t.size
    for pos, vel in ((h.position, h.velocity) for h in hands(column_groups)):
        if not vel:  # every hand's velocity that was learned
            continue
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            V = np.gradient(X[:n, pos], all_t, axis=0)
        if not np.isfinite(V).all():
            raise ValidationError(
                "the generated velocity (the derivative of the positions over the"
                " requested time stamps) is not finite in float64: expected time"
                f" steps of at least 1e-150 and values below 1e300; got steps from"
                f" {float(np.diff(all_t).min()):.3g} and values up to"
                f" {float(np.abs(X[:n, pos]).max()):.3g}"
            )
        X[:n, vel] = V
        X[n:, vel] = np.column_stack([np.interp(key_tau, tq, c) for c in V.T])
    return X
