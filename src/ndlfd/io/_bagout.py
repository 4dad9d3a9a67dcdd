"""ROS 2 bags and joint trajectories out: what a robot replays or runs.

:func:`write_bag` writes a ``PoseStamped`` per sample for position and
orientation, a ``JointState`` for the group ``joints`` and a topic for each other
group (a gripper), with the header stamps and receive times equal (needs
rosbags: the ``ros`` extra). :func:`write_joint_trajectory` writes a
``trajectory_msgs/msg/JointTrajectory``: as YAML (needs nothing else), or as a
bag of that one message for ``ros2 bag play``.

**Units.** ROS measures joint angles in radians (REP 103). Joints recorded in
degrees (LeRobot's SO-100/101 arms) are written with ``units="deg"``: the
positions (and velocities, accelerations) are converted to radians.

**QoS.** Each topic of a written bag carries the QoS profile ``ros2 bag
record`` stores for a publisher it discovered (reliable, volatile, history
unknown, infinite durations), which ``ros2 bag play`` offers again.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .._errors import NdlfdWarning, ValidationError
from .._fileformat import atomic_path
from .._trajectory import rest_points
from ..demonstration import Demonstration
from ._bag import BAG_SUFFIXES, rosbags_modules, typestore

__all__ = [
    "JOINT_UNITS",
    "TRAJECTORY_TOPIC",
    "joint_trajectory_points",
    "write_bag",
    "write_joint_trajectory",
]

#: The units joint angles may be given in: converted to radians for ROS.
JOINT_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}
#: Where a ``joint_trajectory_controller`` named so listens.
TRAJECTORY_TOPIC = "/joint_trajectory_controller/joint_trajectory"


def _start_ns(start_time: float) -> int:
    """Seconds since 1970 as nanoseconds, the whole seconds exact."""
    whole = math.floor(start_time)
    return int(whole) * 1_000_000_000 + round((start_time - whole) * 1e9)


def _time_ns(demo: Demonstration, start_time: float) -> np.ndarray:
    """The stamps ``t + start_time`` in nanoseconds (exact to 1 ns at epoch times)."""
    if not math.isfinite(start_time):
        raise ValidationError(
            f"start_time must be a number of seconds; got {start_time!r}"
        )
    ns = np.round(demo.t * 1e9).astype(np.int64) + _start_ns(start_time)
    if ns[0] < 0:
        raise ValidationError(
            f"a bag's time stamps must be >= 0; the demonstration starts at"
            f" {float(demo.t[0])!r} (pass start_time= to shift it)"
        )
    return ns


def _offered_qos():
    """The QoS profile rosbag2 records for a discovered publisher (rosbags' type)."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )

    forever = QosTime(sec=9223372036, nsec=854775807)  # rmw's "infinite"
    return Qos(
        QosHistory.UNKNOWN,
        0,
        QosReliability.RELIABLE,
        QosDurability.VOLATILE,
        forever,
        forever,
        QosLiveliness.AUTOMATIC,
        forever,
        False,
    )


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
        if g == "joint_velocity" and _joint_velocity(demo) is not None:
            continue  # in the joints' JointState
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


def _joint_velocity(demo: Demonstration) -> np.ndarray | None:
    """The joints' velocities when the group ``joint_velocity`` is ``NAME.vel`` of each.

    As :func:`~ndlfd.io.read_bag` reads a ``JointState``'s velocities (and
    LeRobot names them); ``None`` otherwise.
    """
    if not (demo.has_group("joints") and demo.has_group("joint_velocity")):
        return None
    pairs = list(zip(demo.columns, demo.groups, strict=True))
    joints = [c for c, g in pairs if g == "joints"]
    names = [c for c, g in pairs if g == "joint_velocity"]
    if names != [f"{c}.vel" for c in joints]:
        return None
    return demo.get("joint_velocity")


def _messages(T, demo, stream, ns, frame_id, joints):
    """The messages of one stream, one per sample.

    ``joints`` gives the ``joints`` group's names and positions (radians).
    """
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
    W = None
    if group == "joints":
        cols, V, W = joints
    for i in range(n):
        yield T[msgtype](
            header=_header(T, ns[i], frame_id),
            name=list(cols),
            position=np.array(V[i], dtype=np.float64),
            velocity=empty if W is None else np.array(W[i], dtype=np.float64),
            effort=empty,
        )


def _write_streams(final: Path, streams) -> Path:
    """Write ``streams`` (topic, msgtype, [(ns, message), ...]) as a bag at ``final``.

    ``NAME.mcap`` / ``NAME.db3``: one storage file; any other name: a bag
    folder that must not exist yet. Written beside it and renamed into place.
    """
    rosbag2, _ = rosbags_modules()
    store = typestore()
    suffix = final.suffix.lower()
    if suffix not in BAG_SUFFIXES and final.exists():
        raise ValidationError(
            f"{final} exists; a bag folder is written new (remove it first)"
        )
    final.parent.mkdir(parents=True, exist_ok=True)
    sqlite = suffix == ".db3"
    plugin = rosbag2.StoragePlugin.SQLITE3 if sqlite else rosbag2.StoragePlugin.MCAP
    tmp = Path(
        tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".tmp", dir=final.parent)
    )
    qos = [_offered_qos()]
    try:
        bag = tmp / (final.stem if suffix in BAG_SUFFIXES else final.name)
        with rosbag2.Writer(bag, version=8, storage_plugin=plugin) as writer:
            for topic, msgtype, messages in streams:
                conn = writer.add_connection(
                    topic, msgtype, typestore=store, offered_qos_profiles=qos
                )
                for ns, msg in messages:
                    writer.write(conn, int(ns), store.serialize_cdr(msg, msgtype))
        if suffix in BAG_SUFFIXES:
            with atomic_path(final) as out:
                os.replace(bag / f"{bag.name}{'.db3' if sqlite else '.mcap'}", out)
        else:
            os.rename(bag, final)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return final


