"""JointTrajectory output: ends at rest, names, units, the message's structure."""

import dataclasses

import numpy as np
import pytest

pytest.importorskip("rosbags")

from bag_samples import STORE, T, rosbags_read
from ndlfd import NdlfdWarning
from ndlfd._errors import ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import write_bag, write_joint_trajectory

yaml = pytest.importorskip("yaml")
JT = "trajectory_msgs/msg/JointTrajectory"


def so101_like(n=181, seconds=6.0):
    """Five arm joints and a gripper in degrees, moving at both ends."""
    t = np.linspace(0.0, seconds, n)
    s = t / seconds
    joints = np.column_stack(
        [40 * np.sin(2 * s + 0.3 * k) + 10 * k for k in range(5)]
    )  # degrees, not at rest at either end
    grip = 20 + 15 * np.sin(3 * s)
    names = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll"]
    return Demonstration.from_arrays(
        t, joints=joints, gripper=grip[:, None],
        columns={"joints": names, "gripper": ["gripper"]},
    )  # fmt: skip


NESTED = {
    "header": "std_msgs/msg/Header",
    "stamp": "builtin_interfaces/msg/Time",
    "time_from_start": "builtin_interfaces/msg/Duration",
}


def from_yaml(entry, name):
    """A rosbags message of type ``name`` from a YAML mapping, fields checked.

    Every key must be a field of the type (rosbags' definition of ROS 2's);
    a field left out takes its default as ``ros2 topic pub`` fills it (only
    ``effort`` may be left out).
    """
    fields = [f.name for f in dataclasses.fields(T[name])]
    assert set(entry) <= set(fields), f"{set(entry) - set(fields)} not in {name}"
    values = {}
    for key in fields:
        v = entry.get(key)
        if key in NESTED:
            v = from_yaml(v, NESTED[key])
        elif key == "points":
            v = [from_yaml(p, "trajectory_msgs/msg/JointTrajectoryPoint") for p in v]
        elif key == "effort":
            assert v is None
            v = np.zeros(0)
        elif key in ("positions", "velocities", "accelerations"):
            v = np.array(v, dtype=np.float64)
        values[key] = v
    return T[name](**values)


def check_structure(msg):
    """What a joint_trajectory_controller checks before it accepts a trajectory."""
    raw = STORE.serialize_cdr(msg, JT)  # every field of the right type
    back = STORE.deserialize_cdr(raw, JT)
    n = len(back.joint_names)
    assert n == len(set(back.joint_names)) > 0
    ns = [
        p.time_from_start.sec * 10**9 + p.time_from_start.nanosec for p in back.points
    ]
    assert ns[0] >= 0 and np.all(np.diff(ns) > 0)
    for p in back.points:
        assert len(p.positions) == len(p.velocities) == len(p.accelerations) == n
    for end in (back.points[0], back.points[-1]):
        assert np.all(end.velocities == 0.0)
    return back


def test_trajectory_ends_at_rest_in_radians_with_the_gripper(tmp_path):
    demo = so101_like()
    urdf = ["j1", "j2", "j3", "j4", "j5", "jaw"]
    p = write_joint_trajectory(demo, tmp_path / "t.yaml", units="deg", joint_names=urdf)
    msg = check_structure(from_yaml(yaml.safe_load(p.read_text()), JT))
    assert msg.joint_names == urdf
    want_q = np.deg2rad(np.column_stack([demo.get("joints"), demo.get("gripper")]))
    got_q = np.array([pt.positions for pt in msg.points])
    t = np.array([pt.time_from_start.sec + pt.time_from_start.nanosec * 1e-9
                  for pt in msg.points])  # fmt: skip
    # moving at both ends: eased to rest along the same route, the same step
    assert t[-1] > demo.duration and np.allclose(np.diff(t), demo.t[1])
    assert np.array_equal(got_q[[0, -1]], want_q[[0, -1]])
    steps = np.abs(np.diff(got_q, axis=0))
    assert steps[[0, -1]].max() <= 0.01 * steps.max()  # the positions stop
    # the velocities and accelerations are the positions' own: central
    # differences agree to the step's order
    got_v = np.array([pt.velocities for pt in msg.points])
    got_a = np.array([pt.accelerations for pt in msg.points])
    assert got_v[0].tolist() == got_v[-1].tolist() == [0.0] * 6
    g = np.gradient(got_q, t, axis=0)
    assert np.abs(got_v - g)[1:-1].max() <= 5e-3 * np.abs(g).max()
    ga = np.gradient(got_v, t, axis=0)
    assert np.abs(got_a - ga)[2:-2].max() <= 0.02 * np.abs(ga).max()
    # in the middle the route is the demonstration's, shifted by the easing
    mid = got_q[60:-60]
    near = np.abs(mid[:, None, :] - want_q[None, :, :]).sum(axis=2).min(axis=1)
    assert near.max() <= np.abs(np.diff(want_q, axis=0)).sum(axis=1).max()
    # the same message as a bag of one message, for ros2 bag play
    bag = write_joint_trajectory(demo, tmp_path / "traj_bag", units="deg")
    ((ns, played),) = rosbags_read(bag, "/joint_trajectory_controller/joint_trajectory")
    assert ns == 0 and played.joint_names == [*demo.columns[:5], "gripper"]
    assert np.array_equal([pt.positions for pt in played.points], got_q)
    check_structure(played)
    info = yaml.safe_load((bag / "metadata.yaml").read_text())
    (topic,) = info["rosbag2_bagfile_information"]["topics_with_message_count"]
    qos = yaml.safe_load(topic["topic_metadata"]["offered_qos_profiles"])
    assert qos[0]["reliability"] == 1 and qos[0]["durability"] == 2  # reliable
    assert qos[0]["deadline"] == {"sec": 9223372036, "nsec": 854775807}


