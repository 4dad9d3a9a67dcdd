"""ROS 2 bags in and out (needs rosbags: ``pip install "ndlfd[ros]"``).

**Reading.** A bag is a folder with ``metadata.yaml`` (what ``ros2 bag record``
writes) or one ``.mcap`` / ``.db3`` storage file. The messages of the chosen
topics become named arrays, mapped to groups by
:func:`~ndlfd.io._mapping.map_arrays` like the columns of a CSV file:

* ``geometry_msgs/msg/PoseStamped``, ``PoseWithCovarianceStamped``,
  ``TransformStamped``, ``tf2_msgs/msg/TFMessage`` (``/tf``: the pose of the
  frame ``frame`` in ``base_frame``, composed along the tf tree with the static
  transforms of ``/tf_static``: see :mod:`ndlfd.io._tf`) and
  ``nav_msgs/msg/Odometry`` give ``x, y, z``
  (position) and ``qw, qx, qy, qz`` (orientation, w first; left out when
  every quaternion is all zeros, as a publisher that sets no orientation
  leaves it);
* ``sensor_msgs/msg/JointState`` gives the group ``joints``, one column per
  joint, named after it, in the order the joints first appear (messages may
  list them in any order), and when every message carries velocities, the
  group ``joint_velocity`` with a column ``NAME.vel`` per joint (as LeRobot
  names motor velocities; efforts are not read). Messages that name
  different sets of joints (an arm and a gripper publishing on
  ``/joint_states``) give one stream per set, combined like several topics
  (the set with the most messages first);
* ``std_msgs/msg/Float64`` / ``Float32`` (a gripper command, say) give one
  column in a group named after the last part of the topic's name
  (``/robot/gripper`` → ``gripper``).

A later topic whose groups are taken gets a group named after the topic
instead (a second pose topic ``/target``: group ``target``, columns
``target_x``, ..., ``target_qz``). Time comes from the header stamps; a topic
without a header, or with unset (zero) stamps, uses the time the bag received
the messages. Messages are sorted by time; repeated stamps keep the first
message (one :class:`~ndlfd.NdlfdWarning`). Time starts at 0 at the first
message of the first topic (of each segment). The column mapping options
``groups`` and ``drop`` apply to these names; ``time_column`` is not used.

**Several topics** are resampled onto the stamps of the first topic: each
column linearly (:func:`numpy.interp`), orientations by spherical linear
interpolation (slerp), and values held at the topic's first or last message
outside its span. When the rates of the topics differ by more than a factor of
2 one :class:`~ndlfd.NdlfdWarning` says so (a slow topic is then interpolated
over long gaps).

Writing bags and joint trajectories: ``_bagout``.
"""

from __future__ import annotations

import itertools
import os
import re
import struct
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from .._errors import DataFileError, MissingExtraError, NdlfdWarning, ValidationError
from .._pose_groups import pose_dims
from .._repairs import repaired
from ..demonstration import Demonstration
from ._bag_frames import bag_frame_poses, check_bag_frames, read_bag_frames
from ._mapping import LIBRARY_HINTS, ColumnMapping, map_arrays
from ._motion import REST_SHARE, rest_pieces
from ._tf import tf_edges, tf_pose_rows

__all__ = [
    "BAG_OPTIONS",
    "BAG_SUFFIXES",
    "BAG_TYPES",
    "bag_frame_id",
    "is_bag_folder",
    "read_bag",
    "read_bag_mapped",
    "rosbags_modules",
    "typestore",
]

#: The suffixes (any case) of ROS 2 bag storage files read as bags.
BAG_SUFFIXES = (".mcap", ".db3")
#: The options only the bag reader takes, with their defaults.
BAG_OPTIONS = {
    "topic": None,
    "frame": None,
    "base_frame": None,
    "split_gap": None,
    "split_still": None,
    "frames": None,
}
#: More pieces than this from one bag with ``split_still`` give a warning.
MANY_PIECES = 50
#: How the rates of several topics may differ before a warning.
RATE_RATIO = 2.0