def _check_demo(demo) -> None:
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )


def _check_topic(topic) -> None:
    if not (isinstance(topic, str) and topic.startswith("/") and len(topic) > 1):
        raise ValidationError(f"topic must be a name like '/ndlfd/path'; got {topic!r}")


def write_bag(
    demo: Demonstration,
    path: str | os.PathLike,
    *,
    topic: str = "/ndlfd/path",
    frame_id: str = "world",
    start_time: float = 0.0,
    joint_names: Sequence[str] | None = None,
    units: str = "rad",
) -> Path:
    """Write a demonstration as a ROS 2 bag that ``ros2 bag play`` replays, atomically.

    One message per sample and stream, with the header stamp and the receive
    time both ``t + start_time``: a ``geometry_msgs/msg/PoseStamped`` on
    ``topic`` for position (up to 3 columns, missing ones 0) and orientation
    (identity when absent); a ``sensor_msgs/msg/JointState`` on
    ``TOPIC/joint_states`` for the group ``joints`` (in radians; with the
    velocities of a group ``joint_velocity`` named ``NAME.vel``, as
    :func:`~ndlfd.io.read_bag` reads them, in radians per second); and for each
    other group (a gripper, but not velocity) ``TOPIC/GROUP``: a
    ``std_msgs/msg/Float64`` for one column, a ``JointState`` named after the
    columns for several.

    The bag is rosbag2 format version 8 (ROS 2 Jazzy's), written by rosbags,
    each topic with the QoS profile ``ros2 bag record`` stores; it is written
    beside ``path`` and renamed into place. Velocity is not written (a pose
    stream has none). Needs the ``ros`` extra (``pip install "ndlfd[ros]"``).

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
        The headers' frame (the frame the data were read in: a bag's
        ``header.frame_id``, or the base frame of a tf chain).
    start_time : float, default=0.0
        Seconds added to ``demo.t`` for the stamps (which must be >= 0); the
        seconds since 1970 of a real recording (``time.time()``) give absolute
        stamps.
    joint_names : sequence of str, optional
        The joints' names in the ``JointState`` (the URDF's), one per column of
        the group ``joints``; default: the columns' names.
    units : {"rad", "deg"}, default="rad"
        The units of the group ``joints``; degrees are written as radians.

    Returns
    -------
    path : Path
    """
    _check_demo(demo)
    _check_topic(topic)
    if not isinstance(frame_id, str):
        raise ValidationError(f"frame_id must be a frame name; got {frame_id!r}")
    _units_factor(units)
    rosbags_modules()
    T = typestore().types
    streams = _bag_streams(demo, topic)
    ns = _time_ns(demo, float(start_time))
    joints = None
    if demo.has_group("joints"):
        cols = [
            c for c, g in zip(demo.columns, demo.groups, strict=True) if g == "joints"
        ]
        W = _joint_velocity(demo)
        joints = (
            _mapped(cols, joint_names),
            _radians(demo.get("joints"), cols, units),
            None if W is None else W * JOINT_UNITS[units],
        )
    elif joint_names is not None:
        raise ValidationError(
            "joint_names names the columns of the group 'joints'; the path has"
            f" {', '.join(demo.group_names)}"
        )
    out = [
        (
            st[0],
            st[1],
            zip(ns, _messages(T, demo, st, ns, frame_id, joints), strict=True),
        )
        for st in streams
    ]
    return _write_streams(Path(path), out)


