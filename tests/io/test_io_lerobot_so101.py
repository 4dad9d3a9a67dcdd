"""LeRobot SO-100/101 motor names (``shoulder_pan.pos``, ...): read and learned.

The datasets are written as LeRobot writes them (``tests/lerobot_writer.py``),
with the motor names of LeRobot's ``so101_follower``.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

pytest.importorskip("pyarrow")

from lerobot_writer import (
    SO100_STATE,
    SO101_MOTORS,
    SO101_STATE,
    write_lerobot,
    write_so100,
    write_so101,
)
from ndlfd import KeypointHMM, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import DemoFiles, group_of_column, read_lerobot, write_csv
from ndlfd.io._lerobot import lerobot_episodes, read_episode_mapped
from ndlfd.io._mapping import LIBRARY_HINTS, MAPPING_DEFAULTS, MOTOR_KINDS

JOINTS = SO101_MOTORS[:5]
LAYOUTS = ["v2.1", "v3.0"]


@pytest.mark.parametrize("version", LAYOUTS)
@pytest.mark.parametrize("feature", ["observation.state", "action"])
def test_so101_names_read_as_joints_and_a_gripper(tmp_path, version, feature):
    root, eps = write_so101(tmp_path / "so101", version=version)
    demos = read_lerobot(root, feature=feature)
    assert len(demos) == len(eps)
    for d, e in zip(demos, eps, strict=True):
        assert d.columns == (*JOINTS, "gripper")
        assert d.groups == ("joints",) * 5 + ("gripper",)
        want = e[feature].astype(np.float32).astype(np.float64)  # as stored
        np.testing.assert_array_equal(d.X, want)
        n = len(want)
        np.testing.assert_array_equal(d.t, (np.arange(n) / 30).astype(np.float32))


def test_the_mapping_keeps_the_dataset_names_and_order(tmp_path):
    root, _ = write_so101(tmp_path / "so101")
    (item,) = lerobot_episodes(root, episodes=[2])
    ((_, m),) = read_episode_mapped(item, LIBRARY_HINTS, **MAPPING_DEFAULTS)
    assert m.time == "timestamp"
    assert m.groups == (
        ("joints", tuple(f"{j}.pos" for j in JOINTS)),
        ("gripper", ("gripper.pos",)),
    )
    assert m.order == tuple(SO101_STATE)


def test_velocity_and_effort_names_are_groups_of_their_own(tmp_path):
    names = [f"{j}.{k}" for k in ("pos", "vel", "effort") for j in ("a", "gripper")]
    rng = np.random.default_rng(0)
    eps = [{"observation.state": rng.normal(size=(12, 6))} for _ in range(2)]
    root = write_lerobot(tmp_path / "ds", eps, {"observation.state": names})
    d = read_lerobot(root)[0]
    assert d.columns == ("a", "gripper", "a.vel", "gripper.vel", "a.effort",
                         "gripper.effort")  # fmt: skip
    assert (
        d.groups
        == ("joints", "gripper") + ("joint_velocity",) * 2 + ("joint_effort",) * 2
    )
    np.testing.assert_array_equal(
        d.X, eps[0]["observation.state"].astype(np.float32).astype(np.float64)
    )


_MOTOR = st.from_regex(r"[A-Za-z][A-Za-z0-9_]{0,12}", fullmatch=True)


@given(_MOTOR, st.sampled_from(sorted(MOTOR_KINDS)), st.booleans())
def test_motor_names_give_the_group_of_their_kind(motor, kind, upper):
    suffix = kind.upper() if upper else kind
    group, column = group_of_column(f"{motor}.{suffix}")
    if kind == "pos" and motor.casefold() == "gripper":
        assert (group, column) == ("gripper", motor)
    elif kind == "pos":
        assert (group, column) == ("joints", motor)
    else:
        assert group == {"vel": "joint_velocity", "effort": "joint_effort"}[kind]
        assert column == f"{motor}.{suffix}"
    # other dotted names keep the user-group convention
    assert group_of_column(f"{motor}.width") == (motor, "width")


def _aligned_mean(demos, tau):
    """The demonstrations' values at unit times ``tau``, averaged (reference)."""
    stack = []
    for d in demos:
        u = (d.t - d.t[0]) / (d.t[-1] - d.t[0])
        stack.append(np.column_stack([np.interp(tau, u, x) for x in d.X.T]))
    return np.mean(stack, axis=0)


def test_the_default_fit_learns_the_joints_and_the_gripper(tmp_path):
    root, _ = write_so101(tmp_path / "so101", n_demos=6)
    demos = read_lerobot(root)
    model = KeypointHMM().fit(demos[:5])
    assert model.groups_ == ("gripper", "joints")
    # default levels: 2 for the gripper, 20 for each joint (as for position)
    np.testing.assert_array_equal(model.codebook_.levels, [2] + [20] * 5)
    like = demos[5]
    path = model.generate(like, dense=True)
    assert path.columns[1:] == JOINTS and path.columns[0] == "gripper"
    tau = (path.t - path.t[0]) / (path.t[-1] - path.t[0])
    ref = _aligned_mean(demos[:5], tau)
    joints = path.get("joints")
    err = np.abs(joints - ref[:, :5]).max(axis=0)
    span = np.ptp(ref[:, :5], axis=0)
    assert np.all(err <= 0.05 * span + 1.0), (err, span)  # degrees
    # the gripper keeps its two recorded values
    assert set(np.unique(path.get("gripper"))) <= {np.float32(5.0), np.float32(40.0)}


