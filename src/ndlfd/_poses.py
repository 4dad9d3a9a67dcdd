"""Task frames: named poses a demonstration carries, checked, and the maps between them.

A *task frame* is a pose constant over a demonstration (where the object or
the place was): a position of the position group's dimension, in 3-D
optionally followed by a unit quaternion ``(w, x, y, z)`` (the frame's
orientation). A frame without a quaternion is a translation only.

What was demonstrated relative to a frame is carried to a new pose of that
frame by the rigid map ``x -> A x + b`` with ``A = R_new R_old^T`` and ``b =
o_new - A o_old`` (:func:`frame_maps`); an orientation turns by the same
rotation. Rotations go through scipy's
:class:`~scipy.spatial.transform.Rotation`.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping

import numpy as np

from ._errors import ValidationError
from ._validation import as_float_array

__all__ = [
    "NO_FRAMES",
    "Frames",
    "check_frame_name",
    "check_frames",
    "frame_maps",
    "pose_size_ok",
]


class Frames(Mapping):
    """A read-only mapping of frame name to read-only pose (picklable)."""

    __slots__ = ("_poses",)

    def __init__(self, poses: dict) -> None:
        self._poses = dict(poses)

    def __getitem__(self, name: str) -> np.ndarray:
        return self._poses[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._poses)

    def __len__(self) -> int:
        return len(self._poses)

    def __repr__(self) -> str:
        return f"Frames({self._poses!r})"

    def __reduce__(self):
        return (_frames_of, (list(self._poses.items()),))


def _frames_of(items) -> Frames:
    out = {}
    for name, pose in items:
        p = np.array(pose, dtype=np.float64)
        p.flags.writeable = False
        out[name] = p
    return Frames(out)


#: The frames of a demonstration that has none.
NO_FRAMES: Mapping = Frames({})

_FRAME_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")


def check_frame_name(name, what: str) -> str:
    """A frame's name, checked: letters, digits, ``_`` and ``-``, not a digit first.

    Examples
    --------
    >>> check_frame_name("object", "frames")
    'object'
    """
    if not isinstance(name, str) or not _FRAME_NAME.match(name):
        raise ValidationError(
            f"{what}: a frame's name must be made of letters, digits, '_' and"
            f" '-' (starting with a letter or '_'); got {name!r}"
        )
    return name


def pose_size_ok(size: int, position_dims: int | None) -> bool:
    """Whether a pose of ``size`` values fits positions of ``position_dims``.

    Without a position group (``None``: a joint-space model) a frame is a
    pose in the plane or in space: 2, 3 or 7 values.
    """
    if position_dims is None:
        return size in (2, 3, 7)
    return size == position_dims or (position_dims == 3 and size == 7)


def _expected(position_dims: int | None) -> str:
    if position_dims is None:
        return "2 values (x, y), 3 (x, y, z) or 7 (x, y, z, then a unit quaternion)"
    if position_dims == 3:
        return "3 values (x, y, z) or 7 (x, y, z, then a unit quaternion w, x, y, z)"
    return f"{position_dims} values (a position of the position group's dimension)"


def check_frames(frames, position_dims, *, what: str = "frames") -> Mapping:
    """Checked task frames: a read-only mapping of name to a read-only pose.

    Parameters
    ----------
    frames : mapping of str to array-like of shape (k,) or (k + 4,), or None
        Each frame's pose: a position (``k`` values, the position group's
        dimension), in 3-D optionally followed by a unit quaternion
        ``(w, x, y, z)``.
    position_dims : int or None
        Columns of the position group (``None``: no position group, as in
        joint space: a frame is then any pose of 2, 3 or 7 values).
    what : str, default="frames"
        The argument's name, used in messages.

    Returns
    -------
    frames : mapping of str to ndarray
        In the given order; quaternions normalized with ``w >= 0``.

    Raises
    ------
    ValidationError
        Not a mapping, a bad name, a pose of the wrong size, a non-finite
        value, or a quaternion far from unit length.

    Examples
    --------
    >>> f = check_frames({"object": [0.5, 0.0, 0.02, 1, 0, 0, 0]}, 3)
    >>> list(f), f["object"].shape
    (['object'], (7,))
    """
    if frames is None:
        return NO_FRAMES
    if not isinstance(frames, Mapping):
        raise ValidationError(
            f"{what} must be a mapping of frame name to pose, e.g."
            f" {{'object': [x, y, z]}}; got {type(frames).__name__}"
        )
    if not frames:
        return NO_FRAMES
    out = {}
    for name, pose in frames.items():
        check_frame_name(name, what)
        p = np.array(as_float_array(pose, f"{what}[{name!r}]"), dtype=np.float64)
        if p.ndim != 1 or not pose_size_ok(p.size, position_dims):
            raise ValidationError(
                f"{what}[{name!r}] must hold {_expected(position_dims)}; got an"
                f" array of shape {p.shape}"
            )
        if not np.all(np.isfinite(p)):
            raise ValidationError(f"{what}[{name!r}] must be finite; got {p.tolist()}")
        if p.size == 7:
            norm = float(np.linalg.norm(p[3:]))
            if abs(norm - 1.0) > 1e-3:
                raise ValidationError(
                    f"{what}[{name!r}]: the quaternion (w, x, y, z) = {p[3:].tolist()}"
                    f" must have unit length; got length {norm:.6g}"
                )
            p[3:] /= norm
            if p[3] < 0:
                p[3:] *= -1.0
        p.flags.writeable = False
        out[name] = p
    return Frames(out)


def _rotations(poses: np.ndarray):
    from scipy.spatial.transform import Rotation

    q = poses[:, 3:7]
    return Rotation.from_quat(q[:, [1, 2, 3, 0]])  # scipy is scalar-last


def frame_maps(old: np.ndarray, new: np.ndarray, position_dims: int):
    """The rigid maps that carry poses relative to ``old`` frames to ``new``.

    Parameters
    ----------
    old : ndarray of shape (n, size)
        One frame's pose in each of ``n`` demonstrations.
    new : ndarray of shape (size,)
        The frame's new pose.
    position_dims : int

    Returns
    -------
    A : ndarray of shape (n, k, k)
        The rotations ``R_new R_old^T`` (the identity for a translation).
    b : ndarray of shape (n, k)
        ``o_new - A o_old``.
    dq : ndarray of shape (n, 4) or None
        The rotations as unit quaternions ``(w, x, y, z)`` (``None`` for a
        translation).

    Examples
    --------
    A frame moved by (1, 2): a point 0.5 from the old frame is 0.5 from the
    new one.

    >>> A, b, dq = frame_maps(np.array([[0.0, 0.0]]), np.array([1.0, 2.0]), 2)
    >>> A[0] @ np.array([0.5, 0.0]) + b[0]
    array([1.5, 2. ])
    """
    k = position_dims
    old = np.asarray(old, dtype=np.float64)
    new = np.asarray(new, dtype=np.float64)
    n = old.shape[0]
    if old.shape[1] == k:
        A = np.broadcast_to(np.eye(k), (n, k, k)).copy()
        dq = None
    else:
        delta = _rotations(new[None]) * _rotations(old).inv()
        A = delta.as_matrix()
        dq = delta.as_quat()[:, [3, 0, 1, 2]]
    b = new[None, :k] - np.einsum("nij,nj->ni", A, old[:, :k])
    return A, b, dq