def test_trajectory_names_units_and_errors(tmp_path):
    demo = so101_like(n=31)
    with pytest.warns(NdlfdWarning, match=r"reach .* more than a turn in radians.*"
                      r"units='deg' \(--units deg\)"):  # fmt: skip
        write_joint_trajectory(demo, tmp_path / "deg.yaml")
    with pytest.raises(
        ValidationError,
        match=r"joint_names must give one name per joint: 6 for shoulder_pan,"
        r" .*, gripper; got 2 \(a, b\)",
    ):
        write_joint_trajectory(demo, tmp_path / "x.yaml", joint_names=["a", "b"],
                               units="deg")  # fmt: skip
    with pytest.raises(ValidationError, match=r"units must be one of 'rad', 'deg'"):
        write_joint_trajectory(demo, tmp_path / "x.yaml", units="degrees")
    p = write_joint_trajectory(demo, tmp_path / "arm.yaml", gripper=None, units="deg")
    assert len(yaml.safe_load(p.read_text())["joint_names"]) == 5
    # JointState in a bag: radians, URDF names
    names = ["a", "b", "c", "d", "e"]
    out = write_bag(demo, tmp_path / "js.mcap", units="deg", joint_names=names)
    got = rosbags_read(out, "/ndlfd/path/joint_states")
    assert got[0][1].name == names
    assert np.array_equal([m.position for _, m in got], np.deg2rad(demo.get("joints")))


def test_joint_velocities_go_in_the_joint_states_and_read_back(tmp_path):
    from rosbags.rosbag2 import Reader

    from ndlfd.io import read_bag

    rng = np.random.default_rng(4)
    t = np.arange(12) / 8.0
    q, w = rng.normal(size=(12, 2)) * 30, rng.normal(size=(12, 2)) * 10
    demo = Demonstration.from_arrays(
        t, joints=q, joint_velocity=w,
        columns={"joints": ["a", "b"], "joint_velocity": ["a.vel", "b.vel"]},
    )  # fmt: skip
    out = write_bag(demo, tmp_path / "js.mcap", units="deg")
    with Reader(out) as r:
        assert sorted(r.topics) == ["/ndlfd/path/joint_states"]
    (back,) = read_bag(out)
    assert back.columns == demo.columns and back.groups == demo.groups
    assert np.allclose(back.get("joints"), np.deg2rad(q), rtol=1e-15)
    assert np.allclose(back.get("joint_velocity"), np.deg2rad(w), rtol=1e-15)


def test_a_continuation_starts_moving_and_ends_at_rest(tmp_path):
    # the first point is where a moving robot is now: its velocity is the
    # positions' own there, only the end comes to rest
    demo = so101_like()
    out = write_joint_trajectory(demo, tmp_path / "c.yaml", units="deg",
                                 moving_start=True)  # fmt: skip
    msg = yaml.safe_load(out.read_text())
    V = np.array([p["velocities"] for p in msg["points"]])
    P = np.array([p["positions"] for p in msg["points"]])
    Q = np.radians(np.column_stack([demo.get("joints"), demo.get("gripper")]))
    half = demo.n_samples // 2
    np.testing.assert_allclose(P[:half], Q[:half], atol=1e-12)  # not eased there
    want = np.gradient(Q, demo.t, axis=0, edge_order=2)
    np.testing.assert_allclose(V[:half], want[:half], atol=1e-3 * np.abs(want).max())
    assert np.abs(V[0]).min() > 0.0 and np.all(V[-1] == 0.0)
    rest = write_joint_trajectory(demo, tmp_path / "r.yaml", units="deg")
    first = yaml.safe_load(rest.read_text())["points"][0]
    assert np.all(np.array(first["velocities"]) == 0.0)
