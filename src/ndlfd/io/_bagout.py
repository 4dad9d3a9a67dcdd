"""ROS 2 bags and joint trajectories out: what a robot replays or runs.

:func:`write_bag` writes a ``PoseStamped`` per sample for position and
orientation, a ``JointState`` for the group ``joints`` and a topic for each other
group (a gripper), with the header stamps and receive times equal (needs
rosbags: the ``ros`` extra). :func:`write_joint_trajectory` writes a
``trajectory_msgs/msg/JointTrajectory`` as YAML and needs nothing else.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from .._errors import ValidationError
from .._fileformat import atomic_path
from ..demonstration import Demonstration
from ._bag import BAG_SUFFIXES, rosbags_modules, typestore

__all__ = ["write_bag", "write_joint_trajectory"]


def _time_ns(demo: Demonstration, start_time: float) -> np.ndarray:
    ns = np.round((demo.t + start_time) * 1e9)
    if ns[0] < 0:
        raise ValidationError(
            f"a bag's time stamps must be >= 0; the demonstration starts at"
            f" {float(demo.t[0])!r} (pass start_time= to shift it)"
        )
    return ns.astype(np.int64)


def _header(T, ns: int, frame_id: str):
    stamp = T["builtin_interfaces/msg/Time"](
        sec=int(ns // 1_000_000_000), nanosec=int(ns % 1_000_000_000)
    )
    return T["std_msgs/msg/Header"](stamp=stamp, frame_id=frame_id)


def _bag_streams(demo: Demonstration, topic: str):
    """(topic, msgtype, group, columns) of each stream :func:`write_bag` writes."""
    streams = []
    if demo.has_group("position") or demo.has_group("orientation"):
        if demo.has_group("position") and demo.get("position").shape[1] > 3:
            raise ValidationError(
                "a PoseStamped holds at most 3 position columns; the demonstration"
                f" has {demo.get('position').shape[1]}"
            )
        streams.append((topic, "geometry_msgs/msg/PoseStamped", "pose", ()))
    base = topic.rstrip("/")
    for g in demo.group_names:
        if g in ("position", "orientation", "velocity"):
            continue
        cols = tuple(
            c for c, h in zip(demo.columns, demo.groups, strict=True) if h == g
        )
        name = f"{base}/joint_states" if g == "joints" else f"{base}/{g}"
        scalar = len(cols) == 1 and g != "joints"
        kind = "std_msgs/msg/Float64" if scalar else "sensor_msgs/msg/JointState"
        streams.append((name, kind, g, cols))
    if not streams:
        raise ValidationError(
            "write_bag needs position, orientation, joints or another group to"
            f" write; the demonstration has only {', '.join(demo.group_names)}"
        )
    return streams


def _messages(T, demo, stream, ns, frame_id):
    """The messages of one stream, one per sample."""
    _, msgtype, group, cols = stream
    n = demo.n_samples
    if group == "pose":
        pos = np.zeros((n, 3))
        if demo.has_group("position"):
            P = demo.get("position")
            pos[:, : P.shape[1]] = P
        quat = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
        if demo.has_group("orientation"):
            quat = demo.get("orientation")
        Point, Quat = T["geometry_msgs/msg/Point"], T["geometry_msgs/msg/Quaternion"]
        Pose, PS = T["geometry_msgs/msg/Pose"], T[msgtype]
        for i in range(n):
            x, y, z = (float(v) for v in pos[i])
            w, qx, qy, qz = (float(v) for v in quat[i])
            yield PS(
                header=_header(T, ns[i], frame_id),
                pose=Pose(
                    position=Point(x=x, y=y, z=z),
                    orientation=Quat(x=qx, y=qy, z=qz, w=w),
                ),
            )
        return
    V = demo.get(group)
    if msgtype == "std_msgs/msg/Float64":
        for i in range(n):
            yield T[msgtype](data=float(V[i, 0]))
        return
    empty = np.zeros(0, dtype=np.float64)
    for i in range(n):
        yield T[msgtype](
            header=_header(T, ns[i], frame_id),
            name=list(cols),
            position=np.array(V[i], dtype=np.float64),
            velocity=empty,
            effort=empty,
        )


def write_bag(
    demo: Demonstration,
    path: str | os.PathLike,
    *,
    topic: str = "/ndlfd/path",
    frame_id: str = "world",
    start_time: float = 0.0,
) -> Path:
    """Write a demonstration as a ROS 2 bag that ``ros2 bag play`` replays, atomically.

    One message per sample and stream, with the header stamp and the receive
    time both ``t + start_time``: a ``geometry_msgs/msg/PoseStamped`` on
    ``topic`` for position (up to 3 columns, missing ones 0) and orientation
    (identity when absent); a ``sensor_msgs/msg/JointState`` on
    ``TOPIC/joint_states`` for the group ``joints``; and for each other group
    (a gripper, but not velocity) ``TOPIC/GROUP``: a ``std_msgs/msg/Float64``
    for one column, a ``JointState`` named after the columns for several.

    The bag is rosbag2 format version 8 (ROS 2 Jazzy's), written by rosbags;
    it is written beside ``path`` and renamed into place. Velocity is not
    written (a pose stream has none). Needs the ``ros`` extra (``pip install
    "ndlfd[ros]"``).

    Parameters
    ----------
    demo : Demonstration
        The path (a generated one, say).
    path : str or path-like
        ``NAME.mcap``: one self-contained MCAP file (``ros2 bag play
        NAME.mcap``); ``NAME.db3``: one SQLite file; any other name: a bag
        folder (``metadata.yaml`` and an MCAP file) that must not exist yet.
    topic : str, default="/ndlfd/path"
        The pose topic; the other topics are below it.
    frame_id : str, default="world"
        The headers' frame.
    start_time : float, default=0.0
        Seconds added to ``demo.t`` for the stamps (which must be >= 0).

    Returns
    -------
    path : Path
    """
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )
    if not (isinstance(topic, str) and topic.startswith("/") and len(topic) > 1):
        raise ValidationError(f"topic must be a name like '/ndlfd/path'; got {topic!r}")
    rosbag2, _ = rosbags_modules()
    store = typestore()
    T = store.types
    streams = _bag_streams(demo, topic)
    ns = _time_ns(demo, float(start_time))
    final = Path(path)
    suffix = final.suffix.lower()
    if suffix not in BAG_SUFFIXES and final.exists():
        raise ValidationError(
            f"{final} exists; write_bag writes a new bag folder (remove it first)"
        )
    final.parent.mkdir(parents=True, exist_ok=True)
    sqlite = suffix == ".db3"
    plugin = rosbag2.StoragePlugin.SQLITE3 if sqlite else rosbag2.StoragePlugin.MCAP
    tmp = Path(
        tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".tmp", dir=final.parent)
    )
    try:
        bag = tmp / (final.stem if suffix in BAG_SUFFIXES else final.name)
        with rosbag2.Writer(bag, version=8, storage_plugin=plugin) as writer:
            for stream in streams:
                conn = writer.add_connection(stream[0], stream[1], typestore=store)
                for i, msg in enumerate(_messages(T, demo, stream, ns, frame_id)):
                    writer.write(conn, int(ns[i]), store.serialize_cdr(msg, stream[1]))
        if suffix in BAG_SUFFIXES:
            with atomic_path(final) as out:
                os.replace(bag / f"{bag.name}{'.db3' if sqlite else '.mcap'}", out)
        else:
            os.rename(bag, final)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return final


# ---------------------------------------------------------- joint trajectory
def _yaml_float(v: float) -> str:
    """A float YAML 1.1 (PyYAML, ``ros2 topic pub``) reads back exactly."""
    text = repr(float(v))
    if "e" in text and "." not in text:  # 1e-05 is a string to YAML 1.1
        text = text.replace("e", ".0e")
    return text


def _yaml_name(name: str) -> str:
    return "'" + name.replace("'", "''") + "'"


def _duration(seconds: float) -> str:
    ns = round(seconds * 1e9)
    return f"{{sec: {ns // 1_000_000_000}, nanosec: {ns % 1_000_000_000}}}"


def write_joint_trajectory(
    demo: Demonstration, path: str | os.PathLike, *, group: str = "joints"
) -> Path:
    r"""Write a ``trajectory_msgs/msg/JointTrajectory`` as YAML, atomically.

    One point per sample: the positions of ``group``'s columns (the joint
    names), their velocities (:func:`numpy.gradient` over the real time
    stamps) and ``time_from_start`` (seconds from the first sample, as
    ``sec``/``nanosec``). The header's stamp is zero (start now) and its frame
    empty. The file is the message in YAML flow style, floats written so that
    they read back exactly, so it can be sent as it is::

        ros2 topic pub --once /joint_trajectory_controller/joint_trajectory \
            trajectory_msgs/msg/JointTrajectory "$(cat path.yaml)"

    Needs no extra.

    Parameters
    ----------
    demo : Demonstration
        The path; needs the group ``group``.
    path : str or path-like
        The YAML file.
    group : str, default="joints"
        The group holding the joint positions.

    Returns
    -------
    path : Path

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = Demonstration.from_arrays([0.0, 0.5], joints=[[0.0, 1.0], [0.5, 1.0]],
    ...                               columns={"joints": ["a", "b"]})
    >>> p = write_joint_trajectory(d, pathlib.Path(tempfile.mkdtemp()) / "j.yaml")
    >>> print(p.read_text())
    header: {stamp: {sec: 0, nanosec: 0}, frame_id: ''}
    joint_names: ['a', 'b']
    points:
    - {positions: [0.0, 1.0], velocities: [1.0, 0.0], time_from_start: {sec: 0, nanosec: 0}}
    - {positions: [0.5, 1.0], velocities: [1.0, 0.0], time_from_start: {sec: 0, nanosec: 500000000}}
    <BLANKLINE>
    """  # noqa: E501
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )
    if not demo.has_group(group):
        raise ValidationError(
            f"a joint trajectory needs the group {group!r} (the joint positions);"
            f" the path has {', '.join(demo.group_names)}"
        )
    names = [c for c, g in zip(demo.columns, demo.groups, strict=True) if g == group]
    Q = demo.get(group)
    if demo.n_samples > 1:
        V = np.gradient(Q, demo.t, axis=0)
    else:
        V = np.zeros_like(Q)
    lines = [
        "header: {stamp: {sec: 0, nanosec: 0}, frame_id: ''}",
        f"joint_names: [{', '.join(_yaml_name(c) for c in names)}]",
        "points:",
    ]
    for q, v, t in zip(Q, V, demo.t - demo.t[0], strict=True):
        lines.append(
            f"- {{positions: [{', '.join(map(_yaml_float, q))}],"
            f" velocities: [{', '.join(map(_yaml_float, v))}],"
            f" time_from_start: {_duration(t)}}}"
        )
    final = Path(path)
    with atomic_path(final) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return final
