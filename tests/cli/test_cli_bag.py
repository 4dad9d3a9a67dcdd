import sys

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

pytest.importorskip("rosbags")

from cli_helpers import cli
from rosbags.rosbag2 import StoragePlugin, Writer

from bag_samples import STORE, joint_state, pose_stamped
from bag_samples import rosbags_read as messages
from ndlfd.io import read_bag
from ndlfd.io._bagout import joint_trajectory_points
from ndlfd.learner import KeypointHMM


def reach_bag(path, seed=0, storage=StoragePlugin.MCAP, gaps=0):
    """A bag of a 3-D reach with orientation on /ee_pose and two joints."""
    rng = np.random.default_rng(seed)
    n = 60
    dt = rng.integers(18_000_000, 22_000_000, n)
    dt[1:][np.arange(1, n) % 20 == 0] += 5 * 10**9 * (gaps > 0)  # 5 s pauses
    ns = 1_700_000_000 * 10**9 + np.cumsum(dt)
    s = np.tile(np.linspace(0, 1, 20), 3) if gaps else np.linspace(0, 1, n)
    pos = np.column_stack([s, s**2, np.sin(s)]) + rng.normal(0, 1e-3, (n, 3))
    quat = np.column_stack([np.cos(s / 2), 0 * s, 0 * s, np.sin(s / 2)])
    joints = np.column_stack([s, 1 - s]) + rng.normal(0, 1e-3, (n, 2))
    with Writer(path, version=9, storage_plugin=storage) as w:
        cp = w.add_connection(
            "/ee_pose", "geometry_msgs/msg/PoseStamped", typestore=STORE
        )
        cj = w.add_connection(
            "/joint_states", "sensor_msgs/msg/JointState", typestore=STORE
        )
        for k, p, q, j in zip(ns, pos, quat, joints, strict=True):
            m = pose_stamped(int(k), p, q)
            w.write(cp, int(k), STORE.serialize_cdr(m, m.__msgtype__))
            m = joint_state(int(k), ["shoulder", "elbow"], j)
            w.write(cj, int(k), STORE.serialize_cdr(m, m.__msgtype__))
    return path