_POSE_COLUMNS = ("x", "y", "z", "qw", "qx", "qy", "qz")
#: A JointState velocity column's key: (_VELOCITY, joint name).
_VELOCITY = "velocity"
#: The layout of a bag's :class:`ColumnMapping` (``", frame NAME"`` follows
#: when the poses were read in a frame).
BAG_LAYOUT = "ROS 2 bag"


def bag_frame_id(mapping: ColumnMapping | None) -> str | None:
    """The frame the poses of a bag were read in, from its mapping (or ``None``).

    The ``header.frame_id`` of the first pose topic, or the base frame of a
    tf chain; ``None`` for another file or a bag without poses.

    Examples
    --------
    >>> bag_frame_id(ColumnMapping("b", "t", (), layout="ROS 2 bag, frame base_link"))
    'base_link'
    >>> bag_frame_id(ColumnMapping("a.csv", "t", ())) is None
    True
    """
    layout = getattr(mapping, "layout", "") or ""
    head = f"{BAG_LAYOUT}, frame "
    return layout[len(head) :] if layout.startswith(head) else None


def rosbags_modules():
    """Rosbags' ``rosbag2`` and ``typesys`` modules, or a clear error without them."""
    try:
        from rosbags import rosbag2, typesys
    except ImportError:
        raise MissingExtraError(
            "reading and writing ROS 2 bags needs rosbags; install it with: pip"
            ' install "ndlfd[ros]"'
        ) from None
    return rosbag2, typesys


def typestore():
    """The message types of the latest ROS 2 release (rosbags' own)."""
    _, typesys = rosbags_modules()
    return typesys.get_typestore(typesys.Stores.LATEST)


def is_bag_folder(p: Path) -> bool:
    """Whether ``p`` is a ROS 2 bag folder (a folder with ``metadata.yaml``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> is_bag_folder(d)
    False
    >>> _ = (d / "metadata.yaml").write_text("rosbag2_bagfile_information: {}")
    >>> is_bag_folder(d)
    True
    """
    return p.is_dir() and (p / "metadata.yaml").is_file()


# ------------------------------------------------------------ message fields
def _stamp(msg) -> int:
    s = msg.header.stamp
    return int(s.sec) * 1_000_000_000 + int(s.nanosec)


def _pose(p, o) -> list[float]:
    return [p.x, p.y, p.z, o.w, o.x, o.y, o.z]


def _pose_stamped(m, frame):
    return _stamp(m), _pose(m.pose.position, m.pose.orientation)


def _pose_covariance(m, frame):
    return _stamp(m), _pose(m.pose.pose.position, m.pose.pose.orientation)


def _transform(m, frame):
    if frame is not None and m.child_frame_id != frame:
        return None
    tr = m.transform
    return _stamp(m), _pose(tr.translation, tr.rotation)


def _joint_state(m, frame):
    pos = np.asarray(m.position, dtype=np.float64)
    return _stamp(m), (list(m.name), pos, np.asarray(m.velocity, dtype=np.float64))


def _scalar(m, frame):
    return None, [float(m.data)]


#: The message types read, each with what it gives: ``"pose"``, ``"joints"``
#: or ``"scalar"``, and how (``/tf``'s ``TFMessage`` is read transform by
#: transform as ``TransformStamped``).
BAG_TYPES = {
    "geometry_msgs/msg/PoseStamped": ("pose", _pose_stamped),
    "geometry_msgs/msg/PoseWithCovarianceStamped": ("pose", _pose_covariance),
    "geometry_msgs/msg/TransformStamped": ("pose", _transform),
    "tf2_msgs/msg/TFMessage": ("pose", _transform),
    "nav_msgs/msg/Odometry": ("pose", _pose_covariance),
    "sensor_msgs/msg/JointState": ("joints", _joint_state),
    "std_msgs/msg/Float64": ("scalar", _scalar),
    "std_msgs/msg/Float32": ("scalar", _scalar),
}


