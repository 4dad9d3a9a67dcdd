import pickle

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

pytest.importorskip("rosbags")

from bag_samples import (
    T,
    float64,
    generated,
    joint_state,
    odometry,
    pose_stamped,
    reach_messages,
    rosbags_read,
    transform,
    write_bag,
)
from ndlfd import NdlfdWarning
from ndlfd._errors import DataFileError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import (
    DemoFiles,
    demo_files,
    read_bag,
    read_demos,
    write_joint_trajectory,
)
from ndlfd.io import write_bag as ndlfd_write_bag
from ndlfd.io._bagout import joint_trajectory_points


def seconds(ns):
    return (np.asarray(ns) - ns[0]) / 1e9


@pytest.mark.parametrize("storage,suffix", [("mcap", ".mcap"), ("sqlite3", ".db3")])
def test_pose_bag_reads_the_arrays_written(tmp_path, storage, suffix):
    ns, pos, quat, msgs = reach_messages()
    bag = write_bag(tmp_path / "reach", {"/ee_pose": msgs}, storage)
    want = Demonstration.from_arrays(seconds(ns), position=pos, orientation=quat)
    got = read_bag(bag, "/ee_pose")
    assert got == [want]
    assert np.array_equal(got[0].X[:, :3], pos)  # exactly
    assert np.array_equal(got[0].X[:, 3:], quat)
    # the storage file alone, the only topic by default, a folder of bags
    assert read_bag(bag / f"reach{suffix}") == [want]
    assert read_bag(bag) == [want]
    write_bag(tmp_path / "reach2", {"/ee_pose": msgs}, storage)
    assert demo_files(tmp_path) == [tmp_path / "reach", tmp_path / "reach2"]
    demos, maps = read_demos(tmp_path, topic="/ee_pose", return_mappings=True)
    assert demos == [want, want]
    assert str(maps[0]) == (
        "time=/ee_pose stamps; position=x,y,z; orientation=qw,qx,qy,qz"
        " (ROS 2 bag, frame world)"
    )


def test_bags_stream_one_item_per_bag(tmp_path):
    for i in range(3):
        _, _, _, msgs = reach_messages(seed=i)
        write_bag(tmp_path / f"b{i}", {"/ee_pose": msgs})
    files = DemoFiles(tmp_path, topic="/ee_pose", split_gap=1.0)
    assert len(files) == 3 and files[1].path == tmp_path / "b1"
    first = pickle.loads(pickle.dumps(files[0])).read()  # as a worker reads it
    assert np.array_equal(first[0].get("position"), reach_messages(seed=0)[1])
    with pytest.raises(ValidationError, match=r"unexpected argument.*'topics'"):
        DemoFiles(tmp_path, topics="/ee_pose")


def test_joint_states_by_name_and_by_set_of_joints(tmp_path):
    ns = 10**9 + np.arange(6) * 10_000_000
    values = np.random.default_rng(0).normal(size=(6, 3))
    names = ["wrist", "elbow", "shoulder"]
    msgs = [(int(k), joint_state(k, names, v)) for k, v in zip(ns, values, strict=True)]
    msgs[2] = (int(ns[2]), joint_state(ns[2], names[::-1], values[2, ::-1]))
    bag = write_bag(tmp_path / "js", {"/joint_states": msgs}, "sqlite3")
    (d,) = read_bag(bag, "/joint_states")
    assert d.columns == tuple(names) and d.groups == ("joints",) * 3
    assert np.array_equal(d.X, values) and np.allclose(d.t, seconds(ns))
    # a gripper publishing its own joint on the same topic: a stream of its own
    ns_f = ns[:4] + 5_000_000
    finger = np.array([0.0, 0.01, 0.03, 0.04])
    grip = [
        (int(k), joint_state(k, ["finger"], [f]))
        for k, f in zip(ns_f, finger, strict=True)
    ]
    both = sorted([*msgs, *grip], key=lambda x: x[0])
    bag = write_bag(tmp_path / "js2", {"/joint_states": both})
    (d,) = read_bag(bag, "/joint_states")
    assert d.columns == (*names, "finger") and d.groups == ("joints",) * 4
    assert np.array_equal(d.X[:, :3], values)
    assert np.allclose(d.X[:, 3], np.interp(ns, ns_f, finger))
    # positions that do not match the names
    bad = [*msgs, (int(ns[-1]) + 10**7, joint_state(0, names, [0.0, 1.0]))]
    bag = write_bag(tmp_path / "js3", {"/joint_states": bad})
    with pytest.raises(
        DataFileError,
        match=r"js3: JointState message 6 on '/joint_states' has 2 positions for"
        r" the joints wrist, elbow, shoulder; expected one per joint",
    ):
        read_bag(bag, "/joint_states")


