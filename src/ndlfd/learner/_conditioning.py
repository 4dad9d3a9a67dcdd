"""Conditioning on a start and goal: demonstration weights and pinning.

A requested start (goal) weights every demonstration by a Gaussian kernel on
the distance of its first (last) normalized sample to the requested one
(:func:`condition_log_weights`, the width from :func:`condition_bandwidth`);
the generated path is then shifted onto the requested start and goal with an
offset faded out by a minimum-jerk ramp (:func:`pin`), so it begins and ends
there up to rounding. A start or goal far from every demonstration's is
accepted with a warning (:mod:`ndlfd.learner._extrapolation`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._errors import ValidationError
from .._pose_groups import orientation_blocks
from ._discrete import DISCRETE_GROUPS
from ._extrapolation import warn_far_condition
from ._rests import NO_PROGRESS, contact_window, path_rests, smoothed

__all__ = [
    "BANDWIDTH_FACTOR",
    "BRUTE_FORCE_POINTS",
    "OrientedCondition",
    "check_condition",
    "condition_bandwidth",
    "condition_log_weights",
    "condition_target",
    "condition_weights",
    "fade_pieces",
    "group_columns",
    "log_weights_for",
    "minimum_jerk",
    "orient_condition",
    "pin",
    "pin_offset",
    "progress",
    "switch_window",
]

#: Kernel width in units of the median nearest-neighbour distance between the
#: demonstrations' starts (goals). Chosen on held-out LASA (time + start): 1, 2,
#: 4 and 8 gave DTW 1.01, 0.98, 0.97 and 0.97 times the faded mean on the
#: single shapes and 0.133, 0.135, 0.136 and 0.152 on Multi_Models; narrower
#: kernels copy the nearest demonstration, wider ones start to mix routes.
BANDWIDTH_FACTOR = 4.0

#: Points up to which :func:`condition_bandwidth` measures every pair. On
#: random 2-D points (best of 200, numpy and scipy of the venv) the pairs
#: took 6, 19 and 57 us at 6, 32 and 64 points, a k-d tree 19, 26 and 35 us.
BRUTE_FORCE_POINTS = 32


def minimum_jerk(s: np.ndarray) -> np.ndarray:
    """Minimum-jerk ramp ``10 s^3 - 15 s^4 + 6 s^5`` from 0 at ``s=0`` to 1 at ``s=1``.

    Examples
    --------
    >>> minimum_jerk(np.array([0.0, 0.5, 1.0]))
    array([0. , 0.5, 1. ])
    """
    s = np.clip(np.asarray(s, dtype=np.float64), 0.0, 1.0)
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def fade_pieces(at: np.ndarray, taus: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Offsets given at knots, faded between them by :func:`minimum_jerk` pieces.

    Each piece has zero slope and curvature at its knots, so the result is
    twice continuously differentiable; rows outside the knots take the end
    offsets.

    Parameters
    ----------
    at : ndarray of shape (n_rows,)
    taus : ndarray of shape (n_knots,)
        Increasing, at least two.
    offsets : ndarray of shape (n_knots, n_dims)

    Returns
    -------
    offset : ndarray of shape (n_rows, n_dims)

    Examples
    --------
    >>> fade_pieces(np.array([0.0, 0.25, 0.5]), np.array([0.0, 0.5]),
    ...             np.array([[0.0], [2.0]]))[:, 0]
    array([0., 1., 2.])
    """
    i = np.clip(np.searchsorted(taus, at, side="right") - 1, 0, taus.size - 2)
    s = minimum_jerk((at - taus[i]) / (taus[i + 1] - taus[i]))
    return offsets[i] + (offsets[i + 1] - offsets[i]) * s[:, None]


def pin_offset(X: np.ndarray, fade: np.ndarray, row: int, target, cols=None):
    """Move ``X[row, cols]`` onto ``target``, the offset faded over the rows.

    Every row gets ``(target - X[row, cols]) * fade`` added, and ``X[row,
    cols]`` is then set to ``target`` exactly (not up to the rounding of the
    sum). ``X`` is changed in place.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_dims)
        The path.
    fade : ndarray of shape (n_samples,)
        How much of the offset each row takes: ``1 - minimum_jerk(tau)`` to pin a
        start (row 0), ``minimum_jerk(tau)`` to pin a goal (the last row).
    row : int
        The row that must land on ``target``.
    target : array-like of shape (n_cols,)
        Where it must land.
    cols : sequence of int, optional
        The columns moved (all by default).

    Returns
    -------
    X : ndarray of shape (n_samples, n_dims)

    Examples
    --------
    >>> X = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> pin_offset(X, 1.0 - minimum_jerk(np.array([0.0, 0.5, 1.0])), 0, [0.0, 2.0])
    array([[0., 2.],
           [1., 1.],
           [2., 0.]])
    """
    cols = slice(None) if cols is None else cols
    X[:, cols] += (np.asarray(target, dtype=np.float64) - X[row, cols]) * fade[:, None]
    X[row, cols] = target
    return X


