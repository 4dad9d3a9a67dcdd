"""Task frames read with a recording: a bag's topic or tf frame, a LeRobot feature."""

import numpy as np
import pytest

pytest.importorskip("rosbags")
pytest.importorskip("pyarrow")

from scipy.spatial.transform import Rotation

from bag_samples import (
    T0,
    chain_bag,
    float64,
    header,
    pose,
    pose_stamped,
    reach_messages,
    transform,
    write_bag,
    wxyz,
)
from bag_samples import T as MSG
from lerobot_writer import write_lerobot
from ndlfd._errors import DataFileError, ValidationError
from ndlfd.io import DemoFiles, read_bag, read_demos, read_lerobot
from ndlfd.io._frame_poses import still_pose

OBJECT_P = [0.42, -0.07, 0.021]
OBJECT_Q = wxyz(Rotation.from_euler("zx", [35, 10], degrees=True))  # w, x, y, z
PLACE = [0.3, 0.31, 0.02]


def point_stamped(ns, p, frame="world"):
    point = MSG["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2])
    return MSG["geometry_msgs/msg/PointStamped"](header=header(ns, frame), point=point)


def object_messages(ns, p=OBJECT_P, q=OBJECT_Q, noise=0.0, every=5, seed=1):
    """The object's PoseStamped every ``every`` stamps of ``ns``, with noise (m)."""
    rng = np.random.default_rng(seed)
    out = []
    for k in ns[::every]:
        jitter = rng.normal(0.0, noise, 3) if noise else np.zeros(3)
        out.append((int(k), pose_stamped(int(k), np.add(p, jitter), q)))
    return out


@pytest.fixture
def reach_bag(tmp_path):
    """A reach on /ee_pose, the object on /object_pose, the place once before."""
    ns, _, _, msgs = reach_messages()
    place = [(int(ns[0]) - 10**9, point_stamped(int(ns[0]) - 10**9, PLACE))]
    topics = {"/ee_pose": msgs, "/object_pose": object_messages(ns), "/place": place}
    return write_bag(tmp_path / "reach", topics), ns


def test_topics_give_the_poses_scalar_first(reach_bag):
    bag, _ = reach_bag
    frames = {"object": "/object_pose", "place": "/place"}
    (demo,) = read_bag(bag, "/ee_pose", frames=frames)
    assert list(demo.frames) == ["object", "place"]
    # ROS's x, y, z, w turned w, x, y, z (the message fields were set from it)
    np.testing.assert_allclose(
        demo.frames["object"], [*OBJECT_P, *OBJECT_Q], atol=1e-12
    )
    assert demo.frames["object"][3] == pytest.approx(
        np.cos(np.radians(35 / 2)) * np.cos(np.radians(5))
    )
    # a point published once, before the demonstration: held
    np.testing.assert_array_equal(demo.frames["place"], PLACE)
    # the same through read_demos and DemoFiles (a reader option)
    (again,) = read_demos(bag, topic="/ee_pose", frames=frames)
    assert again == demo
    (item,) = DemoFiles(bag, topic="/ee_pose", frames=frames)
    assert item.read() == [demo]


@pytest.mark.parametrize("kind", ["TransformStamped", "Pose"])
def test_transforms_and_bare_poses(tmp_path, kind):
    """A TransformStamped (one child frame), a Pose (no header: receive times)."""
    ns, _, _, msgs = reach_messages()
    if kind == "Pose":
        obj = [(int(k), pose(OBJECT_P, OBJECT_Q)) for k in ns[::7]]
    else:
        obj = [(int(k), transform(k, "cup", OBJECT_P, OBJECT_Q)) for k in ns[::7]]
    bag = write_bag(tmp_path / kind, {"/ee_pose": msgs, "/object": obj})
    (demo,) = read_bag(bag, "/ee_pose", frames={"object": "/object"})
    np.testing.assert_allclose(
        demo.frames["object"], [*OBJECT_P, *OBJECT_Q], atol=1e-12
    )
    # a bare pose recorded after the demonstration's end: no message for it
    late = [(int(ns[-1]) + 10**9, pose(OBJECT_P, OBJECT_Q))]
    bag = write_bag(tmp_path / "late", {"/ee_pose": msgs, "/object": late})
    with pytest.raises(DataFileError, match="has no message during the demonstration"):
        read_bag(bag, "/ee_pose", frames={"object": "/object"})


def test_a_still_object_with_sensor_noise_is_its_mean(tmp_path):
    ns, _, _, msgs = reach_messages()
    obj = object_messages(ns, noise=5e-4, every=1)
    bag = write_bag(tmp_path / "noisy", {"/ee_pose": msgs, "/object_pose": obj})
    (demo,) = read_bag(bag, "/ee_pose", frames={"object": "/object_pose"})
    mean = np.mean([[m.pose.position.x, m.pose.position.y, m.pose.position.z]
                    for _, m in obj], axis=0)  # fmt: skip
    np.testing.assert_allclose(demo.frames["object"][:3], mean, atol=1e-12)
    assert np.abs(demo.frames["object"][:3] - OBJECT_P).max() < 5e-4


def test_each_piece_of_a_split_bag_gets_its_own_pose(tmp_path):
    a, _, _, first = reach_messages(start_ns=T0)
    b, _, _, second = reach_messages(seed=1, start_ns=T0 + 20 * 10**9)
    moved = [OBJECT_P[0] + 0.1, OBJECT_P[1], OBJECT_P[2]]
    obj = object_messages(a) + object_messages(b, p=moved)
    bag = write_bag(tmp_path / "two", {"/ee_pose": first + second, "/object_pose": obj})
    demos = read_bag(bag, "/ee_pose", split_gap=5.0, frames={"object": "/object_pose"})
    assert len(demos) == 2
    np.testing.assert_allclose(demos[0].frames["object"][:3], OBJECT_P, atol=1e-12)
    np.testing.assert_allclose(demos[1].frames["object"][:3], moved, atol=1e-12)


def test_tf_frames_are_composed_to_the_demonstrations_base(tmp_path):
    bag, _, static, _, _ = chain_bag(tmp_path / "chain")
    frames = {"camera": "tf:camera_link"}
    (demo,) = read_bag(bag, frame="tool0", frames=frames)  # in world, the root
    _, p_base, r_base = static["base_link"]
    _, p_cam, r_cam = static["camera_link"]
    want_p = np.add(p_base, r_base.apply(p_cam))
    got = demo.frames["camera"]
    np.testing.assert_allclose(got[:3], want_p, atol=1e-12)
    turn = Rotation.from_quat(np.roll(got[3:], -1)).inv() * (r_base * r_cam)
    assert turn.magnitude() < 1e-9
    # with base_frame, in that frame: the static transform itself
    (demo,) = read_bag(bag, frame="tool0", base_frame="base_link", frames=frames)
    np.testing.assert_allclose(demo.frames["camera"][:3], p_cam, atol=1e-12)
    np.testing.assert_allclose(demo.frames["camera"][3:], wxyz(r_cam), atol=1e-12)


def test_a_tf_frame_that_moves_is_an_error_saying_how_far(tmp_path):
    bag, *_ = chain_bag(tmp_path / "chain")
    with pytest.raises(DataFileError) as e:
        read_bag(bag, frame="tool0", frames={"arm": "tf:link1"})
    text = str(e.value)
    assert text.startswith(f"{bag}: frames['arm'] (tf:link1) must stay still during")
    assert "it moved 0.05" in text and " m, from [" in text, text
    with pytest.raises(DataFileError, match="not in the tf tree of /tf and"):
        read_bag(bag, frame="tool0", frames={"cup": "tf:cup"})


def test_an_object_that_moved_names_bag_topic_and_distance(tmp_path):
    ns, _, _, msgs = reach_messages()
    obj = object_messages(ns)
    k = obj[3][0]
    obj[3] = (k, pose_stamped(k, np.add(OBJECT_P, [0.03, 0.04, 0.0]), OBJECT_Q))
    bag = write_bag(tmp_path / "moved", {"/ee_pose": msgs, "/object_pose": obj})
    with pytest.raises(DataFileError) as e:
        read_bag(bag, "/ee_pose", frames={"object": "/object_pose"})
    t = (k - ns[0]) / 1e9
    assert str(e.value) == (
        f"{bag}: frames['object'] (/object_pose) must stay still during the"
        " demonstration (a task frame is one pose per demonstration, within"
        " 0.005 m); it moved 0.05 m, from"
        f" {np.round(OBJECT_P, 4).tolist()} at {(obj[0][0] - ns[0]) / 1e9:.3f} s"
        f" to {np.round(np.add(OBJECT_P, [0.03, 0.04, 0]), 4).tolist()} at {t:.3f} s"
    )
    # turned (same place): the angle
    turned = wxyz(Rotation.from_euler("zx", [45, 10], degrees=True))
    obj[3] = (k, pose_stamped(k, OBJECT_P, turned))
    bag = write_bag(tmp_path / "turned", {"/ee_pose": msgs, "/object_pose": obj})
    with pytest.raises(DataFileError, match=r"it turned \d+(\.\d+)? degrees"):
        read_bag(bag, "/ee_pose", frames={"object": "/object_pose"})


@pytest.mark.parametrize(
    ("topics", "frames", "message"),
    [
        (
            {"/object_pose": []},
            {"object": "/object_pose"},
            "frames['object'] reads topic '/object_pose', which has no messages in"
            " the bag; expected at least one",
        ),
        (
            {},
            {"object": "/nope"},
            "frames['object'] reads topic '/nope', which the bag does not have; its"
            " topics are /ee_pose (geometry_msgs/msg/PoseStamped)",
        ),
        (
            {"/grip": [(T0, float64(1.0))]},
            {"object": "/grip"},
            "frames['object'] reads topic '/grip', which holds"
            " std_msgs/msg/Float64; expected one of geometry_msgs/msg/PoseStamped",
        ),
        (
            {"/later": [(T0 + 99 * 10**9, point_stamped(T0 + 99 * 10**9, PLACE))]},
            {"place": "/later"},
            "frames['place'] (/later) has no message during the demonstration or"
            " before it",
        ),
        (
            {"/cam": [(T0, point_stamped(T0, PLACE, frame="camera"))]},
            {"place": "/cam"},
            "frames['place'] (/cam) is in frame 'camera' (its header.frame_id);"
            " expected the demonstrations' frame 'world'",
        ),
        (
            {},
            {"object": "tf:object"},
            "frames['object'] reads tf frame 'object' from /tf and /tf_static; the"
            " bag has no tf topic",
        ),
    ],
)
def test_bad_frame_topics_are_clear_errors(tmp_path, topics, frames, message):
    _, _, _, msgs = reach_messages(start_ns=T0 + 10**9)
    bag = write_bag(tmp_path / "b", {"/ee_pose": msgs, **topics})
    with pytest.raises(DataFileError) as e:
        read_bag(bag, "/ee_pose", frames=frames)
    assert str(e.value).startswith(f"{bag}"), e.value
    assert message in str(e.value), e.value


def test_bad_frames_arguments(reach_bag):
    bag, _ = reach_bag
    with pytest.raises(ValidationError, match=r"must be a topic .* got 'object_pose'"):
        read_bag(bag, "/ee_pose", frames={"object": "object_pose"})
    with pytest.raises(ValidationError, match="frames must be a mapping"):
        read_bag(bag, "/ee_pose", frames=["/object_pose"])
    with pytest.raises(ValidationError, match="a frame's name must be made of"):
        read_bag(bag, "/ee_pose", frames={"9": "/object_pose"})
    # a pose of 7 values for a position of 2 columns
    with pytest.raises(DataFileError) as e:
        read_bag(bag, "/ee_pose", frames={"object": "/object_pose"}, drop=["z"])
    assert "frames['object'] (/object_pose) has 7 value(s); expected 2" in str(e.value)


def test_still_pose_takes_the_quaternions_sign_as_one_turn():
    q = np.array(OBJECT_Q)
    rows = [[*OBJECT_P, *q], [*OBJECT_P, *(-q)]]  # the same orientation
    np.testing.assert_allclose(still_pose(rows, "a", "f")[3:], q, atol=1e-12)
    with pytest.raises(DataFileError, match="must be finite numbers"):
        still_pose([[0.0, np.nan, 0.0]], "a", "f")


# -------------------------------------------------------------------- LeRobot
STATE = ["x", "y", "z", "gripper"]
POSE = ["ox", "oy", "oz", "oqw", "oqx", "oqy", "oqz"]


def lerobot_episodes(n_demos=3, moved=None, size=7):
    """Reaches whose ``observation.object_pose`` is constant over each episode."""
    eps, poses = [], []
    for i in range(n_demos):
        n = 40 + 5 * i
        s = np.linspace(0.0, 1.0, n)[:, None]
        obj = np.array([0.4 + 0.02 * i, -0.05 * i, 0.02, *OBJECT_Q])[:size]
        state = np.column_stack([s * obj[:3], s[:, 0] > 0.5])
        rows = np.tile(obj, (n, 1))
        if moved == i:
            rows[n // 2 :, 1] += 0.25
        eps.append({"observation.state": state, "observation.object_pose": rows})
        poses.append(obj.astype(np.float32).astype(np.float64))
    return eps, poses


@pytest.mark.parametrize("version", ["v2.1", "v3.0"])
def test_a_lerobot_feature_constant_over_each_episode(tmp_path, version):
    eps, poses = lerobot_episodes()
    names = {"observation.state": STATE, "observation.object_pose": POSE}
    root = write_lerobot(tmp_path / "ds", eps, names, version=version, per_file=2)
    frames = {"object": "observation.object_pose"}
    demos = read_lerobot(root, frames=frames)
    assert len(demos) == 3
    for d, want in zip(demos, poses, strict=True):
        assert d.columns == ("x", "y", "z", "gripper")  # not learned as data
        np.testing.assert_allclose(d.frames["object"], want, atol=1e-7)
    assert read_demos(root, frames=frames) == demos


def test_lerobot_frame_errors(tmp_path):
    eps, _ = lerobot_episodes(moved=1)
    names = {"observation.state": STATE, "observation.object_pose": POSE}
    root = write_lerobot(tmp_path / "ds", eps, names)
    with pytest.raises(DataFileError) as e:
        read_lerobot(root, frames={"object": "observation.object_pose"})
    assert str(e.value).startswith(
        f"{root} episode 1: frames['object'] (feature observation.object_pose) must"
        " stay still during the demonstration (a task frame is one pose per"
        " demonstration, within 0.005); it moved 0.25, from"
    ), e.value
    with pytest.raises(DataFileError) as e:
        read_lerobot(root, episodes=[0], frames={"object": "observation.nope"})
    assert "has no column 'observation.nope' (frames['object'])" in str(e.value)
    eps, _ = lerobot_episodes(size=4)
    names = {"observation.state": STATE, "observation.object_pose": POSE[:4]}
    root = write_lerobot(tmp_path / "four", eps, names)
    with pytest.raises(DataFileError) as e:
        read_lerobot(root, frames={"object": "observation.object_pose"})
    assert (
        "frames['object'] (feature observation.object_pose) has 4 value(s);"
        " expected 3 (a position, as the demonstration's position group) or 7"
    ) in str(e.value)