def test_tf_picks_the_child_frame(tmp_path):
    ns, pos, quat, _ = reach_messages(n=10)
    tf = T["tf2_msgs/msg/TFMessage"]
    msgs = [
        (
            int(k),
            tf(
                transforms=[
                    transform(k, "ee", p, q),
                    transform(k, "base", -p, [1.0, 0, 0, 0]),
                ]
            ),
        )
        for k, p, q in zip(ns, pos, quat, strict=True)
    ]
    bag = write_bag(tmp_path / "tf", {"/tf": msgs})
    (d,) = read_bag(bag, "/tf", frame="ee")
    assert np.array_equal(d.get("position"), pos)
    assert np.array_equal(d.get("orientation"), quat)
    with pytest.raises(
        DataFileError,
        match=r"'/tf' has several child frames; pick"
        r" one with frame= \(child frames there: base, ee\)",
    ):
        read_bag(bag, "/tf")
    with pytest.raises(DataFileError, match="no frame 'hand' in the tf tree of /tf;"):
        read_bag(bag, "/tf", frame="hand")
    # TransformStamped on a topic of its own, and Odometry
    one = [
        (int(k), transform(k, "ee", p, q))
        for k, p, q in zip(ns, pos, quat, strict=True)
    ]
    odo = [(int(k), odometry(k, p, q)) for k, p, q in zip(ns, pos, quat, strict=True)]
    bag = write_bag(tmp_path / "more", {"/ee": one, "/odom": odo})
    for topic in ("/ee", "/odom"):
        (d,) = read_bag(bag, topic)
        assert np.array_equal(d.get("position"), pos)


def test_topics_combine_on_the_first_topics_stamps(tmp_path):
    ns, pos, _, msgs = reach_messages(n=60)
    slow = ns[0] + np.arange(0, ns[-1] - ns[0], 100_000_000)  # 10 Hz, no header
    grip = (np.arange(slow.size) % 2).astype(float)
    ns2 = ns[0] + 3_000_000 + np.arange(30) * 15_000_000
    q2 = np.column_stack(
        [
            np.cos(np.linspace(0, 1, 30)),
            np.zeros(30),
            np.sin(np.linspace(0, 1, 30)),
            np.zeros(30),
        ]
    )
    p2 = np.random.default_rng(1).normal(size=(30, 3))
    bag = write_bag(
        tmp_path / "multi",
        {
            "/ee_pose": msgs,
            "/gripper": [(int(k), float64(g)) for k, g in zip(slow, grip, strict=True)],
            "/target": [
                (int(k), pose_stamped(k, p, q))
                for k, p, q in zip(ns2, p2, q2, strict=True)
            ],
        },
    )
    with pytest.warns(
        NdlfdWarning,
        match=r"rates differ by more than 2x .*/gripper"
        r" 10 Hz.*onto the stamps of /ee_pose",
    ):
        (d,) = read_bag(bag, ["/ee_pose", "/gripper", "/target"])
    assert d.group_names == ("position", "orientation", "gripper", "target")
    t = seconds(ns)
    assert np.array_equal(d.get("position"), pos)
    want_grip = np.interp(t, (slow - ns[0]) / 1e9, grip)
    assert np.allclose(d.get("gripper")[:, 0], want_grip)
    from scipy.spatial.transform import Rotation, Slerp

    x2 = (ns2 - ns[0]) / 1e9
    want_q = Slerp(x2, Rotation.from_quat(q2[:, [1, 2, 3, 0]]))(
        np.clip(t, x2[0], x2[-1])
    ).as_quat()[:, [3, 0, 1, 2]]
    got_q = d.get("target")[:, 3:]
    assert np.allclose(np.abs(np.sum(got_q * want_q, axis=1)), 1.0)
    assert d.columns[-7:] == tuple(f"target_{c}" for c in "x y z qw qx qy qz".split())
    assert np.allclose(d.get("target")[:, 0], np.interp(t, x2, p2[:, 0]))