def _flags(how: Mapping[str, str]) -> dict[str, str]:
    """How errors name the bag options: parameters, or the command line's flags."""
    if how.get("groups", "").startswith("--"):
        return {"topic": "--topic", "frame": "--frame", "base_frame": "--base-frame"}
    return {"topic": "topic=", "frame": "frame=", "base_frame": "base_frame="}


def _describe(topics) -> str:
    return ", ".join(
        f"{name} ({info.msgtype or 'mixed types'}, {info.msgcount} messages)"
        for name, info in sorted(topics.items())
    )


class _Topic:
    """The messages of one topic (or one set of joints): stamps and value arrays.

    ``stamps`` are int64 nanoseconds, sorted and unique; ``arrays`` maps each
    column (``None`` for a scalar) to its values; ``label`` names it in news.
    """

    def __init__(self, name, kind, stamps, arrays, label=None):
        self.name, self.kind = name, kind
        self.stamps, self.arrays = stamps, arrays
        self.orientation = "qw" in arrays
        self.label = label or name

    def rate(self) -> float | None:
        span = (self.stamps[-1] - self.stamps[0]) / 1e9
        return (self.stamps.size - 1) / span if span > 0 else None


def _transforms(reader, store, topic) -> list[tuple]:
    """Every transform on a ``TFMessage`` topic: (parent, child, stamps, values)."""
    conns = reader.topics[topic].connections
    out = []
    for conn, received, raw in reader.messages(connections=conns):
        for m in store.deserialize_cdr(raw, conn.msgtype).transforms:
            tr = m.transform
            values = _pose(tr.translation, tr.rotation)
            out.append(
                (m.header.frame_id, m.child_frame_id, _stamp(m), received, values)
            )
    return out


def _read_tf(p, reader, store, topic, frame, base_frame, flags):
    """The pose of ``frame`` in the base frame from the tf tree (:mod:`._tf`)."""
    static_name = topic if topic.endswith("_static") else f"{topic}_static"
    latched = static_name in reader.topics and {
        c.msgtype for c in reader.topics[static_name].connections
    } == {"tf2_msgs/msg/TFMessage"}
    static = _transforms(reader, store, static_name) if latched else []
    dynamic = [] if topic == static_name else _transforms(reader, store, topic)
    if not dynamic and not static:
        raise DataFileError(f"{p}: topic {topic!r} has no messages")
    moving = sorted({tr[1] for tr in dynamic}) or sorted({tr[1] for tr in static})
    if frame is None and len(moving) > 1:
        raise DataFileError(
            f"{p}: topic {topic!r} has several child frames; pick one with"
            f" {flags['frame']} (child frames there: {', '.join(moving)})"
        )
    edges = tf_edges(str(p), static, static=True)
    edges.update(tf_edges(str(p), dynamic, static=False))
    names = f"{topic} and {static_name}" if latched and topic != static_name else topic
    base, ns, values = tf_pose_rows(
        str(p), edges, frame or moving[0], base_frame, topics=names
    )
    return [(int(k), int(k), v) for k, v in zip(ns, values.tolist(), strict=True)], base


