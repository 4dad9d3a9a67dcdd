"""ROS 2 bags written with rosbags' own Writer, for the bag tests."""

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore
from scipy.spatial.transform import Rotation

from ndlfd.demonstration import Demonstration

STORE = get_typestore(Stores.LATEST)
T = STORE.types
STORAGES = {"mcap": StoragePlugin.MCAP, "sqlite3": StoragePlugin.SQLITE3}
T0 = 1_700_000_000 * 10**9


def header(ns, frame="world"):
    stamp = T["builtin_interfaces/msg/Time"](
        sec=int(ns // 10**9), nanosec=int(ns % 10**9)
    )
    return T["std_msgs/msg/Header"](stamp=stamp, frame_id=frame)


def pose(p, q):
    """A geometry_msgs Pose from (x, y, z) and (w, x, y, z)."""
    return T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2]),
        orientation=T["geometry_msgs/msg/Quaternion"](w=q[0], x=q[1], y=q[2], z=q[3]),
    )


def pose_stamped(ns, p, q):
    return T["geometry_msgs/msg/PoseStamped"](header=header(ns), pose=pose(p, q))


def transform(ns, child, p, q, parent="world"):
    """A TransformStamped: the pose (x, y, z), (w, x, y, z) of child in parent."""
    tr = T["geometry_msgs/msg/Transform"](
        translation=T["geometry_msgs/msg/Vector3"](x=p[0], y=p[1], z=p[2]),
        rotation=T["geometry_msgs/msg/Quaternion"](w=q[0], x=q[1], y=q[2], z=q[3]),
    )
    return T["geometry_msgs/msg/TransformStamped"](
        header=header(ns, parent), child_frame_id=child, transform=tr
    )


def tf_message(*transforms):
    """A tf2_msgs/msg/TFMessage (what /tf and /tf_static carry)."""
    return T["tf2_msgs/msg/TFMessage"](transforms=list(transforms))


def odometry(ns, p, q):
    cov = T["geometry_msgs/msg/PoseWithCovariance"](
        pose=pose(p, q), covariance=np.zeros(36)
    )
    twist = T["geometry_msgs/msg/TwistWithCovariance"](
        twist=T["geometry_msgs/msg/Twist"](
            linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
            angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
        ),
        covariance=np.zeros(36),
    )
    return T["nav_msgs/msg/Odometry"](
        header=header(ns), child_frame_id="base", pose=cov, twist=twist
    )


def joint_state(ns, names, values):
    empty = np.zeros(0)
    return T["sensor_msgs/msg/JointState"](
        header=header(ns, ""),
        name=list(names),
        position=np.array(values, dtype=float),
        velocity=empty,
        effort=empty,
    )


def float64(v):
    return T["std_msgs/msg/Float64"](data=float(v))


def offered_qos(latched=False):
    """The QoS profile ``ros2 bag record`` stores for a publisher it discovered.

    Reliable and volatile (a sensor or ``/tf``), or transient local
    (``latched``: ``/tf_static``); history unknown, durations infinite.
    """
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )

    forever = QosTime(sec=9223372036, nsec=854775807)
    durable = QosDurability.TRANSIENT_LOCAL if latched else QosDurability.VOLATILE
    return Qos(
        QosHistory.UNKNOWN,
        0,
        QosReliability.RELIABLE,
        durable,
        forever,
        forever,
        QosLiveliness.AUTOMATIC,
        forever,
        False,
    )


def write_bag(path, topics, storage="mcap"):
    """A bag at ``path`` with ``topics``: {name: [(receive ns, msg), ...]}.

    Topics are recorded with the QoS ``ros2 bag record`` stores (``/tf_static``
    and other ``*_static`` topics latched).
    """
    with Writer(path, version=9, storage_plugin=STORAGES[storage]) as w:
        for name, msgs in topics.items():
            types = sorted({m.__msgtype__ for _, m in msgs}) or [
                "geometry_msgs/msg/PoseStamped"
            ]
            qos = [offered_qos(latched=name.endswith("_static"))]
            conns = {
                ty: w.add_connection(
                    name, ty, typestore=STORE, offered_qos_profiles=qos
                )
                for ty in types
            }
            for ns, m in msgs:
                w.write(conns[m.__msgtype__], ns, STORE.serialize_cdr(m, m.__msgtype__))
    return path


