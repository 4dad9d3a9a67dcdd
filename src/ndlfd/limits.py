"""A robot's limits: a path's peak velocity and acceleration; time-scaling to them.

A generated path follows the timing it was asked for; a robot has maximum
joint (or axis) velocities and accelerations. :func:`path_peaks` measures a
path's peaks per column (``numpy.gradient`` over its own stamps, as a
controller sampling it would see them); :func:`time_scale` slows the path
down where it would exceed the limits, along the same geometric path, with
TOPP-RA (`toppra <https://github.com/hungpham2511/toppra>`_, the extra
``limits``): the time-optimal parameterization under velocity and
acceleration constraints, with one more constraint that the path's clock
never runs faster than its own timing, so the path is only ever slowed down,
never sped up. The result starts and ends at rest, but for the
continuation of an executed prefix (``keep=``): the prefix's samples and
stamps are kept, and the rest leaves its last sample at the speed the path
has there (slowed to the limits if faster).

Limits are given per group (one value for every column of the group, or one
per column) or per column by its name, in the group's units per second (per
second squared, cubed):
``{"joints": {"velocity": 90.0, "acceleration": [400, 400, 300]},
"wrist_roll": {"velocity": 60.0}}``.
Each column is limited on its own, as a robot's joints are; a Cartesian
``position`` group is limited axis by axis (its speed can reach ``sqrt(3)``
times a common limit). Limits on a group's norm (:mod:`ndlfd._norm_limits`)
bound a position-like group's ``speed`` and the quaternion group
``orientation``'s ``angular_velocity`` (rad/s) and ``angular_acceleration``
(rad/s^2): ``{"position": {"speed": 0.05}, "orientation":
{"angular_velocity": 0.5, "angular_acceleration": 2.0}}``. Quaternions are
carried along on the same clock (a normalized cubic spline of them), as are
two-valued grippers (held between samples) and a ``velocity`` group derived
from ``position`` (derived again).

The limits hold on the samples (their finite differences, :func:`path_peaks`)
and, for the joints (and a gripper), on the curve a controller follows
through them: the cubic spline at rest at the ends whose derivatives a
JointTrajectory carries (:mod:`ndlfd._trajectory`).

TOPP-RA bounds velocity and acceleration; a jerk limit is met by slowing the
TOPP-RA timing down uniformly until the samples' jerk is within it (not
time-optimal: ruckig bounds jerk optimally but plans point to point and would
not keep the learned path).
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np
from scipy.interpolate import CubicSpline

from ._errors import MissingExtraError, ValidationError
from ._norm_limits import (
    ANGULAR_KINDS,
    NORM_KINDS,
    QuaternionCurve,
    angular_rates,
    norm_constraints,
    row_norm,
)
from ._pose_groups import hand_group, hand_name, hands
from ._pose_groups import kind as group_kind
from ._trajectory import curve_peaks, rest_curve
from ._validation import check_positive_int
from .demonstration import Demonstration

__all__ = [
    "ALL_KINDS",
    "KINDS",
    "NORM_KINDS",
    "LimitError",
    "check_limits",
    "limited",
    "path_peaks",
    "time_scale",
]

#: The quantities that can be limited column by column.
KINDS = ("velocity", "acceleration", "jerk")
#: And every quantity that can be limited (the norms: one value per group).
ALL_KINDS = KINDS + NORM_KINDS

#: Relative tolerance of the measured peaks against the limits (TOPP-RA
#: meets its constraints at its grid points; between them, and through the
#: finite differences of the samples, peaks measured 1.0001 times a limit on
#: a 400-sample path). Above it the limits are tightened and the scaling run
#: again (:data:`RETRIES` times) before :class:`LimitError`.
TOLERANCE = 1e-3

#: Attempts with tightened limits before giving up.
RETRIES = 3

#: How far below the limits the scaling aims (and tightens again after an
#: overshoot). Without it 2 to 4 runs of TOPP-RA were needed where one now
#: does (``benchmarks/bench_limits.py``).
MARGIN = 0.01

#: Grid points of TOPP-RA: three per sample of the path (its constraints
#: hold at grid points only; one per sample let a noisy path's samples
#: overshoot by 20 %), at most this many (its cost is linear in them:
#: ``benchmarks/bench_limits.py``).
GRID_PER_SAMPLE = 3
MAX_GRIDPOINTS = 20_000

_UNLIMITED = ("orientation",)
#: Groups that are not positions: no speed of theirs is limited.
_NOT_POSITIONS = ("orientation", "velocity", "gripper", "joints", "force",
                  "joint_velocity", "joint_effort")  # fmt: skip


class LimitError(ValidationError):
    """A path cannot be made to meet the given limits."""


def _toppra():
    try:
        import toppra
        import toppra.algorithm
        import toppra.constraint
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            "time-scaling to limits needs toppra; install it with: "
            'pip install "ndlfd[limits]"'
        ) from None
    logging.getLogger("toppra").setLevel(logging.WARNING)
    return toppra


def _is_discrete(demo: Demonstration, cols) -> bool:
    return all(np.unique(demo.X[:, c]).size <= 2 for c in cols)


def check_limits(limits, demo: Demonstration) -> dict[str, np.ndarray]:
    """Checked limits as one array per kind, one value per column of ``demo``.

    Parameters
    ----------
    limits : mapping of str to mapping of str to float or array-like
        ``{group or column: {kind: value}}`` with ``kind`` in :data:`KINDS`:
        for a group, one value for each of its columns or one per column;
        for a column (by its name), one value. A column named twice (by its
        group and by its name) takes the smaller limit. Or ``kind`` in
        :data:`NORM_KINDS`, one value for a whole group: ``"speed"`` of a
        position-like group, ``"angular_velocity"`` and
        ``"angular_acceleration"`` of the quaternion group ``orientation``.
    demo : Demonstration
        The path the limits are for.

    Returns
    -------
    limits : dict of str to ndarray of shape (n_dims,)
        One per kind of :data:`ALL_KINDS`; ``inf`` for columns without a
        limit (a norm limit stands on every column of its group).

    Examples
    --------
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 0], [1, 1]])
    >>> lim = check_limits({"position": {"velocity": 2.0}, "y": {"velocity": 1.0}}, d)
    >>> lim["velocity"]
    array([2., 1.])
    >>> check_limits({"position": {"speed": 0.5}}, d)["speed"]
    array([0.5, 0.5])
    """
    if not isinstance(limits, Mapping):
        raise ValidationError(
            "limits must be a mapping like {'joints': {'velocity': 90.0}}; "
            f"got {type(limits).__name__}"
        )
    out = {kind: np.full(demo.n_dims, np.inf) for kind in ALL_KINDS}
    for key, per_kind in limits.items():
        if not isinstance(per_kind, Mapping):
            raise ValidationError(
                f"limits[{key!r}] must map {', '.join(KINDS)} to values, e.g."
                f" {{{key!r}: {{'velocity': 1.0}}}}; got {type(per_kind).__name__}"
            )
        for kind, value in per_kind.items():
            if kind not in ALL_KINDS:
                raise ValidationError(
                    f"unknown limit {kind!r} of {key!r}; expected one of"
                    f" {', '.join(ALL_KINDS)}"
                )
            if kind in NORM_KINDS:
                cols = _norm_group(demo, key, kind)
                v = _limit_values(value, demo, key, kind, cols[:1])
            else:
                cols = _limited_columns(demo, key)
                v = _limit_values(value, demo, key, kind, cols)
            out[kind][cols] = np.minimum(out[kind][cols], v)
    return out


def _position_groups(demo: Demonstration) -> list[str]:
    """The groups whose speed can be limited (vectors of positions)."""
    return [
        g
        for g in demo.group_names
        if g not in _NOT_POSITIONS
        and group_kind(g) not in _NOT_POSITIONS
        and not g.endswith("_joints")
    ]


def _quaternion_groups(demo: Demonstration) -> list[str]:
    return [
        g
        for g in demo.group_names
        if group_kind(g) in _UNLIMITED and demo.columns_of(g).size == 4
    ]


def _norm_group(demo: Demonstration, key, kind) -> np.ndarray:
    """The columns of the group whose norm ``kind`` limits."""
    angular = kind in ANGULAR_KINDS
    valid = _quaternion_groups(demo) if angular else _position_groups(demo)
    if not (isinstance(key, str) and key in valid):
        what = "a quaternion group (w, x, y, z)" if angular else "a position group"
        raise ValidationError(
            f"a {kind} limit is of {what}; {key!r} is not one: the path has "
            + (", ".join(map(repr, valid)) if valid else "none")
            + (
                ""
                if angular
                else " (joints are limited one by one: {'joints': {'velocity': v}})"
            )
        )
    return demo.columns_of(key)


def _limited_columns(demo: Demonstration, key) -> np.ndarray:
    """The columns of a group or the one column of that name."""
    if isinstance(key, str) and demo.has_group(key):
        group, cols = key, demo.columns_of(key)
    elif isinstance(key, str) and key in demo.columns:
        cols = np.array([demo.columns.index(key)])
        group = demo.groups[cols[0]]
    else:
        raise ValidationError(
            f"no group or column {key!r} to limit; the path has the groups"
            f" {', '.join(demo.group_names)} and the columns {', '.join(demo.columns)}"
        )
    if group_kind(group) in _UNLIMITED:
        raise ValidationError(
            f"{key!r} holds quaternions and cannot be limited column by "
            "column; limit its rotation: {'orientation': {'angular_velocity': w,"
            " 'angular_acceleration': a}} (rad/s, rad/s^2)"
        )
    if group_kind(group) == "velocity" and demo.has_group(
        hand_group(hand_name(group), "position")
    ):
        raise ValidationError(
            "limit the position group's velocity and acceleration "
            "(limits={'position': {'velocity': ...}}), not the velocity group"
        )
    return cols


def _limit_values(value, demo, key, kind, cols) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValidationError(
            f"the {kind} limit of {key!r} must be numbers; got {value!r}"
        ) from None
    if kind in NORM_KINDS and v.size != 1:
        raise ValidationError(
            f"the {kind} limit of {key!r} must be one value (of the group's"
            f" norm); got {v.size}"
        )
    if v.ndim > 1 or (v.ndim == 1 and v.size not in (1, cols.size)):
        raise ValidationError(
            f"the {kind} limit of {key!r} must be one value or {cols.size} "
            f"(one per column: {', '.join(demo.columns[c] for c in cols)}); "
            f"got {v.size}"
        )
    if not (np.isfinite(v).all() and (v > 0).all()):
        raise ValidationError(
            f"the {kind} limit of {key!r} must be finite and > 0; got {value!r}"
        )
    return np.broadcast_to(v.reshape(-1), cols.shape).copy()


def path_peaks(path: Demonstration) -> dict[str, np.ndarray]:
    """The largest absolute velocity, acceleration and jerk of every column.

    Measured as a controller sampling the path sees them: ``numpy.gradient``
    over the path's own stamps (second order at the ends, as
    :func:`~ndlfd.with_velocity`), once for velocity, again for acceleration
    and again for jerk. And the norms (:data:`NORM_KINDS`) of the groups they
    are of, on each of the group's columns (0 on others): the ``speed`` of a
    position-like group (the norm of its velocity), the ``angular_velocity``
    and ``angular_acceleration`` of ``orientation`` (quaternions; see
    :func:`ndlfd._norm_limits.angular_rates`).

    Parameters
    ----------
    path : Demonstration
        At least three samples.

    Returns
    -------
    peaks : dict of str to ndarray of shape (n_dims,)
        One per kind of :data:`ALL_KINDS`.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> d = Demonstration.from_arrays(t, position=np.column_stack([2 * t, t * t]))
    >>> {k: v.round(6).tolist() for k, v in path_peaks(d).items() if k in KINDS}
    {'velocity': [2.0, 2.0], 'acceleration': [0.0, 2.0], 'jerk': [0.0, 0.0]}
    >>> round(float(path_peaks(d)["speed"][0]), 6)  # at t = 1: |(2, 2)|
    2.828427
    """
    if path.n_samples < 3:
        raise ValidationError(
            f"peaks need a path of at least 3 samples; got {path.n_samples}"
        )
    V = np.gradient(path.X, path.t, axis=0, edge_order=2)
    A = np.gradient(V, path.t, axis=0, edge_order=2)
    J = np.gradient(A, path.t, axis=0, edge_order=2)
    out = {
        "velocity": np.abs(V).max(axis=0),
        "acceleration": np.abs(A).max(axis=0),
        "jerk": np.abs(J).max(axis=0),
    }
    out.update({k: np.zeros(path.n_dims) for k in NORM_KINDS})
    for g in _position_groups(path):
        cols = path.columns_of(g)
        out["speed"][cols] = row_norm(V[:, cols]).max()
    for g in _quaternion_groups(path):
        cols = path.columns_of(g)
        w, a = angular_rates(path.X[:, cols], path.t)
        out["angular_velocity"][cols] = w.max()
        out["angular_acceleration"][cols] = a.max()
    return out


def _within(peaks, lim, tol: float = TOLERANCE) -> bool:
    return all(bool(np.all(peaks[k] <= lim[k] * (1.0 + tol))) for k in ALL_KINDS)


def _roles(path: Demonstration):
    """Columns scaled by TOPP-RA, quaternion columns, held columns, derived velocity."""
    # every hand's velocity is derived again from its positions
    derived = [(h.position, h.velocity) for h in hands(path.groups) if h.velocity]
    skip = {path.groups[c[0]] for _, c in derived}
    quat, held, spline = [], [], []
    for g in path.group_names:
        cols = list(path.columns_of(g))
        if group_kind(g) in _UNLIMITED and len(cols) == 4:
            quat.append(cols)
        elif g in skip:
            continue
        elif g == "gripper" and _is_discrete(path, cols):
            held += cols
        else:
            spline += cols
    return spline, quat, held, derived


#: Without an acceleration limit a column may reach its top speed (its
#: velocity limit, else its own peak) in this share of the path's duration.
RAMP_SHARE = 0.02


def _own_acceleration(path, peaks, lim, spline) -> np.ndarray:
    """The acceleration allowed to a column without a limit.

    Its own peak, or what reaches its top speed in :data:`RAMP_SHARE` of the
    path's duration if that is more (a straight line at constant speed has
    no acceleration of its own, and must still start and stop): without a
    bound the scaling would jump from one speed to the next.
    """
    top = np.minimum(peaks["velocity"][spline], lim["velocity"][spline])
    ramp = top / (RAMP_SHARE * path.duration)
    return np.maximum(np.maximum(peaks["acceleration"][spline], ramp), 1e-12)


def _norm_limits(path, spline, curves, lim) -> dict:
    """The norm limits for :func:`~ndlfd._norm_limits.norm_constraints`."""
    norm: dict[str, list] = {k: [] for k in NORM_KINDS}
    for g in _position_groups(path):
        cols = path.columns_of(g)
        if np.isfinite(lim["speed"][cols[0]]):
            where = [spline.index(c) for c in cols]
            norm["speed"].append((where, lim["speed"][cols[0]]))
    for cols, curve in curves.items():
        for k in ANGULAR_KINDS:
            if np.isfinite(lim[k][cols[0]]):
                norm[k].append((curve, lim[k][cols[0]]))
    return norm


def _clock_at(toppra, path, peaks, spline, lim, n_grid, moving=False, curves=None):
    """TOPP-RA's new clock: for each new time, the path's own time.

    From rest, or (``moving``) at the path's own pace where the limits allow
    it (the first sample's velocity by a one-sided difference). ``curves``:
    the quaternion groups' :class:`~ndlfd._norm_limits.QuaternionCurve` by
    their columns.
    """
    t = path.t - path.t[0]
    way = np.column_stack([path.X[:, spline], t])
    interp = toppra.SplineInterpolator(t, way)
    # the clock column may not run faster than the path's own timing
    v = np.append(lim["velocity"][spline], 1.0)
    given = lim["acceleration"][spline]
    a_lim = np.where(
        np.isfinite(given), given, _own_acceleration(path, peaks, lim, spline)
    )
    a = np.append(a_lim, 1e3 / t[-1])
    con = toppra.constraint
    cv = con.JointVelocityConstraint(np.column_stack([-v, v]))
    ca = con.JointAccelerationConstraint(
        np.column_stack([-a, a]),
        discretization_scheme=con.DiscretizationType.Interpolation,
    )
    norm = norm_constraints(toppra, interp, _norm_limits(path, spline, curves, lim))
    grid = np.linspace(0.0, t[-1], n_grid)
    algo = toppra.algorithm.TOPPRA([cv, ca, *norm], interp, gridpoints=grid,
                                   parametrizer="ParametrizeConstAccel")  # fmt: skip
    pace = 0.0
    if moving:  # the clock's speed at which the first step meets the limits
        step = np.abs(path.X[1, spline] - path.X[0, spline]) / t[1]
        with np.errstate(divide="ignore"):
            pace = float(np.min(np.append(v[:-1] / step, 1.0)))
        # and from which the limits can still be kept (TOPP-RA's controllable
        # set at the start, of the squared pace, to the path's end at rest)
        reach = algo.compute_controllable_sets(0.0, 0.0)
        if reach is None or not np.all(np.isfinite(reach[0])):
            return None
        pace = min(pace, float(np.sqrt(max(reach[0][1], 0.0))))
    return algo.compute_trajectory(pace, 0.0)


def _resample(path, clock, new_t, spline, curves, held, derived) -> Demonstration:
    t = path.t - path.t[0]
    X = np.empty((new_t.size, path.n_dims))
    if spline:
        X[:, spline] = CubicSpline(t, path.X[:, spline])(clock)
    i = np.clip(np.searchsorted(t, clock, side="right") - 1, 0, t.size - 2)
    s = np.clip((clock - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0)[:, None]
    for cols, curve in curves.items():  # on the sign the path has there
        X[:, list(cols)] = curve(clock) * curve.sign[i][:, None]
    X[[0, -1]] = path.X[[0, -1]]  # the ends exactly, not up to the splines
    if held:
        j = np.where(s[:, 0] >= 1.0, i + 1, i)
        X[:, held] = path.X[j][:, held]
    for pos, vel in derived:
        X[:, vel] = np.gradient(X[:, pos], new_t, axis=0, edge_order=2)
    return Demonstration(new_t + path.t[0], X, path.columns, path.groups)


def time_scale(
    path: Demonstration, limits, *, rate: float | None = None, keep: int = 0
):
    """Slow a path down where it exceeds velocity or acceleration limits.

    A path already within the limits is returned as it is. Otherwise its
    limited columns (and every other vector column, on the same clock) are
    re-timed by TOPP-RA with the path's own timing as a speed limit on its
    clock, sampled on a uniform grid of the path's median step (or
    ``1 / rate``) up to the new duration (stretched to a whole number of
    steps), and checked: the measured peaks (:func:`path_peaks`) must be
    within the limits up to :data:`TOLERANCE`.

    Parameters
    ----------
    path : Demonstration
        A dense path (at least three samples).
    limits : mapping
        ``{group or column: {"velocity": v, "acceleration": a, "jerk": j}}``
        (:func:`check_limits`; any of the three).
    rate : float, optional
        Samples per second of the result (stamps ``k / rate`` after the
        path's first); the path's own median step by default.
    keep : int, default=0
        The path's first samples that are kept as they are, with their
        stamps (an executed prefix, ``generate(observed=)``): the rest is
        time-scaled from the last of them on (its stamps ``k / rate`` after
        that one), leaving it at the path's own speed there, or at the
        limits if that is faster.

    Returns
    -------
    path : Demonstration
        The same columns and groups; the stamps start where the path's did.

    Raises
    ------
    LimitError
        When the limits cannot be met (TOPP-RA finds no parameterization, or
        the measured peaks stay above the limits).

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> d = Demonstration.from_arrays(t, position=np.column_stack([3 * t, 0 * t]))
    >>> slow = time_scale(d, {"position": {"velocity": 1.5, "acceleration": 10.0}})
    >>> bool(path_peaks(slow)["velocity"].max() <= 1.5 * (1 + 1e-3))
    True
    >>> bool(slow.duration > 2.0), slow.X[-1].tolist()
    (True, [3.0, 0.0])
    """
    if not isinstance(path, Demonstration):
        raise ValidationError(
            f"path must be a Demonstration; got {type(path).__name__}"
        )
    lim = check_limits(limits, path)
    keep = check_positive_int(keep, "keep", minimum=0)
    if keep > path.n_samples - 2:
        raise ValidationError(
            f"keep must leave at least two samples to time-scale (0 to"
            f" {path.n_samples - 2} for a path of {path.n_samples}); got {keep}"
        )
    if keep > 0:
        rest = _scaled(path.take(np.arange(keep - 1, path.n_samples)), lim, rate, True)
        if rest is None:
            return path
        return Demonstration(
            np.concatenate([path.t[: keep - 1], rest.t]),
            np.vstack([path.X[: keep - 1], rest.X]),
            path.columns,
            path.groups,
            path.frames,
        )
    out = _scaled(path, lim, rate, False)
    return path if out is None else out


def _scaled(path, lim, rate, moving):
    """:func:`time_scale` of checked limits; ``None`` if already within them."""
    own = path_peaks(path)  # once: the retries below reuse it
    if _within(own, lim):
        return None
    toppra = _toppra()
    spline, quat, held, derived = _roles(path)
    curves = {tuple(c): QuaternionCurve(path.t - path.t[0], path.X[:, c]) for c in quat}
    step = float(np.median(np.diff(path.t))) if rate is None else _step(rate)
    n_grid = int(min(MAX_GRIDPOINTS, max(GRID_PER_SAMPLE * path.n_samples, 100)))
    # aimed a margin below the limits: TOPP-RA meets them at its grid points,
    # the samples between overshoot by up to a few per mille
    tight = {k: v * (1.0 - MARGIN) for k, v in lim.items()}
    stretch = 1.0  # a uniform slow-down after TOPP-RA, for jerk
    for _ in range(RETRIES + 1):
        traj = _clock_at(toppra, path, own, spline, tight, n_grid, moving, curves)
        if traj is None:
            raise LimitError(
                "no timing of the path meets the limits (TOPP-RA found none): "
                "check that every limit is above zero and in the path's units"
            )
        n = max(int(np.ceil(stretch * traj.duration / step - 1e-9)), 2)
        new_t = np.arange(n + 1) * step if rate is None else np.arange(n + 1) / rate
        # stretched to a whole number of steps: only slower, so still within
        clock = traj(new_t * (traj.duration / new_t[-1]))[:, -1]
        clock = np.clip(np.maximum.accumulate(clock), 0.0, path.t[-1] - path.t[0])
        clock[0], clock[-1] = 0.0, path.t[-1] - path.t[0]
        out = _resample(path, clock, new_t, spline, curves, held, derived)
        peaks = _written_peaks(out, spline, moving)
        if _within(peaks, lim):
            return out
        for k in ("velocity", "acceleration", *NORM_KINDS):
            over = peaks[k] / lim[k]
            tight[k] = tight[k] / (np.maximum(over.max(), 1.0) * (1.0 + MARGIN))
        # jerk falls as the square (an acceleration step sampled) to the cube
        # of a uniform slow-down: the square root is enough either way
        over = float(np.max(peaks["jerk"] / lim["jerk"]))
        stretch *= np.sqrt(max(over, 1.0)) * (1.0 + MARGIN)
    worst = max(ALL_KINDS, key=lambda k: float(np.max(peaks[k] / lim[k])))
    raise LimitError(
        f"the path's {worst} stays above its limits after {RETRIES + 1} "
        f"attempts: at most {float(np.max(peaks[worst] / lim[worst])):.3g} times "
        "the limit; the path may be too rough (noise) for the sample rate"
    )


#: The groups a JointTrajectory carries with their velocities and accelerations.
_TRAJECTORY_GROUPS = ("joints", "gripper")


def _written_peaks(out, spline, moving):
    """:func:`path_peaks`, and the velocity and acceleration a controller follows.

    The cubic spline through the samples at rest at the ends (moving at the
    start after a prefix, :func:`ndlfd._trajectory.rest_curve`): what a
    JointTrajectory writes as velocities and accelerations, of the groups it
    carries (:data:`_TRAJECTORY_GROUPS`). Where TOPP-RA's acceleration jumps
    (bang-bang), the curve's, continuous, overshoots the samples' differences
    by a few per cent: the limits are tightened for it (a path of joints
    takes a few per cent longer than the bare time-optimal one).
    """
    peaks = path_peaks(out)
    sent = [c for c in spline if out.groups[c] in _TRAJECTORY_GROUPS]
    if sent and out.n_samples >= 2:
        curve = rest_curve(out.t, out.X[:, sent], moving_start=moving)
        cv, ca = curve_peaks(curve, out.t)
        peaks["velocity"][sent] = np.maximum(peaks["velocity"][sent], cv)
        peaks["acceleration"][sent] = np.maximum(peaks["acceleration"][sent], ca)
    return peaks


def limited(path, limits, dense: bool, return_std: bool, observed=None):
    """What :meth:`~ndlfd.KeypointHMM.generate` returns with ``limits=``.

    The dense path :func:`time_scale`-d (after an ``observed`` prefix, kept
    as it is); key points (``dense=False``) and a band (``return_std=True``)
    have no meaning on a new clock and are refused.
    """
    if not dense or return_std:
        raise ValidationError(
            "limits= time-scales the dense path: pass dense=True and no "
            f"return_std (got dense={dense}, return_std={return_std})"
        )
    keep = 0 if observed is None else observed.n_samples
    return time_scale(path, limits, keep=keep)


def _step(rate) -> float:
    try:
        r = float(rate)
    except (TypeError, ValueError):
        raise ValidationError(f"rate must be a number of Hz; got {rate!r}") from None
    if not (np.isfinite(r) and r > 0):
        raise ValidationError(f"rate must be finite and > 0 Hz; got {rate!r}")
    return 1.0 / r