def test_fit_streams_the_dataset_like_read_lerobot(tmp_path):
    root, _ = write_so101(tmp_path / "so101", n_demos=4, version="v2.1")
    a = KeypointHMM().fit(DemoFiles(root))
    b = KeypointHMM().fit(read_lerobot(root))
    assert a.groups_ == b.groups_ == ("gripper", "joints")
    t = np.linspace(0.0, 3.0, 40)
    np.testing.assert_array_equal(a.generate(t).X, b.generate(t).X)


def test_a_generated_path_is_written_with_the_dataset_names(tmp_path):
    root, _ = write_so101(tmp_path / "so101", n_demos=3)
    (item,) = lerobot_episodes(root, episodes=[0])
    ((demo, m),) = read_episode_mapped(item, LIBRARY_HINTS, **MAPPING_DEFAULTS)
    model = KeypointHMM().fit(read_lerobot(root))
    path = model.generate(demo, dense=True)  # gripper first, then the joints
    out = write_csv(path, tmp_path / "out.csv", mapping=m)
    lines = out.read_text().splitlines()
    assert lines[0].split(",") == ["timestamp", *SO101_STATE]
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_array_equal(table[:, 0], path.t)
    np.testing.assert_array_equal(table[:, 1:6], path.get("joints"))
    np.testing.assert_array_equal(table[:, 6], path.get("gripper")[:, 0])


def test_a_float32_prefix_continues_a_float64_plan(tmp_path):
    # LeRobot stores timestamp as float32; the plan is the float64 clock k / fps
    root, _ = write_so101(tmp_path / "so101", n_demos=6)
    demos = read_lerobot(root)
    model = KeypointHMM().fit(demos[:5])
    episode = demos[5]
    n = episode.n_samples
    plan = np.arange(n) / 30.0
    prefix = Demonstration(episode.t[:9], episode.X[:9], episode.columns,
                           episode.groups)  # fmt: skip
    assert prefix.t[8] != plan[8]  # 0.2666666805744171 against 0.26666666666666666
    path = model.generate(plan, observed=prefix)
    np.testing.assert_array_equal(path.t[9:], plan[9:])
    np.testing.assert_allclose(path.t[:9], plan[:9], rtol=0, atol=6e-8)
    # the prefix is kept (the path starts where the robot was)
    np.testing.assert_allclose(path.get("joints")[:9], prefix.get("joints"), atol=1e-9)
    # a stamp a microsecond off is another sample: a clear error
    late = plan.copy()
    late[8] += 1e-6
    with pytest.raises(ValidationError, match=r"its sample 8 is at .* expected at"):
        model.generate(late, observed=prefix)


@pytest.mark.parametrize("names_as", [dict, list])
def test_so100_main_names_read_as_joints_and_a_gripper(tmp_path, names_as):
    root, eps = write_so100(tmp_path / "so100", names_as=names_as)
    demos = read_lerobot(root)
    for d, e in zip(demos, eps, strict=True):
        assert d.columns == tuple(SO100_STATE)  # each column keeps its name
        assert d.groups == ("joints",) * 5 + ("gripper",)
        want = e["observation.state"].astype(np.float32).astype(np.float64)
        np.testing.assert_array_equal(d.X, want)
    (item,) = lerobot_episodes(root, episodes=[1])
    ((_, m),) = read_episode_mapped(item, LIBRARY_HINTS, **MAPPING_DEFAULTS)
    assert m.groups == (
        ("joints", tuple(SO100_STATE[:5])),
        ("gripper", ("main_gripper",)),
    )
    # learned as the SO-101 names are: the same model on the same numbers
    so101, _ = write_so101(tmp_path / "so101", version="v2.1")
    a, b = KeypointHMM().fit(demos), KeypointHMM().fit(read_lerobot(so101))
    assert a.groups_ == b.groups_ == ("gripper", "joints")
    t = np.linspace(0.0, 3.0, 40)
    np.testing.assert_array_equal(a.generate(t).X, b.generate(t).X)
    assert a.generate(t).columns == ("main_gripper", *SO100_STATE[:5])


@given(
    st.sampled_from(SO101_MOTORS),
    st.lists(st.booleans(), min_size=30, max_size=30),
    st.sampled_from(["", "x", "_", ".pos2", "s"]),
    st.sampled_from(["main_", "left_", "follower_", "main", "Main_"]),
)
def test_main_names_only_as_so100_writes_them(motor, upper, tail, prefix):
    name = "".join(
        ch.upper() if up else ch
        for ch, up in zip(prefix + motor + tail, upper, strict=False)
    )
    hit = group_of_column(name)
    if prefix.casefold() == "main_" and tail == "":  # any case
        assert hit == ("gripper" if motor == "gripper" else "joints", name)
    elif hit is not None:  # another convention's reading, never a joint
        assert hit[0] not in ("joints", "gripper")