def _radians(Q: np.ndarray, cols, units: str) -> np.ndarray:
    """The joints in radians; a warning when radians were said but look like degrees."""
    factor = _units_factor(units)
    peak = float(np.max(np.abs(Q))) if Q.size else 0.0
    if units == "rad" and peak > 2 * math.pi:
        warnings.warn(
            f"the joints {', '.join(cols)} reach {peak:.4g}, more than a turn in"
            " radians: if they are degrees (LeRobot's SO-100/101 arms), say so"
            " with units='deg' (--units deg); ROS wants radians",
            NdlfdWarning,
            stacklevel=4,
        )
    return Q * factor


def _units_factor(units) -> float:
    if units not in JOINT_UNITS:
        raise ValidationError(
            f"units must be one of {', '.join(map(repr, JOINT_UNITS))} (the joint"
            f" angles' units; ROS wants radians); got {units!r}"
        )
    return JOINT_UNITS[units]


def _mapped(columns: Sequence[str], joint_names) -> list[str]:
    """The joints' names: ``joint_names`` (one per column) or the columns'."""
    if joint_names is None:
        return list(columns)
    if isinstance(joint_names, str):
        raise ValidationError(
            f"joint_names must be a list of names; got the string {joint_names!r}"
        )
    names = list(joint_names)
    if len(names) != len(columns) or not all(isinstance(n, str) and n for n in names):
        raise ValidationError(
            f"joint_names must give one name per joint: {len(columns)} for"
            f" {', '.join(columns)}; got {len(names)} ({', '.join(map(str, names))})"
        )
    if len(set(names)) != len(names):
        raise ValidationError(f"joint_names names a joint twice; got {names}")
    return names


# ---------------------------------------------------------- joint trajectory
def _yaml_float(v: float) -> str:
    """A float YAML 1.1 (PyYAML, ``ros2 topic pub``) reads back exactly."""
    text = repr(float(v))
    if "e" in text and "." not in text:  # 1e-05 is a string to YAML 1.1
        text = text.replace("e", ".0e")
    return text


def _yaml_name(name: str) -> str:
    return "'" + name.replace("'", "''") + "'"


def _split_ns(seconds: float) -> tuple[int, int]:
    ns = round(seconds * 1e9)
    return ns // 1_000_000_000, ns % 1_000_000_000


def _duration(seconds: float) -> str:
    sec, nanosec = _split_ns(seconds)
    return f"{{sec: {sec}, nanosec: {nanosec}}}"