def assert_at_rest_on_the_path(t, Q, V, A, path, units="rad"):
    """A JointTrajectory's points are ``path`` come to rest, as the writer says.

    The positions those of :func:`joint_trajectory_points` (the path eased
    to rest at its moving ends), beginning and ending on the path's own;
    the velocities and accelerations the clamped cubic spline's through the
    written positions, the end velocities exactly 0.
    """
    factor = np.pi / 180.0 if units == "deg" else 1.0
    _, s, P, _, _ = joint_trajectory_points(path, units=units)
    np.testing.assert_allclose(t, s, rtol=0, atol=1e-9)  # nanoseconds
    # up to the rounding of the path's time stamps, computed again here
    np.testing.assert_allclose(Q, P, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(
        Q[[0, -1]], path.get("joints")[[0, -1]] * factor, rtol=1e-12, atol=1e-15
    )
    curve = CubicSpline(s, Q, axis=0, bc_type="clamped")  # s: unrounded
    assert not np.any(V[[0, -1]])
    np.testing.assert_allclose(V, curve(s, 1), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(A, curve(s, 2), rtol=1e-9, atol=1e-12)


def bags(folder):
    folder.mkdir()
    for i in range(3):
        reach_bag(folder / f"demo{i}", seed=i)
    reach_bag(folder / "sq", seed=3, storage=StoragePlugin.SQLITE3)
    (folder / "loose").mkdir()
    reach_bag(folder / "loose" / "one", seed=4)
    (folder / "loose" / "one" / "one.mcap").rename(folder / "one.mcap")
    return folder


def test_fit_bags_generate_a_bag_read_back_with_rosbags(tmp_path, capsys):
    folder = bags(tmp_path / "bags")
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", folder, "--topic", "/ee_pose", "-o", model)
    assert rc == 0, err
    assert err[0] == (
        "read 5 demonstration(s) from 5 file(s): time=/ee_pose stamps;"
        " position=x,y,z; orientation=qw,qx,qy,qz (ROS 2 bag, frame world)"
    )
    assert "on position, velocity, orientation (velocity derived" in err[1]
    out = tmp_path / "path.mcap"
    rc, err = cli(
        capsys,
        "generate",
        model,
        "--duration",
        1.5,
        "--samples",
        40,
        "--dense",
        "-o",
        out,
        "--topic",
        "/ndlfd/path",
    )
    assert rc == 0, err
    assert err[-1] == f"generated 40 samples -> {out}"  # after the path's peaks
    want = KeypointHMM.load(model).generate(np.linspace(0.0, 1.5, 40), dense=True)
    got = messages(out, "/ndlfd/path")
    assert [ns for ns, _ in got] == [round(t * 1e9) for t in want.t]
    assert [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for _, m in got] == [
        ns for ns, _ in got
    ]
    P = np.array(
        [[m.pose.position.x, m.pose.position.y, m.pose.position.z] for _, m in got]
    )
    Q = np.array(
        [
            [
                m.pose.orientation.w,
                m.pose.orientation.x,
                m.pose.orientation.y,
                m.pose.orientation.z,
            ]
            for _, m in got
        ]
    )
    assert np.array_equal(P, want.get("position"))
    assert np.array_equal(Q, want.get("orientation"))
    assert np.allclose(np.linalg.norm(Q, axis=1), 1.0, atol=1e-12)
    # and ndlfd reads it back as the path it generated
    rc, err = cli(capsys, "generate", model, "--like", out, "-o", tmp_path / "a.csv")
    assert rc == 0, err


def test_several_topics_and_split_gap(tmp_path, capsys):
    bag = reach_bag(tmp_path / "long", gaps=2)
    rc, err = cli(
        capsys,
        "fit",
        bag,
        "--topic",
        "/ee_pose",
        "--topic",
        "/joint_states",
        "--split-gap",
        1,
        "-o",
        tmp_path / "m.ndlfd",
    )
    assert rc == 0, err
    assert err[0].startswith("read 3 demonstration(s) from 1 file(s): time=/ee_pose")
    assert "joints=joints.shoulder,joints.elbow (ROS 2 bag, frame world)" in err[0]
    # the pieces between the 5 s pauses (test_split_still_on_the_command_line)
    assert err[1].startswith(f"pieces of {bag}, in seconds from its first stamp:")
    assert len(err[1].split("stamp: ")[1].split(", ")) == 3
    assert "on position, velocity, orientation, joints (" in err[2]  # all learned
    rc, err = cli(
        capsys,
        "fit",
        bag,
        "--topic",
        "/ee_pose",
        "--split-gap",
        0,
        "-o",
        tmp_path / "m.ndlfd",
    )
    assert rc == 2 and err == [
        "ndlfd fit: error: --split-gap must be a number of seconds > 0; got 0"
    ]


def test_joint_trajectory_yaml_from_a_joint_model(tmp_path, capsys):
    yaml = pytest.importorskip("yaml")
    folder = bags(tmp_path / "bags")
    model = tmp_path / "j.ndlfd"
    rc, err = cli(
        capsys,
        "fit",
        folder,
        "--topic",
        "/joint_states",
        "--groups",
        "joints",
        "--levels",
        "joints=12",
        "-o",
        model,
    )
    assert rc == 0, err
    assert "joints=joints.shoulder,joints.elbow" in err[0]
    out = tmp_path / "traj.yaml"
    rc, err = cli(
        capsys,
        "generate",
        model,
        "--duration",
        2,
        "--samples",
        30,
        "--dense",
        "-o",
        out,
    )
    assert rc == 0, err
    want = KeypointHMM.load(model).generate(np.linspace(0.0, 2.0, 30), dense=True)
    msg = yaml.safe_load(out.read_text())
    assert msg["joint_names"] == ["shoulder", "elbow"]
    pts = msg["points"]
    t = np.array([p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"]
                  for p in pts])  # fmt: skip
    Q, V, A = (np.array([p[k] for p in pts])
               for k in ("positions", "velocities", "accelerations"))  # fmt: skip
    # the path moves at its ends: eased to rest there, a little longer
    assert len(pts) > 30 and t[-1] > 2.0
    assert_at_rest_on_the_path(t, Q, V, A, want)
    # the peaks said are those written (before: of the path before easing)
    v, a = np.abs(V).max(axis=0), np.abs(A).max(axis=0)
    names = ("shoulder", "elbow")
    assert (
        f"peaks: joints velocity {v.max():.3g} /s ({names[v.argmax()]}),"
        f" acceleration {a.max():.3g} /s^2 ({names[a.argmax()]})"
    ) in err
    # replanning: the first 12 samples executed; the trajectory sent is the
    # rest, from where the robot is now (the last observed sample, moving)
    prefix = want.take(np.arange(12)).select("joints")
    np.savetxt(tmp_path / "prefix.csv", np.column_stack([prefix.t, prefix.X]),
               delimiter=",", header="t,joints.shoulder,joints.elbow", comments="",
               fmt="%.17g")  # fmt: skip
    rc, err = cli(capsys, "generate", model, "--duration", 2, "--samples", 30,
                  "--observed", tmp_path / "prefix.csv",
                  "-o", tmp_path / "cont.yaml")  # fmt: skip
    assert rc == 0, err
    assert "the trajectory starts at the last observed sample" in " ".join(err)
    cont = yaml.safe_load((tmp_path / "cont.yaml").read_text())["points"]
    np.testing.assert_allclose(cont[0]["positions"], prefix.X[-1], rtol=1e-12)
    # the path's 30 - 11 samples from there, its moving end eased to rest
    path = KeypointHMM.load(model).generate(np.linspace(0.0, 2.0, 30),
                                            observed=prefix)  # fmt: skip
    _, s, P, W, _ = joint_trajectory_points(path.take(np.arange(11, 30)),
                                            moving_start=True)  # fmt: skip
    assert len(cont) == s.size > 30 - 11
    np.testing.assert_allclose([p["positions"] for p in cont], P, rtol=1e-12)
    assert np.any(cont[0]["velocities"]) and not np.any(cont[-1]["velocities"])
    np.testing.assert_allclose([p["velocities"] for p in cont], W, rtol=1e-9,
                               atol=1e-12)  # fmt: skip
    assert cont[0]["time_from_start"] == {"sec": 0, "nanosec": 0}
    assert np.abs(cont[0]["velocities"]).max() > 0.0  # moving, not from rest
    assert np.all(np.array(cont[-1]["velocities"]) == 0.0)
    # a bag of the joints: JointState on TOPIC/joint_states
    rc, err = cli(
        capsys,
        "generate",
        model,
        "--duration",
        2,
        "-o",
        tmp_path / "j.mcap",
        "--topic",
        "/arm",
        "--samples",
        30,
        "--dense",
    )
    assert rc == 0, err
    got = messages(tmp_path / "j.mcap", "/arm/joint_states")
    assert got[0][1].name == ["shoulder", "elbow"] and len(got) == want.n_samples


def test_bag_errors_on_the_command_line(tmp_path, capsys):
    bag = reach_bag(tmp_path / "b")
    rc, err = cli(capsys, "fit", bag, "--topic", "/nope", "-o", tmp_path / "m.ndlfd")
    assert rc == 2 and len(err) == 1
    assert err[0] == (
        f"ndlfd fit: error: {bag}: the bag has no topic '/nope'; its topics are"
        " /ee_pose (geometry_msgs/msg/PoseStamped, 60 messages), /joint_states"
        " (sensor_msgs/msg/JointState, 60 messages)"
    )
    rc, err = cli(capsys, "fit", bag, "-o", tmp_path / "m.ndlfd")
    assert rc == 2 and err[0].startswith(
        f"ndlfd fit: error: {bag}: name the topic to read with --topic; the bag's"
    )
    model = tmp_path / "m.ndlfd"
    assert cli(capsys, "fit", bag, "--topic", "/ee_pose", "-o", model)[0] == 0
    rc, err = cli(
        capsys,
        "generate",
        model,
        "--duration",
        1,
        "-o",
        tmp_path / "p.csv",
        "--topic",
        "/x",
    )
    assert rc == 2 and err == [
        "ndlfd generate: error: --topic sets a ROS 2 output (-o PATH.mcap, a bag"
        f" folder PATH/, or PATH.yaml); -o {tmp_path / 'p.csv'} writes csv"
    ]
    rc, err = cli(
        capsys,
        "generate",
        model,
        "--duration",
        1,
        "-o",
        tmp_path / "p.csv",
        "--format",
        "bag",
    )
    assert rc == 2 and "--format bag writes one .mcap (or .db3) file" in err[0]
    rc, err = cli(capsys, "generate", model, "--duration", 1, "-o", tmp_path / "p.yaml")
    assert rc == 2 and err[-1] == (
        "ndlfd generate: error: a joint trajectory needs the group 'joints' (the"
        " joint positions); the path has position, velocity, orientation"
    )
    rc, err = cli(
        capsys,
        "generate",
        model,
        "--like",
        bag,
        "--like-topic",
        "/nope",
        "-o",
        tmp_path / "p.csv",
    )
    assert rc == 2 and "the bag has no topic '/nope'" in err[0]


def test_bags_without_rosbags_say_how_to_install_it(tmp_path, capsys, monkeypatch):
    bag = reach_bag(tmp_path / "b")
    monkeypatch.setitem(sys.modules, "rosbags", None)  # import rosbags now fails
    rc, err = cli(capsys, "fit", bag, "--topic", "/ee_pose", "-o", tmp_path / "m")
    assert rc == 2 and err == [
        "ndlfd fit: error: reading and writing ROS 2 bags needs rosbags; install it"
        ' with: pip install "ndlfd[ros]"'
    ]


def test_frame_reads_tf_composed_to_the_base_frame(tmp_path, capsys):
    from bag_samples import chain_bag
    from ndlfd.io import read_bag

    bag, *_ = chain_bag(tmp_path / "chain")
    model = tmp_path / "m.ndlfd"
    rc, err = cli(
        capsys, "fit", bag, "--frame", "tool0", "--base-frame", "base_link", "-o", model
    )
    assert rc == 0, err
    assert err[0] == (
        "read 1 demonstration(s) from 1 file(s): time=/tf stamps; position=x,y,z;"
        " orientation=qw,qx,qy,qz (ROS 2 bag, frame base_link)"
    )
    out = tmp_path / "p.csv"
    rc, err = cli(capsys, "generate", model, "--like", bag, "--like-frame", "tool0",
                  "--like-base-frame", "base_link", "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    (want,) = read_bag(bag, frame="tool0", base_frame="base_link")
    got = np.loadtxt(out, delimiter=",", skiprows=1)
    assert np.allclose(got[:, 0], want.t)  # the composed pose's stamps
    rc, err = cli(
        capsys, "fit", bag, "--topic", "/tf_static", "--frame", "camera_link",
        "-o", model,
    )  # fmt: skip
    assert rc == 2 and err == [
        f"ndlfd fit: error: {bag}: the pose of 'camera_link' in 'world' is"
        " constant (only static transforms: camera_link -> base_link -> world),"
        " not a demonstration; read a frame that moves, from /tf"
    ]
    rc, err = cli(capsys, "fit", bag, "--frame", "tool0", "--base-frame", "map",
                  "-o", model)  # fmt: skip
    assert rc == 2 and err[0].endswith(
        "no base frame 'map' in the tf tree of /tf and /tf_static; the frames"
        " found are base_link, camera_link, link1, link2, tool0, world"
    )


def test_bag_outputs_carry_the_inputs_frame_and_absolute_stamps(tmp_path, capsys):
    from bag_samples import chain_bag

    bag, *_ = chain_bag(tmp_path / "chain")
    model = tmp_path / "m.ndlfd"
    rc, err = cli(
        capsys, "fit", bag, "--frame", "tool0", "--base-frame", "base_link", "-o", model
    )
    assert rc == 0, err
    out = tmp_path / "out_bag"
    rc, err = cli(capsys, "generate", model, "--duration", 1, "--samples", 11,
                  "--dense", "-o", f"{out}/")  # fmt: skip
    assert rc == 0, err
    assert (out / "metadata.yaml").is_file()  # a bag folder
    got = messages(out, "/ndlfd/path")
    assert {m.header.frame_id for _, m in got} == {"base_link"}  # the input's
    assert [ns for ns, _ in got] == [round(k * 1e8) for k in range(11)]
    rc, err = cli(capsys, "generate", model, "--duration", 1, "--samples", 11,
                  "--dense", "--format", "bag", "--frame-id", "map", "--start-time",
                  1_700_000_000.25, "-o", tmp_path / "abs")  # fmt: skip
    assert rc == 0, err
    got = messages(tmp_path / "abs", "/ndlfd/path")
    assert {m.header.frame_id for _, m in got} == {"map"}
    want = [1_700_000_000_250_000_000 + round(k * 1e8) for k in range(11)]
    assert [ns for ns, _ in got] == want
    stamps = [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for _, m in got]
    assert stamps == want
    rc, err = cli(capsys, "generate", model, "--duration", 1, "-o", tmp_path / "p.csv",
                  "--frame-id", "map")  # fmt: skip
    assert rc == 2 and "--frame-id sets a ROS 2 output" in err[0]
    rc, err = cli(capsys, "generate", model, "--duration", 1, "--format", "bag",
                  "-o", tmp_path / "p.txt")  # fmt: skip
    assert rc == 2 and "--format bag writes one .mcap (or .db3) file or a bag" in err[0]


def test_joint_trajectory_bag_with_urdf_names_in_radians(tmp_path, capsys):
    folder = bags(tmp_path / "bags")
    model = tmp_path / "j.ndlfd"
    rc, err = cli(capsys, "fit", folder, "--topic", "/joint_states", "--groups",
                  "joints", "--levels", "joints=12", "-o", model)  # fmt: skip
    assert rc == 0, err
    out = tmp_path / "traj_bag"
    rc, err = cli(capsys, "generate", model, "--duration", 2, "--samples", 30,
                  "--dense", "--format", "joint-trajectory", "--units", "deg",
                  "--joint-names", "joint_1,joint_2", "-o", out)  # fmt: skip
    assert rc == 0, err
    ((ns, msg),) = messages(out, "/joint_trajectory_controller/joint_trajectory")
    want = KeypointHMM.load(model).generate(np.linspace(0.0, 2.0, 30), dense=True)
    assert ns == 0 and msg.joint_names == ["joint_1", "joint_2"]
    t = np.array([p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec
                  for p in msg.points])  # fmt: skip
    Q, V, A = (np.array([getattr(p, k) for p in msg.points])
               for k in ("positions", "velocities", "accelerations"))  # fmt: skip
    assert_at_rest_on_the_path(t, Q, V, A, want, units="deg")
    rc, err = cli(capsys, "generate", model, "--duration", 2, "--joint-names", "a",
                  "-o", tmp_path / "t.yaml")  # fmt: skip
    assert rc == 2 and err[-1] == (
        "ndlfd generate: error: --joint-names must give one name per joint: 2 for"
        " shoulder, elbow; got 1 (a)"
    )


def test_split_still_on_the_command_line(tmp_path, capsys):
    from bag_samples import session, tf_bag

    t, P, _ = session()
    bag = tf_bag(tmp_path / "session", t, P)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", bag, "--frame", "tool0", "--split-still", 2.5,
                  "-o", model)  # fmt: skip
    assert rc == 0, err
    assert err[0].startswith("read 5 demonstration(s) from 1 file(s): time=/tf")
    # each piece's time span in the session: its first pose found in it
    pieces = []
    for d in read_bag(bag, frame="tool0", split_still=2.5):
        (i0,) = np.flatnonzero((P == d.get("position")[0]).all(axis=1))
        pieces.append(f"{t[i0]:.2f}-{t[i0] + d.t[-1]:.2f}")
    assert err[1] == (
        f"pieces of {bag}, in seconds from its first stamp: {', '.join(pieces)}"
    )
    rc, err = cli(capsys, "fit", bag, "--frame", "tool0", "--split-still", 0,
                  "-o", model)  # fmt: skip
    assert rc == 2 and err == [
        "ndlfd fit: error: --split-still must be a number of seconds > 0; got 0"
    ]


def test_readme_joint_trajectory_commands_run(tmp_path, capsys, monkeypatch):
    import re
    import shlex
    from pathlib import Path

    readme = (Path(__file__).parents[2] / "README.md").read_text()
    section = readme.split("### Joint trajectories for a ROS 2 controller")[1]
    block = re.search(r"```console\n(.*?)```", section, re.S).group(1)
    commands = [shlex.split(line[2:]) for line in block.splitlines()]
    assert [c[:2] for c in commands] == [
        ["ndlfd", "fit"], ["ndlfd", "generate"], ["ros2", "bag"]
    ]  # fmt: skip
    bags(tmp_path / "arm_bags")
    monkeypatch.chdir(tmp_path)
    for args in commands[:2]:  # ROS 2 is not installed here: not ros2 bag play
        rc, err = cli(capsys, *args[1:])
        assert rc == 0, err
    out = tmp_path / "traj_bag"
    ((ns, msg),) = messages(out, "/joint_trajectory_controller/joint_trajectory")
    assert ns == 0 and msg.joint_names == ["joint_1", "joint_2"]
    # 601 samples over 6 s, moving at both ends: eased to rest over 10 % of
    # the duration at each, which covers half of it (0.3 s, 30 more points)
    assert len(msg.points) == 661
    last = msg.points[-1].time_from_start
    assert (last.sec, last.nanosec) == (6, 600_000_000)
    t = np.array([p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec
                  for p in msg.points])  # fmt: skip
    Q, V, A = (np.array([getattr(p, k) for p in msg.points])
               for k in ("positions", "velocities", "accelerations"))  # fmt: skip
    want = KeypointHMM.load(tmp_path / "arm.ndlfd").generate(
        np.linspace(0.0, 6.0, 601), dense=True
    )
    assert_at_rest_on_the_path(t, Q, V, A, want)
    assert np.any(A[[0, -1]])  # the curve's own accelerations at rest, not 0
