"""tf trees of ROS 2 bags: a frame's pose in a base frame, chains composed.

``robot_state_publisher`` publishes a robot's links as a tree of transforms:
the moving joints on ``/tf`` (``tf2_msgs/msg/TFMessage``), the fixed ones once,
latched, on ``/tf_static``. Each ``TransformStamped`` gives the pose of its
``child_frame_id`` in its ``header.frame_id`` (the parent). The pose of a frame
in a base frame is the product of the transforms along the path between them
in the tree, the way ``tf2``'s ``lookupTransform`` composes it:

* the **base** is the ``base_frame`` asked for, or by default the root of the
  frame's tree (the frame above which there is no parent);
* the path goes up from the frame and from the base to their lowest common
  ancestor; a transform on the base's side enters inverted;
* **static** transforms (those of the ``*tf_static`` topic) are constant (the
  last one published for a child counts);
* **dynamic** transforms are taken at the *reference stamps*: the stamps of the
  dynamic transform nearest the frame on the path (the frame's own transform
  when it moves). Every other dynamic transform is interpolated at those
  stamps: its translation linearly, its rotation by spherical linear
  interpolation (slerp), and held at its first or last value outside its span.
  Stamps are the header stamps, or the times the bag received the messages
  when a transform's stamps are unset (zero).

A path of static transforms only is a constant pose, not a demonstration: an
error says so. So do a frame that is not in the tree, a base that is not
connected to the frame (both list the frames found), a child with two
parents, and a loop.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .._errors import DataFileError

__all__ = ["TfEdge", "tf_edges", "tf_pose_at", "tf_pose_rows"]


@dataclass(frozen=True)
class TfEdge:
    """The transforms from one parent frame to one child frame.

    Attributes
    ----------
    parent, child : str
        The frames (``header.frame_id`` and ``child_frame_id``).
    static : bool
        From ``/tf_static``: one constant transform (the last published).
    stamps : ndarray of int64, shape (n,)
        Nanoseconds, sorted and unique (header stamps, or receive times when
        any stamp is unset).
    values : ndarray of shape (n, 7)
        ``x, y, z, qw, qx, qy, qz`` of the child in the parent at each stamp.
    """

    parent: str
    child: str
    static: bool
    stamps: np.ndarray
    values: np.ndarray

    def at(self, ns: np.ndarray) -> np.ndarray:
        """The transform at the times ``ns``: linear and slerp, held at the ends."""
        if self.static or self.stamps.size == 1:
            return np.tile(self.values[-1], (ns.size, 1))
        if ns.size == self.stamps.size and np.array_equal(ns, self.stamps):
            return self.values.copy()
        from scipy.spatial.transform import Rotation, Slerp

        x = (self.stamps - self.stamps[0]) / 1e9
        xi = np.clip((ns - self.stamps[0]) / 1e9, x[0], x[-1])
        out = np.empty((ns.size, 7))
        for j in range(3):
            out[:, j] = np.interp(xi, x, self.values[:, j])
        q = Rotation.from_quat(self.values[:, [4, 5, 6, 3]])
        r = Slerp(x, q)(xi).as_quat()
        out[:, 3], out[:, 4:] = r[:, 3], r[:, :3]
        return out


def tf_edges(
    where: str, transforms: Sequence[tuple], *, static: bool
) -> dict[str, TfEdge]:
    """The edges of a tree, by child frame, from the transforms read.

    Parameters
    ----------
    where : str
        What errors name (the bag).
    transforms : sequence of (parent, child, stamp ns, received ns, values)
        Every ``TransformStamped`` in the order read; ``values`` are ``x, y, z,
        qw, qx, qy, qz``.
    static : bool
        From ``/tf_static``.

    Returns
    -------
    edges : dict of str to TfEdge
    """
    by_child: dict[str, list] = {}
    for parent, child, stamp, received, values in transforms:
        by_child.setdefault(child, []).append((parent, stamp, received, values))
    edges = {}
    for child, rows in by_child.items():
        parents = sorted({r[0] for r in rows})
        if len(parents) > 1:
            raise DataFileError(
                f"{where}: frame {child!r} has several parents in the tf tree"
                f" ({', '.join(map(repr, parents))}); expected one"
            )
        if static:
            rows = rows[-1:]
        unset = any(r[1] == 0 for r in rows)
        stamps = np.array([r[2] if unset else r[1] for r in rows], dtype=np.int64)
        values = np.array([r[3] for r in rows], dtype=np.float64).reshape(-1, 7)
        order = np.argsort(stamps, kind="stable")
        stamps, values = stamps[order], values[order]
        keep = np.concatenate([[True], np.diff(stamps) > 0])
        edges[child] = TfEdge(parents[0], child, static, stamps[keep], values[keep])
    return edges


def _up(where: str, edges: dict[str, TfEdge], frame: str) -> list[TfEdge]:
    """The edges from ``frame`` up to the root of its tree, frame's first."""
    path: list[TfEdge] = []
    seen = {frame}
    while frame in edges:
        edge = edges[frame]
        path.append(edge)
        frame = edge.parent
        if frame in seen:
            loop = " -> ".join(e.child for e in path)
            raise DataFileError(
                f"{where}: the tf transforms make a loop ({loop} -> {frame});"
                " expected a tree"
            )
        seen.add(frame)
    return path