def _read_topic(p, reader, store, topic, frame, flags, base_frame=None):
    """The kind of ``topic``, its (stamp or None, receive time, values), its frame.

    The frame is the messages' ``header.frame_id`` (the first message's), the
    base frame of a tf tree, or ``None`` without a header.
    """
    topics = reader.topics
    if topic not in topics:
        raise DataFileError(
            f"{p}: the bag has no topic {topic!r}; its topics are {_describe(topics)}"
        )
    info = topics[topic]
    types = sorted({c.msgtype for c in info.connections})
    if len(types) > 1:
        raise DataFileError(
            f"{p}: topic {topic!r} mixes message types {', '.join(types)}; expected one"
        )
    msgtype = types[0]
    if msgtype not in BAG_TYPES:
        raise DataFileError(
            f"{p}: topic {topic!r} holds {msgtype}, which ndlfd does not read;"
            f" expected one of {', '.join(BAG_TYPES)}"
        )
    kind, field = BAG_TYPES[msgtype]
    if msgtype == "tf2_msgs/msg/TFMessage":
        rows, base = _read_tf(p, reader, store, topic, frame, base_frame, flags)
        return kind, rows, base
    frames: dict[str, int] = {}
    rows = []
    frame_id = None
    for conn, received, raw in reader.messages(connections=info.connections):
        m = store.deserialize_cdr(raw, conn.msgtype)
        if msgtype.endswith("TransformStamped"):
            frames[m.child_frame_id] = frames.get(m.child_frame_id, 0) + 1
        got = field(m, frame)
        if got is not None:
            rows.append((got[0], received, got[1]))
            if frame_id is None and hasattr(m, "header"):
                frame_id = m.header.frame_id
    if frames and ((frame is None and len(frames) > 1) or not rows):
        which = "several child frames" if frame is None else f"no child frame {frame!r}"
        raise DataFileError(
            f"{p}: topic {topic!r} has {which}; pick one with {flags['frame']}"
            f" (child frames there: {', '.join(sorted(frames))})"
        )
    if not rows:
        raise DataFileError(f"{p}: topic {topic!r} has no messages")
    return kind, rows, frame_id or None


def _stamps_of(rows) -> np.ndarray:
    """Header stamps, or the receive times without a header or with unset stamps."""
    if any(r[0] is None or r[0] == 0 for r in rows):
        return np.array([r[1] for r in rows], dtype=np.int64)
    return np.array([r[0] for r in rows], dtype=np.int64)


def _joint_sets(p, topic, rows) -> list[tuple[list[str], list]]:
    """The joints' columns (in the order they first appear) and rows of each set.

    Messages may list the joints in any order; messages that name different
    sets of joints (an arm and a gripper publishing on one topic) make one set
    each, the set with the most messages first.
    """
    seen: dict[str, None] = {}
    sets: dict[frozenset, list] = {}
    for i, (stamp, received, (names, v, vel)) in enumerate(rows):
        if v.shape != (len(names),) or len(set(names)) != len(names):
            raise DataFileError(
                f"{p}: JointState message {i} on {topic!r} has {v.size} positions"
                f" for the joints {', '.join(names) or '(none)'}; expected one per"
                " joint, each named once"
            )
        if vel.size not in (0, len(names)):
            raise DataFileError(
                f"{p}: JointState message {i} on {topic!r} has {vel.size}"
                f" velocities for {len(names)} joints; expected none or one per"
                " joint"
            )
        seen.update(dict.fromkeys(names))
        value = dict(zip(names, v.tolist(), strict=True))
        if vel.size:
            value.update(
                zip([(_VELOCITY, n) for n in names], vel.tolist(), strict=True)
            )
        sets.setdefault(frozenset(names), []).append((stamp, received, value))
    out = []
    for key, part in sets.items():
        cols = [n for n in seen if n in key]
        if cols and all((_VELOCITY, cols[0]) in v for _, _, v in part):  # each
            cols += [(_VELOCITY, n) for n in cols]
        out.append((cols, [(s, r, [v[c] for c in cols]) for s, r, v in part]))
    out.sort(key=lambda x: -len(x[1]))  # stable: ties keep the first seen
    return out