def test_receive_time_without_stamps_and_split_gap(tmp_path):
    ns = np.concatenate([np.arange(10), 600 + np.arange(5)]) * 10_000_000 + 5 * 10**9
    pos = np.random.default_rng(0).normal(size=(15, 3))
    msgs = [
        (int(k), pose_stamped(0, p, [1.0, 0, 0, 0]))  # header stamps unset
        for k, p in zip(ns, pos, strict=True)
    ]
    bag = write_bag(tmp_path / "gap", {"/ee_pose": msgs})
    (d,) = read_bag(bag, "/ee_pose")
    assert np.allclose(d.t, seconds(ns))
    demos, maps = read_demos(bag, topic="/ee_pose", split_gap=1.0, return_mappings=True)
    assert [x.n_samples for x in demos] == [10, 5]
    assert [m.source for m in maps] == [f"{bag}:0", f"{bag}:1"]
    # where each piece lies: 0 to 90 ms, then 6.00 s to 6.04 s after the first
    assert [m.span for m in maps] == [(0.0, 0.09), (6.0, 6.04)]
    assert read_demos(bag, topic="/ee_pose", return_mappings=True)[1][0].span is None
    assert np.array_equal(demos[1].get("position"), pos[10:])
    assert demos[1].t[0] == 0.0
    with pytest.raises(ValidationError, match="split_gap must be a number of seconds"):
        read_bag(bag, split_gap=0)


def test_repeated_stamps_keep_the_first_message(tmp_path):
    _, pos, _, msgs = reach_messages(n=8)
    k, m = msgs[3]
    bag = write_bag(tmp_path / "rep", {"/p": [*msgs[:4], (k + 1, m), *msgs[4:]]})
    with pytest.warns(NdlfdWarning, match="dropped 1 message.* on /p whose time stamp"):
        (d,) = read_bag(bag, "/p")
    assert np.array_equal(d.get("position"), pos)


def test_bag_errors_are_one_line_and_name_what_is_there(tmp_path):
    ns, _, _, msgs = reach_messages(n=5)
    bag = write_bag(
        tmp_path / "bad",
        {
            "/ee_pose": msgs,
            "/empty": [],
            "/mixed": [msgs[0], (int(ns[1]), float64(1.0))],
            "/text": [(int(ns[0]), T["std_msgs/msg/String"](data="hi"))],
        },
    )
    with pytest.raises(
        DataFileError,
        match=r"bad: the bag has no topic '/pose'; its"
        r" topics are /ee_pose \(geometry_msgs/msg/PoseStamped, 5"
        r" messages\), /empty .* 0 messages\), /mixed \(mixed types,"
        r" 2 messages\), /text \(std_msgs/msg/String, 1 messages\)$",
    ):
        read_bag(bag, "/pose")
    with pytest.raises(DataFileError, match="topic '/empty' has no messages"):
        read_bag(bag, ["/ee_pose", "/empty"])
    with pytest.raises(
        DataFileError,
        match="'/mixed' mixes message types"
        " geometry_msgs/msg/PoseStamped, std_msgs/msg/Float64",
    ):
        read_bag(bag, "/mixed")
    with pytest.raises(
        DataFileError,
        match="holds std_msgs/msg/String, which ndlfd does not read; expected one of",
    ):
        read_bag(bag, "/text")
    with pytest.raises(DataFileError, match="name the topic to read with topic="):
        read_bag(bag)
    with pytest.raises(ValidationError, match="topic names a topic twice"):
        read_bag(bag, ["/ee_pose", "/ee_pose"])
    (tmp_path / "junk.mcap").write_bytes(b"not a bag")
    with pytest.raises(DataFileError, match=r"junk.mcap: expected a ROS 2 bag"):
        read_bag(tmp_path / "junk.mcap")
    with pytest.raises(DataFileError, match=r"nothing.db3: no such file"):
        read_bag(tmp_path / "nothing.db3")


