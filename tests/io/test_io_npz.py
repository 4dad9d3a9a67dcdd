import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from io_samples import reach, rich_demo

from ndlfd._errors import DataFileError
from ndlfd._fileformat import save_npz
from ndlfd.demonstration import Demonstration
from ndlfd.io import (
    read_csv,
    read_demos,
    read_npz,
    write_csv,
    write_npz,
)


@settings(max_examples=25, deadline=None)
@given(
    st.integers(1, 8),
    st.integers(1, 5),
    st.floats(-1e9, 1e9, allow_nan=False),
    st.integers(0, 2**32 - 1),
)
def test_csv_and_npz_round_trip_property(tmp_path_factory, n, k, scale, seed):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(1e-3, 10, n)) - 5.0
    d = Demonstration.from_arrays(
        t, position=rng.normal(size=(n, k)) * scale, other=rng.normal(size=(n, 1))
    )
    folder = tmp_path_factory.mktemp("rt")
    assert read_csv(write_csv(d, folder / "d.csv")) == d
    assert read_npz(write_npz(d, folder / "d.npz")) == d


def test_npz_bad_files(tmp_path):
    with pytest.raises(DataFileError, match=r"none\.npz: no such file"):
        read_npz(tmp_path / "none.npz")
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, t=np.zeros(2))
    with pytest.raises(
        DataFileError, match=r"foreign\.npz: expected value columns besides the time"
    ):
        read_npz(foreign)
    good = write_npz(rich_demo(), tmp_path / "good.npz")
    trunc = tmp_path / "trunc.npz"
    trunc.write_bytes(good.read_bytes()[:100])
    with pytest.raises(
        DataFileError, match=r"trunc\.npz: expected an \.npz archive .* not readable"
    ):
        read_npz(trunc)
    other = save_npz(
        tmp_path / "model.npz", {"a": np.zeros(1)}, kind="DiscreteHMM", version=1
    )
    with pytest.raises(
        DataFileError, match="expected an ndlfd Demonstration file; got a 'DiscreteHMM'"
    ):
        read_npz(other)
    newer = save_npz(
        tmp_path / "v2.npz", {"t": np.zeros(1)}, kind="Demonstration", version=2
    )
    with pytest.raises(
        DataFileError, match="expected Demonstration format version 1; got version 2"
    ):
        read_npz(newer)
    lacking = save_npz(
        tmp_path / "lack.npz", {"t": np.zeros(1)}, kind="Demonstration", version=1
    )
    with pytest.raises(
        DataFileError,
        match=r"lack\.npz: the Demonstration file lacks \['X', 'columns', 'groups'\]",
    ):
        read_npz(lacking)
    bad = save_npz(
        tmp_path / "bad.npz",
        {"t": [0.0, 1.0], "X": [[0.0], [np.nan]]},
        kind="Demonstration",
        version=1,
        metadata={"columns": ["x"], "groups": ["position"]},
    )
    with pytest.raises(DataFileError, match=r"bad\.npz: X must be finite.*at row 1"):
        read_npz(bad)
    odd = save_npz(
        tmp_path / "odd.npz",
        {"t": [0.0], "X": [[0.0]]},
        kind="Demonstration",
        version=1,
        metadata={"columns": "x", "groups": ["position"]},
    )
    with pytest.raises(DataFileError, match="columns and groups must be lists"):
        read_npz(odd)


