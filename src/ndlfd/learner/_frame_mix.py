"""Task frames in generation: each part of the motion where the demonstrations agree.

A demonstration may carry task frames (:class:`~ndlfd.Demonstration`'s
``frames``: where the object and the place were). Given new poses of those
frames (``generate(t, frames={"object": pose})``), the blended templates are
taken on their own clocks (:func:`~ndlfd.learner._frames.clock_aligned`) and
each is seen from every frame: as demonstrated (the *world*), and carried
rigidly from its own pose of the frame to the new one
(:func:`ndlfd._poses.frame_maps`; a frame with an orientation gives two
views, moved and turned or moved only, of which the tighter counts,
:func:`_pick_weight`). At every phase each view gives a Gaussian over the
position, the templates' weighted mean and covariance there, the covariance
shrunk toward its mean variance (:func:`shrunk_covariance`: a few templates,
as on a minor route, have directions of no spread by chance, which the
product would follow through an obstacle the demonstrations went around);
the views are combined as a product of Gaussians (as task-parameterized
mixtures do, Calinon 2016), so where the demonstrations agree in the
object's frame (near the grasp the hand is rigid in it) the object's frame
decides, and where they agree in the world (the start, around a fixed
obstacle) the world does. No time is needed: the phase comes from the
templates. Then each combined template is moved along a ridge regression of
the templates on their frames' origins
(:func:`~ndlfd.learner._frame_slopes.frame_slopes`): a part of the motion
between two frames (the carry from the object to the place) moves with both,
which no one view gives, and the regression finds how much. The weights and
slopes are computed on a phase grid and smoothed along it
(:data:`FRAME_SMOOTH`). Each hand (a position group: ``position``,
``left_position``, ...) is combined from its own views; a model without a
hand (joint space) is moved along the slopes alone.

:func:`frame_mixer` returns the step :func:`~ndlfd.learner._blend.warped`
applies to the time-warped templates: each template becomes the combination
of its frame views, so the blend's mean is the product's mean and the
conditioning on a start, goal or via point
(:func:`~ndlfd.learner._blend.condition_offsets`) works on the combined
templates' deviations. Velocity turns with the position; orientation turns
with each frame, the views averaged with weights inverse to their angular
spread. Where the demonstrations never varied (a height every object had),
every frame is as sure as the world, and a new pose that leaves it is
followed only in part (the product's mean).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping

import numpy as np

from .._errors import NdlfdWarning
from .._pose_groups import hands
from .._poses import frame_maps
from ._blend import warped
from ._discrete import DISCRETE_GROUPS
from ._frame_slopes import frame_features, frame_slopes, quadratic_features
from ._frames import FRAME_FLOOR, clock_aligned, frame_allowed, quat_multiply

__all__ = [
    "FRAME_SMOOTH",
    "frame_mixer",
    "frame_parts",
    "shrunk_covariance",
]


def shrunk_covariance(S: np.ndarray, n: float) -> np.ndarray:
    """Covariances of ``n`` samples shrunk toward their mean variance (OAS).

    The oracle approximating shrinkage of Chen, Wiesel, Eldar and Hero
    (2010): ``(1 - rho) S + rho tr(S) / k I`` with ``rho = min(1, ((1 - 2/k)
    tr(S^2) + tr(S)^2) / ((n + 1 - 2/k) (tr(S^2) - tr(S)^2 / k)))``, the
    closed form near the least mean squared error for Gaussian samples. A
    sample covariance of few points has directions of near-zero variance by
    chance (three templates in 3-D: a plane), which would claim certainty a
    product of Gaussians follows; shrunk, a view's certainty is its spread
    where the samples cannot tell directions apart, and the sample
    covariance where they can.

    Parameters
    ----------
    S : ndarray of shape (..., k, k)
        Sample covariances (normalized by the weights, not ``n - 1``).
    n : float
        The number of samples (effective, for weighted ones), at least 1.

    Returns
    -------
    ndarray of shape (..., k, k)

    Examples
    --------
    Two points in the plane give a covariance of rank one; shrunk, it is
    the isotropic mean variance:

    >>> shrunk_covariance(np.array([[1.0, 0.0], [0.0, 0.0]]), 2.0)
    array([[0.5, 0. ],
           [0. , 0.5]])
    """
    k = S.shape[-1]
    tr = np.trace(S, axis1=-2, axis2=-1)
    tr2 = np.einsum("...ab,...ba->...", S, S)
    num = (1.0 - 2.0 / k) * tr2 + tr**2
    den = (n + 1.0 - 2.0 / k) * (tr2 - tr**2 / k)
    # den is 0 where S is already isotropic (or zero): nothing to shrink
    rho = np.ones_like(tr)
    ok = den > 1e-12 * np.maximum(tr2, 1e-300)
    rho[ok] = np.minimum(1.0, num[ok] / den[ok])
    iso = (rho * tr / k)[..., None, None] * np.eye(k)
    return (1.0 - rho)[..., None, None] * S + iso


def _gauss(C: np.ndarray, w: np.ndarray, floor: float):
    """The precision of the templates ``C`` (n_templates, n_out, k) at every row.

    The inverse of their weighted covariance, shrunk
    (:func:`shrunk_covariance`, with the weights' effective number), plus
    ``floor`` on the diagonal.
    """
    mu = np.tensordot(w, C, axes=1)  # (n_out, k)
    D = C - mu[None]
    Dt = D.transpose(1, 0, 2)  # (n_out, n_templates, k)
    S = np.matmul(Dt.transpose(0, 2, 1) * w, Dt)  # sum_j w_j D_j D_j^T per row
    S = shrunk_covariance(S, 1.0 / float(np.sum(w * w)))
    S += floor * np.eye(C.shape[2])[None]
    return np.linalg.inv(S)


def _angular_precision(Q: np.ndarray, w: np.ndarray, floor: float) -> np.ndarray:
    """Inverse weighted mean squared angle of the quaternions to their mean."""
    m = np.tensordot(w, Q, axes=1)
    m /= np.maximum(np.linalg.norm(m, axis=-1, keepdims=True), 1e-300)
    dots = np.clip(np.abs(np.sum(Q * m[None], axis=-1)), 0.0, 1.0)
    ang2 = (2.0 * np.arccos(dots)) ** 2
    return 1.0 / (np.tensordot(w, ang2, axes=1) + floor)


def _views(est, demos, frames, k, unit: float) -> list:
    """The maps of each frame's views of the templates: a list of ``(A, b, dq)``.

    A frame with a position only: its move. A frame with an orientation: its
    move and turn (what is rigid in the frame, near it), and its move alone
    (a part of the motion that moves with the frame without turning with
    it); the orientation turns with the frame in both. Positions in ``unit``.
    """
    out = []
    for name, pose in frames.items():
        old = np.array(est.task_frames_[name][demos], dtype=np.float64)
        old[:, :k] /= unit
        pose = np.concatenate([pose[:k] / unit, pose[k:]])
        A, b, dq = frame_maps(old, pose, k)
        views = [(A, b, dq)]
        if pose.size == 7:
            views.append((*frame_maps(old[:, :k], pose[:k], k)[:2], dq))
        out.append(views)
    return out


def _spread(C: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Weighted total variance of the templates at every row (n_out,)."""
    mu = np.tensordot(w, C, axes=1)
    return np.tensordot(w, np.sum((C - mu[None]) ** 2, axis=-1), axes=1)


#: How sharply a frame's tighter view wins (:func:`_pick_weight`). Measured on
#: ``synth.pick_place`` turned by up to 60 deg, where the hand's position
#: does not turn with the object (``benchmarks/probe_task_frames.py``,
#: DTW/range): both views multiplied as if independent 0.0021; weighed by
#: inverse variance to the power 1, 2, 4, 16: 0.0018, 0.0014, 0.0011, 0.0011
#: (the moved view alone: 0.0011).
_SHARPNESS = 4


def _pick_weight(views, w, floor) -> np.ndarray:
    """The weight of a frame's first view (turned) against its second (moved).

    The two are views of the same frame, not independent evidence, so they
    are not multiplied: each row weighs them by their inverse total variance
    to the power :data:`_SHARPNESS` (one view only: weight 1).

    Returns
    -------
    a : ndarray of shape (n_out,)
    """
    if len(views) == 1:
        return np.ones(views[0][0].shape[1])
    p1 = (1.0 / (_spread(views[0][0], w) + floor)) ** _SHARPNESS
    p2 = (1.0 / (_spread(views[1][0], w) + floor)) ** _SHARPNESS
    return p1 / (p1 + p2)


def _merged(views, a):
    """A frame's views as one: ``a`` times the first plus the rest the second."""
    if len(views) == 1:
        return views[0]
    (P1, V1, Q1), (P2, V2, _) = views
    V = None if V1 is None else a * V1 + (1 - a) * V2
    return a * P1 + (1 - a) * P2, V, Q1


#: The phase grid the frames' weights and slopes are computed on
#: (:func:`frame_mixer`), and the half-width of the moving average that
#: smooths them along it (a share of the motion). Computed row by row, the
#: weights switch between views as fast as the templates' spreads cross, and
#: the slopes on the origins carry the templates' noise, amplified where the
#: new origins lie far out. Measured on ``synth.pick_place`` turned by up to
#: 60 deg, demonstration 4 held out: the path's largest acceleration was
#: 15.6 m/s^2 row by row, 10.1 with the weights smoothed over 0.02 of the
#: motion, 9.5 with the slopes too (the noise-free demonstration's: 6.9;
#: ndlfd without frames: 9.1); over the 12 folds, the largest speed over the
#: demonstrations' 95th percentile at the phase went from 2.44 to 1.15
#: (translated set) and 1.26 to 1.23 (turned), DTW unchanged or better.
_GRID = 201
FRAME_SMOOTH = 0.02


def _smooth(A: np.ndarray, half: int) -> np.ndarray:
    """Moving average along the first axis (``2 * half + 1`` rows, ends repeated)."""
    if half < 1:
        return A
    pad = np.concatenate([np.repeat(A[:1], half, 0), A, np.repeat(A[-1:], half, 0)])
    c = np.cumsum(pad, axis=0)
    c = np.concatenate([np.zeros_like(c[:1]), c])
    return (c[2 * half + 1 :] - c[: -2 * half - 1]) / (2 * half + 1)


def _smooth_along(B: np.ndarray, half: int) -> np.ndarray:
    """Slopes ``(p, n_grid, c)`` smoothed along the grid (:func:`_smooth`)."""
    return np.moveaxis(_smooth(np.moveaxis(B, 1, 0), half), 0, 1)


def _frame_views(X, maps, pos, vel, quat, Q=None):
    """Every frame's views of templates in physical units: lists of (P, V, Q).

    A view that only moves (a frame given as a position: ``A`` the identity
    for every template) adds its move, and one that does not turn keeps the
    orientation ``Q`` (by default ``X``'s) as it is, the same array: the same
    values as the general map, without it.
    """
    P = X[:, :, pos]
    if quat and Q is None:
        Q = X[:, :, quat]
    out = []
    for frame in maps:
        seen = []
        for A, b, dq in frame:
            if np.array_equal(A, np.broadcast_to(np.eye(A.shape[-1]), A.shape)):
                Pf = P + b[:, None, :]
                Vf = X[:, :, vel] if vel else None
            else:
                At = A.transpose(0, 2, 1)  # row vectors: P A^T is A applied to each
                Pf = P @ At + b[:, None, :]
                Vf = X[:, :, vel] @ At if vel else None
            Qf = Q
            if quat and dq is not None:
                Qf = quat_multiply(dq[:, None, :], Q)
                Qf = np.where(np.sum(Qf * Q, -1, keepdims=True) < 0, -Qf, Qf)
            seen.append((Pf, Vf, Qf))
        out.append(seen)
    return out


def _interp(tq, grid, A) -> np.ndarray:
    """``A`` (on ``grid`` along axis 0) at ``tq``, every other entry linearly.

    As ``np.interp`` of each entry (ends held outside the grid), all at once.

    Examples
    --------
    >>> A = np.array([[0.0, 10.0], [1.0, 20.0]])
    >>> _interp(np.array([-1.0, 0.25, 2.0]), np.array([0.0, 1.0]), A)
    array([[ 0. , 10. ],
           [ 0.25, 12.5 ],
           [ 1. , 20. ]])
    """
    x = np.clip(tq, grid[0], grid[-1])
    i = np.clip(np.searchsorted(grid, x, side="right") - 1, 0, grid.size - 2)
    f = (x - grid[i]) / (grid[i + 1] - grid[i])
    f = f.reshape((-1,) + (1,) * (A.ndim - 1))
    return A[i] * (1.0 - f) + A[i + 1] * f


def _mixed(M: list, V: list) -> np.ndarray:
    """``sum_f M[f] @ V[f]`` row by row: ``(n_out, k, k)`` on ``(n, n_out, k)``.

    The same sums as ``np.einsum("tab,jtb->jta", ...)`` added over the views
    (up to rounding), as one batched product per row of the views side by
    side: ``[V_1 ... V_F] [M_1 ... M_F]^T`` (three times faster than a column
    at a time for 3-D positions and three views).

    Examples
    --------
    >>> M = [np.eye(2)[None] * 2.0]
    >>> _mixed(M, [np.ones((1, 1, 2))])
    array([[[2., 2.]]])
    """
    Va = np.concatenate(V, axis=2).transpose(1, 0, 2)  # (n_out, n, F k)
    Ma = np.concatenate(M, axis=2)  # (n_out, k, F k)
    return np.matmul(Va, Ma.transpose(0, 2, 1)).transpose(1, 0, 2)


def _hand_stats(hand, maps, Xg, wg, half, floor):
    """One hand's weights of its frame views on the grid (see :func:`frame_mixer`).

    Returns
    -------
    picks : list of ndarray of shape (n_grid,)
        Per frame, the weight of its first view against its second.
    mixes : ndarray of shape (n_views, n_grid, k, k)
        Each view's share of the product (its precision over their sum).
    shares : ndarray of shape (n_grid, n_views) or None
        Each view's share of the orientation (``None``: the hand has none).
    """
    pos, vel, quat = hand.position, hand.velocity, hand.orientation
    Qg = Xg[:, :, quat] if quat else None
    seen_g = _frame_views(Xg, maps, pos, vel, quat, Qg)
    picks = [_smooth(_pick_weight(seen, wg, floor), half) for seen in seen_g]
    views_g = [(Xg[:, :, pos], None, Qg)]
    views_g += [
        _merged(seen, a[None, :, None]) for seen, a in zip(seen_g, picks, strict=True)
    ]
    prec = np.array([_smooth(_gauss(v[0], wg, floor), half) for v in views_g])
    mixes = np.linalg.inv(prec.sum(axis=0))[None] @ prec  # (n_views, G, k, k)
    shares = None
    if quat:
        known = {}  # views that do not turn share the templates' own array
        for v in views_g:
            if id(v[2]) not in known:
                known[id(v[2])] = _angular_precision(v[2], wg, FRAME_FLOOR**2)
        a = np.array([known[id(v[2])] for v in views_g])
        shares = _smooth((a / a.sum(axis=0, keepdims=True)).T, half)  # (G, n_views)
    return picks, mixes, shares


def _hand_combine(hand, maps, stats, grid):
    """One hand's product of its frame views at its frames' poses ``maps``.

    Returns
    -------
    combine : callable
        ``combine(X, out, tq)``: writes the hand's combined position,
        velocity and orientation of the physical templates ``X`` at phases
        ``tq`` into ``out``.
    """
    pos, vel, quat = hand.position, hand.velocity, hand.orientation
    picks, mixes, shares = stats

    def combine(X, out, tq):
        Q = X[:, :, quat] if quat else None
        seen = _frame_views(X, maps, pos, vel, quat, Q)
        views = [(X[:, :, pos], X[:, :, vel] if vel else None, Q)]
        views += [
            _merged(v, np.interp(tq, grid, a)[None, :, None])
            for v, a in zip(seen, picks, strict=True)
        ]
        M = [_interp(tq, grid, m) for m in mixes]  # (n_out, k, k) each
        out[:, :, pos] = _mixed(M, [v[0] for v in views])
        if vel:
            out[:, :, vel] = _mixed(M, [v[1] for v in views])
        if quat:
            a = _interp(tq, grid, shares)  # (n_out, n_views)
            out[:, :, quat] = sum(
                a[None, :, f, None] * v[2] for f, v in enumerate(views)
            )

    return combine


def _slope_parts(est, groups, found, frames) -> list:
    """What the slopes move: ``(columns, scored, frames)`` per regression.

    With hands: one per hand, its position, velocity and orientation moved
    on the frames that may move it (``frame_hands``), the choice of features
    scored on its position. Without (joint space): every column but a
    two-valued gripper's, on every frame, scored on all of them.
    """
    if not found:
        moved = [j for j, g in enumerate(groups) if g not in DISCRETE_GROUPS]
        return [(moved, list(range(len(moved))), dict(frames))]
    out = []
    for h in found:
        own = {f: p for f, p in frames.items() if frame_allowed(est, f, h.name)}
        if own:
            out.append((h.moved, list(range(len(h.position))), own))
    return out


def _features(est, demos, own, unit, curved: bool) -> tuple:
    """The candidates' features of the templates and at the new poses ``own``.

    Returns
    -------
    candidates : list of (ndarray of shape (n_templates, p), ndarray of shape (p,))
        As :func:`~ndlfd.learner._frame_slopes.frame_features`.
    squares : tuple of (ndarray, ndarray) or None
        The first candidate's squares and products (``curved``: a model
        without a hand, whose joints are a curved function of the frames).
    """
    candidates = frame_features(est, demos, own, unit)
    return candidates, quadratic_features(*candidates[0]) if curved else None


def _canonical(est, demos, frames) -> dict:
    """The poses the frames' statistics are computed at (see :func:`frame_mixer`)."""
    return {
        name: pose if pose.size == 7 else est.task_frames_[name][demos].mean(axis=0)
        for name, pose in frames.items()
    }


def _statistics(est, demos, frames, found, k, unit, physical, grid_warp):
    """What :func:`frame_mixer` learns on the grid: per hand and per regression.

    Returns
    -------
    stats : tuple of (list, list)
        Per hand :func:`_hand_stats`; per regression ``(part, slopes)``: its
        index in :func:`_slope_parts` and its
        :class:`~ndlfd.learner._frame_slopes.Slopes`, smoothed along the grid.
    """
    grid = np.linspace(0.0, 1.0, _GRID)
    half = round(FRAME_SMOOTH * (_GRID - 1))
    Wg, wg = grid_warp()
    # the frames' statistics from every template alike: a sample's random
    # blend weights (or a condition's) weigh the blend, not what the frames say
    wg = np.full(wg.size, 1.0 / wg.size)
    Xg = physical(Wg)
    maps = _views(est, demos, frames, k, unit) if found else []
    per_hand, combines = [], []
    for h in found:  # each hand from the views of the frames that may move it
        own = [
            m
            for m, f in zip(maps, frames, strict=True)
            if frame_allowed(est, f, h.name)
        ]
        per_hand.append(_hand_stats(h, own, Xg, wg, half, FRAME_FLOOR**2))
        combines.append(_hand_combine(h, own, per_hand[-1], grid))
    # the slopes on the origins, on the grid, smoothed: per row they carry the
    # templates' noise, amplified where the new origins lie far out
    Cg = Xg.copy()
    for combine in combines:
        combine(Xg, Cg, grid)
    regressions = []
    parts = _slope_parts(est, est.column_groups_, found, frames)
    for i, (moved, scored, own) in enumerate(parts):
        candidates, squares = _features(est, demos, own, unit, not found)
        fit = frame_slopes(
            Cg[:, :, moved],
            wg,
            [F for F, _ in candidates],
            scored,
            curved=None if squares is None else squares[0],
        )
        if fit is not None:
            regressions.append((i, fit._replace(B=_smooth_along(fit.B, half))))
    return per_hand, regressions


def frame_mixer(
    est, templates: np.ndarray, frames: Mapping, warp, grid_warp=None, memo=None
):
    """The step that combines the templates' frame views (see the module).

    Each hand (a position group, with its velocity and orientation:
    :func:`ndlfd._pose_groups.hands`) is combined on its own: its views'
    product decides, phase by phase, which frame holds that hand. A model
    without a hand (joint space) has no views; its templates are moved along
    the slopes alone (:func:`~ndlfd.learner._frame_slopes.frame_slopes`,
    every column but a gripper's), as a contextual ProMP conditions its
    weights on a context.

    The weights of the views (which of a frame's two views, and each view's
    share of the product) are computed on a fixed phase grid of
    :data:`_GRID` points and smoothed along it (:data:`FRAME_SMOOTH`), so
    they change gently with the phase and the same at any set of rows.
    Neither they nor the slopes depend on where a frame without an
    orientation moved to: its view of template ``j`` is ``x_j + (new -
    old_j)``, whose spread about the templates' mean is the same for any
    ``new``, and the combined templates' deviations from their mean, which
    the slopes regress, likewise. So they are computed at the templates'
    mean pose of such a frame (the same numbers whatever pose comes first)
    and kept by ``memo`` for every new pose of it; a frame with an
    orientation turns its views, and its pose is part of them.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with task frames.
    templates : ndarray of int
        The blended templates (indices into ``est.template_indices_``), in
        the blend's order.
    frames : mapping of str to ndarray
        Checked new poses (:func:`~ndlfd.learner._frames.check_new_frames`).
    warp : callable
        ``warp(tq) -> (W, w)``: the templates time-warped to phases ``tq``
        and their weights (:func:`~ndlfd.learner._blend.warped`).
    grid_warp : callable, optional
        ``grid_warp() -> (W, w)``: ``warp`` on the phase grid (the same for
        any frames: a replanning robot's plan pays it once).
    memo : callable, optional
        ``memo(build) -> stats``: keeps the grid's statistics (``build()``)
        for the frames' key (:func:`frame_parts`).

    Returns
    -------
    mix : callable
        ``mix(W, w, tq) -> W``: time-warped templates of shape
        ``(n_templates, n_out, n_dims)`` (normalized, unweighted) at phases
        ``tq``, and their weights, to the combined templates.
    """
    groups = est.column_groups_
    found = hands(groups)
    pos = [j for h in found for j in h.position]
    k = len(found[0].position) if found else None
    demos = est.template_indices_[np.asarray(templates, dtype=np.int64)]
    scaler = est.scaler_
    # positions in units of their range: the views' squares stay in float64
    # whatever the data's magnitude (1e-200 underflowed, 1e200 overflowed)
    unit = 1.0
    if pos:
        unit = float(np.max(scaler.data_max_[pos] - scaler.data_min_[pos]))
        unit = unit if np.isfinite(unit) and unit > 0 else 1.0

    def physical(W):
        n_t, n_out, d = W.shape
        X = scaler.inverse_transform(W.reshape(-1, d), weighted=False)
        X = X.reshape(n_t, n_out, d)
        X[:, :, pos] /= unit
        return X

    grid = np.linspace(0.0, 1.0, _GRID)

    def build():
        at = _canonical(est, demos, frames)
        gw = grid_warp if grid_warp is not None else (lambda: warp(grid))
        return _statistics(est, demos, at, found, k, unit, physical, gw)

    per_hand, regressions = build() if memo is None else memo(build)
    maps = _views(est, demos, frames, k, unit) if found else []
    mixers = [
        _hand_combine(
            h,
            [
                m
                for m, f in zip(maps, frames, strict=True)
                if frame_allowed(est, f, h.name)
            ],
            stats,
            grid,
        )
        for h, stats in zip(found, per_hand, strict=True)
    ]
    slopes = []  # (columns, dz, B) of each regression, at the new poses
    parts = _slope_parts(est, groups, found, frames)
    for i, fit in regressions:
        moved, _, own = parts[i]
        candidates, squares = _features(est, demos, own, unit, not found)
        f_new = squares[1] if fit.which < 0 else candidates[fit.which][1]
        slopes.append((moved, fit.dz(f_new), fit.B))
    if not slopes and not found:
        warnings.warn(
            f"this model learned no relation between its task frames"
            f" ({', '.join(frames)}) and its path: it has no hand (position"
            " group) to move, and its demonstrations' frames did not vary (or"
            " were fewer than 3); the path is generated as without frames",
            NdlfdWarning,
            stacklevel=5,
        )
    quats = [h.orientation for h in found if h.orientation]

    def mix(W: np.ndarray, w: np.ndarray, tq: np.ndarray) -> np.ndarray:
        tq = np.asarray(tq, dtype=np.float64)
        X = physical(W)
        out = X.copy()
        for combine in mixers:
            combine(X, out, tq)
        for moved, dz, B in slopes:
            Bq = np.moveaxis(_interp(tq, grid, np.moveaxis(B, 1, 0)), 0, 1)
            out[:, :, moved] -= np.tensordot(dz, Bq, axes=1)
        for quat in quats:
            Q = out[:, :, quat]
            Q /= np.maximum(np.linalg.norm(Q, axis=-1, keepdims=True), 1e-300)
            out[:, :, quat] = Q
        out[:, :, pos] *= unit
        U = scaler.transform(out.reshape(-1, out.shape[2]), weighted=False)
        return U.reshape(out.shape)

    return mix


def frame_parts(est, plan, frames, quat_cols, cache):
    """The templates' alignment and the frames' step of a plan's blend.

    Without frames, the plan's own alignment and no step. With frames, the
    templates on their own clocks
    (:func:`~ndlfd.learner._frames.clock_aligned`) and :func:`frame_mixer`'s
    step, kept in the model's cache for a decoded plan (a replanning robot
    with the same frames pays it once per route; a sample's drawn plan, of
    log-probability NaN, is not kept), and its statistics kept for every new
    pose of a frame without an orientation (a new object each call pays
    the combination only).

    Returns
    -------
    index : list of ndarray
    mix : callable or None
    """
    if frames is None:
        return plan.index, None
    index = clock_aligned(plan.taus, plan.knots)
    templates = (plan.values, plan.taus, index, plan.weights, plan.knots)

    def warp(p):
        return warped(*templates, p, quat_cols=quat_cols)

    if not np.isfinite(plan.logp) or not hasattr(cache, "memo"):
        return index, frame_mixer(est, plan.templates, frames, warp)
    plan_key = (plan.knots.tobytes(), np.asarray(plan.templates).tobytes())

    def grid_warp():
        grid = np.linspace(0.0, 1.0, _GRID)
        return cache.memo(("frame grid", *plan_key), lambda: warp(grid))

    # the statistics' key: a turning frame's pose is part of them (see
    # frame_mixer), a moving one's is not
    turning = tuple((k, v.tobytes() if v.size == 7 else b"") for k, v in frames.items())

    def memo(build):
        return cache.memo(("frame stats", *plan_key, turning), build)

    def make():
        return frame_mixer(est, plan.templates, frames, warp, grid_warp, memo)

    key = ("frames", *plan_key, tuple((k, v.tobytes()) for k, v in frames.items()))
    return index, cache.memo(key, make)