def test_poses_without_orientation_give_position_only(tmp_path):
    ns, pos, _, _ = reach_messages(n=6)
    msgs = [
        (int(k), pose_stamped(k, p, [0.0] * 4)) for k, p in zip(ns, pos, strict=True)
    ]
    (d,) = read_bag(write_bag(tmp_path / "p", {"/p": msgs}), "/p")
    assert d.group_names == ("position",) and np.array_equal(d.X, pos)


def test_one_message_and_nan_in_a_pose(tmp_path):
    ns, pos, quat, msgs = reach_messages(n=4)
    bag = write_bag(tmp_path / "one", {"/p": msgs[:1]})
    (d,) = read_bag(bag, "/p")
    assert d.n_samples == 1 and d.t[0] == 0.0
    assert np.array_equal(d.get("position"), pos[:1])
    nan = pose_stamped(int(ns[2]), [0.0, np.nan, 0.0], quat[2])
    bag = write_bag(tmp_path / "nan", {"/p": [*msgs[:2], (int(ns[2]), nan)]})
    with pytest.raises(
        DataFileError,
        match=r"nan: X must be finite; got .*nan.* at"
        r" row 2",
    ):
        read_bag(bag, "/p")


@pytest.mark.parametrize("name", ["out.mcap", "out.db3", "folder"])
def test_write_bag_round_trip(tmp_path, name):
    demo = generated()
    out = ndlfd_write_bag(demo, tmp_path / name, topic="/gen")
    assert out == tmp_path / name
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]  # no temporary left
    poses = rosbags_read(out, "/gen")
    assert [ns for ns, _ in poses] == [round(t * 1e9) for t in demo.t]
    P = np.array(
        [[m.pose.position.x, m.pose.position.y, m.pose.position.z] for _, m in poses]
    )
    o = [m.pose.orientation for _, m in poses]
    Q = np.array([[q.w, q.x, q.y, q.z] for q in o])
    assert np.array_equal(P, demo.get("position"))
    assert np.array_equal(Q, demo.get("orientation"))
    joints = rosbags_read(out, "/gen/joint_states")
    assert joints[0][1].name == ["j1", "j2"]
    assert np.array_equal(np.array([m.position for _, m in joints]), demo.get("joints"))
    grip = rosbags_read(out, "/gen/gripper")
    assert [m.data for _, m in grip] == demo.get("gripper")[:, 0].tolist()
    back = read_bag(out, ["/gen", "/gen/joint_states", "/gen/gripper"])
    assert back == [demo]


def test_write_bag_refuses_what_it_cannot_write(tmp_path):
    demo = generated()
    (tmp_path / "taken").mkdir()
    with pytest.raises(ValidationError, match="taken exists; a bag folder is written"):
        ndlfd_write_bag(demo, tmp_path / "taken")
    wide = Demonstration.from_arrays([0.0, 1.0], position=np.zeros((2, 4)))
    with pytest.raises(ValidationError, match=r"at most 3 position columns; .* has 4"):
        ndlfd_write_bag(wide, tmp_path / "w.mcap")
    early = Demonstration.from_arrays([-1.0, 1.0], position=np.zeros((2, 2)))
    with pytest.raises(ValidationError, match=r"stamps must be >= 0; .* starts at -1"):
        ndlfd_write_bag(early, tmp_path / "e.mcap")
    ndlfd_write_bag(early, tmp_path / "e.mcap", start_time=1.0)
    (d,) = read_bag(tmp_path / "e.mcap")
    assert np.array_equal(d.get("position")[:, 2], [0.0, 0.0])  # z padded
    with pytest.raises(ValidationError, match="topic must be a name like"):
        ndlfd_write_bag(demo, tmp_path / "x.mcap", topic="gen")


