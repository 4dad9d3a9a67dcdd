"""Limits on a group's norm: a position's speed, an orientation's rotation rate.

Per-column limits (:mod:`ndlfd.limits`) bound each axis on its own: a
Cartesian position limited to ``v`` per axis moves at up to ``sqrt(3) v``.
Here the limits are on the group as a whole:

- ``speed`` of a position-like group: ``|dP/dt| <= v``;
- ``angular_velocity`` of the quaternion group ``orientation`` (w, x, y, z):
  ``|omega| <= w`` in radians per second;
- ``angular_acceleration`` of it: ``|d omega / dt| <= a``.

Along a path ``P(s)`` re-timed by a clock ``s(t)`` (TOPP-RA's path parameter,
``x = sdot^2``, ``u = sddot``) the speed is ``|P'(s)| sdot``: the speed limit is
a bound ``x <= v^2 / |P'(s)|^2`` at every grid point, and the angular velocity
one is the same with the body rate per unit of ``s``, ``|2 vec(q* q'(s))|``
(``q`` the path's unit quaternion, ``q*`` its conjugate).

The angular acceleration of a unit quaternion path is exactly
``alpha = 2 vec(q* qddot)`` (the term ``2 qdot* qdot`` is real), so
``alpha = 2 vec(q* q'') x + 2 vec(q* q') u``: linear in ``(u, x)`` like a joint
acceleration, but bounded in its norm, a cone TOPP-RA's linear solvers cannot
take. It is bounded instead by a polytope inside the ball: ``n . alpha <=
INSCRIBED * a`` for the 26 unit directions ``n`` of ``{-1, 0, 1}^3`` (a cube's
faces, edges and corners), whose every point lies within ``a`` of the origin.
The bound is conservative: ``|alpha|`` may reach between ``INSCRIBED * a``
(0.886 a, along the directions) and ``a`` (at the polytope's corners),
depending on the axis it turns about; the axis-by-axis box ``|alpha_i| <= a /
sqrt(3)`` would allow as little as 0.577 a.

The path's quaternions are read as one curve: a cubic spline of their
(sign-continuous) components, normalized. Its derivatives (of the unit
quaternion, through the normalization) are what the constraints use, and the
time-scaled path is sampled from it.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.interpolate import CubicSpline

from .orientation import make_continuous

__all__ = [
    "ANGULAR_KINDS",
    "DIRECTIONS",
    "INSCRIBED",
    "NORM_KINDS",
    "QuaternionCurve",
    "angular_rates",
    "norm_constraints",
    "row_norm",
]

#: The limits on a group's norm.
NORM_KINDS = ("speed", "angular_velocity", "angular_acceleration")
#: Those of a quaternion group.
ANGULAR_KINDS = ("angular_velocity", "angular_acceleration")

#: The 26 unit directions of ``{-1, 0, 1}^3`` without the origin.
DIRECTIONS = np.array(
    [d for d in itertools.product((-1.0, 0.0, 1.0), repeat=3) if any(d)]
)
DIRECTIONS /= np.linalg.norm(DIRECTIONS, axis=1, keepdims=True)

#: ``{x : n . x <= INSCRIBED}`` over :data:`DIRECTIONS` lies in the unit ball
#: and touches it: the farthest vertices of ``{x : n . x <= 1}`` are
#: ``(1, sqrt(2) - 1, sqrt(3) - sqrt(2))`` (a face, an edge and a corner
#: direction active), signed and permuted, at ``1 / INSCRIBED`` (checked by
#: enumerating the vertices in the tests).
INSCRIBED = float(
    1.0 / np.sqrt(1.0 + (np.sqrt(2.0) - 1.0) ** 2 + (np.sqrt(3.0) - np.sqrt(2.0)) ** 2)
)


def _qmul_conj(q: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The vector part of ``conj(q) p`` for rows of (w, x, y, z)."""
    w, v = q[:, :1], q[:, 1:]
    pw, pv = p[:, :1], p[:, 1:]
    return w * pv - pw * v - np.cross(v, pv)