def joint_trajectory_points(
    demo: Demonstration,
    *,
    group: str = "joints",
    gripper: str | None = "gripper",
    joint_names: Sequence[str] | None = None,
    units: str = "rad",
    ease: float | None = None,
    moving_start: bool = False,
):
    """The joints, positions, velocities and accelerations of a JointTrajectory.

    The positions are the path's (in radians), come to rest: where the path
    still moves at its first or last sample, its clock is eased to a stop
    along the same route (:func:`ndlfd._trajectory.come_to_rest`; the
    trajectory then lasts a little longer, half the easing at each such
    end). The velocities and accelerations are the derivatives of one curve
    through those positions, the cubic spline with velocity 0 at the ends
    (:func:`ndlfd._trajectory.rest_curve`): a ROS 2
    ``joint_trajectory_controller``, interpolating quintic (positions,
    velocities, accelerations) or cubic (positions, velocities) Hermite
    polynomials between the points, follows exactly that curve, and it stops
    at the last point (``allow_nonzero_velocity_at_trajectory_end`` false).
    A column switching between two values (a gripper) is held and written
    with velocity and acceleration 0.

    Parameters
    ----------
    demo : Demonstration
        The path; needs the group ``group``.
    group : str, default="joints"
        The group holding the joint positions.
    gripper : str or None, default="gripper"
        A group written as more joints after them when the path has it (each
        column one joint, named after it); ``None``: left out.
    joint_names : sequence of str, optional
        The joints' names (the URDF's), one per joint written; default the
        columns' names.
    units : {"rad", "deg"}, default="rad"
        The units of the positions; degrees are converted to radians.
    ease : float, optional
        The least seconds over which a moving end is eased to rest; default
        10 % of the duration (longer where that would decelerate harder than
        the path's own peak).
    moving_start : bool, default=False
        The first point is where a moving robot is now (the continuation of
        an executed prefix): its velocity and acceleration are the path's
        there, not 0, and only the last end comes to rest.

    Returns
    -------
    names : list of str
    times : ndarray of shape (m,)
        Seconds from the first point (``m >= n``: longer when eased).
    positions, velocities, accelerations : ndarray of shape (m, n_joints)

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> d = Demonstration.from_arrays(t, joints=np.column_stack([t * t * (3 - 2 * t)]))
    >>> _, s, Q, V, A = joint_trajectory_points(d)  # at rest at both ends already
    >>> s.size, V[[0, -1], 0].tolist()
    (101, [0.0, 0.0])
    >>> bool(np.allclose(V[:, 0], 6 * t * (1 - t), atol=1e-4))  # the curve's own
    True
    """
    _check_demo(demo)
    if not demo.has_group(group):
        raise ValidationError(
            f"a joint trajectory needs the group {group!r} (the joint positions);"
            f" the path has {', '.join(demo.group_names)}"
        )
    groups = [group]
    if gripper is not None and gripper != group and demo.has_group(gripper):
        groups.append(gripper)
    cols = [c for g in groups for c, h in zip(demo.columns, demo.groups, strict=True)
            if h == g]  # fmt: skip
    names = _mapped(cols, joint_names)
    Q = _radians(np.column_stack([demo.get(g) for g in groups]), cols, units)
    t = demo.t - demo.t[0]
    if demo.n_samples < 2:
        zeros = np.zeros_like(Q)
        return names, t, Q, zeros, zeros.copy()
    span = float(t[-1])
    if ease is not None and not (isinstance(ease, (int, float)) and 0 <= ease <= span):
        raise ValidationError(
            f"ease must be a number of seconds in [0, {span:g}] (the path's"
            f" duration); got {ease!r}"
        )
    held = np.array([np.unique(Q[:, j]).size == 2 for j in range(Q.shape[1])])
    t, Q, V, A = rest_points(t, Q, moving_start=moving_start, ease=ease, held=held)
    return names, t, Q, V, A


def _point_lines(names, t, Q, V, A) -> list[str]:
    lines = [
        "header: {stamp: {sec: 0, nanosec: 0}, frame_id: ''}",
        f"joint_names: [{', '.join(_yaml_name(c) for c in names)}]",
        "points:",
    ]
    for q, v, a, s in zip(Q, V, A, t, strict=True):
        lines.append(
            f"- {{positions: [{', '.join(map(_yaml_float, q))}],"
            f" velocities: [{', '.join(map(_yaml_float, v))}],"
            f" accelerations: [{', '.join(map(_yaml_float, a))}],"
            f" time_from_start: {_duration(s)}}}"
        )
    return lines


def _trajectory_message(names, t, Q, V, A):
    T = typestore().types
    Duration = T["builtin_interfaces/msg/Duration"]
    Point = T["trajectory_msgs/msg/JointTrajectoryPoint"]
    points = [
        Point(
            positions=np.array(q, dtype=np.float64),
            velocities=np.array(v, dtype=np.float64),
            accelerations=np.array(a, dtype=np.float64),
            effort=np.zeros(0, dtype=np.float64),
            time_from_start=Duration(*_split_ns(s)),
        )
        for q, v, a, s in zip(Q, V, A, t, strict=True)
    ]
    return T["trajectory_msgs/msg/JointTrajectory"](
        header=_header(T, 0, ""), joint_names=list(names), points=points
    )