def reach_messages(n=40, seed=0, start_ns=1_700_000_000 * 10**9):
    """PoseStamped messages of a 3-D reach: (ns, pos, quat, messages)."""
    rng = np.random.default_rng(seed)
    ns = start_ns + np.cumsum(rng.integers(5_000_000, 20_000_000, n))
    s = np.linspace(0, 1, n)
    pos = np.column_stack([s, s**2, np.sin(s)]) + rng.normal(0, 1e-3, (n, 3))
    half = 0.5 * s
    quat = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
    msgs = [
        (int(k), pose_stamped(int(k), p, q))
        for k, p, q in zip(ns, pos, quat, strict=True)
    ]
    return ns, pos, quat, msgs


def rosbags_read(path, topic):
    """(receive ns, message) of ``topic``, read with rosbags alone."""
    from rosbags.rosbag2 import Reader

    with Reader(path) as r:
        conns = [c for c in r.connections if c.topic == topic]
        return [
            (ns, STORE.deserialize_cdr(raw, c.msgtype))
            for c, ns, raw in r.messages(connections=conns)
        ]


def pick_place_messages(n=120, seed=0, start_ns=1_700_000_000 * 10**9):
    """A 3-D pick-and-place recorded at about 20 Hz: (ns, pos, quat, poses, grip).

    The hand moves down to the grasp (0.4, 0, 0), closes, lifts and carries
    the part to the place (0.4, 0.5, 0) while turning 90 degrees about z, and
    opens there; each recording a little apart. ``poses`` are PoseStamped
    messages, ``grip`` Float64 messages of the gripper (0 open, 1 closed).
    """
    rng = np.random.default_rng(seed)
    ns = start_ns + np.cumsum(rng.integers(45_000_000, 55_000_000, n))
    tau = np.linspace(0.0, 1.0, n)

    def ramp(x):  # minimum jerk from 0 to 1
        x = np.clip(x, 0.0, 1.0)
        return 10 * x**3 - 15 * x**4 + 6 * x**5

    start, grasp, place = np.array([0.0, 0, 0.25]), np.array([0.4, 0, 0]), [0.4, 0.5, 0]
    a = ramp(tau / 0.35)[:, None]
    b = ramp((tau - 0.45) / 0.45)[:, None]
    pos = start + a * (grasp - start) + b * (np.asarray(place) - grasp)
    pos[:, 2] += 0.15 * np.sin(np.pi * b[:, 0])  # lift while carrying
    pos += rng.normal(0, 0.004, 3)
    yaw = 0.5 * np.pi * b[:, 0] + rng.normal(0, 0.02)
    pitch = 0.3 * np.sin(np.pi * a[:, 0])  # tilt on the way down
    # q = q_z(yaw) * q_y(pitch), as (w, x, y, z)
    cy, sy, cp, sp = (
        np.cos(yaw / 2),
        np.sin(yaw / 2),
        np.cos(pitch / 2),
        np.sin(pitch / 2),
    )
    quat = np.column_stack([cy * cp, -sy * sp, cy * sp, sy * cp])
    closed = (tau > 0.4) & (tau < 0.93)
    poses = [
        (int(k), pose_stamped(int(k), p, q))
        for k, p, q in zip(ns, pos, quat, strict=True)
    ]
    grip = [(int(k), float64(c)) for k, c in zip(ns, closed, strict=True)]
    return ns, pos, quat, poses, grip


