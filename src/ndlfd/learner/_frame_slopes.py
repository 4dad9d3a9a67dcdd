"""Task frames in generation: how the templates move with their frames' poses.

A ridge regression of every value of the templates on their frames'
origins (and turns; for a joint-space model also their squares), the
candidate features chosen by exact leave-one-out (a joint-space model's
squares by the templates' number): what
:func:`~ndlfd.learner._frame_mix.frame_mixer` moves each combined template
along, so that a part of the motion between two frames moves with both,
and a model without a hand moves with its frames at all.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "FRAME_RIDGE",
    "Slopes",
    "fit_slopes",
    "frame_features",
    "frame_slopes",
    "quadratic_features",
]

#: Ridge of the regression on the frames' origins, as a share of their
#: standardized variance. Leave-one-out on ``synth.pick_place`` (12
#: demonstrations, ``benchmarks/probe_task_frames.py``): 0.1 shrank every
#: template's correction by a tenth (DTW/range 0.0016 translated, 0.0040
#: turned); 1e-3 and 1e-4 gave 0.0016 and 0.0024.
FRAME_RIDGE = 1e-3

#: With fewer templates than this many per feature (plus two), the
#: regression is shrunk hard (ridge 1): it would otherwise fit their noise.
#: A model without a hand is shrunk only below one per feature (plus one:
#: the intercept), and takes its features' squares from this many per
#: feature on (see :func:`frame_slopes`).
_FEW = 2


def frame_features(est, demos, frames, unit: float) -> list:
    """Candidate regression features of the templates' frames, and the new values.

    The frames' origins; and, when a frame has an orientation, the origins
    and each such frame's turn from its new pose (a rotation vector). Which
    one the slopes use is chosen by leave-one-out (:func:`frame_slopes`): turns
    that do not move the hand fit noise (on ``synth.pick_place`` with a
    vertical approach, turned by up to 60 deg: DTW/range 0.0011 with the
    origins, 0.0020 with the turns too), turns that do are needed (the
    approach turned with the object: 0.0030 and 0.0025).

    Returns
    -------
    candidates : list of (ndarray of shape (n_templates, p), ndarray of shape (p,))
    """
    from scipy.spatial.transform import Rotation

    def k(pose):  # a frame's position: 2 or 3 values (7: then a quaternion)
        return 3 if pose.size == 7 else pose.size

    F = np.hstack(
        [est.task_frames_[n][demos][:, : k(p)] / unit for n, p in frames.items()]
    )
    f = np.concatenate([pose[: k(pose)] / unit for pose in frames.values()])
    out = [(F, f)]
    turns = []
    for name, pose in frames.items():
        if pose.size == 7:
            old = est.task_frames_[name][demos]
            ref = Rotation.from_quat(pose[[4, 5, 6, 3]])
            turns.append(
                (ref.inv() * Rotation.from_quat(old[:, [4, 5, 6, 3]])).as_rotvec()
            )
    if turns:
        out.append(
            (np.hstack([F, *turns]), np.concatenate([f, np.zeros(3 * len(turns))]))
        )
    return out


def _varying(F: np.ndarray, w: np.ndarray):
    """The weighted mean, spread and mask of the features that vary.

    A feature that does not vary is left out: its spread is rounding's (the
    weighted mean of equal values is not exactly their value), which
    standardized would be noise the slopes fit.
    """
    mf = w @ F
    Fc = F - mf
    sd = np.sqrt(w @ (Fc * Fc))
    ref = max(float(sd.max(initial=0.0)), float(np.abs(F).max(initial=0.0)))
    return mf, sd, sd > 1e-9 * max(ref, 1e-300)


def quadratic_features(F: np.ndarray, f: np.ndarray) -> tuple:
    """The features with their squares and products about the templates' mean.

    A joint-space model's angles are a curved function of a frame's origin
    (the inverse kinematics); a second-order term lets the slopes follow the
    curve where the templates span it. Measured on a planar 2-link arm
    reaching a target moved +-12 cm (reach 1 m; ``tests/hands_data.py``,
    30 demonstrations, 10 new targets): the tip's end error median 6.0 mm,
    largest 8.2 mm with the origins alone; see the test for the quadratic.
    """
    c = F.mean(axis=0)
    D, d = F - c, f - c
    i, j = np.triu_indices(F.shape[1])
    return np.hstack([F, D[:, i] * D[:, j]]), np.concatenate([f, d[i] * d[j]])


class Slopes(NamedTuple):
    """A regression of the templates' values on their frames' features.

    Attributes
    ----------
    Z : ndarray of shape (n_templates, p)
        The templates' standardized features (those that vary).
    B : ndarray of shape (p, n_out, c)
        The slopes.
    mean, scale : ndarray of shape (n_features,)
        The standardization (weighted mean and spread of each feature).
    keep : ndarray of shape (n_features,), dtype bool
        The features that vary.
    which : int
        The candidate chosen (its index; -1 for the curved features).
    """

    Z: np.ndarray
    B: np.ndarray
    mean: np.ndarray
    scale: np.ndarray
    keep: np.ndarray
    which: int

    def dz(self, f_new: np.ndarray) -> np.ndarray:
        """Each template's standardized features minus the new ones ``(n, p)``."""
        k = self.keep
        return self.Z - (f_new[k] - self.mean[k]) / self.scale[k]