def _topic_arrays(p, topic, kind, rows) -> list[_Topic]:
    """The topic's streams (one, or one per set of joints) as :class:`_Topic`."""
    if kind == "joints":
        sets = _joint_sets(p, topic, rows)
    else:
        sets = [(list(_POSE_COLUMNS) if kind == "pose" else [None], rows)]
    out = []
    for columns, part in sets:
        stamps = _stamps_of(part)
        values = np.array([r[2] for r in part], dtype=np.float64)
        values = values.reshape(len(part), len(columns))
        order = np.argsort(stamps, kind="stable")
        stamps, values = stamps[order], values[order]
        keep = np.concatenate([[True], np.diff(stamps) > 0])
        shown = [c for c in columns if isinstance(c, str)]
        label = topic if len(sets) == 1 else f"{topic} ({', '.join(shown)})"
        if not keep.all():
            repaired(
                "stamps",
                int((~keep).sum()),
                f"dropped {int((~keep).sum())} message(s) on {label} whose time"
                " stamp repeats an earlier one (kept the first of each)",
                stacklevel=4,
            )
            stamps, values = stamps[keep], values[keep]
        arrays = dict(zip(columns, values.T, strict=True))
        if kind == "pose" and not np.any(values[:, 3:]):  # orientation unset
            for c in _POSE_COLUMNS[3:]:
                del arrays[c]
        out.append(_Topic(topic, kind, stamps, arrays, label))
    return out


def _group_name(topic: str) -> str:
    """The last part of the topic's name as a group name (``/ndlfd/gripper``)."""
    last = topic.rstrip("/").rsplit("/", 1)[-1]
    name = re.sub(r"[^A-Za-z0-9_\-]+", "_", last).strip("_") or "topic"
    return name if re.match(r"[A-Za-z_]", name) else f"_{name}"


def _named(topics: list[_Topic]) -> list[tuple[_Topic, dict[str, str]]]:
    """Each topic's array keys: ``x``/``joints.NAME``, or named after the topic."""
    owner: dict[str, str] = {}  # kind -> the topic that has its groups
    out = []
    for tp in topics:
        base = _group_name(tp.name)
        first = owner.setdefault(tp.kind, tp.name) == tp.name
        if tp.kind == "pose" and first:
            keys = {c: c for c in tp.arrays}
        elif tp.kind == "joints":  # velocities: NAME.vel, the joint_velocity group
            head = "joints." if first else f"{base}."
            keys = {
                c: f"{'' if first else base + '.'}{c[1]}.vel"
                if isinstance(c, tuple)
                else f"{head}{c}"
                for c in tp.arrays
            }
        elif tp.kind == "scalar":
            keys = {None: f"{base}.{base}"}
        else:  # column names stay unique: target_x, ...
            keys = {c: f"{base}.{base}_{c}" for c in tp.arrays}
        out.append((tp, keys))
    return out


def _resample(tp: _Topic, at: np.ndarray) -> dict:
    """The topic's arrays at the times ``at`` (ns): linear, orientation by slerp."""
    if tp.stamps.size == at.size and np.array_equal(tp.stamps, at):
        return dict(tp.arrays)
    x = (tp.stamps - at[0]) / 1e9
    xi = (at - at[0]) / 1e9
    out = {c: np.interp(xi, x, v) for c, v in tp.arrays.items()}
    if tp.orientation and tp.stamps.size > 1:
        from scipy.spatial.transform import Rotation, Slerp

        q = np.column_stack([tp.arrays[c] for c in ("qx", "qy", "qz", "qw")])
        norms = np.linalg.norm(q, axis=1)
        if np.all(np.isfinite(q)) and np.all(norms > 0):
            slerp = Slerp(x, Rotation.from_quat(q))
            r = slerp(np.clip(xi, x[0], x[-1])).as_quat()
            for j, c in enumerate(("qx", "qy", "qz", "qw")):
                out[c] = r[:, j]
    return out


def _rates_note(p, topics: list[_Topic]) -> None:
    rates = [(tp.label, tp.rate()) for tp in topics]
    known = [r for _, r in rates if r is not None]
    if len(known) > 1 and max(known) > RATE_RATIO * min(known):
        shown = ", ".join(f"{n} {r:.3g} Hz" for n, r in rates if r is not None)
        warnings.warn(
            f"the topics' rates differ by more than {RATE_RATIO:g}x ({shown});"
            f" all are resampled onto the stamps of {topics[0].label} (linear,"
            " orientation by slerp)",
            NdlfdWarning,
            stacklevel=3,
        )