def condition_bandwidth(points: np.ndarray) -> float:
    """Kernel width of :func:`condition_weights` for these points.

    :data:`BANDWIDTH_FACTOR` times the median distance from each point to its
    nearest other one (the width of the whole set if most coincide; 1 for a
    single point). Up to :data:`BRUTE_FORCE_POINTS` points by all pairwise
    distances (a k-d tree costs more to build than they take: continuing a
    prefix asks for one width per observed sample), beyond by a k-d tree in
    ``O(n log n)``.

    Examples
    --------
    >>> condition_bandwidth(np.array([[0.0], [0.5], [3.0], [3.5]]))
    2.0
    """
    points = np.asarray(points, dtype=np.float64)
    if points.shape[0] < 2:
        return 1.0
    if points.shape[0] <= BRUTE_FORCE_POINTS:
        diff = points[:, None, :] - points[None, :, :]
        d2 = np.einsum("ijk,ijk->ij", diff, diff)
        np.fill_diagonal(d2, np.inf)
        nearest = np.sqrt(d2.min(axis=1))
    else:
        from scipy.spatial import cKDTree

        nearest = cKDTree(points).query(points, k=2)[0][:, 1]
    h = BANDWIDTH_FACTOR * float(np.median(nearest))
    if not h > 0:  # most points coincide: the width of the whole set
        h = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) or 1.0
    return h


def condition_weights(
    points: np.ndarray, target: np.ndarray, bandwidth: float | None = None
) -> np.ndarray:
    """Gaussian-kernel weights of demonstrations for a requested start or goal.

    The bandwidth is :data:`BANDWIDTH_FACTOR` times the median, over the
    demonstrations, of the distance from each one's point to the nearest other
    one's: demonstrations of one route lie within it of each other, routes
    that start apart fall out.

    Parameters
    ----------
    points : ndarray of shape (n_demos, n_dims)
        Each demonstration's first (or last) sample, normalized units.
    target : ndarray of shape (n_dims,)
        The requested start (or goal), normalized units.
    bandwidth : float, optional
        :func:`condition_bandwidth` of ``points``, if known already.

    Returns
    -------
    weights : ndarray of shape (n_demos,)
        In ``(0, 1]``, the largest is 1.

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [0.1, 0.0], [5.0, 5.0], [5.1, 5.0]])
    >>> np.round(condition_weights(pts, np.array([5.0, 5.05])), 3)
    array([0.   , 0.   , 1.   , 0.969])
    """
    logw = condition_log_weights(points, target, bandwidth)
    return np.exp(logw - logw.max())


def condition_log_weights(
    points: np.ndarray, target: np.ndarray, bandwidth: float | None = None
) -> np.ndarray:
    """Logarithms of :func:`condition_weights`, before normalizing.

    Normalize them over any subset of the demonstrations with
    ``np.exp(logw[subset] - logw[subset].max())``: however far the target
    lies, the nearest demonstration of the subset weighs 1 (the weights over
    all of them may underflow to 0 outside the nearest one's subset).

    Examples
    --------
    >>> pts = np.array([[0.0], [1.0], [3.0]])
    >>> condition_log_weights(pts, np.array([0.0]), bandwidth=1.0)
    array([-0. , -0.5, -4.5])
    """
    points = np.asarray(points, dtype=np.float64)
    if points.shape[0] < 2:
        return np.zeros(points.shape[0])
    d = np.linalg.norm(points - target, axis=1)
    h = condition_bandwidth(points) if bandwidth is None else bandwidth
    return -0.5 * (d / h) ** 2


def group_columns(column_groups, group: str) -> list[int]:
    """Indices of the columns of ``group``.

    Examples
    --------
    >>> group_columns(("position", "position", "velocity"), "position")
    [0, 1]
    """
    return [i for i, g in enumerate(column_groups) if g == group]


