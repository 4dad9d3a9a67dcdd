"""Task frames of ROS 2 bags: where an object or a place was, from a topic or tf.

``read_bag(..., frames={"object": "/object_pose", "place": "tf:place"})``
(``ndlfd fit --task-frame object=/object_pose``) gives each demonstration of
the bag the frames' poses (:attr:`~ndlfd.Demonstration.frames`):

* a **topic** of ``geometry_msgs/msg/PoseStamped``,
  ``PoseWithCovarianceStamped``, ``Pose``, ``TransformStamped`` (one child
  frame), ``PointStamped`` or ``Point``: its messages during the
  demonstration (stamped from its first to its last sample; header stamps,
  or the receive times without a header or with unset stamps), or when none
  falls there the last one before it (a pose published once). A pose gives
  ``x, y, z, qw, qx, qy, qz`` (ROS's ``x, y, z, w`` turned scalar first), or
  ``x, y, z`` when its orientation is unset (all zeros) or it is a point.
  The messages' ``header.frame_id`` must be the demonstrations' frame when
  both are known;
* a **tf frame** ``tf:NAME``: its pose composed along the tf tree of ``/tf``
  and ``/tf_static`` (:func:`~ndlfd.io._tf.tf_pose_at`) to the base frame of
  the demonstrations (``base_frame``, else the frame their poses are in, else
  the root of the frame's tree), at the demonstration's stamps; a frame of
  ``/tf_static`` only is a constant pose.

The pose must stay still over the demonstration (within
:data:`~ndlfd.io._frame_poses.FRAME_TOLERANCE` metres and
:data:`~ndlfd.io._frame_poses.FRAME_ANGLE_TOLERANCE` degrees): the frame is
the mean of its samples (:func:`~ndlfd.io._frame_poses.still_pose`). An object
that moved, a topic without messages, a frame not in the tree are errors
naming the bag, the frame and the topic.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .._errors import DataFileError, ValidationError
from ._frame_poses import check_frame_sources, frame_flag, sized_pose, still_pose
from ._tf import tf_edges, tf_pose_at

__all__ = [
    "FRAME_TYPES",
    "TF_PREFIX",
    "BagFrame",
    "bag_frame_poses",
    "check_bag_frames",
    "read_bag_frames",
]

#: The prefix of a frame read from the tf tree: ``tf:object``.
TF_PREFIX = "tf:"
_TF = "tf2_msgs/msg/TFMessage"
_EXAMPLE = "{'object': '/object_pose'} or {'object': 'tf:object_frame'}"


def _pose(p, o) -> list[float]:
    return [p.x, p.y, p.z, o.w, o.x, o.y, o.z]


def _po(pose):
    return pose.position, pose.orientation


def _point(p) -> list[float]:
    return [p.x, p.y, p.z]


#: The message types a frame's topic may hold: each gives (header or None,
#: child frame or None, values).
FRAME_TYPES = {
    "geometry_msgs/msg/PoseStamped": lambda m: (m.header, None, _pose(*_po(m.pose))),
    "geometry_msgs/msg/PoseWithCovarianceStamped": lambda m: (
        m.header,
        None,
        _pose(*_po(m.pose.pose)),
    ),
    "geometry_msgs/msg/Pose": lambda m: (None, None, _pose(*_po(m))),
    "geometry_msgs/msg/TransformStamped": lambda m: (
        m.header,
        m.child_frame_id,
        _pose(m.transform.translation, m.transform.rotation),
    ),
    "geometry_msgs/msg/PointStamped": lambda m: (m.header, None, _point(m.point)),
    "geometry_msgs/msg/Point": lambda m: (None, None, _point(m)),
}


@dataclass(frozen=True)
class BagFrame:
    """Where one task frame of a bag is: a topic's messages, or a tf tree.

    Attributes
    ----------
    name, source : str
        The frame and where it is read (a topic, or ``tf:`` and a tf frame).
    stamps : ndarray of int64, shape (n,)
        A topic's message times, nanoseconds, sorted (empty for tf).
    values : ndarray of shape (n, 3) or (n, 7)
        A topic's poses (``x, y, z[, qw, qx, qy, qz]``).
    frame_id : str or None
        A topic's ``header.frame_id`` (the first message's).
    edges : dict of str to TfEdge or None
        The tf tree of a tf frame.
    topics : str
        The tf topics read, for messages.
    """

    name: str
    source: str
    stamps: np.ndarray
    values: np.ndarray
    frame_id: str | None = None
    edges: dict | None = None
    topics: str = ""


def check_bag_frames(frames, how: Mapping[str, str]) -> dict[str, str] | None:
    """``frames`` of a bag checked: each a topic (``/NAME``) or ``tf:FRAME``."""
    cli = how.get("groups", "").startswith("--")
    out = check_frame_sources(frames, "--task-frame" if cli else "frames", _EXAMPLE)
    for name, source in (out or {}).items():
        tf = source.startswith(TF_PREFIX) and source[len(TF_PREFIX) :].strip()
        if not (tf or (source.startswith("/") and len(source) > 1)):
            raise ValidationError(
                f"{frame_flag(how, name)} of a ROS 2 bag must be a topic (such as"
                f" /object_pose) or a tf frame (such as tf:object_frame); got"
                f" {source!r}"
            )
    return out


def _describe(reader) -> str:
    return (
        ", ".join(
            f"{n} ({i.msgtype or 'mixed types'})"
            for n, i in sorted(reader.topics.items())
        )
        or "none"
    )


def _tf_tree(p, reader, store, what: str, frame: str) -> tuple[dict, str]:
    """The tf tree of the bag's ``/tf`` and ``/tf_static`` (every TFMessage topic)."""
    names = [n for n, i in reader.topics.items() if i.msgtype == _TF]
    if not names:
        raise DataFileError(
            f"{p}: {what} reads tf frame {frame!r} from /tf and /tf_static; the bag"
            f" has no tf topic (tf2_msgs/msg/TFMessage); its topics are"
            f" {_describe(reader)}"
        )
    static, dynamic = [], []
    for name in sorted(names):
        conns = reader.topics[name].connections
        into = static if name.endswith("_static") else dynamic
        for conn, received, raw in reader.messages(connections=conns):
            for m in store.deserialize_cdr(raw, conn.msgtype).transforms:
                s = m.header.stamp
                stamp = int(s.sec) * 1_000_000_000 + int(s.nanosec)
                tr = m.transform
                values = _pose(tr.translation, tr.rotation)
                into.append(
                    (m.header.frame_id, m.child_frame_id, stamp, received, values)
                )
    edges = tf_edges(str(p), static, static=True)
    edges.update(tf_edges(str(p), dynamic, static=False))
    return edges, " and ".join(sorted(names))