def _segments(stamps: np.ndarray, split_gap: float | None) -> list[slice]:
    if split_gap is None:
        return [slice(0, stamps.size)]
    cuts = np.flatnonzero(np.diff(stamps) / 1e9 > split_gap) + 1
    edges = [0, *cuts.tolist(), stamps.size]
    return [slice(a, b) for a, b in itertools.pairwise(edges)]


def _default_topic(p, reader, frame, flags) -> list[str]:
    """The bag's only readable topic; with a frame, its ``/tf`` (or only tf topic)."""
    if frame is not None:
        tf = [
            n
            for n, i in reader.topics.items()
            if i.msgtype == "tf2_msgs/msg/TFMessage" and not n.endswith("_static")
        ]
        if "/tf" in tf or len(tf) == 1:
            return ["/tf" if "/tf" in tf else tf[0]]
        raise DataFileError(
            f"{p}: {flags['frame']} {frame} reads a tf topic; the bag has"
            f" {'several' if tf else 'none'} ({', '.join(tf)}); name one with"
            f" {flags['topic']}; its topics are {_describe(reader.topics) or 'none'}"
        )
    usable = [n for n, i in reader.topics.items() if i.msgtype in BAG_TYPES]
    if len(usable) != 1:
        raise DataFileError(
            f"{p}: name the topic to read with {flags['topic']}; the"
            f" bag's topics are {_describe(reader.topics) or 'none'}"
        )
    return usable


def _still_segments(p, at, arrays, segs, seconds) -> list[slice]:
    """``segs`` cut further at rests of at least ``seconds`` (:mod:`._motion`)."""
    keys = list(arrays)
    X = np.column_stack([arrays[k] for k in keys])
    quats = [
        [keys.index(k[:-2] + c) for c in ("qw", "qx", "qy", "qz")]
        for k in keys
        if k.endswith("qw") and all(k[:-2] + c in arrays for c in ("qx", "qy", "qz"))
    ]
    out = []
    for seg in segs:
        t = (at[seg] - at[seg][0]) / 1e9
        found = rest_pieces(t, X[seg], seconds, quats)
        out.extend(slice(seg.start + a, seg.start + b) for a, b in found)
    if len(out) <= len(segs):
        warnings.warn(
            f"{p}: no rest of at least {seconds:g} s found (a stretch where"
            f" nothing moves faster than {REST_SHARE:.0%} of the recording's"
            " typical moving speed); read as it is",
            NdlfdWarning,
            stacklevel=4,
        )
    elif len(out) > MANY_PIECES:
        warnings.warn(
            f"{p}: {len(out)} pieces between rests of at least {seconds:g} s; a"
            " longer split_still (--split-still) finds the pauses between"
            " demonstrations only",
            NdlfdWarning,
            stacklevel=4,
        )
    return out


def _check_options(topic, frame, base_frame, splits: dict) -> list[str] | None:
    if topic is not None:
        topic = [topic] if isinstance(topic, str) else list(topic)
        if not topic or not all(isinstance(s, str) and s for s in topic):
            raise ValidationError(
                f"topic must be a topic name or a list of them; got {topic!r}"
            )
        if len(set(topic)) != len(topic):
            raise ValidationError(f"topic names a topic twice; got {topic!r}")
    for name, value in (("frame", frame), ("base_frame", base_frame)):
        if value is not None and not (isinstance(value, str) and value):
            raise ValidationError(f"{name} must be a frame name; got {value!r}")
    for name, value in splits.items():
        if value is not None and not (
            isinstance(value, (int, float)) and np.isfinite(value) and value > 0
        ):
            raise ValidationError(
                f"{name} must be a number of seconds > 0; got {value!r}"
            )
    return topic


