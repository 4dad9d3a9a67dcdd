"""Two arms read by their names: lab exports with left_/right_ prefixes (issue 43).

The convention: each hand's pose is its own groups (``left_position``,
``left_orientation``; ``right_...``), its joints ``left_joints``, and both
grippers one group ``gripper``. Every expected mapping below is written out
by hand; rotations are checked against scipy's ``Rotation`` directly.
"""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from ndlfd import DataFileError
from ndlfd.io import (
    group_of_column,
    read_csv,
    read_demos,
    write_csv,
)
from ndlfd.io._names import lab_groups

T = np.arange(6) * 0.1


def _write(path, names, X):
    lines = [",".join(names)] + [",".join(repr(float(v)) for v in row) for row in X]
    path.write_text("\n".join(lines) + "\n")
    return path


def _unit_quaternions(n, seed):
    """Quaternions w, x, y, z with w > 0.5 (no sign flip along the rows)."""
    rng = np.random.default_rng(seed)
    q = np.column_stack([np.full(n, 2.0), rng.normal(0, 0.5, (n, 3))])
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _angle(q1, q2):
    """The rotation angle between two arrays of quaternions w, x, y, z (rad)."""
    r1 = Rotation.from_quat(q1, scalar_first=True)
    r2 = Rotation.from_quat(q2, scalar_first=True)
    return (r1.inv() * r2).magnitude()


def _lab(names):
    return lab_groups(names, group_of_column, group_of_column)


def _groups(names):
    return _lab(names).groups


def test_hand_names_against_a_hand_made_table():
    xyz = ("x", "y", "z")
    table = [
        # lab names of each hand
        (
            [f"left_{c}" for c in xyz] + [f"right_{c}" for c in xyz],
            {
                "left_position": ["left_x", "left_y", "left_z"],
                "right_position": ["right_x", "right_y", "right_z"],
            },
        ),
        (
            [f"left_pos_{c}" for c in xyz] + [f"right_ee_{c}" for c in "zyx"],
            {
                "left_position": ["left_pos_x", "left_pos_y", "left_pos_z"],
                "right_position": ["right_ee_x", "right_ee_y", "right_ee_z"],
            },
        ),
        (  # quaternions of each hand put in w, x, y, z order by their names
            ["left_qx", "left_qy", "left_qz", "left_qw"]
            + ["right_quat_w", "right_quat_x", "right_quat_y", "right_quat_z"],
            {
                "left_orientation": ["left_qw", "left_qx", "left_qy", "left_qz"],
                "right_orientation": [
                    "right_quat_w",
                    "right_quat_x",
                    "right_quat_y",
                    "right_quat_z",
                ],
            },
        ),
        (  # joints by number and by ALOHA's names; one gripper group of both
            ["left_joint_1", "left_joint_2", "left_gripper"]
            + ["right_waist", "right_shoulder", "right_gripper"],
            {
                "left_joints": ["left_joint_1", "left_joint_2"],
                "gripper": ["left_gripper", "right_gripper"],
                "right_joints": ["right_waist", "right_shoulder"],
            },
        ),
        (  # LeRobot's bimanual SO-100 motor names
            ["left_shoulder_pan.pos", "left_gripper.pos"]
            + ["right_shoulder_pan.pos", "right_gripper.pos"],
            {
                "left_joints": ["left_shoulder_pan.pos"],
                "gripper": ["left_gripper.pos", "right_gripper.pos"],
                "right_joints": ["right_shoulder_pan.pos"],
            },
        ),
        (  # an unprefixed position stays position beside the hands' grippers
            ["x", "y", "z", "left_gripper", "right_gripper"],
            {
                "position": ["x", "y", "z"],
                "gripper": ["left_gripper", "right_gripper"],
            },
        ),
        (  # one hand alone is one arm, as before
            ["right_pos_x", "right_pos_y", "right_pos_z"],
            {"position": ["right_pos_x", "right_pos_y", "right_pos_z"]},
        ),
    ]
    for names, want in table:
        assert _groups(names) == want, names
    # a measured and a commanded set of one hand: the commanded left out
    names = [f"left_current_pos_{c}" for c in xyz] + [f"left_goal_pos_{c}" for c in xyz]
    names += [f"right_pos_{c}" for c in xyz]
    found = _lab(names)
    assert found.groups == {
        "left_position": names[:3],
        "right_position": names[6:],
    }
    assert found.left_out == names[3:6]
    # three columns of a hand that do not say their representation
    found = _lab([f"{h}_r{c}" for h in ("left", "right") for c in xyz])
    assert found.unsure == [
        ("left_orientation", ["left_rx", "left_ry", "left_rz"]),
        ("right_orientation", ["right_rx", "right_ry", "right_rz"]),
    ]
    # without the convention's rule, no name is a hand's (as before)
    assert lab_groups(["left_x", "right_x"]).unknown == ["left_x", "right_x"]