def fit_slopes(Y, w, F, scored, *, few: int = _FEW, spare: int = 2, which: int = 0):
    """One candidate's regression (:func:`frame_slopes`) and its leave-one-out error.

    The error is over the columns ``scored`` of ``Y`` only (one unit: the
    position), each template's residual divided by ``1 - h_jj`` (the exact
    leave-one-out residual of a linear smoother), weighted by ``w``. With
    fewer than ``few`` templates per varying feature plus ``spare`` the ridge
    is 1 (:data:`_FEW`), else :data:`FRAME_RIDGE`. Nothing here depends on the
    frames' new poses: :meth:`Slopes.dz` takes them.

    Returns
    -------
    slopes : Slopes or None
        ``None``: no feature varies, or fewer than 3 templates.
    loo : float
    """
    mf, sd, keep = _varying(F, w)
    n_t = Y.shape[0]
    if not keep.any() or n_t < 3:
        return None, np.inf
    Z = (F[:, keep] - mf[keep]) / sd[keep]
    G = (Z.T * w) @ Z
    ridge = FRAME_RIDGE if n_t >= few * Z.shape[1] + spare else 1.0
    G += ridge * np.eye(G.shape[0])
    flat = Y.reshape(n_t, -1)
    D = flat - w @ flat
    B = np.linalg.solve(G, (Z.T * w) @ D)  # (p, n_out * c)
    h = w * np.einsum("jp,pq,jq->j", Z, np.linalg.inv(G), Z)
    E = (D - Z @ B).reshape(Y.shape)[:, :, scored]
    loo = E / np.maximum(1.0 - h, 1e-6)[:, None, None]
    slopes = Slopes(Z, B.reshape(-1, *Y.shape[1:]), mf, sd, keep, which)
    return slopes, float(w @ np.sum(loo**2, axis=(1, 2)))


def frame_slopes(Y, w, features, scored, *, curved=None):
    """How the templates' values move with their frames.

    The weighted ridge regression of every value of ``Y`` (n_templates,
    n_out, c) on standardized features, one slope per row and column, with
    the candidate features (``features``: each candidate's features of the
    templates, :func:`frame_features`) of least leave-one-out error on the
    columns ``scored``. Moving template ``j`` by ``-dz_j B``
    (:meth:`Slopes.dz` at the new frames' features) gives what its values
    would be had its frames been the new ones, as far as they vary linearly
    with them (a part of the motion between two frames moves with both,
    which no single frame's view gives).

    A model without a hand (joint space) passes its features' squares and
    products as ``curved`` (:func:`quadratic_features`): taken whenever there
    are :data:`_FEW` templates per varying feature (plus two), over the
    candidates, and the candidates shrunk only below one per feature (plus
    one, the intercept: the fewest that determine the slopes). Its
    angles are a curved function of the frames (the inverse kinematics),
    and leave-one-out over the whole path does not see where that matters:
    its error is the templates' timing, the same for any features, while a
    grasp at the edge of the objects' range needs the curve. Measured in
    ALOHA Transfer Cube (12 joints given the cube, ``ndlfd evaluate --tasks
    transfer-cube``, 200 held-out poses, N = 5 / 10 / 20 / 50
    demonstrations): success 0.14 / 0.15 / 0.87 / 0.86 chosen by
    leave-one-out and shrunk below two per feature, 0.65 / 0.85 / 1.00 / 1.00
    so; Insertion (two objects) 0.02 / 0.03 / 0.64 / 0.68 and 0.30 / 0.34 /
    0.64 / 0.81 (0.07 at N = 5 shrunk below one per feature plus two). Each
    arm moved on its own object only, chosen per joint by leave-one-out:
    0.07 / 0.18 / 0.38 / 0.29 (an arm's meeting pose depends on both held
    objects).

    Returns
    -------
    slopes : Slopes or None
        ``None``: no feature varies, or fewer than 3 templates.
    """
    if curved is not None:
        _, _, keep = _varying(curved, w)
        if Y.shape[0] >= _FEW * int(keep.sum()) + 2:
            return fit_slopes(Y, w, curved, scored, few=1, spare=1, which=-1)[0]
    few, spare = (_FEW, 2) if curved is None else (1, 1)
    fits = [
        fit_slopes(Y, w, F, scored, few=few, spare=spare, which=i)
        for i, F in enumerate(features)
    ]
    return min(fits, key=lambda fit: fit[1])[0]
