"""ndlfd fit --task-frame of ROS 2 bags (topics, tf frames) and LeRobot features."""

import numpy as np
import pytest

pytest.importorskip("rosbags")
pytest.importorskip("pyarrow")

from cli_helpers import cli, fit_model

from bag_samples import (
    T0,
    float64,
    header,
    pose_stamped,
    tf_message,
    transform,
    write_bag,
)
from bag_samples import T as MSG
from lerobot_writer import write_lerobot
from ndlfd import synth
from ndlfd.io import read_csv
from ndlfd.learner import KeypointHMM

NEW_OBJECT = [0.45, 0.05, 0.02, 0.0, 1.0, 0.0, 0.0]
NEW_PLACE = [0.35, 0.3, 0.02]
T = np.linspace(0.0, 6.0, 60)


def point_stamped(ns, p):
    point = MSG["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2])
    return MSG["geometry_msgs/msg/PointStamped"](header=header(ns), point=point)


def write_pick_place_bags(folder, n_demos=6):
    """``synth.pick_place`` as bags: /ee_pose, /gripper, /object_pose, /place."""
    folder.mkdir(parents=True, exist_ok=True)
    demos, frames = synth.pick_place(n_demos, n_samples=100)
    for i, (d, f) in enumerate(zip(demos, frames, strict=True)):
        ns = T0 + np.round(d.t * 1e9).astype(np.int64)
        P, Q, G = d.get("position"), d.get("orientation"), d.get("gripper")[:, 0]
        ee = [
            (int(k), pose_stamped(int(k), p, q))
            for k, p, q in zip(ns, P, Q, strict=True)
        ]
        grip = [(int(k), float64(g)) for k, g in zip(ns, G, strict=True)]
        o = f["object"]
        obj = [(int(k), pose_stamped(int(k), o[:3], o[3:])) for k in ns[::20]]
        place = [(int(ns[0]), point_stamped(int(ns[0]), f["place"][:3]))]
        topics = {"/ee_pose": ee, "/gripper": grip, "/object_pose": obj}
        write_bag(folder / f"demo{i}.mcap", {**topics, "/place": place})
    return folder, frames


BAG_FLAGS = (
    "--topic",
    "/ee_pose",
    "--topic",
    "/gripper",
    "--task-frame",
    "object=/object_pose",
    "--task-frame",
    "place=/place",
)


@pytest.fixture(scope="module")
def bag_model(tmp_path_factory):
    root = tmp_path_factory.mktemp("bags")
    folder, frames = write_pick_place_bags(root / "bags")
    model = fit_model(folder, root / "m.ndlfd", *BAG_FLAGS)
    return root, model, frames


def test_fit_takes_frames_from_bag_topics(capsys, tmp_path, bag_model):
    root, model, frames = bag_model
    assert list(model.task_frames_) == ["object", "place"]
    np.testing.assert_allclose(
        model.task_frames_["object"], [f["object"] for f in frames], atol=1e-12
    )
    np.testing.assert_array_equal(
        model.task_frames_["place"], [f["place"][:3] for f in frames]
    )
    assert model.groups_ == ("position", "velocity", "orientation", "gripper")
    rc, err = cli(capsys, "fit", root / "bags", "-o", tmp_path / "m.ndlfd", *BAG_FLAGS)
    assert rc == 0, err
    assert "task frame object=/object_pose; task frame place=/place" in err[0], err
    line = next(e for e in err if e.startswith("task frames"))
    places = np.array([f["place"][:3] for f in frames])
    apart = max(np.linalg.norm(a - b) for a in places for b in places)
    assert (
        "object (7 values" in line
        and f"place (3 values; moved over {apart:.3g})" in line
    )


def test_generate_with_new_poses_after_a_bag_fit(capsys, tmp_path, bag_model):
    root, model, _ = bag_model
    flags = [
        "--task-frame",
        "object=" + ",".join(map(str, NEW_OBJECT)),
        "--task-frame",
        "place=" + ",".join(map(str, NEW_PLACE)),
    ]
    out = tmp_path / "g.csv"
    rc, err = cli(capsys, "generate", root / "m.ndlfd", "--duration", "6",
                  "--samples", "60", "--dense", *flags, "-o", out)  # fmt: skip
    assert rc == 0, err
    want = model.generate(
        T, dense=True, frames={"object": NEW_OBJECT, "place": NEW_PLACE}
    )
    got = read_csv(out)
    X = got.X[:, [got.columns.index(c) for c in want.columns]]
    np.testing.assert_allclose(X, want.X, rtol=5e-10, atol=1e-12)
    assert np.abs(model.generate(T, dense=True).X - want.X).max() > 1e-3


def test_fit_takes_a_tf_frame_in_the_demonstrations_base(capsys, tmp_path):
    """The hand on /tf (tool0 in world), the object a static frame of base_link."""
    deg = np.radians
    rng = np.random.default_rng(0)
    want = []
    for i in range(3):
        ns = T0 + np.arange(50) * 20_000_000
        s = np.linspace(0.0, 1.0, 50)
        obj = [0.2 + 0.05 * i, rng.uniform(-0.1, 0.1), 0.0]
        hand = [
            (int(k), tf_message(transform(k, "tool0", [0.5 * v, 0.1 * v, 0.3 - 0.2 * v],
                                          [1.0, 0, 0, 0], "world")))
            for k, v in zip(ns, s, strict=True)
        ]  # fmt: skip
        turn = [np.cos(deg(45)), 0, 0, np.sin(deg(45))]  # 90 degrees about z
        static = tf_message(
            transform(T0, "base_link", [0.1, 0.0, 0.0], turn, "world"),
            transform(T0, "object", obj, [1.0, 0, 0, 0], "base_link"),
        )
        write_bag(
            tmp_path / "bags" / f"d{i}", {"/tf": hand, "/tf_static": [(T0, static)]}
        )
        # base_link turned 90 degrees about z: (x, y) -> (-y, x), then moved
        want.append([0.1 - obj[1], obj[0], 0.0])
    model = fit_model(tmp_path / "bags", tmp_path / "m.ndlfd", "--frame", "tool0",
                      "--task-frame", "object=tf:object")  # fmt: skip
    got = model.task_frames_["object"]
    np.testing.assert_allclose(got[:, :3], want, atol=1e-12)
    np.testing.assert_allclose(np.abs(got[:, 3]), np.cos(deg(45)), atol=1e-12)
    # in base_link: the static transform itself
    flags = ("--frame", "tool0", "--base-frame", "base_link")
    model = fit_model(
        tmp_path / "bags",
        tmp_path / "b.ndlfd",
        *flags,
        "--task-frame",
        "object=tf:object",
    )
    assert model.task_frames_["object"].shape == (3, 7)
    np.testing.assert_allclose(model.task_frames_["object"][:, 3], 1.0)


def test_bag_frame_errors_are_one_line(capsys, tmp_path):
    folder, _ = write_pick_place_bags(tmp_path / "bags", n_demos=2)
    base = ("fit", folder, "-o", tmp_path / "m.ndlfd", "--topic", "/ee_pose")
    rc, err = cli(capsys, *base, "--task-frame", "object=ox,oy,oz")
    assert rc == 2 and len(err) == 1, err
    assert err[0] == (
        f"ndlfd fit: error: --task-frame object names 3 columns (ox,oy,oz);"
        f" {folder / 'demo0.mcap'} is a ROS 2 bag, whose frame is a topic (such as"
        " /object_pose) or a tf frame (such as tf:object_frame): --task-frame"
        " object=/object_pose"
    )
    rc, err = cli(capsys, *base, "--task-frame", "object=/ee_pose")
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(
        f"ndlfd fit: error: {folder / 'demo0.mcap'}: --task-frame object"
        " (/ee_pose) must stay still during the demonstration"
    ), err
    assert " m); it moved 0." in err[0]
    rc, err = cli(capsys, *base, "--task-frame", "object=/nope")
    assert rc == 2 and len(err) == 1, err
    assert (
        "--task-frame object reads topic '/nope', which the bag does not have" in err[0]
    )


# -------------------------------------------------------------------- LeRobot
def write_dataset(root, n_demos=6, moved=None):
    """pick_place's hand and gripper as observation.state, the object a feature."""
    demos, frames = synth.pick_place(n_demos, n_samples=60)
    eps = []
    for i, (d, f) in enumerate(zip(demos, frames, strict=True)):
        obj = np.tile(f["object"], (d.n_samples, 1))
        if moved == i:
            obj[30:, 0] += 0.1
        state = np.column_stack([d.get("position"), d.get("gripper")])
        eps.append({"observation.state": state, "observation.object_pose": obj})
    names = {
        "observation.state": ["x", "y", "z", "gripper"],
        "observation.object_pose": ["ox", "oy", "oz", "oqw", "oqx", "oqy", "oqz"],
    }
    write_lerobot(root, eps, names, per_file=3)
    poses = [f["object"].astype(np.float32).astype(np.float64) for f in frames]
    return root, poses


def test_fit_takes_frames_from_a_lerobot_feature(capsys, tmp_path):
    root, poses = write_dataset(tmp_path / "ds")
    flag = ("--task-frame", "object=observation.object_pose")
    rc, err = cli(capsys, "fit", root, "-o", tmp_path / "m.ndlfd", *flag)
    assert rc == 0, err
    assert "task frame object=observation.object_pose" in err[0], err
    model = KeypointHMM.load(tmp_path / "m.ndlfd")
    got = model.task_frames_["object"]
    np.testing.assert_allclose(got[:, :3], np.array(poses)[:, :3], atol=1e-7)
    # the quaternion (about 0, 1, 0, 0) up to its sign, normalized from float32
    np.testing.assert_allclose(
        np.abs(got[:, 3:]), np.abs(np.array(poses)[:, 3:]), atol=1e-6
    )
    rc, err = cli(capsys, "generate", tmp_path / "m.ndlfd", "--duration", "6",
                  "--task-frame", "object=" + ",".join(map(str, NEW_OBJECT)),
                  "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 0, err
    # a feature that moves in one episode, and columns instead of a feature
    root, _ = write_dataset(tmp_path / "moved", n_demos=3, moved=2)
    rc, err = cli(capsys, "fit", root, "-o", tmp_path / "x.ndlfd", *flag)
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(
        f"ndlfd fit: error: {root} episode 2: --task-frame object (feature"
        " observation.object_pose) must stay still during the demonstration"
    ), err
    assert "it moved 0.1, from" in err[0], err
    rc, err = cli(capsys, "fit", root, "-o", tmp_path / "x.ndlfd",
                  "--task-frame", "object=ox,oy,oz")  # fmt: skip
    assert rc == 2 and len(err) == 1, err
    assert "is a LeRobot episode, whose frame is a feature" in err[0], err