def test_two_arm_lab_csv_reads_into_each_hands_groups(tmp_path):
    n = T.size
    rng = np.random.default_rng(1)
    qL, qR = _unit_quaternions(n, 2), _unit_quaternions(n, 3)
    pL, pR = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    jL, jR = rng.normal(size=(n, 6)), rng.normal(size=(n, 6))
    gL, gR = np.linspace(0, 1, n), np.linspace(1, 0, n)
    names = [
        "t",
        "left_x",
        "left_y",
        "left_z",
        "left_qw",
        "left_qx",
        "left_qy",
        "left_qz",
        "left_gripper",
    ]
    names += [f"left_joint_{i}" for i in range(1, 7)]
    names += [
        "right_pos_x",
        "right_pos_y",
        "right_pos_z",
        "right_quat_x",
        "right_quat_y",
        "right_quat_z",
        "right_quat_w",
        "right_gripper",
    ]
    names += [f"right_joint_{i}" for i in range(1, 7)]
    X = np.column_stack([T, pL, qL, gL, jL, pR, qR[:, [1, 2, 3, 0]], gR, jR])
    p = _write(tmp_path / "arms.csv", names, X)
    demos, maps = read_demos(p, return_mappings=True)
    d, m = demos[0], maps[0]
    assert dict(m.groups) == {
        "left_position": ("left_x", "left_y", "left_z"),
        "left_orientation": ("left_qw", "left_qx", "left_qy", "left_qz"),
        "gripper": ("left_gripper", "right_gripper"),
        "left_joints": tuple(f"left_joint_{i}" for i in range(1, 7)),
        "right_position": ("right_pos_x", "right_pos_y", "right_pos_z"),
        "right_orientation": (
            "right_quat_w",
            "right_quat_x",
            "right_quat_y",
            "right_quat_z",
        ),
        "right_joints": tuple(f"right_joint_{i}" for i in range(1, 7)),
    }
    assert str(m).startswith(
        "time=t; left_position=left_x,left_y,left_z; left_orientation=left_qw,"
        "left_qx,left_qy,left_qz; gripper=left_gripper,right_gripper; left_joints="
    )
    assert d.group_names == (
        "left_position",
        "left_orientation",
        "gripper",
        "left_joints",
        "right_position",
        "right_orientation",
        "right_joints",
    )
    assert d.columns[7:9] == ("left_gripper", "right_gripper")
    np.testing.assert_array_equal(d.t, T)
    for group, want in [
        ("left_position", pL),
        ("right_position", pR),
        ("left_joints", jL),
        ("right_joints", jR),
        ("left_orientation", qL),
        ("right_orientation", qR),
        ("gripper", np.column_stack([gL, gR])),
    ]:
        np.testing.assert_allclose(d.get(group), want, rtol=0, atol=1e-15)
    for group in ("left_orientation", "right_orientation"):
        np.testing.assert_allclose(np.linalg.norm(d.get(group), axis=1), 1, atol=1e-15)


@pytest.mark.parametrize("euler", [None, "ZYX"])
def test_euler_angles_of_each_hand_against_scipy_and_back(tmp_path, euler):
    n = T.size
    rng = np.random.default_rng(4)
    aL = rng.uniform(-1.2, 1.2, (n, 3))  # roll, pitch, yaw
    aR = rng.uniform(-1.2, 1.2, (n, 3))
    names = [
        "t",
        "left_x",
        "left_y",
        "left_z",
        "left_roll",
        "left_pitch",
        "left_yaw",
        "right_x",
        "right_y",
        "right_z",
        "right_yaw",
        "right_pitch",
        "right_roll",
    ]
    X = np.column_stack(
        [T, rng.normal(size=(n, 3)), aL, rng.normal(size=(n, 3)), aR[:, ::-1]]
    )
    p = _write(tmp_path / "euler.csv", names, X)
    d, m = read_demos(p, euler=euler, return_mappings=True)
    d, m = d[0], m[0]
    seq = euler or "xyz"
    assert m.euler == seq
    assert d.columns[3:7] == ("left_qw", "left_qx", "left_qy", "left_qz")
    assert d.columns[10:14] == ("right_qw", "right_qx", "right_qy", "right_qz")
    for group, a in (("left_orientation", aL), ("right_orientation", aR)):
        # the angles about x, y and z, in the convention's order for scipy
        ordered = a[:, ["xyz".index(c) for c in seq.lower()]]
        want = Rotation.from_euler(seq, ordered).as_quat(scalar_first=True)
        q = d.get(group)
        assert np.max(_angle(q, want)) < 1e-9
        np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1, atol=1e-15)
    # written back with the mapping: the same angles under the same names
    back = write_csv(d, tmp_path / "back.csv", mapping=m)
    header = back.read_text().splitlines()[0].split(",")
    assert header == names
    Y = np.loadtxt(back, delimiter=",", skiprows=1)
    np.testing.assert_allclose(Y, X, rtol=0, atol=1e-9)