def generated(n=25):
    """A path with every stream write_bag writes: pose, joints, gripper."""
    rng = np.random.default_rng(3)
    t = np.arange(n) / 64.0  # exact in nanoseconds
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return Demonstration.from_arrays(
        t,
        position=rng.normal(size=(n, 3)),
        orientation=q,
        joints=rng.normal(size=(n, 2)),
        gripper=(np.arange(n) > n // 2).astype(float),
        columns={"joints": ["j1", "j2"], "gripper": ["gripper"]},
    )


def wxyz(r):
    """A scipy Rotation as a quaternion (w, x, y, z)."""
    x, y, z, w = r.as_quat()
    return [w, x, y, z]


def chain_bag(path):
    """world -(static)- base_link - link1 - link2 -(static)- tool0, and a camera.

    link1 turns about z at 0.8 rad/s and rises 0.05 m/s, published every
    20 ms; link2 turns about y at -0.5 rad/s, published every 20 ms 7 ms
    later (another publisher): both linear in time, so slerp and linear
    interpolation between their messages are exact.
    """
    s1 = T0 + np.arange(60) * 20_000_000
    s2 = s1[:-2] + 7_000_000
    deg = Rotation.from_euler
    static = {
        "base_link": ("world", [1.0, 2.0, 0.0], deg("z", 30, degrees=True)),
        "tool0": ("link2", [0.1, 0.0, 0.05], deg("y", 20, degrees=True)),
        "camera_link": ("base_link", [0.2, -0.1, 0.5], deg("xz", [-90, 10], True)),
    }

    def link1(t):
        return [0.0, 0.0, 0.1 + 0.05 * t], Rotation.from_euler("z", 0.8 * t)

    def link2(t):
        return [0.3, 0.0, 0.0], Rotation.from_euler("y", 0.3 - 0.5 * t)

    tf = []
    for a, b in zip(s1, s2, strict=False):
        p, r = link1((a - T0) / 1e9)
        tf.append((int(a), tf_message(transform(a, "link1", p, wxyz(r), "base_link"))))
        p, r = link2((b - T0) / 1e9)
        tf.append((int(b), tf_message(transform(b, "link2", p, wxyz(r), "link1"))))
    for a in s1[len(s2) :]:
        p, r = link1((a - T0) / 1e9)
        tf.append((int(a), tf_message(transform(a, "link1", p, wxyz(r), "base_link"))))
    latched = tf_message(
        *(transform(T0, c, p, wxyz(r), parent) for c, (parent, p, r) in static.items())
    )
    js = [(int(a), joint_state(a, ["j1"], [0.8 * (a - T0) / 1e9])) for a in s1]
    write_bag(path, {"/tf": tf, "/tf_static": [(T0, latched)], "/joint_states": js})
    return path, s2, static, link1, link2


def _ramp(x):
    x = np.clip(x, 0.0, 1.0)
    return 10 * x**3 - 15 * x**4 + 6 * x**5


def session(n_demos=5, move=20.4, rest=3.0, hz=50, seed=0):
    """A robot's /tf over one session: rests of ``rest`` s between reaches.

    Each reach goes out and back (minimum jerk, 0.2 m along x and up in z);
    the arm rests between them with 20 um of encoder noise and /tf keeps
    publishing at ``hz``. Returns the stamps (s) and the motions' spans.
    """
    rng = np.random.default_rng(seed)
    total = rest + n_demos * (move + rest)
    t = np.arange(0.0, total, 1.0 / hz)
    x = np.full(t.size, 0.3)
    z = np.full(t.size, 0.2)
    spans = []
    for i in range(n_demos):
        a = rest + i * (move + rest)
        spans.append((a, a + move))
        u = (t - a) / move
        out = _ramp(2 * u) - _ramp(2 * u - 1)  # out and back
        x += (0.15 + 0.02 * i) * out
        z += 0.1 * np.sin(np.pi * np.clip(u, 0, 1)) ** 2
    x += rng.normal(0, 2e-5, t.size)
    return t, np.column_stack([x, 0 * x, z]), spans


def tf_bag(path, t, P):
    """A bag of /tf: tool0 in base_link at the poses ``P`` (no rotation)."""
    ns = T0 + np.round(t * 1e9).astype(np.int64)
    msgs = [
        (int(k), tf_message(transform(k, "tool0", p, [1.0, 0, 0, 0], "base_link")))
        for k, p in zip(ns, P, strict=True)
    ]
    return write_bag(path, {"/tf": msgs})