def read_bag_mapped(
    p: Path,
    how=LIBRARY_HINTS,
    *,
    topic=None,
    frame=None,
    base_frame=None,
    split_gap=None,
    split_still=None,
    frames=None,
    groups=None,
    drop=(),
    quaternion_order="wxyz",
    time_column=None,
    euler="xyz",
    bad_rows="error",
) -> list[tuple[Demonstration, ColumnMapping]]:
    """Every demonstration of the bag ``p`` (one, or one per segment) with its mapping.

    ``time_column`` is not used (the time is the stamps); ``groups``, ``drop``
    and ``euler`` map the bag's array names (``x``, ``qw``, ``joints.NAME``,
    ``gripper.gripper``) like CSV columns; ``frames`` gives each
    demonstration task frames (:mod:`ndlfd.io._bag_frames`).
    """
    topics = _check_options(
        topic, frame, base_frame, {"split_gap": split_gap, "split_still": split_still}
    )
    flags = _flags(how)
    sources = check_bag_frames(frames, how)
    rosbag2, _ = rosbags_modules()
    if not p.exists():
        raise DataFileError(f"{p}: no such file or bag folder")
    store = typestore()
    try:
        with rosbag2.Reader(p) as reader:
            if topics is None:
                topics = _default_topic(p, reader, frame, flags)
            read = [
                (t, *_read_topic(p, reader, store, t, frame, flags, base_frame))
                for t in topics
            ]
            held = read_bag_frames(p, reader, store, sources, how) if sources else []
    except DataFileError:
        raise
    except (
        rosbag2.ReaderError,
        OSError,
        KeyError,
        ValueError,
        IndexError,
        struct.error,
    ) as exc:  # a damaged file: the message does not parse
        raise DataFileError(
            f"{p}: expected a ROS 2 bag (a folder with metadata.yaml, or an .mcap"
            f" or .db3 file); it is not readable as one ({exc})"
        ) from None
    tps = [tp for t, kind, rows, _ in read for tp in _topic_arrays(p, t, kind, rows)]
    if len(tps) > 1:
        _rates_note(p, tps)
    at = tps[0].stamps
    arrays: dict[str, np.ndarray] = {}
    for tp, keys in _named(tps):
        for c, v in _resample(tp, at).items():
            arrays[keys[c]] = v
    what = f"{tps[0].label} stamps"
    in_frames = [f for _, kind, _, f in read if kind == "pose" and f]
    layout = f"{BAG_LAYOUT}, frame {in_frames[0]}" if in_frames else BAG_LAYOUT
    base = in_frames[0] if in_frames else base_frame  # the frames' base
    out = []
    segs = _segments(at, split_gap)
    if split_still is not None:
        segs = _still_segments(p, at, arrays, segs, float(split_still))
    for i, seg in enumerate(segs):
        source = str(p) if len(segs) == 1 else f"{p}:{i}"
        part = {k: v[seg] for k, v in arrays.items()}
        part["t"] = (at[seg] - at[seg][0]) / 1e9
        demo, mapping = map_arrays(
            source,
            part,
            time_column="t",
            groups=groups,
            drop=drop,
            quaternion_order=quaternion_order,
            how=how,
            euler=euler,
            source=source,
            bad_rows=bad_rows,
        )
        if held:  # the task frames over this demonstration
            dims = pose_dims(demo.groups)
            poses = bag_frame_poses(source, held, at[seg], dims, base, how)
            demo = demo.with_frames(poses)
        span = None
        if len(segs) > 1:  # where the piece lies in the recording
            first, last = (at[seg][[0, -1]] - at[0]) / 1e9
            span = (float(first), float(last))
        out.append((demo, replace(mapping, time=what, layout=layout, span=span)))
    return out