def _topic_frame(p, reader, store, name: str, topic: str, what: str) -> BagFrame:
    if topic not in reader.topics:
        raise DataFileError(
            f"{p}: {what} reads topic {topic!r}, which the bag does not have; its"
            f" topics are {_describe(reader)}"
        )
    info = reader.topics[topic]
    types = sorted({c.msgtype for c in info.connections})
    if len(types) != 1 or types[0] not in FRAME_TYPES:
        raise DataFileError(
            f"{p}: {what} reads topic {topic!r}, which holds {', '.join(types)};"
            f" expected one of {', '.join(FRAME_TYPES)} (or a tf frame:"
            f" tf:FRAME)"
        )
    rows, children, frame_id = [], set(), None
    for conn, received, raw in reader.messages(connections=info.connections):
        header, child, values = FRAME_TYPES[types[0]](
            store.deserialize_cdr(raw, conn.msgtype)
        )
        stamp = 0
        if header is not None:
            stamp = int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)
            frame_id = frame_id or header.frame_id or None
        children.add(child)
        rows.append((stamp, received, values))
    if not rows:
        raise DataFileError(
            f"{p}: {what} reads topic {topic!r}, which has no messages in the"
            " bag; expected at least one (the frame's pose)"
        )
    if len(children) > 1:
        raise DataFileError(
            f"{p}: {what} reads topic {topic!r}, whose transforms have several"
            f" child frames ({', '.join(sorted(map(str, children)))}); expected"
            " one (read one from the tf tree with tf:FRAME)"
        )
    unset = any(r[0] == 0 for r in rows)
    stamps = np.array([r[1] if unset else r[0] for r in rows], dtype=np.int64)
    values = np.array([r[2] for r in rows], dtype=np.float64)
    if values.shape[1] == 7 and not np.any(values[:, 3:]):  # orientation unset
        values = values[:, :3]
    order = np.argsort(stamps, kind="stable")
    return BagFrame(name, topic, stamps[order], values[order], frame_id)


