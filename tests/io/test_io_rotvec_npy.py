"""Rotation vectors and explicit representations; .npy files (issue 37)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from lab_logs import write_ur
from scipy.spatial.transform import Rotation

from ndlfd import DataFileError, ValidationError
from ndlfd.io import read_csv, read_demos, read_npy, read_table, write_csv
from ndlfd.orientation import (
    check_representation,
    from_quaternions,
    quaternions_to_rotvec,
    rotvec_to_quaternions,
    to_quaternions,
)

# rotation vectors of angle below pi (scipy's own range), one stream
ROTVECS = arrays(
    np.float64, st.tuples(st.integers(1, 20), st.just(3)), elements=st.floats(-1.8, 1.8)
)


@settings(max_examples=80, deadline=None)
@given(rv=ROTVECS)
def test_rotvec_round_trip_through_rotation_within_1e9(rv):
    rv = rv[np.linalg.norm(rv, axis=1) < np.pi - 1e-3]
    if rv.shape[0] == 0:
        return
    Q = rotvec_to_quaternions(rv)
    ref = Rotation.from_rotvec(rv).as_quat(scalar_first=True)
    np.testing.assert_allclose(np.abs(np.sum(Q * ref, axis=1)), 1.0, atol=1e-12)
    # one stream at a time: each row back on its own
    for k in range(rv.shape[0]):
        back = quaternions_to_rotvec(Q[k : k + 1])
        np.testing.assert_allclose(back[0], rv[k], atol=1e-9)


def test_rotvec_stream_through_pi_continues():
    angle = np.linspace(2.8, 3.5, 40)  # about z, through pi
    rv = np.column_stack([0 * angle, 0 * angle, angle])
    logged = Rotation.from_rotvec(rv).as_rotvec()  # scipy flips past pi
    assert np.abs(np.diff(logged[:, 2])).max() > 6  # the jump a log shows
    Q = rotvec_to_quaternions(logged)
    back = quaternions_to_rotvec(Q)
    np.testing.assert_allclose(back, rv, atol=1e-9)  # continuous, as recorded


def test_representations_against_scipy():
    rng = np.random.default_rng(0)
    rot = Rotation.random(7, random_state=rng)
    want = rot.as_quat(scalar_first=True)
    for rep, values in [
        ("rotvec", rot.as_rotvec()),
        ("euler-xyz", rot.as_euler("xyz")),
        ("euler-ZYX", rot.as_euler("ZYX")),
        ("quat-xyzw", rot.as_quat()),
        ("quat-wxyz", want),
    ]:
        Q = to_quaternions(values, rep)
        np.testing.assert_allclose(np.abs(np.sum(Q * want, axis=1)), 1.0, atol=1e-12)
        again = Rotation.from_quat(from_quaternions(Q, rep)[:, [1, 2, 3, 0]]
                                   if rep == "quat-wxyz" else
                                   to_quaternions(from_quaternions(Q, rep), rep)[
                                       :, [1, 2, 3, 0]])  # fmt: skip
        assert np.allclose((again * rot.inv()).magnitude(), 0.0, atol=1e-9)
    for bad in ("axis", "euler-xyzw", "quat-abcd", 3):
        with pytest.raises(ValidationError, match=r"rotvec .* euler-SEQ"):
            check_representation(bad)


def test_ur_rotvec_csv_read_and_written_back(tmp_path):
    ((_, _, rv),) = write_ur(tmp_path / "ur", n_demos=1)
    p = tmp_path / "ur" / "reach0.csv"
    # three unnamed orientation columns: an error naming the choices
    with pytest.raises(DataFileError, match=r"rx, ry, rz hold an orientation of"
                       r" three numbers.*rotvec.*euler-SEQ.*"
                       r"representation='rotvec'"):  # fmt: skip
        read_csv(p)
    demos, maps = read_demos(p, representation="rotvec", return_mappings=True)
    d, m = demos[0], maps[0]
    assert str(m) == "time=t; position=x,y,z; orientation=rx,ry,rz (rotation vector)"
    ref = Rotation.from_rotvec(rv).as_quat(scalar_first=True)
    np.testing.assert_allclose(np.abs(np.sum(d.get("orientation") * ref, 1)), 1.0)
    # a rotation vector read as Euler angles would be a different rotation
    wrong = Rotation.from_euler("xyz", rv) * Rotation.from_rotvec(rv).inv()
    assert wrong.magnitude().max() > 1.0  # radians
    out = write_csv(d, tmp_path / "back.csv", mapping=m)
    names, data = read_table(out)
    assert names == ["t", "x", "y", "z", "rx", "ry", "rz"]
    got = Rotation.from_rotvec(data[:, 4:])
    assert (got * Rotation.from_rotvec(rv).inv()).magnitude().max() < 1e-9
    # the same file with the group named by hand
    e = read_csv(p, groups={"orientation": ["rx", "ry", "rz"]},
                 representation="rotvec")  # fmt: skip
    np.testing.assert_array_equal(e.get("orientation"), d.get("orientation"))


def test_three_mapped_columns_need_a_representation(tmp_path):
    """Before issue 37 they were read as Euler xyz; now they are an error."""
    p = tmp_path / "a.csv"
    p.write_text("t,a,b,c\n0,0.1,0.2,0.3\n1,0.2,0.1,0.0\n")
    with pytest.raises(DataFileError, match=r"has three columns, which hold"
                       r" rotation vectors or Euler angles: name which"):  # fmt: skip
        read_csv(p, groups={"orientation": ["a", "b", "c"]})
    with pytest.raises(DataFileError, match=r"representation quat-wxyz takes 4"):
        read_csv(p, groups={"orientation": ["a", "b", "c"]},
                 representation="quat-wxyz")  # fmt: skip
    d = read_csv(p, groups={"orientation": ["a", "b", "c"]},
                 representation="euler-ZYX")  # fmt: skip
    ref = Rotation.from_euler("ZYX", [[0.1, 0.2, 0.3], [0.2, 0.1, 0.0]])
    ref = ref.as_quat(scalar_first=True)
    np.testing.assert_allclose(np.abs(np.sum(d.get("orientation") * ref, 1)), 1.0)


def _npy(tmp_path, name="a.npy", n=30):
    rng = np.random.default_rng(1)
    data = np.column_stack([np.cumsum(rng.normal(size=(n, 2)), axis=0),
                            rng.normal(size=(n, 3))])  # fmt: skip
    np.save(tmp_path / name, data)
    return data


def test_npy_columns_by_option_or_sidecar(tmp_path):
    data = _npy(tmp_path)
    names = ["x", "y", "joint_1", "joint_2", "joint_3"]
    demos, maps = read_demos(tmp_path / "a.npy", columns=names, rate=10,
                             return_mappings=True)  # fmt: skip
    d = demos[0]
    np.testing.assert_array_equal(d.t, np.arange(30) / 10)
    np.testing.assert_array_equal(d.X, data)
    assert str(maps[0]) == (
        "time=(row number) / 10 Hz; position=x,y; joints=joint_1,joint_2,joint_3 (npy)"
    )
    (tmp_path / "a.columns.txt").write_text("# names\nx, y\njoint_1,joint_2\njoint_3\n")
    again = read_demos(tmp_path, rate=10)  # a folder of .npy files
    assert again[0] == d
    # a time column among the names
    t = np.arange(30) * 0.05
    np.save(tmp_path / "b.npy", np.column_stack([t, data[:, :2]]))
    b = read_npy(tmp_path / "b.npy", columns=["t", "x", "y"])
    np.testing.assert_array_equal(b.t, t)


def test_npy_errors_say_what_was_expected(tmp_path):
    _npy(tmp_path)
    with pytest.raises(DataFileError, match=r"holds no column names; name its"
                       r" columns with columns= a,b,c or in a sidecar file"
                       r" a\.columns\.txt"):  # fmt: skip
        read_npy(tmp_path / "a.npy")
    with pytest.raises(DataFileError, match=r"has 5 columns .*names 2"):
        read_npy(tmp_path / "a.npy", columns=["x", "y"])
    np.save(tmp_path / "o.npy", np.array([{"a": 1}, None], dtype=object))
    with pytest.raises(DataFileError, match=r"loaded without pickle"):
        read_npy(tmp_path / "o.npy", columns=["x"])
    np.save(tmp_path / "v.npy", np.arange(5.0))
    with pytest.raises(DataFileError, match=r"shape \(n_samples, n_columns\); got"
                       r" shape \(5,\) \(one column: save a.reshape"):  # fmt: skip
        read_npy(tmp_path / "v.npy", columns=["x"])
    np.save(tmp_path / "c.npy", np.ones((3, 2), dtype=complex))
    with pytest.raises(DataFileError, match=r"real numbers .*complex128"):
        read_npy(tmp_path / "c.npy", columns=["x", "y"])
    np.save(tmp_path / "k.npy", np.ones((3, 2, 2)))
    with pytest.raises(DataFileError, match=r"got shape \(3, 2, 2\)"):
        read_npy(tmp_path / "k.npy", columns=["x", "y"])
