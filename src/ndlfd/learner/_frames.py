"""Task frames: what a model learns of them and the checks of new poses.

A demonstration may carry task frames (:class:`~ndlfd.Demonstration`'s
``frames``: where the object and the place were). This module checks the
frames a model learned (:func:`check_learned_frames`, which hands each may
move: :func:`check_frame_hands`) and new poses given to ``generate``
(:func:`check_new_frames`), takes the templates on their own clocks
(:func:`clock_aligned`) and multiplies quaternions (:func:`quat_multiply`).
How the templates are combined from the frames' views is
:mod:`ndlfd.learner._frame_mix`.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._errors import NdlfdWarning, ValidationError
from .._pose_groups import (
    frame_hands_problem,
    hand_label,
    hand_labels,
    hands,
    pose_dims,
    position_columns,
)
from .._poses import check_frames

__all__ = [
    "FRAME_FLOOR",
    "check_frame_hands",
    "check_learned_frames",
    "check_new_frames",
    "clock_aligned",
    "frame_allowed",
    "quat_multiply",
    "split_frames",
]

# With task frames, a start, goal, via point or executed prefix chooses the
# route only, and every template on it weighs the same in the blend
# (``make_plan(even=)``), and the frames' spreads and slopes are estimated
# with even weights (a sample's Dirichlet weights weigh its blend only). The
# conditions' kernel weights favour the demonstrations that started (or
# passed) near, which left few templates to estimate from: on
# ``synth.pick_place`` turned by up to 60 deg (demonstration 0 held out,
# ``random_state=2``) the largest distance to the held-out demonstration was
# 0.0905 m given its first 100 samples as a prefix and 0.0311 given its grasp
# as a via point; 0.0221 and 0.0206 with even weights (the frames alone:
# 0.0233); DTW/range given a start unchanged (0.0011, 0.0024).

#: Floor of a view's spread: its square (in units of the positions' range,
#: squared) is added to every covariance, and (radians squared) to the
#: angular spread of orientation, so views in which the templates coincide
#: exactly still combine (no singular covariance).
FRAME_FLOOR = 1e-3


def split_frames(values: np.ndarray, spec) -> dict:
    """The fit statistics' frame poses by name.

    Parameters
    ----------
    values : ndarray of shape (n_demos, n_frame_values)
        Every demonstration's frames, one after another.
    spec : tuple of (str, int)
        Their names and pose sizes.

    Returns
    -------
    frames : dict of str to ndarray of shape (n_demos, size)
        Read-only.
    """
    out, at = {}, 0
    for name, size in spec:
        a = np.array(values[:, at : at + size], dtype=np.float64)
        a.flags.writeable = False
        out[name] = a
        at += size
    return out


#: How far a new frame may lie from the demonstrations' frames, in ranges of
#: the positions: farther, the views' squares leave float64 (a frame at 1e150
#: m overflowed); a pose that far is a unit or typing mistake.
_FAR = 1e6


#: How far the demonstrations' frames may lie from their positions (in
#: ranges of the positions) before a fit warns: an object 10 workspaces away
#: is most likely in other units (millimetres against metres).
_WORKSPACES = 10.0


def check_learned_frames(est) -> None:
    """Warn when a learned frame's origins lie far outside the positions.

    One :class:`~ndlfd.NdlfdWarning` per such frame, saying how far (in
    ranges of the positions) and asking for the units.
    """
    frames = getattr(est, "task_frames_", None)
    if not frames:
        return
    scaler = est.scaler_
    found = hands(est.column_groups_)
    if not found:  # a joint-space model: no positions to compare with
        return
    k = len(found[0].position)
    pos = position_columns(est.column_groups_)
    lo = scaler.data_min_[pos].reshape(-1, k).min(axis=0)
    hi = scaler.data_max_[pos].reshape(-1, k).max(axis=0)
    span = float(np.max(hi - lo))
    if not span > 0:
        return
    for name, poses in frames.items():
        outside = np.maximum(lo - poses[:, :k], poses[:, :k] - hi)
        far = float(np.max(outside, initial=0.0)) / span
        if far > _WORKSPACES:
            warnings.warn(
                f"task frame {name!r}: its origins lie up to {far:.3g} times the"
                f" positions' range ({span:.3g}) outside the positions; are they"
                " in the same units (and frame) as the positions?",
                NdlfdWarning,
                stacklevel=3,
            )


def check_frame_hands(est) -> None:
    """Check ``frame_hands`` against the learned frames and hands (after fit).

    Raises
    ------
    ValidationError
        A frame the demonstrations did not carry, or a hand the model has not.
    """
    frames = est.task_frames_
    problem = frame_hands_problem(getattr(est, "frame_hands", None), frames,
                                  est.column_groups_)  # fmt: skip
    if problem is None:
        return
    name, hand = problem
    if hand is None:
        raise ValidationError(
            f"frame_hands names the frame {name!r}, which the demonstrations"
            f" did not carry; their frames: {', '.join(frames) or 'none'}"
        )
    labels = hand_labels(est.column_groups_)
    raise ValidationError(
        f"frame_hands[{name!r}] names the hand {hand_label(hand)!r}; this model's"
        f" hands are {', '.join(map(repr, labels)) or 'none'}"
        " (a hand is a position group: position, <hand>_position)"
    )


def frame_allowed(est, frame: str, hand: str) -> bool:
    """Whether ``frame`` may move ``hand`` (``frame_hands``; default: yes)."""
    fh = getattr(est, "frame_hands", None)
    if not fh or frame not in fh:
        return True
    return hand_label(hand) in {hand_label(h) for h in fh[frame]}


def check_new_frames(est, frames) -> dict | None:
    """New poses of the model's task frames, checked (``None``: none given).

    Frames the model learned but not given are left out of the product (as if
    the demonstrations had not had them).
    """
    if frames is None:
        return None
    learned = est.task_frames_
    got = check_frames(frames, pose_dims(est.column_groups_), what="frames")
    if not got:
        return None
    if not learned:
        raise ValidationError(
            f"frames {list(got)} were given, but this model learned no task frames"
            " (its demonstrations carried none: Demonstration.from_arrays(...,"
            " frames=...) or --task-frame when fitting)"
        )
    unknown = [k for k in got if k not in learned]
    if unknown:
        raise ValidationError(
            f"unknown task frame {unknown[0]!r}; this model learned"
            f" {', '.join(repr(k) for k in learned)}"
        )
    for name, pose in got.items():
        size = learned[name].shape[1]
        k = 3 if size == 7 else size
        origins = learned[name][:, :k]
        span, what = _span(est, origins)
        gap = pose[:k] - origins.mean(axis=0)
        top = float(np.max(np.abs(gap), initial=0.0))  # no overflow in squares
        far = top * float(np.linalg.norm(gap / top)) if top > 0 else 0.0
        if pose.size == size and not far <= _FAR * span:
            raise ValidationError(
                f"frames[{name!r}] at {pose[:k].tolist()} lies {far:.3g}"
                f" from where the demonstrations' {name!r} frames were (their"
                f" mean {origins.mean(axis=0).round(6).tolist()}); expected within"
                f" {_FAR:g} times {what} ({span:.3g}): same units?"
            )
        if pose.size != size:
            kind = (
                "position and unit quaternion (w, x, y, z)" if size == 7 else "position"
            )
            raise ValidationError(
                f"frames[{name!r}] must hold {size} values ({kind}), as the"
                f" demonstrations' did; got {pose.size}"
            )
    return dict(got)


def _span(est, origins) -> tuple[float, str]:
    """The scale a new frame's distance is judged in, and its name.

    The hands' positions' range; without a hand (joint space), the
    demonstrations' frame origins' range (at least 1e-300).
    """
    pos = position_columns(est.column_groups_)
    if pos:
        lo, hi = est.scaler_.data_min_[pos], est.scaler_.data_max_[pos]
        return max(float(np.max(hi - lo)), 1e-300), "the positions' range"
    spread = float(np.max(origins.max(axis=0) - origins.min(axis=0), initial=0.0))
    scale = float(np.max(np.abs(origins), initial=0.0))
    return max(spread, scale, 1e-300), "the demonstrations' frames' range"


def clock_aligned(taus, knots) -> list:
    """Each template's samples at the skeleton's knots on its own clock.

    With task frames the templates are matched to the skeleton by time, not
    by place: the skeleton is decoded where the demonstrations were (the
    world), and matching a template whose object lay elsewhere by place
    pulls its phase toward the skeleton's. Measured on ``synth.pick_place``
    leave-one-out (``benchmarks/probe_task_frames.py``): DTW/range 0.0016
    and 0.0024 (translated, turned by up to 60 deg) matched by place, 0.0011
    and 0.0021 by time (ProMP given the start, the grasp and the goal:
    0.0013). Demonstrations of different pace are then blended as the plain
    time-normalized mean blends them.

    Parameters
    ----------
    taus : list of ndarray of shape (n_j,)
        The templates' normalized times (0 to 1).
    knots : ndarray of shape (n_keys,)
        Normalized skeleton times (0 to 1).

    Returns
    -------
    index : list of ndarray of shape (n_keys,), dtype int64
        Non-decreasing, the first 0 and the last ``n_j - 1``.

    Examples
    --------
    >>> clock_aligned([np.linspace(0.0, 1.0, 5)], np.array([0.0, 0.6, 1.0]))
    [array([0, 2, 4])]
    """
    out = []
    for tau in taus:
        i = np.clip(np.searchsorted(tau, knots), 1, tau.size - 1)
        i = np.where(knots - tau[i - 1] <= tau[i] - knots, i - 1, i)
        i[0], i[-1] = 0, tau.size - 1
        out.append(np.maximum.accumulate(i).astype(np.int64))
    return out


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of quaternions ``(w, x, y, z)`` (broadcast).

    Examples
    --------
    >>> i = np.array([0.0, 1.0, 0.0, 0.0])
    >>> quat_multiply(i, i)
    array([-1.,  0.,  0.,  0.])
    """
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )
