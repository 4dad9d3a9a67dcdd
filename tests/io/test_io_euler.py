"""Euler angle columns: to unit quaternions on the way in, back on the way out."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from ndlfd import DataFileError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import (
    ColumnMapping,
    euler_columns,
    group_of_column,
    read_csv,
    read_demos,
    read_npz,
    read_table,
    write_csv,
    write_table,
)
from ndlfd.orientation import (
    check_euler,
    euler_to_quaternions,
    quaternions_to_euler,
)

SEQS = ["xyz", "zyx", "XYZ", "ZYX", "xzy", "YXZ"]
# away from gimbal lock: the middle angle within 1.2 rad of 0 (lock at pi/2)
ANGLES = arrays(
    np.float64,
    st.tuples(st.integers(1, 12), st.just(3)),
    elements=st.floats(-1.2, 1.2),
)


def _scipy_wxyz(angles, seq):
    return Rotation.from_euler(seq, angles).as_quat()[:, [3, 0, 1, 2]]


@settings(max_examples=60, deadline=None)
@given(angles=ANGLES, seq=st.sampled_from(SEQS))
def test_euler_quaternion_euler_round_trip_against_rotation(angles, seq):
    Q = euler_to_quaternions(angles, seq)
    ref = _scipy_wxyz(angles, seq)
    # the same rotation (q or -q), unit norm
    dots = np.abs(np.sum(Q * ref, axis=1))
    np.testing.assert_allclose(dots, 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(Q, axis=1), 1.0, atol=1e-12)
    back = quaternions_to_euler(Q, seq)
    # the angles within (-1.2, 1.2) come back as they were (no unwrap jump)
    np.testing.assert_allclose(back, angles, atol=1e-9)


def test_extrinsic_xyz_is_intrinsic_zyx_reversed():
    rpy = np.array([[0.1, -0.4, 2.5], [0.3, 0.2, -3.0]])
    np.testing.assert_allclose(
        euler_to_quaternions(rpy, "xyz"),
        euler_to_quaternions(rpy[:, ::-1], "ZYX"),
        atol=1e-12,
    )


def test_continuous_yaw_is_unwrapped_on_the_way_back():
    yaw = np.linspace(0, 4 * np.pi, 50)
    angles = np.column_stack([0 * yaw, 0 * yaw, yaw])
    back = quaternions_to_euler(euler_to_quaternions(angles), "xyz")
    np.testing.assert_allclose(back, angles, atol=1e-9)


def test_bad_conventions_are_refused():
    for bad in ["xyZ", "xxy", "xy", "abc", 3]:
        with pytest.raises(ValidationError, match=r"euler must be three axes.*got"):
            check_euler(bad)
    with pytest.raises(ValidationError, match=r"shape \(n_samples, 3\)"):
        euler_to_quaternions([[0.0, 1.0]])


def test_names_give_the_orientation_and_gripper_groups():
    assert group_of_column("Roll") == ("orientation", "Roll")
    assert group_of_column("gripper") == ("gripper", "gripper")
    assert group_of_column("rx") is None  # a rotation vector on many robots


def _rpy_csv(path, rpy, order=("roll", "pitch", "yaw"), extra=True):
    n = len(rpy)
    t = np.arange(n) * 0.1
    cols = {"roll": rpy[:, 0], "pitch": rpy[:, 1], "yaw": rpy[:, 2]}
    names = ["time", "x", "y", *order] + (["gripper"] if extra else [])
    data = [t, np.linspace(0, 1, n), np.linspace(1, 0, n)]
    data += [cols[c] for c in order]
    if extra:
        data.append((t > 0.2).astype(float))
    write_table(path, names, np.column_stack(data))
    return t


@pytest.mark.parametrize("seq", ["xyz", "ZYX", "XYZ"])
@pytest.mark.parametrize("order", [("roll", "pitch", "yaw"), ("yaw", "roll", "pitch")])
def test_csv_roll_pitch_yaw_read_and_written_back(tmp_path, seq, order):
    rng = np.random.default_rng(3)
    rpy = rng.uniform(-1.2, 1.2, (6, 3))
    p = tmp_path / "a.csv"
    _rpy_csv(p, rpy, order)
    demos, maps = read_demos(p, euler=seq, return_mappings=True)
    d, m = demos[0], maps[0]
    assert d.group_names == ("position", "orientation", "gripper")
    axes = [dict(zip("xyz", (0, 1, 2), strict=True))[a] for a in seq.lower()]
    ref = _scipy_wxyz(rpy[:, axes], seq)
    np.testing.assert_allclose(np.abs(np.sum(d.get("orientation") * ref, 1)), 1.0)
    assert m.euler == seq
    names = dict(m.groups)["orientation"]
    assert names == tuple(["roll", "pitch", "yaw"][a] for a in axes)
    assert str(m) == (
        f"time=time; position=x,y; orientation={','.join(names)} (Euler {seq});"
        " gripper=gripper"
    )
    # back: the file's names, the recorded angles
    out = write_csv(d, tmp_path / "out.csv", mapping=m)
    header = out.read_text().splitlines()[0].split(",")
    # its time column too, and the file's order of the angles
    assert header == ["time", "x", "y", *order, "gripper"]
    got = dict(zip(header, read_table(out)[1].T, strict=True))
    for j, name in enumerate(("roll", "pitch", "yaw")):
        np.testing.assert_allclose(got[name], rpy[:, j], atol=1e-12)
    again = read_csv(out, euler=seq)
    np.testing.assert_allclose(again.X, d.X, atol=1e-12)
    cols, groups, X = euler_columns(d, m)
    j = cols.index("roll")
    np.testing.assert_allclose(X[:, j], rpy[:, 0], atol=1e-12)
    assert groups[j] == "orientation"


def test_three_columns_mapped_to_orientation_are_euler_angles_in_order(tmp_path):
    p = tmp_path / "a.csv"
    angles = np.array([[0.1, 0.2, 0.3], [0.2, 0.1, 0.0]])
    write_table(p, ["t", "a", "b", "c"], np.column_stack([[0.0, 1.0], angles]))
    d = read_csv(p, groups={"orientation": ["c", "b", "a"]}, euler="ZYX")
    ref = _scipy_wxyz(angles[:, ::-1], "ZYX")
    np.testing.assert_allclose(np.abs(np.sum(d.get("orientation") * ref, 1)), 1.0)


def test_euler_errors(tmp_path):
    p = tmp_path / "a.csv"
    write_table(p, ["t", "roll", "yaw"], np.array([[0.0, 0.1, 0.2], [1, 0.1, 0.2]]))
    with pytest.raises(DataFileError, match=r"four quaternion columns .* or three"):
        read_csv(p)
    q = tmp_path / "b.csv"
    _rpy_csv(q, np.zeros((3, 3)))
    with pytest.raises(DataFileError, match=r"'zyz' turns about z twice"):
        read_csv(q, euler="zyz")
    with pytest.raises(ValidationError, match=r"euler must be three axes"):
        read_csv(q, euler="xyzw")
    z = tmp_path / "c.npz"
    np.savez(z, t=[0.0, 1, 2], roll=[0.0, 0, 0], pitch=[0, 0, np.nan], yaw=[0.0] * 3)
    with pytest.raises(DataFileError, match=r"c\.npz: .*finite.*at row 2"):
        read_npz(z)


def test_a_mapping_without_euler_leaves_quaternions():
    d = Demonstration.from_arrays([0.0, 1.0], orientation=[[1, 0, 0, 0]] * 2)
    m = ColumnMapping("a.csv", "t", (("orientation", ("qw", "qx", "qy", "qz")),))
    cols, groups, X = euler_columns(d, m)
    assert cols == ["qw", "qx", "qy", "qz"]
    assert groups == ["orientation"] * 4
    assert X is d.X
