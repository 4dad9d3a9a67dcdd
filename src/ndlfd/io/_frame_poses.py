"""Task frames read with a recording: a pose that stays still over a demonstration.

A task frame (:attr:`~ndlfd.Demonstration.frames`) is one pose per
demonstration: where the object or the place was. A ROS 2 bag records it as a
topic or a tf frame (:mod:`ndlfd.io._bag_frames`), a LeRobot dataset as a
feature (a vector per row, :func:`feature_frame_poses`). Either gives many
samples of the pose over the demonstration; :func:`still_pose` checks that they
stay within :data:`FRAME_TOLERANCE` (position) and
:data:`FRAME_ANGLE_TOLERANCE` (orientation) of the first, so that an object
that moved during the recording is an error saying how far, and returns their
mean (the quaternions' sign-aligned, normalized mean).

Poses are ``(position...)`` or, in 3-D, ``(x, y, z, qw, qx, qy, qz)`` with the
quaternion scalar first, as :class:`~ndlfd.Demonstration` takes them.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._errors import DataFileError, ValidationError
from .._poses import check_frame_name, pose_size_ok

__all__ = [
    "FRAME_ANGLE_TOLERANCE",
    "FRAME_TOLERANCE",
    "check_frame_sources",
    "feature_frame_poses",
    "frame_flag",
    "sized_pose",
    "still_pose",
]

#: How far a task frame's position may move over a demonstration, in the
#: position's units (metres in a ROS bag): sensor noise, not a moved object.
FRAME_TOLERANCE = 0.005
#: How far its orientation may turn over a demonstration, in degrees.
FRAME_ANGLE_TOLERANCE = 3.0


def frame_flag(how: Mapping[str, str], name: str) -> str:
    """How messages name frame ``name``: the flag or the parameter.

    Examples
    --------
    >>> frame_flag({"groups": "--group"}, "object")
    '--task-frame object'
    >>> frame_flag({"groups": "groups="}, "object")
    "frames['object']"
    """
    if how.get("groups", "").startswith("--"):
        return f"--task-frame {name}"
    return f"frames[{name!r}]"


def check_frame_sources(frames, what: str, example: str) -> dict[str, str] | None:
    """``frames`` checked: a mapping of frame name to where it is read from.

    Parameters
    ----------
    frames : mapping of str to str, or None
    what : str
        What it is, for messages (``"frames of a bag"``).
    example : str
        A valid mapping, for messages.

    Returns
    -------
    frames : dict of str to str, or None
        ``None`` for no frames.

    Examples
    --------
    >>> check_frame_sources({"object": "/object_pose"}, "frames", "")
    {'object': '/object_pose'}
    """
    if frames is None:
        return None
    if not isinstance(frames, Mapping):
        raise ValidationError(
            f"{what} must be a mapping of frame name to source, e.g. {example};"
            f" got {type(frames).__name__}"
        )
    out = {}
    for name, source in frames.items():
        check_frame_name(name, what)
        if not isinstance(source, str) or not source.strip():
            raise ValidationError(
                f"{what}[{name!r}] must name where the frame is read from, e.g."
                f" {example}; got {source!r}"
            )
        out[name] = source.strip()
    return out or None


def sized_pose(values: np.ndarray, dims, where: str, what: str) -> np.ndarray:
    """``values`` (n, k) checked against a position group of ``dims`` columns.

    Without a position group (``dims`` 0 or ``None``: a joint-space model) a
    frame is a pose in the plane or in space: 2, 3 or 7 values.
    """
    k = values.shape[1]
    if pose_size_ok(k, dims or None):
        return values
    if not dims:
        raise DataFileError(
            f"{where}: {what} has {k} value(s); expected 2 (x, y), 3 (x, y, z)"
            " or 7 (x, y, z, then a unit quaternion qw, qx, qy, qz)"
        )
    seven = " or 7 (x, y, z, then a unit quaternion qw, qx, qy, qz)"
    raise DataFileError(
        f"{where}: {what} has {k} value(s); expected {dims} (a position, as the"
        f" demonstration's position group){seven if dims == 3 else ''}"
    )


def _at(t, i: int) -> str:
    return "" if t is None else f" at {float(t[i]):.3f} s"


def still_pose(values, where: str, what: str, t=None, unit: str = "") -> np.ndarray:
    """The pose a task frame keeps over a demonstration: the samples' mean.

    Parameters
    ----------
    values : array-like of shape (n, k)
        The frame's samples: a position, or ``x, y, z, qw, qx, qy, qz``.
    where, what : str
        The file (and piece) and the frame, for messages.
    t : array-like of shape (n,), optional
        The samples' times in seconds from the demonstration's start, for
        messages.
    unit : str, optional
        The position's unit, for messages (``" m"``).

    Returns
    -------
    pose : ndarray of shape (k,)

    Raises
    ------
    DataFileError
        A value that is not finite, a zero quaternion, or a frame that moved
        more than :data:`FRAME_TOLERANCE` or turned more than
        :data:`FRAME_ANGLE_TOLERANCE` degrees from its first sample.

    Examples
    --------
    >>> still_pose([[1.0, 2.0, 3.0], [1.002, 2.0, 3.0]], "a", "f").round(6)
    array([1.001, 2.   , 3.   ])
    """
    v = np.asarray(values, dtype=np.float64)
    bad = np.flatnonzero(~np.all(np.isfinite(v), axis=1))
    if bad.size:
        i = int(bad[0])
        raise DataFileError(
            f"{where}: {what} must be finite numbers; got {v[i].tolist()}{_at(t, i)}"
        )
    quat = v.shape[1] == 7
    pos = v[:, :3] if quat else v
    moved = np.linalg.norm(pos - pos[0], axis=1)
    i = int(np.argmax(moved))
    if moved[i] > FRAME_TOLERANCE:
        raise DataFileError(
            f"{where}: {what} must stay still during the demonstration (a task"
            f" frame is one pose per demonstration, within {FRAME_TOLERANCE:g}"
            f"{unit}); it moved {moved[i]:.4g}{unit}, from"
            f" {np.round(pos[0], 4).tolist()}{_at(t, 0)} to"
            f" {np.round(pos[i], 4).tolist()}{_at(t, i)}"
        )
    out = pos.mean(axis=0)
    if not quat:
        return out
    q = v[:, 3:]
    norms = np.linalg.norm(q, axis=1)
    if np.any(norms < 1e-9):
        i = int(np.argmin(norms))
        raise DataFileError(
            f"{where}: {what}: expected a unit quaternion (w, x, y, z); got"
            f" {q[i].tolist()}{_at(t, i)}"
        )
    q = q / norms[:, None]
    q = q * np.where(q @ q[0] < 0, -1.0, 1.0)[:, None]  # q and -q: one turn
    turned = np.degrees(2 * np.arccos(np.clip(np.abs(q @ q[0]), 0.0, 1.0)))
    i = int(np.argmax(turned))
    if turned[i] > FRAME_ANGLE_TOLERANCE:
        raise DataFileError(
            f"{where}: {what} must stay still during the demonstration (a task"
            f" frame is one pose per demonstration, within"
            f" {FRAME_ANGLE_TOLERANCE:g} degrees); it turned {turned[i]:.3g}"
            f" degrees, from its pose{_at(t, 0) or ' first'} to its pose"
            f"{_at(t, i) or f' {i}'}"
        )
    mean = q.mean(axis=0)
    mean /= np.linalg.norm(mean)
    return np.concatenate([out, mean * (1.0 if mean[0] >= 0 else -1.0)])


def _feature_rows(column, feature: str, where) -> np.ndarray:
    """A feature's Parquet column as an (n, k) array, ``k`` from its lists."""
    import pyarrow as pa
    import pyarrow.compute as pc

    col = column.combine_chunks() if hasattr(column, "combine_chunks") else column
    n = len(col)
    if col.null_count:
        row = int(np.flatnonzero(np.asarray(col.is_null()))[0])
        raise DataFileError(
            f"{where}: feature {feature!r} is empty (null) at row {row}"
        )
    if not (
        pa.types.is_list(col.type)
        or pa.types.is_large_list(col.type)
        or pa.types.is_fixed_size_list(col.type)
    ):
        return col.to_numpy(zero_copy_only=False).astype(np.float64).reshape(n, 1)
    lengths = np.asarray(pc.list_value_length(col))
    if n and np.any(lengths != lengths[0]):
        row = int(np.flatnonzero(lengths != lengths[0])[0])
        raise DataFileError(
            f"{where}: feature {feature!r} has {int(lengths[row])} values at row"
            f" {row} and {int(lengths[0])} at row 0; expected the same every row"
        )
    k = int(lengths[0]) if n else 0
    flat = col.flatten().to_numpy(zero_copy_only=False).astype(np.float64)
    return flat.reshape(n, k)


def feature_frame_poses(item, table, frames: dict, dims: int, how) -> dict:
    """Each frame's pose from its feature's rows of one LeRobot episode.

    Parameters
    ----------
    item : LeRobotEpisode
        The episode, for messages.
    table : pyarrow.Table
        Its rows, with ``timestamp`` and the frames' features.
    frames : dict of str to str
        Each frame's feature.
    dims : int
        The position group's columns.
    how : dict
        How messages name the settings.

    Returns
    -------
    poses : dict of str to ndarray
    """
    t = table.column("timestamp").to_numpy().astype(np.float64)
    out = {}
    for name, feature in frames.items():
        what = f"{frame_flag(how, name)} (feature {feature})"
        rows = _feature_rows(table.column(feature), feature, item)
        rows = sized_pose(rows, dims, str(item), what)
        out[name] = still_pose(rows, str(item), what, t - t[0])
    return out