def read_bag(
    path: str | os.PathLike,
    topic: str | Sequence[str] | None = None,
    *,
    frame: str | None = None,
    base_frame: str | None = None,
    split_gap: float | None = None,
    split_still: float | None = None,
    frames: Mapping[str, str] | None = None,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    drop: Sequence[str] = (),
    bad_rows: str = "error",
) -> list[Demonstration]:
    """Read demonstrations from a ROS 2 bag: one, or one per segment.

    Needs the ``ros`` extra (``pip install "ndlfd[ros]"``, pure Python: no ROS
    installation). See :mod:`ndlfd.io._bag` for the message types read and how
    several topics are combined.

    Parameters
    ----------
    path : str or path-like
        A bag folder (with ``metadata.yaml``) or an ``.mcap`` / ``.db3`` file.
    topic : str or sequence of str, optional
        The topic(s) to read; the first gives the time stamps and the others are
        resampled onto them. Default: the bag's only topic of a type ndlfd reads.
    frame : str, optional
        The frame whose pose is read from a ``/tf`` (``TFMessage``) topic, or
        the child frame of a ``TransformStamped`` topic; needed when it has
        several. Without ``topic``, a frame reads ``/tf``. On ``/tf`` the
        frame's pose is composed along the tf tree to ``base_frame``, with the
        static transforms of ``/tf_static`` (see :mod:`ndlfd.io._tf`): each
        moving transform of the chain is interpolated (linear, slerp) at the
        stamps of the one nearest the frame.
    base_frame : str, optional
        The frame the pose of ``frame`` is in (default: the root of its tf
        tree, e.g. ``base_link`` or ``world``). A frame not connected to it, or
        not in the tree, is an error listing the frames found.
    split_gap : float, optional
        Start a new demonstration wherever the first topic's stamps are more
        than this many seconds apart.
    split_still : float, optional
        Cut the recording where the motion rests for at least this many
        seconds (a robot that keeps publishing while it waits between
        demonstrations): one demonstration per stretch between rests, each
        from the end of the rest before it to the start of the rest after it.
        A sample rests when its speed (every read column scaled by its range,
        averaged over a quarter of ``split_still`` on each side) is below 5 %
        of the recording's typical moving speed (the 90th percentile of the
        speeds); see :mod:`ndlfd.io._motion`. One :class:`~ndlfd.NdlfdWarning`
        when no rest is found, or more than 50 pieces.
    frames : mapping of str to str, optional
        Task frames (:attr:`~ndlfd.Demonstration.frames`: where the object or
        the place was), each named after where it is read: a topic
        (``{"object": "/object_pose"}``: ``PoseStamped``, ``Pose``,
        ``PoseWithCovarianceStamped``, ``TransformStamped``, ``PointStamped``
        or ``Point``; its messages during the demonstration, else the last
        before it) or a tf frame (``{"object": "tf:object_frame"}``: composed
        along ``/tf`` and ``/tf_static`` to ``base_frame``, else to the frame
        the demonstrations' poses are in). The pose must stay within 5 mm and
        3 degrees of its first sample over each demonstration, and becomes
        ``x, y, z`` or ``x, y, z, qw, qx, qy, qz`` (scalar first); see
        :mod:`ndlfd.io._bag_frames`.
    groups, drop
        As in :func:`~ndlfd.io.read_csv`, on the arrays' names (``x``, ``qw``,
        ``joints.NAME``, ``gripper.gripper``).
    bad_rows : {"error", "drop"}, default="error"
        A row with NaN or inf is an error naming it, or (``"drop"``) dropped
        with one :class:`~ndlfd.NdlfdWarning`, as in :func:`~ndlfd.io.read_csv`;
        at least 2 rows must remain in
        each demonstration (after resampling onto the first topic's stamps).

    Returns
    -------
    demos : list of Demonstration
        Time in seconds from each one's first sample.

    Raises
    ------
    DataFileError
        An unreadable bag, a missing topic (the message lists the bag's topics),
        a topic with no messages or of a type not read, or values that do not
        make a demonstration (NaN in a pose); a frame's topic without
        messages, in another frame than the demonstrations, or a frame that
        moved during a demonstration (the message says how far).
    ValidationError
        ``frames`` not a mapping of names to topics or ``tf:`` frames.
    MissingExtraError
        rosbags is not installed.
    """
    return [
        d
        for d, _ in read_bag_mapped(
            Path(path),
            topic=topic,
            frame=frame,
            base_frame=base_frame,
            split_gap=split_gap,
            split_still=split_still,
            frames=frames,
            groups=groups,
            drop=drop,
            bad_rows=bad_rows,
        )
    ]