def check_condition(values, what: str, column_groups, groups) -> dict | None:
    """Check a start or goal mapping; return it as ``{group: float array}``.

    Parameters
    ----------
    values : mapping of str to array-like, or None
        The requested values per group, physical units.
    what : str
        ``"start"`` or ``"goal"`` (for the messages).
    column_groups : sequence of str
        The group of each learned column.
    groups : sequence of str
        The learned groups (for the messages).

    Returns
    -------
    condition : dict of str to ndarray, or None
    """
    if values is None:
        return None
    if not isinstance(values, Mapping) or not values:
        raise ValidationError(
            f"{what} must be a mapping of group to values, e.g."
            f" {{'position': [x, y]}}; got {values!r}"
        )
    out = {}
    for g, v in values.items():
        cols = group_columns(column_groups, g)
        if not cols:
            raise ValidationError(
                f"{what} names group {g!r}, which is not learned; the learned"
                f" groups are {', '.join(groups)}"
            )
        arr = np.asarray(v, dtype=np.float64).reshape(-1)
        if arr.size != len(cols) or not np.all(np.isfinite(arr)):
            raise ValidationError(
                f"{what}[{g!r}] must hold {len(cols)} finite value(s); got"
                f" {np.asarray(v).tolist()!r}"
            )
        out[g] = arr
    return out


class OrientedCondition(dict):
    """A start or goal :func:`orient_condition` returned (a plain ``dict`` else).

    Orienting it again returns it as it is: a generation that plans twice
    (an executed prefix completed from a first plan) warns of a far goal
    once.
    """


def orient_condition(cond, points, scaler, column_groups, what: str) -> dict | None:
    """A requested orientation as a unit quaternion on the demonstrations' side.

    ``q`` and ``-q`` are one rotation: the requested quaternion is scaled to
    unit norm and, when it points away from the mean of the demonstrations'
    (first or last) orientations, negated, so the kernel weights and the
    offset pinned onto the path compare it with the same sign. A start or
    goal far outside the demonstrations' is then warned about
    (:func:`~ndlfd.learner._extrapolation.warn_far_condition`).

    Parameters
    ----------
    cond : dict of str to ndarray, or None
        From :func:`check_condition`.
    points : ndarray of shape (n_demos, n_columns) or None
        The demonstrations' first (start) or last (goal) normalized samples;
        ``None`` (a model without them): the norm only.
    scaler : GroupScaler
        The fitted normalization.
    column_groups : sequence of str
    what : str
        For the message (``"start"``, ``"goal"``).

    Returns
    -------
    condition : OrientedCondition or None

    Examples
    --------
    >>> from ndlfd import GroupScaler
    >>> cg = ("orientation",) * 4
    >>> sc = GroupScaler(cg, mode="none").fit(np.eye(4))
    >>> orient_condition({"orientation": np.array([-1.0, 0.1, 0.0, 0.0])},
    ...                  np.array([[1.0, 0, 0, 0]]), sc, cg, "start")
    {'orientation': array([ 0.99503719, -0.09950372, -0.        , -0.        ])}
    """
    if cond is None or isinstance(cond, OrientedCondition):
        return cond
    for cols in orientation_blocks(column_groups):  # every hand's
        name = column_groups[cols[0]]
        if name not in cond:
            continue
        q = cond[name]
        norm = float(np.linalg.norm(q))
        if not norm > 1e-12:
            raise ValidationError(
                f"{what}[{name!r}] must be a quaternion w, x, y, z of non-zero"
                f" norm; got {q.tolist()}"
            )
        q = q / norm
        if points is not None:
            P = scaler.inverse_transform(points, weighted=False)
            q = -q if float(q @ P[:, cols].mean(axis=0)) < 0.0 else q
        cond = {**cond, name: q}
    if what in ("start", "goal"):  # a via point's values are another matter
        warn_far_condition(cond, points, scaler, column_groups, what)
    return OrientedCondition(cond)


def condition_target(
    cond, scaler, column_groups, *, weighted: bool = False
) -> tuple[list[int], np.ndarray]:
    """The columns a checked condition names and its values there, normalized.

    Parameters
    ----------
    cond : dict of str to ndarray
        From :func:`check_condition` (a start, goal or via point).
    scaler : GroupScaler
        The fitted normalization.
    column_groups : sequence of str
        The group of each column.
    weighted : bool, default=False
        In the group-weighted units the templates are blended in.

    Returns
    -------
    cols : list of int
    target : ndarray of shape (len(cols),)
    """
    cols = [c for g in cond for c in group_columns(column_groups, g)]
    row = scaler.data_min_.copy()
    for g, v in cond.items():
        row[group_columns(column_groups, g)] = v
    return cols, scaler.transform(row[None, :], weighted=weighted)[0, cols]