class QuaternionCurve:
    """A path's unit quaternions as one smooth curve of its time.

    A cubic spline through the components (made sign-continuous, so ``q`` and
    ``-q`` do not pull it through zero), normalized.

    Parameters
    ----------
    t : ndarray of shape (n,)
        The path's times (increasing).
    Q : ndarray of shape (n, 4)
        Quaternions w, x, y, z.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 21)
    >>> Q = np.column_stack([np.cos(t / 2), np.sin(t / 2), 0 * t, 0 * t])
    >>> c = QuaternionCurve(t, Q)
    >>> w, _ = c.rates(np.array([0.5]))
    >>> w.round(6).tolist()  # 1 rad/s about x
    [[1.0, 0.0, 0.0]]
    """

    def __init__(self, t: np.ndarray, Q: np.ndarray) -> None:
        C = make_continuous(Q)
        #: +1 or -1 per sample: the given sign against the continuous one
        self.sign = np.where(np.sum(C * Q, axis=1) < 0, -1.0, 1.0)
        self._spline = CubicSpline(t, C)

    def __call__(self, s: np.ndarray, order: int = 0) -> np.ndarray:
        """The unit quaternion (``order=0``) or its derivatives at ``s``."""
        p = self._spline(s)
        n = np.linalg.norm(p, axis=1, keepdims=True)
        q = p / n
        if order == 0:
            return q
        p1 = self._spline(s, 1)
        n1 = np.sum(p * p1, axis=1, keepdims=True) / n
        q1 = (p1 - q * n1) / n
        if order == 1:
            return q1
        p2 = self._spline(s, 2)
        n2 = (np.sum(p1 * p1 + p * p2, axis=1, keepdims=True) - n1 * n1) / n
        return (p2 - 2.0 * q1 * n1 - q * n2) / n

    def rates(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The body rates per unit of ``s``: ``2 vec(q* q')`` and ``2 vec(q* q'')``.

        Returns
        -------
        w, b : ndarray of shape (len(s), 3)
            The angular velocity is ``w sdot``, the angular acceleration
            ``b sdot^2 + w sddot``.
        """
        q = self(s)
        return 2.0 * _qmul_conj(q, self(s, 1)), 2.0 * _qmul_conj(q, self(s, 2))


def row_norm(M: np.ndarray) -> np.ndarray:
    """The Euclidean norm of each row, without overflow on huge values.

    Scaled by the row's largest magnitude before squaring (``numpy.linalg.norm``
    squares first: rows past about ``1e154`` overflow); a row whose norm is past
    the largest float is ``inf``.

    Parameters
    ----------
    M : ndarray of shape (n, k)

    Returns
    -------
    norms : ndarray of shape (n,)

    Examples
    --------
    >>> row_norm(np.array([[3.0, -4.0], [0.0, 0.0]])).tolist()
    [5.0, 0.0]
    >>> f"{row_norm(np.array([[3e200, 4e200]]))[0]:.6g}"  # numpy.linalg.norm: inf
    '5e+200'
    """
    A = np.abs(np.asarray(M, dtype=np.float64))
    if A.shape[1] == 0:
        return np.zeros(A.shape[0])
    top = A.max(axis=1)
    safe = np.where((top > 0) & np.isfinite(top), top, 1.0)
    with np.errstate(over="ignore"):
        norms = top * np.sqrt(np.sum((A / safe[:, None]) ** 2, axis=1))
    return np.where(np.isfinite(top), norms, top)


def angular_rates(Q: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Angular velocity and acceleration norms of sampled quaternions.

    ``2 |vec(q* qdot)|`` and ``2 |vec(q* qddot)|`` with ``qdot`` and
    ``qddot`` by ``numpy.gradient`` (second-order ends) of the sign-continuous
    components, as :func:`ndlfd.limits.path_peaks` measures other columns.

    Parameters
    ----------
    Q : ndarray of shape (n, 4)
        Unit quaternions w, x, y, z.
    t : ndarray of shape (n,)

    Returns
    -------
    omega, alpha : ndarray of shape (n,)
        Radians per second, per second squared.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> Q = np.column_stack([np.cos(t / 2), 0 * t, 0 * t, np.sin(t / 2)])
    >>> w, a = angular_rates(Q, t)
    >>> round(float(w.max()), 4), round(float(a.max()), 2)
    (1.0, 0.0)
    """
    C = make_continuous(Q)
    d1 = np.gradient(C, t, axis=0, edge_order=2)
    d2 = np.gradient(d1, t, axis=0, edge_order=2)
    w = 2.0 * row_norm(_qmul_conj(C, d1))
    a = 2.0 * row_norm(_qmul_conj(C, d2))
    return w, a


def norm_constraints(toppra, interp, norm: dict) -> list:
    """TOPP-RA constraints of the norm limits.

    Parameters
    ----------
    toppra : module
        The imported ``toppra``.
    interp : toppra.SplineInterpolator
        The path TOPP-RA re-times (its parameter the path's own time).
    norm : dict
        ``{"speed": [(columns of the path, v), ...], "angular_velocity":
        [(QuaternionCurve, w), ...], "angular_acceleration": [(QuaternionCurve,
        a), ...]}``: the columns are ``interp``'s.

    Returns
    -------
    constraints : list of toppra constraints
    """
    con = toppra.constraint
    out = []

    class _RateBound(con.LinearConstraint):
        """``x <= (limit / rate(s))^2`` at every grid point."""

        def __init__(self, rate, limit) -> None:
            super().__init__()
            self.dof = interp.dof
            self._rate, self._limit = rate, float(limit)

        def compute_constraint_params(self, path, gridpoints, *args, **kwargs):
            r = np.asarray(self._rate(path, gridpoints), dtype=np.float64)
            with np.errstate(divide="ignore"):
                top = np.where(r > 0, (self._limit / r) ** 2, np.inf)
            xbound = np.column_stack([np.zeros_like(top), np.minimum(top, 1e12)])
            return None, None, None, None, None, None, xbound

    class _AngularAcceleration(con.LinearConstraint):
        """``n . (b x + w u) <= INSCRIBED * limit`` for the 26 directions ``n``."""

        def __init__(self, curve, limit) -> None:
            super().__init__()
            self.dof = interp.dof
            self._curve, self._limit = curve, float(limit)
            self.set_discretization_type(con.DiscretizationType.Interpolation)
            self.identical = True

        def compute_constraint_params(self, path, gridpoints, *args, **kwargs):
            w, b = self._curve.rates(gridpoints)
            g = np.full(len(DIRECTIONS), INSCRIBED * self._limit)
            return con.linear_constraint.canlinear_colloc_to_interpolate(
                w, b, np.zeros_like(w), DIRECTIONS, g, None, None,
                gridpoints, identical=True,
            )  # fmt: skip

    for cols, v in norm.get("speed", []):
        out.append(_RateBound(
            lambda path, s, c=cols: row_norm(path(s, 1)[:, c]), v
        ))  # fmt: skip
    for curve, w in norm.get("angular_velocity", []):
        out.append(_RateBound(
            lambda path, s, c=curve: row_norm(c.rates(s)[0]), w
        ))  # fmt: skip
    for curve, a in norm.get("angular_acceleration", []):
        out.append(_AngularAcceleration(curve, a))
    return out