def read_bag_frames(p, reader, store, frames: dict, how) -> list[BagFrame]:
    """Each frame's messages (or the tf tree) from an open bag ``reader``."""
    out, tree = [], None
    for name, source in frames.items():
        what = frame_flag(how, name)
        if source.startswith(TF_PREFIX):
            frame = source[len(TF_PREFIX) :].strip()
            if tree is None:
                tree = _tf_tree(p, reader, store, what, frame)
            edges, topics = tree
            found = {*edges, *(e.parent for e in edges.values())}
            if frame not in found:
                raise DataFileError(
                    f"{p}: {what} reads tf frame {frame!r}, which is not in the tf"
                    f" tree of {topics}; the frames found are"
                    f" {', '.join(sorted(found)) or 'none'}"
                )
            empty = np.zeros(0, dtype=np.int64)
            out.append(
                BagFrame(name, source, empty, np.zeros((0, 7)), None, edges, topics)
            )
        else:
            out.append(_topic_frame(p, reader, store, name, source, what))
    return out


def _seconds(ns) -> str:
    return f"{ns / 1e9:.3f} s"


def bag_frame_poses(
    where: str, held: list[BagFrame], at: np.ndarray, dims: int, base, how
) -> dict:
    """Each frame's pose over one demonstration, stamped ``at`` (ns).

    Parameters
    ----------
    where : str
        The bag (and piece), for messages.
    held : list of BagFrame
    at : ndarray of int64
        The demonstration's stamps.
    dims : int
        The position group's columns.
    base : str or None
        The frame the demonstrations' poses are in (``None``: unknown).
    how : dict
        How messages name the settings.

    Returns
    -------
    poses : dict of str to ndarray
    """
    a, b = int(at[0]), int(at[-1])
    out = {}
    for f in held:
        what = f"{frame_flag(how, f.name)} ({f.source})"
        if f.edges is not None:
            frame = f.source[len(TF_PREFIX) :].strip()
            _, values = tf_pose_at(where, f.edges, frame, base, at, topics=f.topics)
            values = sized_pose(values, dims, where, what)
            out[f.name] = still_pose(values, where, what, (at - a) / 1e9, " m")
            continue
        if base and f.frame_id and f.frame_id != base:
            raise DataFileError(
                f"{where}: {what} is in frame {f.frame_id!r} (its header.frame_id);"
                f" expected the demonstrations' frame {base!r} (publish it there,"
                " or read it from the tf tree with tf:FRAME)"
            )
        inside = np.flatnonzero((f.stamps >= a) & (f.stamps <= b))
        if not inside.size:
            before = np.flatnonzero(f.stamps < a)
            if not before.size:
                raise DataFileError(
                    f"{where}: {what} has no message during the demonstration or"
                    f" before it; expected at least one (its {f.stamps.size}"
                    f" message(s) are from {_seconds(f.stamps[0] - a)} to"
                    f" {_seconds(f.stamps[-1] - a)} after the demonstration's"
                    f" start, which lasts {_seconds(b - a)})"
                )
            inside = before[-1:]
        values = sized_pose(f.values[inside], dims, where, what)
        t = (f.stamps[inside] - a) / 1e9
        out[f.name] = still_pose(values, where, what, t, " m")
    return out