def log_weights_for(cond, points, scaler, column_groups, cache, key) -> np.ndarray:
    """Every demonstration's log weight for a checked start or goal.

    Parameters
    ----------
    cond : dict of str to ndarray, or None
        From :func:`check_condition`; ``None`` gives zeros.
    points : ndarray of shape (n_demos, n_columns)
        Each demonstration's first (for a start) or last (goal) normalized
        sample.
    scaler : GroupScaler
        The fitted normalization.
    column_groups : sequence of str
        The group of each column.
    cache : dict
        Kernel widths by ``(key, columns)``: the width depends on the
        training points only, so it is computed once per model.
    key : hashable
        Which points these are (e.g. 0 for the starts, -1 for the goals).

    Returns
    -------
    log_weights : ndarray of shape (n_demos,)
    """
    if cond is None:
        return np.zeros(points.shape[0])
    cols, target = condition_target(cond, scaler, column_groups)
    pts = points[:, cols]
    ckey = (key, tuple(cols))
    if ckey not in cache:
        cache[ckey] = condition_bandwidth(pts)
    return condition_log_weights(pts, target, cache[ckey])


def switch_window(X, tq, column_groups) -> tuple[float, float]:
    """Normalized times around the first and last switch of a gripper.

    A discrete channel (:data:`~ndlfd.learner._discrete.DISCRETE_GROUPS`) on
    two values that changes value marks a contact event even where the hand does not
    slow down: a start's offset must be gone by the last row before the
    first switch, a goal's must come in from the first row after the last.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_columns)
        The path in time order.
    tq : ndarray of shape (n_samples,)
        Their normalized times, increasing.
    column_groups : sequence of str

    Returns
    -------
    first, last : float
        ``(1, 0)`` without a switch strictly inside the motion.

    Examples
    --------
    >>> X = np.array([[0.0, 0], [1.0, 0], [2.0, 1], [3.0, 1], [4.0, 0]])
    >>> switch_window(X, np.linspace(0.0, 1.0, 5), ("position", "gripper"))
    (0.25, 0.5)

    A gripper on more than two values (a continuous position) does not switch:

    >>> X[:, 1] = [30.0, 30.1, 45.0, 49.9, 50.0]
    >>> switch_window(X, np.linspace(0.0, 1.0, 5), ("position", "gripper"))
    (1.0, 0.0)
    """
    first, last = 1.0, 0.0
    for c, g in enumerate(column_groups):
        # a gripper recorded as a continuous position (an SO-101's gripper.pos)
        # changes at every sample: only one on two values switches
        if g not in DISCRETE_GROUPS or np.unique(X[:, c]).size != 2:
            continue
        at = np.flatnonzero(np.diff(X[:, c]) != 0)
        before, after = tq[at], tq[at + 1]  # the rows either side of each switch
        inside = (before > 0.0) & (after < 1.0)
        if inside.any():
            first = min(first, float(before[inside][0]))
            last = max(last, float(after[inside][-1]))
    return first, last


def progress(X, tq, column_groups, n_dense=None) -> np.ndarray:
    """How far the path has moved by each row: its cumulative length.

    Measured on the moving average (:func:`~ndlfd.learner._rests.smoothed`)
    of the columns of every group but
    :data:`~ndlfd.learner._rests.NO_PROGRESS`, each scaled by its range over
    the path (so joints in degrees and a position in metres both count), between
    consecutive rows of the first ``n_dense`` (the path in time order); the
    other rows are interpolated at their normalized times. A path at rest
    makes no progress, however long it rests.

    Parameters
    ----------
    X : ndarray of shape (n_rows, n_columns)
    tq : ndarray of shape (n_rows,)
        Normalized time of each row, increasing over the first ``n_dense``.
    column_groups : sequence of str
    n_dense : int, optional

    Returns
    -------
    length : ndarray of shape (n_rows,)
        From 0 at the first row; all zeros where no column moves.

    Examples
    --------
    At rest, then two unit steps, then at rest (the moving average of each
    row and its neighbours starts moving a row earlier and stops a row later):

    >>> X = np.array([[0.0], [0.0], [0.0], [1.0], [2.0], [2.0], [2.0]])
    >>> progress(X, np.linspace(0.0, 1.0, 7), ("position",)).round(3)
    array([0.   , 0.   , 0.167, 0.5  , 0.833, 1.   , 1.   ])
    """
    n = X.shape[0] if n_dense is None else n_dense
    cols = [c for c, g in enumerate(column_groups) if g not in NO_PROGRESS]
    if not cols or n < 2:
        return np.zeros(X.shape[0])
    P = smoothed(X[:n, cols])
    span = np.ptp(P, axis=0)
    P = P / np.where(span > 0, span, 1.0)
    length = np.concatenate(
        [[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))]
    )
    if X.shape[0] == n:
        return length
    return np.concatenate([length, np.interp(tq[n:], tq[:n], length)])