def test_plain_npz_is_mapped_like_csv_columns(tmp_path):
    t, pos, quat = reach()
    ref = Demonstration.from_arrays(t, position=pos, orientation=quat)
    a = tmp_path / "a.npz"
    np.savez(a, t=t, pos=pos, quat=quat, name=np.array("reach"), fps=np.array(100))
    d, maps = read_demos(a, return_mappings=True)
    assert d[0] == ref
    assert str(maps[0]) == "time=t; position=pos; orientation=quat; ignored name,fps"
    # conventional full names, a 1-D key per column, xyzw quaternions
    b = tmp_path / "b.npz"
    np.savez(b, Time=t, position=pos, qx=quat[:, 1], qy=quat[:, 2], qz=quat[:, 3],
             qw=quat[:, 0])  # fmt: skip
    assert read_npz(b).get("orientation").tolist() == quat.tolist()
    c = tmp_path / "c.npz"
    np.savez(c, stamp=t, P=pos, R=quat[:, [1, 2, 3, 0]], extra=pos[:, 0])
    groups = {"position": "p", "orientation": "r"}
    e = read_npz(c, time_column="STAMP", groups=groups, quaternion_order="xyzw",
                 drop=["extra"])  # fmt: skip
    assert e == ref
    with pytest.raises(
        DataFileError, match=r"c\.npz: cannot tell the group of array\(s\) \['P', 'R'"
    ):
        read_npz(c, time_column="stamp", drop=["extra"])


@pytest.mark.parametrize(
    ("arrays", "kwargs", "match"),
    [
        ({"t": [0.0, 1, 2], "pos": np.zeros((2, 2))}, {},
         r"array 'pos' has 2 rows; expected 3, like the time array 't'"),
        ({"t": [0.0, 1, 2], "pos": np.zeros((2, 3))}, {},
         r"has 2 rows \(transposed\?\)"),
        ({"t": [0.0, 1, 1], "pos": np.zeros((3, 2))}, {},
         r"time array 't' must be strictly increasing; got 1\.0 at row 2 after 1\.0"),
        ({"t": np.zeros((3, 2)), "pos": np.zeros((3, 2))}, {},
         r"the time array 't' must hold one number per sample"),
        ({"t": [0.0, 1], "pos": np.zeros((2, 2, 2))}, {},
         r"array 'pos' must hold numbers of shape \(n,\) or \(n, k\)"),
        ({"x": [0.0, 1]}, {}, r"expected a time column named 't' or 'time'"),
        ({"t": [0.0, 1], "x": [1.0, 2]}, {"groups": {"velocity": "v"}},
         r"groups velocity names 'v', but there is no such column"),
        ({"t": [0.0, 1], "x": [0.0, 1], "v": [1, 1]},
         {"groups": {"velocity": "v", "position": "V"}},
         r"maps array 'v' to both 'velocity' and 'position'"),
    ],
)  # fmt: skip
def test_plain_npz_errors(tmp_path, arrays, kwargs, match):
    p = tmp_path / "bad.npz"
    np.savez(p, **{k: np.asarray(v) for k, v in arrays.items()})
    with pytest.raises(DataFileError, match=match):
        read_npz(p, **kwargs)


def test_npz_never_unpickles(tmp_path):
    import pickle

    p = tmp_path / "obj.npz"
    np.savez(p, t=np.arange(2.0), pos=np.array([{"x": 1}, 2], dtype=object))
    with pytest.raises(
        DataFileError, match="pickled Python objects, which ndlfd never"
    ):
        read_npz(p)
    q = tmp_path / "evil.npz"
    q.write_bytes(pickle.dumps({"t": [0, 1]}))
    with pytest.raises(DataFileError) as info:
        read_npz(q)
    assert "a Python pickle, which ndlfd never loads" in str(info.value)
    assert "allow_pickle" not in str(info.value)
    assert "pickle.load" not in str(info.value)


@pytest.mark.parametrize("compress", [False, True])
def test_write_npz_stores_or_deflates_and_reads_back_the_same(tmp_path, compress):
    import zipfile

    d = rich_demo(40, 3)
    p = write_npz(d, tmp_path / "d.npz", compress=compress)
    assert read_npz(p) == d
    with zipfile.ZipFile(p) as z:
        kinds = {i.compress_type for i in z.infolist()}
    assert kinds == {zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED}
    if not compress:  # the default (the archive's time stamps differ: not bytes)
        with zipfile.ZipFile(write_npz(d, tmp_path / "default.npz")) as z:
            assert {i.compress_type for i in z.infolist()} == {zipfile.ZIP_STORED}