def test_rotation_vectors_of_each_hand_need_their_representation(tmp_path):
    n = T.size
    rng = np.random.default_rng(5)
    rL, rR = rng.normal(0, 0.8, (n, 3)), rng.normal(0, 0.8, (n, 3))
    names = ["t"] + [
        f"{h}_{k}{c}" for h in ("left", "right") for k in ("", "r") for c in "xyz"
    ]
    X = np.column_stack([T, rng.normal(size=(n, 3)), rL, rng.normal(size=(n, 3)), rR])
    p = _write(tmp_path / "ur.csv", names, X)
    with pytest.raises(DataFileError) as err:
        read_csv(p)
    msg = str(err.value)
    assert "left_rx, left_ry, left_rz, right_rx, right_ry, right_rz hold" in msg
    assert msg.endswith(
        "representation='rotvec' (or another representation in place of rotvec)"
    )
    assert "'left_orientation': ['left_rx', 'left_ry', 'left_rz']" in msg
    d = read_csv(p, representation="rotvec")
    for group, r in (("left_orientation", rL), ("right_orientation", rR)):
        want = Rotation.from_rotvec(r).as_quat(scalar_first=True)
        assert np.max(_angle(d.get(group), want)) < 1e-9
    # named rotation vectors say theirs
    named = [c.replace("_r", "_rotvec_") for c in names]
    d2 = read_csv(_write(tmp_path / "named.csv", named, X))
    np.testing.assert_array_equal(d2.X, d.X)
    assert d2.group_names == (
        "left_position",
        "left_orientation",
        "right_position",
        "right_orientation",
    )


def test_two_groups_claiming_one_column(tmp_path):
    names = ["t", "left_x", "left_y", "left_z", "right_x", "right_y", "right_z"]
    p = _write(tmp_path / "a.csv", names, np.column_stack([T, np.ones((6, 6))]))
    groups = {
        "left_position": ["left_x", "left_y", "left_z"],
        "right_position": ["left_x", "right_y", "right_z"],
    }
    with pytest.raises(
        DataFileError,
        match=r"groups maps column 'left_x' to both"
        r" 'left_position' and 'right_position'",
    ):
        read_csv(p, groups=groups)


def test_a_hand_with_two_position_columns(tmp_path):
    names = [
        "t",
        "left_pos_x",
        "left_pos_y",
        "right_pos_x",
        "right_pos_y",
        "right_pos_z",
    ]
    X = np.column_stack([T, np.arange(30.0).reshape(6, 5)])
    p = _write(tmp_path / "a.csv", names, X)
    with pytest.raises(DataFileError) as err:
        read_csv(p)
    msg = str(err.value)
    assert (
        "a hand's position takes 3 columns (x, y, z); got left_position 2"
        " (left_pos_x, left_pos_y); give each hand all three" in msg
    )
    line = msg.split("e.g. ")[1]
    assert line == "groups={'left_xy': ['left_pos_x', 'left_pos_y']}"
    # pasted, it reads (the right hand's names left alone are one arm's)
    d = read_csv(p, groups={"left_xy": ["left_pos_x", "left_pos_y"]})
    assert d.group_names == ("left_xy", "position")
    np.testing.assert_array_equal(d.get("left_xy"), X[:, 1:3])
    # mapped by hand alike
    with pytest.raises(DataFileError, match=r"got right_position 2 \(right_pos_x,"):
        read_csv(
            p,
            groups={"right_position": ["right_pos_x", "right_pos_y"]},
            drop=["left_*", "right_pos_z"],
        )


def test_hands_in_two_representations_are_an_error(tmp_path):
    names = [
        "t",
        "left_x",
        "left_y",
        "left_z",
        "left_roll",
        "left_pitch",
        "left_yaw",
        "right_x",
        "right_y",
        "right_z",
        "right_rotvec_x",
        "right_rotvec_y",
        "right_rotvec_z",
    ]
    X = np.column_stack([T, np.full((6, 12), 0.1)])
    p = _write(tmp_path / "a.csv", names, X)
    with pytest.raises(
        DataFileError,
        match=r"left_orientation is read as xyz and"
        r" right_orientation as rotvec; expected the hands'"
        r" orientations in one representation",
    ):
        read_csv(p)


_POOL = ["x", "y", "z", "qw", "qx", "qy", "qz", "roll", "pitch", "yaw", "gripper",
         "pos_x", "pos_y", "current_pos_x", "goal_pos_x", "joint_1", "q1", "rx",
         "ry", "rz", "rotvec_x", "left_pos_x", "left_pos_y", "left_x",
         "left_gripper", "right_pos_x", "right_gripper", "right_waist", "ee_x",
         "shoulder_pan.pos", "gripper.pos", "grip.w", "left.x", "quat_w",
         "main_gripper", "left_joints.a", "right_joints.b", "speed"]  # fmt: skip


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(_POOL), min_size=1, max_size=8, unique=True))
def test_names_of_one_hand_or_none_read_as_without_hands(names):
    """Only names of both hands change what a header reads as."""
    sides = {side for n in names for side in ("left_", "right_") if n.startswith(side)}
    assume(len(sides) < 2)
    assert _lab(names) == lab_groups(names, group_of_column)  # no rule: no hand