def _held_in_rests(c: np.ndarray, tq: np.ndarray, n: int, rests) -> np.ndarray:
    """Progress ``c`` that stands still within the ``rests``: their noise is no motion.

    Examples
    --------
    >>> c = np.array([0.0, 1.0, 1.1, 1.2, 2.2])
    >>> _held_in_rests(c, np.linspace(0.0, 1.0, 5), 5, np.array([[0.25, 0.75]]))
    array([0., 1., 1., 1., 2.])
    """
    if not len(rests):
        return c
    mid = (tq[1:n] + tq[: n - 1]) / 2.0
    still = np.zeros(n - 1, dtype=bool)
    for a, b in rests:
        still |= (mid > a) & (mid < b)
    dense = np.concatenate([[0.0], np.cumsum(np.where(still, 0.0, np.diff(c[:n])))])
    return np.concatenate([dense, np.interp(tq[n:], tq[:n], dense)])


def pin(X, tq, start, goal, column_groups, n_dense=None) -> np.ndarray:
    """Shift a path onto ``start`` and ``goal`` with an offset faded before contact.

    The offsets are measured on the first and last of the first ``n_dense``
    rows (the path at normalized times 0 and 1) and applied to every row at
    its normalized time ``tq``, faded by :func:`minimum_jerk`: the start's
    offset is gone by the path's first slow-down
    (:func:`~ndlfd.learner._rests.contact_window`, on the position columns;
    the whole motion if it has none) or its first gripper switch if that
    comes earlier (:func:`switch_window`), the goal's offset comes in after
    the last of them, so the path reaches a grasp or placement where the
    demonstrations do, not shifted by a start elsewhere.
    The ramp runs on the path's :func:`progress`, not its clock: the offset
    is absorbed as the path moves, in proportion, and a path at rest (a robot
    waiting before it moves) stays at rest, as it does in its rests
    (:func:`~ndlfd.learner._rests.path_rests`: a grasp in a joint-space
    path, which has no position to find the contact by, holds the share of
    the offset it has);
    a window without motion fades by time.

    Parameters
    ----------
    X : ndarray of shape (n_rows, n_columns)
        The path, physical units.
    tq : ndarray of shape (n_rows,)
        Normalized time of each row.
    start, goal : dict of str to ndarray, or None
        Checked conditions (:func:`check_condition`).
    column_groups : sequence of str
        The group of each column.
    n_dense : int, optional
        Rows that make the path proper, in time order (the rest are extra
        rows, e.g. key points); all rows by default.

    Returns
    -------
    X : ndarray of shape (n_rows, n_columns)
        A new array (``X`` itself when there is nothing to pin).

    Examples
    --------
    >>> X = np.array([[0.0], [1.0], [2.0]])
    >>> pin(X, np.array([0.0, 0.5, 1.0]), {"p": np.array([1.0])}, None, ("p",))
    array([[1. ],
           [1.5],
           [2. ]])
    """
    if start is None and goal is None:
        return X
    n = X.shape[0] if n_dense is None else n_dense
    pos = group_columns(column_groups, "position")
    first, last = contact_window(X[:n, pos], tq[:n]) if pos else (1.0, 0.0)
    switch_first, switch_last = switch_window(X[:n], tq[:n], column_groups)
    first, last = min(first, switch_first), max(last, switch_last)
    c = _held_in_rests(progress(X, tq, column_groups, n), tq, n,
                       path_rests(X[:n], tq[:n], column_groups))  # fmt: skip
    c_first, c_last = np.interp([first, last], tq[:n], c[:n])
    if c_first > 0.0:
        to_start = 1.0 - minimum_jerk(c / c_first)
    else:  # no motion before the contact: by time
        to_start = 1.0 - minimum_jerk(tq / first)
    if c[n - 1] > c_last:
        to_goal = minimum_jerk((c - c_last) / (c[n - 1] - c_last))
    else:
        to_goal = minimum_jerk((tq - last) / (1.0 - last))
    X = X.copy()
    for cond, fade, row in ((start, to_start, 0), (goal, to_goal, n - 1)):
        for g, v in (cond or {}).items():
            pin_offset(X, fade, row, v, group_columns(column_groups, g))
    return X
