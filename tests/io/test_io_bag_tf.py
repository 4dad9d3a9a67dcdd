"""tf chains: a frame's pose composed to a base frame, against a hand composition."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("rosbags")

from scipy.spatial.transform import Rotation

from bag_samples import (
    T0,
    chain_bag,
    rosbags_read,
    tf_message,
    transform,
    write_bag,
    wxyz,
)
from ndlfd._errors import DataFileError
from ndlfd.io import read_bag
from ndlfd.io._tf import TfEdge, tf_pose_rows


def by_hand(*links):
    """The pose (p, Rotation) of the last frame: p = p1 + R1 (p2 + R2 (...))."""
    p, r = np.zeros(3), Rotation.identity()
    for q, s in links:
        p, r = p + r.apply(q), r * s
    return p, r


def assert_pose(demo, want):
    """Position and orientation of each sample equal the hand composition."""
    P, Q = demo.get("position"), demo.get("orientation")
    for i, (p, r) in enumerate(want):
        assert np.allclose(P[i], p, atol=1e-12, rtol=0)
        got = Rotation.from_quat(np.roll(Q[i], -1))
        assert (got.inv() * r).magnitude() < 1e-9


def test_robot_state_publisher_chain_is_composed_to_the_root(tmp_path):
    # base_link -> link1 (a revolute joint about z) -> tool0 (0.45 m out, 0.10 up)
    n = 40
    ns = T0 + np.arange(n) * 20_000_000
    theta = np.linspace(0.0, 1.2, n)
    theta[25] = 0.7994
    msgs = [
        (
            int(k),
            tf_message(
                transform(k, "link1", [0, 0, 0], wxyz(Rotation.from_euler("z", a)),
                          parent="base_link"),
                transform(k, "tool0", [0.45, 0, 0.10], [1.0, 0, 0, 0], parent="link1"),
            ),
        )
        for k, a in zip(ns, theta, strict=True)
    ]  # fmt: skip
    bag = write_bag(tmp_path / "rsp", {"/tf": msgs})
    (d,) = read_bag(bag, "/tf", frame="tool0")
    want = np.column_stack(
        [0.45 * np.cos(theta), 0.45 * np.sin(theta), 0.1 + 0 * theta]
    )
    assert np.allclose(d.get("position"), want, atol=1e-12)
    assert np.round(d.get("position")[25], 3).tolist() == [0.314, 0.323, 0.1]
    assert np.allclose(d.t, (ns - ns[0]) / 1e9)
    # the frame's own transform alone (what was read before) is not the pose
    assert not np.allclose(d.get("position")[25], [0.45, 0, 0.10], atol=0.1)
    # the base asked for is the frame's parent: its own transform
    (own,) = read_bag(bag, "/tf", frame="tool0", base_frame="link1")
    assert np.allclose(own.get("position"), [[0.45, 0, 0.10]] * n, atol=1e-15)


def test_a_chain_with_static_parts_interpolated_at_the_frames_stamps(tmp_path):
    bag, s2, static, link1, link2 = chain_bag(tmp_path / "chain")
    t = (s2 - T0) / 1e9  # tool0 is static: link2's stamps are the reference

    def s(name):
        return static[name][1:]

    (d,) = read_bag(bag, "/tf", frame="tool0")  # default: the root, world
    assert np.allclose(d.t, t - t[0])
    assert_pose(d, [by_hand(s("base_link"), link1(x), link2(x), s("tool0")) for x in t])
    (d,) = read_bag(bag, frame="tool0", base_frame="base_link")  # /tf implied
    assert_pose(d, [by_hand(link1(x), link2(x), s("tool0")) for x in t])
    # a base on another branch: the camera's transform enters inverted
    p, r = s("camera_link")
    inv = (-r.inv().apply(p), r.inv())
    (d,) = read_bag(bag, "/tf", frame="tool0", base_frame="camera_link")
    assert_pose(d, [by_hand(inv, link1(x), link2(x), s("tool0")) for x in t])
    # a moving frame's own stamps; the frame and base swapped: the inverse
    (d,) = read_bag(bag, "/tf", frame="link1")
    heads = [m.transforms[0] for _, m in rosbags_read(bag, "/tf")]
    t1 = np.array([h.header.stamp.sec * 10**9 + h.header.stamp.nanosec
                   for h in heads if h.child_frame_id == "link1"])  # fmt: skip
    t1 = (t1 - T0) / 1e9
    assert np.allclose(d.t, t1 - t1[0])
    assert_pose(d, [by_hand(s("base_link"), link1(x)) for x in t1])
    # beyond link2's last message, link2 is held at its last transform
    (w,) = read_bag(bag, "/tf", frame="world", base_frame="link2")
    assert w.n_samples == len(s2)


def test_tf_errors_name_the_bag_and_the_frames_found(tmp_path):
    bag, *_ = chain_bag(tmp_path / "chain")
    found = "base_link, camera_link, link1, link2, tool0, world"
    with pytest.raises(
        DataFileError,
        match=rf"chain: no frame 'hand' in the tf tree of /tf and /tf_static; the"
        rf" frames found are {found}$",
    ):
        read_bag(bag, frame="hand")
    with pytest.raises(DataFileError, match=r"no base frame 'map' in the tf tree"):
        read_bag(bag, frame="tool0", base_frame="map")
    # a constant transform is not a demonstration
    with pytest.raises(
        DataFileError,
        match=rf"^{bag}: the pose of 'camera_link' in 'world' is constant \(only"
        r" static transforms: camera_link -> base_link -> world\), not a"
        r" demonstration",
    ):
        read_bag(bag, "/tf_static", frame="camera_link")
    with pytest.raises(DataFileError, match="is constant"):
        read_bag(bag, "/tf", frame="camera_link", base_frame="base_link")
    # two trees: a marker seen by a tracker in its own map
    ns = T0 + np.arange(5) * 10**8
    two = [
        (int(k), tf_message(transform(k, "link1", [0, 0, i], [1.0, 0, 0, 0], "base"),
                            transform(k, "marker", [i, 0, 0], [1.0, 0, 0, 0], "map")))
        for i, k in enumerate(ns)
    ]  # fmt: skip
    bag2 = write_bag(tmp_path / "two", {"/tf": two})
    with pytest.raises(
        DataFileError,
        match=r"frame 'marker' is not connected to the base frame 'base' in the tf"
        r" tree of /tf \('marker' goes up to 'map', 'base' to 'base'\); the frames"
        r" found are base, link1, map, marker",
    ):
        read_bag(bag2, frame="marker", base_frame="base")
    (d,) = read_bag(bag2, frame="marker")
    assert np.array_equal(d.get("position")[:, 0], np.arange(5.0))
    # a frame with two parents
    other = transform(1, "marker", [0, 0, 0], [1.0, 0, 0, 0], "base")
    bad = [*two, (int(ns[-1]) + 1, tf_message(other))]
    bag3 = write_bag(tmp_path / "bad", {"/tf": bad})
    with pytest.raises(
        DataFileError, match=r"frame 'marker' has several parents.*'base', 'map'"
    ):
        read_bag(bag3, frame="marker")


def matrix(values):
    """The 4x4 homogeneous matrix of x, y, z, qw, qx, qy, qz."""
    m = np.eye(4)
    m[:3, :3] = Rotation.from_quat(np.roll(values[3:], -1)).as_matrix()
    m[:3, 3] = values[:3]
    return m


@settings(max_examples=40, deadline=None)
@given(
    parents=st.lists(st.integers(0, 10), min_size=2, max_size=7),
    moving=st.lists(st.booleans(), min_size=7, max_size=7),
    pick=st.tuples(st.integers(0, 7), st.integers(0, 7)),
    seed=st.integers(0, 2**16),
)
def test_any_frame_in_any_base_equals_the_matrix_product(parents, moving, pick, seed):
    """Random trees: the pose against 4x4 matrices multiplied by hand."""
    rng = np.random.default_rng(seed)
    n_frames = len(parents) + 1  # frame k > 0 has parent parents[k-1] % k
    parent = {k: parents[k - 1] % k for k in range(1, n_frames)}
    if not any(moving[: n_frames - 1]):
        moving = [True, *moving[1:]]
    ns = np.arange(6, dtype=np.int64) * 10**8
    edges, values = {}, {}
    for k, p in parent.items():
        dyn = moving[k - 1]
        q = Rotation.random(len(ns) if dyn else 1, random_state=rng).as_quat()
        v = np.column_stack([rng.normal(size=(len(q), 3)), q[:, 3], q[:, :3]])
        values[k] = v if dyn else np.repeat(v, len(ns), axis=0)
        edges[f"f{k}"] = TfEdge(f"f{p}", f"f{k}", not dyn, ns if dyn else ns[:1], v)

    def root_to(k, i):  # the pose of frame k in f0 at stamp i
        m = np.eye(4)
        while k:
            m = matrix(values[k][i]) @ m
            k = parent[k]
        return m

    frame, base = (f % n_frames for f in pick)
    path = [frame]
    while path[-1]:
        path.append(parent[path[-1]])
    up = [base]
    while up[-1]:
        up.append(parent[up[-1]])
    common = next(f for f in path if f in up)
    chain = {*path[: path.index(common)], *up[: up.index(common)]}
    if not any(moving[k - 1] for k in chain):
        with pytest.raises(DataFileError, match="is constant"):
            tf_pose_rows("bag", edges, f"f{frame}", f"f{base}", topics="/tf")
        return
    got_base, stamps, got = tf_pose_rows(
        "bag", edges, f"f{frame}", f"f{base}", topics="/tf"
    )
    assert got_base == f"f{base}" and np.array_equal(stamps, ns)
    for i in range(len(ns)):
        want = np.linalg.inv(root_to(base, i)) @ root_to(frame, i)
        assert np.allclose(matrix(got[i]), want, atol=1e-9)