def test_joint_trajectory_yaml_parses_back_exactly(tmp_path):
    yaml = pytest.importorskip("yaml")
    demo = generated()
    X = demo.X.copy()
    X[:, 7:9] *= 1e-5  # the joints: floats written with an exponent
    demo = Demonstration(demo.t + 2.0, X, demo.columns, demo.groups)
    p = write_joint_trajectory(demo, tmp_path / "traj.yaml", gripper=None)
    msg = yaml.safe_load(p.read_text())
    assert msg["joint_names"] == ["j1", "j2"]
    assert msg["header"] == {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""}
    pts = msg["points"]
    Q, V, A = (np.array([x[k] for x in pts])
               for k in ("positions", "velocities", "accelerations"))  # fmt: skip
    ns = [
        x["time_from_start"]["sec"] * 10**9 + x["time_from_start"]["nanosec"]
        for x in pts
    ]
    # every float reads back as the points computed, bit for bit
    _, t, *want = joint_trajectory_points(demo, gripper=None)
    for got, w in zip((Q, V, A), want, strict=True):
        assert np.array_equal(got, w)
    assert ns == [round(s * 1e9) for s in t]
    # the noisy joints move at both ends: eased to rest along their route,
    # the samples a step (1/64 s) apart from 0, the ends the path's own
    assert np.array_equal(ns, np.arange(len(pts)) * 15_625_000)
    assert len(pts) > demo.n_samples
    assert np.array_equal(Q[[0, -1]], demo.get("joints")[[0, -1]])
    # velocities and accelerations: the clamped cubic spline's through the
    # written positions, at rest at the ends exactly
    curve = CubicSpline(t, Q, axis=0, bc_type="clamped")
    np.testing.assert_allclose(V, curve(t, 1), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(A, curve(t, 2), rtol=1e-9, atol=1e-12)
    assert not np.any(V[[0, -1]])
    plain = Demonstration.from_arrays([0.0, 1.0], position=[[0, 0], [1, 1]])
    with pytest.raises(
        ValidationError, match=r"needs the group 'joints'.* has position"
    ):
        write_joint_trajectory(plain, tmp_path / "p.yaml")


def test_joint_state_velocities_are_the_group_joint_velocity(tmp_path):
    ns = 10**9 + np.arange(8) * 10_000_000
    rng = np.random.default_rng(1)
    pos, vel = rng.normal(size=(8, 2)), rng.normal(size=(8, 2))
    msgs = []
    for k, p, v in zip(ns, pos, vel, strict=True):
        m = joint_state(k, ["shoulder", "elbow"], p)
        m.velocity = np.array(v)
        msgs.append((int(k), m))
    bag = write_bag(tmp_path / "js", {"/joint_states": msgs})
    (d,) = read_bag(bag, "/joint_states")
    assert d.columns == ("shoulder", "elbow", "shoulder.vel", "elbow.vel")
    assert d.groups == ("joints", "joints", "joint_velocity", "joint_velocity")
    assert np.array_equal(d.get("joints"), pos)
    assert np.array_equal(d.get("joint_velocity"), vel)  # as published
    # velocities for some joints only: a clear error
    m = joint_state(ns[-1] + 10**7, ["shoulder", "elbow"], [0.0, 0.0])
    m.velocity = np.array([1.0])
    bag = write_bag(
        tmp_path / "bad", {"/joint_states": [*msgs, (int(ns[-1]) + 10**7, m)]}
    )
    with pytest.raises(
        DataFileError,
        match=r"JointState message 8 on '/joint_states' has 1 velocities for 2"
        r" joints; expected none or one per joint",
    ):
        read_bag(bag, "/joint_states")