def write_joint_trajectory(
    demo: Demonstration,
    path: str | os.PathLike,
    *,
    group: str = "joints",
    gripper: str | None = "gripper",
    joint_names: Sequence[str] | None = None,
    units: str = "rad",
    ease: float | None = None,
    topic: str = TRAJECTORY_TOPIC,
    start_time: float = 0.0,
    moving_start: bool = False,
) -> Path:
    r"""Write a ``trajectory_msgs/msg/JointTrajectory``, atomically: YAML or a bag.

    One point per sample: the positions of ``group``'s columns (then the
    gripper's), in radians, come to rest at the ends; the velocities and
    accelerations of the one curve through them that a
    ``joint_trajectory_controller`` follows (see
    :func:`joint_trajectory_points`); and
    ``time_from_start`` (seconds from the first sample, as ``sec``/
    ``nanosec``). The header's stamp is zero (start now) and its frame empty.

    ``path`` ending in ``.yaml``/``.yml``: the message in YAML flow style,
    floats written so that they read back exactly (needs no extra). Any other
    name: a ROS 2 bag (``.mcap``, ``.db3`` or a bag folder, as
    :func:`write_bag`) holding the one message on ``topic``, received at
    ``start_time``; ``ros2 bag play`` sends it to the controller whatever its
    size (a YAML file of a few thousand points is too long for a shell's
    argument list, so ``ros2 topic pub ... "$(cat path.yaml)"`` fails)::

        ros2 bag play traj_bag

    Parameters
    ----------
    demo : Demonstration
        The path; needs the group ``group``.
    path : str or path-like
        The YAML file or the bag.
    group, gripper, joint_names, units, ease, moving_start
        See :func:`joint_trajectory_points`.
    topic : str, default="/joint_trajectory_controller/joint_trajectory"
        The topic of a bag.
    start_time : float, default=0.0
        The receive time of a bag's message (seconds since 1970).

    Returns
    -------
    path : Path

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = Demonstration.from_arrays(  # a smooth step, at rest at both ends
    ...     [0.0, 0.25, 0.5, 0.75, 1.0],
    ...     joints=[[0.0, 1.0], [0.15625, 1.0], [0.5, 1.0], [0.84375, 1.0], [1.0, 1.0]],
    ...     columns={"joints": ["a", "b"]})
    >>> p = write_joint_trajectory(d, pathlib.Path(tempfile.mkdtemp()) / "j.yaml")
    >>> print(p.read_text())
    header: {stamp: {sec: 0, nanosec: 0}, frame_id: ''}
    joint_names: ['a', 'b']
    points:
    - {positions: [0.0, 1.0], velocities: [0.0, 0.0], accelerations: [6.0, 0.0], time_from_start: {sec: 0, nanosec: 0}}
    - {positions: [0.15625, 1.0], velocities: [1.125, 0.0], accelerations: [3.0, 0.0], time_from_start: {sec: 0, nanosec: 250000000}}
    - {positions: [0.5, 1.0], velocities: [1.5, 0.0], accelerations: [0.0, 0.0], time_from_start: {sec: 0, nanosec: 500000000}}
    - {positions: [0.84375, 1.0], velocities: [1.125, 0.0], accelerations: [-3.0, 0.0], time_from_start: {sec: 0, nanosec: 750000000}}
    - {positions: [1.0, 1.0], velocities: [0.0, 0.0], accelerations: [-6.0, 0.0], time_from_start: {sec: 1, nanosec: 0}}
    <BLANKLINE>
    """  # noqa: E501
    names, t, Q, V, A = joint_trajectory_points(
        demo,
        group=group,
        gripper=gripper,
        joint_names=joint_names,
        units=units,
        ease=ease,
        moving_start=moving_start,
    )
    final = Path(path)
    if final.suffix.lower() in (".yaml", ".yml"):
        with atomic_path(final) as tmp:
            tmp.write_text("\n".join(_point_lines(names, t, Q, V, A)) + "\n")
        return final
    _check_topic(topic)
    ns = _start_ns(float(start_time)) if math.isfinite(start_time) else -1
    if not ns >= 0:
        raise ValidationError(f"start_time must be >= 0 seconds; got {start_time!r}")
    msg = _trajectory_message(names, t, Q, V, A)
    return _write_streams(
        final, [(topic, "trajectory_msgs/msg/JointTrajectory", [(ns, msg)])]
    )