def _compose(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The transforms ``a * b`` (each row ``x, y, z, qw, qx, qy, qz``)."""
    from scipy.spatial.transform import Rotation

    ra = Rotation.from_quat(a[:, [4, 5, 6, 3]])
    rb = Rotation.from_quat(b[:, [4, 5, 6, 3]])
    out = np.empty_like(a)
    out[:, :3] = a[:, :3] + ra.apply(b[:, :3])
    q = (ra * rb).as_quat()
    out[:, 3], out[:, 4:] = q[:, 3], q[:, :3]
    return out


def _inverse(a: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    r = Rotation.from_quat(a[:, [4, 5, 6, 3]]).inv()
    out = np.empty_like(a)
    out[:, :3] = -r.apply(a[:, :3])
    q = r.as_quat()
    out[:, 3], out[:, 4:] = q[:, 3], q[:, :3]
    return out


def _identity(n: int) -> np.ndarray:
    out = np.zeros((n, 7))
    out[:, 3] = 1.0
    return out


def _path(where, edges, frame, base_frame, topics):
    """The base frame and the edges up from ``frame`` and from the base."""
    found = sorted({*edges, *(e.parent for e in edges.values())})
    listed = ", ".join(found) or "none"
    for name, what in ((frame, "frame"), (base_frame, "base frame")):
        if name is not None and name not in found:
            raise DataFileError(
                f"{where}: no {what} {name!r} in the tf tree of {topics}; the"
                f" frames found are {listed}"
            )
    up = _up(where, edges, frame)
    chain = [frame, *(e.parent for e in up)]
    base = chain[-1] if base_frame is None else base_frame
    down = _up(where, edges, base)
    above_base = [base, *(e.parent for e in down)]
    common = next((f for f in chain if f in above_base), None)
    if common is None:
        raise DataFileError(
            f"{where}: frame {frame!r} is not connected to the base frame"
            f" {base!r} in the tf tree of {topics} ({frame!r} goes up to"
            f" {chain[-1]!r}, {base!r} to {above_base[-1]!r}); the frames found"
            f" are {listed}"
        )
    up = up[: chain.index(common)]
    down = down[: above_base.index(common)]
    path = " -> ".join([*chain[: len(up) + 1], *reversed(above_base[: len(down)])])
    return base, up, down, path


def _composed(up, down, ns: np.ndarray) -> np.ndarray:
    pose = _identity(ns.size)
    for e in up:  # common -> ... -> frame: left to right from the top
        pose = _compose(e.at(ns), pose)
    for e in reversed(down):  # common -> ... -> base, inverted, on the left
        pose = _compose(_inverse(e.at(ns)), pose)
    return pose


def tf_pose_at(
    where: str,
    edges: dict[str, TfEdge],
    frame: str,
    base_frame: str | None,
    ns: np.ndarray,
    *,
    topics: str,
) -> tuple[str, np.ndarray]:
    """The pose of ``frame`` in the base frame at the times ``ns``.

    As :func:`tf_pose_rows`, but at given times (each moving transform
    interpolated there, held at its ends), and a path of static transforms
    only is allowed (a constant pose: a task frame's, say).

    Parameters
    ----------
    where, edges, frame, base_frame, topics
        As for :func:`tf_pose_rows`.
    ns : ndarray of int64, shape (n,)
        The times, nanoseconds.

    Returns
    -------
    base : str
        The base frame.
    values : ndarray of shape (n, 7)
        ``x, y, z, qw, qx, qy, qz`` of ``frame`` in ``base``.
    """
    base, up, down, _ = _path(where, edges, frame, base_frame, topics)
    return base, _composed(up, down, np.asarray(ns, dtype=np.int64))


def tf_pose_rows(
    where: str,
    edges: dict[str, TfEdge],
    frame: str,
    base_frame: str | None,
    *,
    topics: str,
) -> tuple[str, np.ndarray, np.ndarray]:
    """The pose of ``frame`` in the base frame at the reference stamps.

    Parameters
    ----------
    where : str
        What errors name (the bag).
    edges : dict of str to TfEdge
        The tree: dynamic and static edges by child frame.
    frame : str
        The frame whose pose is read.
    base_frame : str or None
        The frame the pose is in; ``None``: the root of ``frame``'s tree.
    topics : str
        The topics the tree comes from, for errors (``"/tf and /tf_static"``).

    Returns
    -------
    base : str
        The base frame.
    stamps : ndarray of int64, shape (n,)
        The reference stamps (nanoseconds, sorted, unique).
    values : ndarray of shape (n, 7)
        ``x, y, z, qw, qx, qy, qz`` of ``frame`` in ``base``.
    """
    base, up, down, path = _path(where, edges, frame, base_frame, topics)
    moving = [e for e in (*up, *down) if not e.static]
    if not moving:
        raise DataFileError(
            f"{where}: the pose of {frame!r} in {base!r} is constant (only"
            f" static transforms: {path}), not a demonstration; read a frame that"
            " moves, from /tf"
        )
    ns = moving[0].stamps
    return base, ns, _composed(up, down, ns)
