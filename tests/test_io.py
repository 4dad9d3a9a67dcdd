import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from ndlfd._errors import DataFileError, ValidationError
from ndlfd.io import read_table, write_table


def _reference_parse(text):
    """Obviously-correct parser of the dialect: strip, skip blanks and comments."""
    lines = [ln.strip() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln and not ln.startswith("#")]
    header = [h.strip() for h in lines[0].split(",")]
    rows = [[float(v) for v in ln.split(",")] for ln in lines[1:]]
    return header, np.array(rows)


# ---------------------------------------------------------------- read_table
def test_read_table_known_answer(tmp_path):
    text = "# recorded 2024\n t , x,y \n\n0,1,2\n# pause\n0.5, -1e-3 ,3\n"
    p = tmp_path / "a.csv"
    p.write_text(text)
    cols, data = read_table(p)
    ref_cols, ref = _reference_parse(text)
    assert cols == ["t", "x", "y"] == ref_cols
    assert data.dtype == np.float64 and data.flags.c_contiguous
    np.testing.assert_array_equal(data, ref)
    np.testing.assert_array_equal(data, [[0, 1, 2], [0.5, -1e-3, 3]])


def test_read_table_accepts_bom_and_crlf(tmp_path):
    p = tmp_path / "bom.csv"
    p.write_bytes(b"\xef\xbb\xbft,x\r\n0,1\r\n1,2\r\n")
    cols, data = read_table(p)
    assert cols == ["t", "x"]
    np.testing.assert_array_equal(data, [[0, 1], [1, 2]])


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", r"bad\.csv: expected a header row and data rows; got an empty file"),
        ("# only a comment\n\n", r"bad\.csv: .*got an empty file"),
        ("t,x\n", r"bad\.csv: expected data rows below the header on line 1"),
        ("t,x\n0,1\n1,2,3\n", r"bad\.csv, line 3: expected 2 comma-separated .*got 3"),
        ("t,x\n0,1\n1\n", r"bad\.csv, line 3: expected 2 .* got 1"),
        (
            "t,x\n0,1\n1,abc\n",
            r"bad\.csv, line 3, column 'x': expected a number;"
            " got 'abc'",
        ),
        ("t,x\n0,\n", r"bad\.csv, line 2, column 'x': expected a number; got ''"),
        (
            "t,x\n0,1\n#c\n1,nan\n",
            r"bad\.csv, line 4, column 'x': expected a finite"
            " number; got 'nan'",
        ),
        ("t,x\n0,inf\n", r"line 2, column 'x': expected a finite number; got 'inf'"),
        (
            "t,x,t\n0,1,2\n",
            r"bad\.csv, line 1: expected unique column names;"
            " got 't' in columns 1 and 3",
        ),
        (
            "t,,y\n0,1,2\n",
            r"bad\.csv, line 1: expected a name for every"
            " column.*column 2 is empty",
        ),
        (
            "0,1\n1,2\n",
            r"bad\.csv, line 1: expected a header row of"
            " column names; got only numbers",
        ),
    ],
)
def test_read_table_bad_files(tmp_path, text, match):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(DataFileError, match=match):
        read_table(p)


def test_read_table_missing_file_and_directory(tmp_path):
    with pytest.raises(DataFileError, match=r"nope\.csv: no such file"):
        read_table(tmp_path / "nope.csv")
    with pytest.raises(DataFileError, match="expected a CSV file; got a directory"):
        read_table(tmp_path)


def test_read_table_binary_file(tmp_path):
    p = tmp_path / "bin.csv"
    p.write_bytes(b"t,x\n\xff\xfe\x00\n")
    with pytest.raises(DataFileError, match=r"bin\.csv: expected a UTF-8 text"):
        read_table(p)


# ---------------------------------------------------------------- write_table
def test_write_table_exact_round_trip_known_values(tmp_path):
    data = np.array([[0.0, 0.1, 1 / 3], [1e-300, -2.5e300, np.pi], [5e-324, 7.0, -0.0]])
    p = write_table(tmp_path / "sub" / "r.csv", ["t", "a", "b"], data)
    cols, back = read_table(p)
    assert cols == ["t", "a", "b"]
    assert back.tobytes() == data.tobytes()  # bit-exact, -0.0 included


def test_write_table_integers_stay_integers(tmp_path):
    p = write_table(tmp_path / "i.csv", ["k", "n"], np.array([[1, -2], [3, 40]]))
    assert p.read_text() == "k,n\n1,-2\n3,40\n"
    _, back = read_table(p)
    np.testing.assert_array_equal(back, [[1, -2], [3, 40]])


@settings(max_examples=40, deadline=None)
@given(
    hnp.arrays(
        np.float64,
        hnp.array_shapes(min_dims=2, max_dims=2, min_side=1, max_side=6),
        elements=st.floats(allow_nan=False, allow_infinity=False),
    )
)
def test_write_read_round_trip_property(tmp_path_factory, data):
    p = tmp_path_factory.mktemp("rt") / "p.csv"
    cols = [f"c{j}" for j in range(data.shape[1])]
    write_table(p, cols, data)
    back_cols, back = read_table(p)
    assert back_cols == cols
    np.testing.assert_array_equal(back, data)


@pytest.mark.parametrize(
    ("columns", "data", "match"),
    [
        (["a", "a"], [[1.0, 2.0]], "columns must be unique; got 'a' twice"),
        (["a"], [[1.0, 2.0]], r"columns must name every column of data \(2\); got 1"),
        (["a,b"], [[1.0]], "must not contain commas"),
        ([" a"], [[1.0]], "without surrounding spaces; got ' a'"),
        ([""], [[1.0]], "non-empty str"),
        ("ab", [[1.0, 2.0]], "columns must be a sequence of str"),
        (["a"], [[np.nan]], r"data must be finite; got \[nan\] .* at row 0"),
        (["a"], np.zeros((0, 1)), r"data must have at least 1 row"),
        (["a"], [1.0, 2.0], r"data must have shape \(n_points, n_dims\)"),
    ],
)
def test_write_table_refuses_bad_input(tmp_path, columns, data, match):
    with pytest.raises(ValidationError, match=match):
        write_table(tmp_path / "w.csv", columns, data)
    assert list(tmp_path.iterdir()) == []  # nothing, not even a temporary file


def test_write_table_replaces_atomically(tmp_path):
    p = tmp_path / "x.csv"
    write_table(p, ["a"], [[1.0]])
    with pytest.raises(ValidationError):
        write_table(p, ["a"], [[np.inf]])
    assert p.read_text() == "a\n1.0\n"  # the old file is untouched
    write_table(p, ["b"], [[2.0]])
    assert p.read_text() == "b\n2.0\n"
    assert [q.name for q in tmp_path.iterdir()] == ["x.csv"]


# ---------------------------------------------------------------- demonstrations
from ndlfd._fileformat import save_npz  # noqa: E402
from ndlfd.demonstration import Demonstration  # noqa: E402
from ndlfd.io import (  # noqa: E402
    group_of_column,
    read_csv,
    read_demos,
    read_npz,
    write_csv,
    write_npz,
)


def _rich_demo(n=6, seed=0):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.01, 1.0, n))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return Demonstration.from_arrays(
        t,
        position=rng.normal(size=(n, 3)) * 1e3,
        velocity=rng.normal(size=(n, 3)),
        orientation=q,
        force=rng.normal(size=(n, 2)),
        grip=rng.normal(size=n),
    )


def test_csv_round_trip_exact(tmp_path):
    d = _rich_demo()
    p = write_csv(d, tmp_path / "d.csv")
    header = p.read_text().splitlines()[0]
    assert header == "t,x,y,z,vx,vy,vz,qw,qx,qy,qz,fx,fy,grip.grip0"
    back = read_csv(p)
    assert back == d
    assert back.t.tobytes() == d.t.tobytes() and back.X.tobytes() == d.X.tobytes()


def test_csv_round_trip_awkward_names(tmp_path):
    t = [0.0, 1.0]
    d = Demonstration(
        t,
        np.arange(14.0).reshape(2, 7),
        ["p0", "p1", "p2", "p3", "t", "velocity.vx", "x2"],
        ["position"] * 4 + ["extra", "velocity", "velocity"],
    )
    p = write_csv(d, tmp_path / "a.csv")
    assert p.read_text().splitlines()[0] == (
        "t,p0,p1,p2,p3,extra.t,velocity.velocity.vx,velocity.x2"
    )
    assert read_csv(p) == d


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


def test_read_csv_explicit_groups_drop_and_orders(tmp_path):
    p = tmp_path / "robot.csv"
    p.write_text("time,X,Y,label,ox,oy,oz,ow\n0,1,2,7,0,0,0,1\n0.5,2,3,7,0,0,0,-1\n")
    d = read_csv(
        p,
        time_column="time",
        groups={"position": ["X", "Y"], "orientation": ["ox", "oy", "oz", "ow"]},
        quaternion_order="xyzw",
        drop=["label"],
    )
    assert d.columns == ("X", "Y", "ow", "ox", "oy", "oz")
    np.testing.assert_array_equal(d.get("orientation"), [[1, 0, 0, 0], [1, 0, 0, 0]])
    np.testing.assert_array_equal(d.t, [0, 0.5])
    # quaternion columns named qw.. are ordered by name, whatever the file order
    q = tmp_path / "q.csv"
    q.write_text("t,qx,qy,qz,qw\n0,0.6,0,0,0.8\n")
    e = read_csv(q, quaternion_order="xyzw")
    assert e.columns == ("qw", "qx", "qy", "qz")
    np.testing.assert_array_equal(e.X, [[0.8, 0.6, 0, 0]])
    assert read_csv(q) == e
    # no time column: the row number is the time
    r = tmp_path / "r.csv"
    r.write_text("x,y\n0,0\n1,1\n3,3\n")
    np.testing.assert_array_equal(read_csv(r, time_column=None).t, [0.0, 1.0, 2.0])


def test_group_of_column_convention():
    assert group_of_column("x") == ("position", "x")
    assert group_of_column("p7") == ("position", "p7")
    assert group_of_column("vz") == ("velocity", "vz")
    assert group_of_column("qw") == ("orientation", "qw")
    assert group_of_column("f2") == ("force", "f2")
    assert group_of_column("tool.angle") == ("tool", "angle")
    assert group_of_column("speed") is None
    assert group_of_column(".x") is None and group_of_column("g.") is None


@pytest.mark.parametrize(
    ("text", "kwargs", "match"),
    [
        (
            "x,y\n0,1\n",
            {},
            r"d\.csv: expected a time column named 't' or 'time' \(any case\); got"
            r" columns \['x', 'y'\]; pass time_column=",
        ),
        (
            "t,x\n0,1\n0.5,2\n0.5,3\n",
            {},
            r"d\.csv, line 4: time column 't' must be strictly"
            r" increasing; got 0\.5 after 0\.5 on line 3",
        ),
        ("t,x\n0,1\n#\n-1,2\n", {}, r"d\.csv, line 4: time column 't'"),
        (
            "t,x,speed,w\n0,1,2,3\n",
            {},
            r"d\.csv: cannot tell the group of column\(s\)"
            r" \['speed', 'w'\] from their names.*pass groups=",
        ),
        (
            "t,a,b\n0,1,2\n",
            {"groups": {"position": ["a", "c"]}},
            r"d\.csv: groups position names 'c', but there is no such column; got"
            r" columns \['t', 'a', 'b'\]",
        ),
        (
            "t,a,b\n0,1,2\n",
            {"groups": {"position": ["a"], "g": ["a", "b"]}},
            "maps column 'a' to both 'position' and 'g'",
        ),
        (
            "t,a,b\n0,1,2\n",
            {"groups": {"position": "a"}},
            r"cannot tell the group of column\(s\) \['b'\] from their names.*"
            r"pass groups=.*drop=",
        ),
        (
            "t,a,b\n0,1,2\n",
            {"groups": {"position": ["t", "a", "b"]}},
            "time column or dropped",
        ),
        ("t,x\n0,1\n", {"drop": ["y"]}, r"drop names unknown column\(s\) \['y'\]"),
        (
            "t,x\n0,1\n",
            {"drop": ["x"]},
            "expected value columns besides the time column",
        ),
        (
            "t,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,0,0.5\n",
            {},
            r"d\.csv: orientation must have unit norm .* at row 1.*\(line 3\)",
        ),
    ],
)
def test_read_csv_errors(tmp_path, text, kwargs, match):
    p = tmp_path / "d.csv"
    p.write_text(text)
    with pytest.raises(DataFileError, match=match):
        read_csv(p, **kwargs)


def test_read_csv_option_errors(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("t,x\n0,1\n")
    from ndlfd._errors import OptionError

    with pytest.raises(OptionError, match="unknown quaternion_order"):
        read_csv(p, quaternion_order="q")
    with pytest.raises(ValidationError, match="groups must be a mapping"):
        read_csv(p, groups=["position"])
    with pytest.raises(ValidationError, match="demo must be a Demonstration"):
        write_csv(np.zeros((2, 2)), tmp_path / "x.csv")
    with pytest.raises(ValidationError, match="demo must be a Demonstration"):
        write_npz("x", tmp_path / "x.npz")


def test_npz_bad_files(tmp_path):
    with pytest.raises(DataFileError, match=r"none\.npz: no such file"):
        read_npz(tmp_path / "none.npz")
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, t=np.zeros(2))
    with pytest.raises(
        DataFileError, match=r"foreign\.npz: expected value columns besides the time"
    ):
        read_npz(foreign)
    good = write_npz(_rich_demo(), tmp_path / "good.npz")
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


def test_read_demos_folder_glob_list(tmp_path):
    demos = [_rich_demo(4, s) for s in range(3)]
    write_csv(demos[0], tmp_path / "b.csv")
    write_npz(demos[1], tmp_path / "a.npz")
    write_csv(demos[2], tmp_path / "c.csv")
    (tmp_path / "notes.txt").write_text("not data")
    (tmp_path / "sub").mkdir()
    got = read_demos(tmp_path)
    assert got == [demos[1], demos[0], demos[2]]
    assert read_demos(str(tmp_path / "*.csv")) == [demos[0], demos[2]]
    assert read_demos([tmp_path / "c.csv", tmp_path / "a.npz"]) == [demos[2], demos[1]]
    assert read_demos(tmp_path / "b.csv") == [demos[0]]
    r = tmp_path / "sub" / "r.csv"
    r.write_text("x\n1\n2\n")
    assert read_demos(r, time_column=None)[0].t.tolist() == [0.0, 1.0]


def test_demo_files_read_lazily_like_read_demos(tmp_path):
    import pickle

    from ndlfd import KeypointHMM
    from ndlfd.io import DemoFile, DemoFiles

    demos = [_rich_demo(6, s) for s in range(3)]
    for i, d in enumerate(demos):
        write_csv(d, tmp_path / f"d{i}.csv")
    (tmp_path / "d1.csv").rename(tmp_path / "renamed.csv")  # no longer sorted last
    files = DemoFiles(tmp_path)
    assert len(files) == 3 and all(isinstance(f, DemoFile) for f in files)
    assert [f.path.name for f in files] == ["d0.csv", "d2.csv", "renamed.csv"]
    assert [x for f in files for x in f.read()] == read_demos(tmp_path)
    assert [f.path for f in files[1:]] == [f.path for f in list(files)[1:]]
    # items travel to worker processes (pickled), not their data
    f = pickle.loads(pickle.dumps(files[0]))
    assert f == files[0] and f.read() == [demos[0]]
    # the column mapping goes with every file
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "r.csv").write_text("stamp,a,b\n0,1,2\n1,3,4\n")
    mapped = DemoFiles(sub, time_column="stamp", groups={"position": ["a", "b"]})
    assert mapped[0].read() == read_demos(
        sub, time_column="stamp", groups={"position": ["a", "b"]}
    )
    with pytest.raises(ValidationError, match=r"DemoFiles got .*\['colums'\]"):
        DemoFiles(sub, colums=["a"])
    # fitting from it: the model of the demonstrations in memory
    kw = dict(epsilon=0.1, n_time_bins=5, n_jobs=1)
    a = KeypointHMM(**kw).fit(DemoFiles(tmp_path / "*.csv"))
    b = KeypointHMM(**kw).fit(read_demos(tmp_path / "*.csv"))
    assert a.fit_stats_ == b.fit_stats_


def test_read_demos_errors(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(
        DataFileError,
        match=r"empty: expected \.csv, \.tsv, \.npz, \.h5 or \.hdf5 files in the"
        r" folder \(any case\); found none",
    ):
        read_demos(tmp_path / "empty")
    with pytest.raises(DataFileError, match=r"\*\.csv: the pattern matched no files"):
        read_demos(str(tmp_path / "*.csv"))
    with pytest.raises(DataFileError, match=r"missing\.csv: no such file"):
        read_demos(tmp_path / "missing.csv")
    with pytest.raises(
        DataFileError, match="expected at least one file; got an empty list"
    ):
        read_demos([])
    with pytest.raises(
        ValidationError, match="paths must be str or path-like; got int"
    ):
        read_demos([1])
    with pytest.raises(ValidationError, match="source must be a file, a folder"):
        read_demos(3.5)


# ---------------------------------------------------------------- data as it comes
from ndlfd._errors import MissingExtraError  # noqa: E402
from ndlfd.io import ColumnMapping, read_hdf5  # noqa: E402


def _reach(n=40, seed=0):
    """A 3-D reach with orientation at irregular time stamps."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.005, 0.02, n))
    s = np.linspace(0, 1, n)
    pos = np.column_stack([s, s**2, np.sin(s)]) + rng.normal(0, 1e-3, (n, 3))
    half = 0.5 * s  # rotation about z by s radians, exact unit quaternions
    quat = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
    return t, pos, quat


@pytest.mark.parametrize("sep", [",", ";", "\t", " ", "  \t "])
def test_read_csv_detects_the_delimiter(tmp_path, sep):
    t, pos, _ = _reach()
    lines = [sep.join(["time", "X", "Y", "Z"])]
    rows = np.column_stack([t, pos]).tolist()
    lines += [sep.join(repr(v) for v in row) for row in rows]
    p = tmp_path / "d.csv"
    p.write_text("# recorded at 100 Hz\n" + "\n".join(lines) + "\n")
    d, maps = read_demos(p, return_mappings=True)
    np.testing.assert_array_equal(d[0].t, t)
    np.testing.assert_array_equal(d[0].get("position"), pos)
    assert d[0].columns == ("X", "Y", "Z")
    layout = ("tab" if "\t" in sep else {",": "comma", ";": "semicolon"}.get(
        sep, "whitespace"))  # fmt: skip
    end = "" if layout == "comma" else f" ({layout}-separated)"
    assert str(maps[0]) == "time=time; position=X,Y,Z" + end
    # a short row says which separator was expected
    p.write_text(lines[0] + "\n" + sep.join(["0", "1", "2"]) + "\n")
    with pytest.raises(DataFileError, match=r"line 2: expected 4 \w+-separated"):
        read_csv(p)


def test_read_csv_matches_names_in_any_case(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("TIME,Pos_X,pos_y,QW,qx,qy,qz\n0,1,2,1,0,0,0\n0.5,2,3,1,0,0,0\n")
    d, maps = read_demos(
        p, groups={"position": ["pos_x", "POS_Y"]}, return_mappings=True
    )
    assert d[0].columns == ("Pos_X", "pos_y", "QW", "qx", "qy", "qz")
    assert d[0].groups == ("position",) * 2 + ("orientation",) * 4
    np.testing.assert_array_equal(d[0].t, [0, 0.5])
    assert maps[0] == ColumnMapping(
        str(p),
        "TIME",
        (("position", ("Pos_X", "pos_y")), ("orientation", ("QW", "qx", "qy", "qz"))),
    )
    assert maps[0].group_names == ("position", "orientation")
    assert read_csv(p, time_column="Time", drop=["QW", "QX", "QY", "QZ"],
                    groups={"position": ["POS_X", "POS_Y"]}).n_dims == 2  # fmt: skip
    # an exact match wins; two names equal up to case are ambiguous
    q = tmp_path / "q.csv"
    q.write_text("t,x,X,Pos,POS\n0,1,2,3,4\n")
    d = read_csv(q, groups={"a": ["x"], "b": ["X"]}, drop=["Pos", "POS"])
    assert d.columns == ("x", "X")
    with pytest.raises(DataFileError, match=r"'pos'.*\['Pos', 'POS'\], which differ"):
        read_csv(q, time_column="T", groups={"position": ["pos"]})
    with pytest.raises(DataFileError, match=r"names 'Z', but there is no such column"):
        read_csv(q, time_column="T", groups={"position": ["Z"]})


def test_read_csv_explicit_group_owns_its_conventional_columns(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("t,pos_x,pos_y,z\n0,1,2,3\n")
    with pytest.raises(
        DataFileError,
        match=r"column 'z' belongs to group 'position' by its name, but groups"
        r" position does not list it; .* drop=",
    ):
        read_csv(p, groups={"position": ["pos_x", "pos_y"]})
    d = read_csv(p, groups={"position": ["pos_x", "pos_y", "z"]})
    assert d.columns == ("pos_x", "pos_y", "z")


def test_write_table_float_format(tmp_path):
    p = tmp_path / "f.csv"
    write_table(p, ["a", "b"], [[0.38246072499999995, 1.0]], float_format="%.10g")
    assert p.read_text() == "a,b\n0.382460725,1\n"
    write_table(p, ["a", "b"], [[0.1 + 0.2, 1.0]], float_format=[None, "%d"])
    assert p.read_text() == "a,b\n0.30000000000000004,1\n"
    with pytest.raises(ValidationError, match=r"'%d' and must hold whole numbers"):
        write_table(p, ["a"], [[0.5]], float_format="%d")
    with pytest.raises(ValidationError, match="one format or one per column"):
        write_table(p, ["a"], [[0.5]], float_format=["%g", "%g"])
    with pytest.raises(ValidationError, match="float_format must be a %-format"):
        write_table(p, ["a"], [[0.5]], float_format="%s %s")
    d = Demonstration.from_arrays([0.0, 1 / 3], position=[[1 / 3, 2.0]] * 2)
    write_csv(d, p, float_format="%.10g")
    assert (
        p.read_text()
        == "t,x,y\n0.0,0.3333333333,2\n0.3333333333333333,0.3333333333,2\n"
    )
    write_csv(d, p, float_format="%.10g", time_format="%.3g")
    assert p.read_text() == "t,x,y\n0,0.3333333333,2\n0.333,0.3333333333,2\n"


def test_plain_npz_is_mapped_like_csv_columns(tmp_path):
    t, pos, quat = _reach()
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


h5py = pytest.importorskip("h5py")


def test_hdf5_one_group_per_episode(tmp_path):
    p = tmp_path / "reach.h5"
    demos = []
    with h5py.File(p, "w") as f:
        for i in (2, 10, 1):  # natural order: ep1, ep2, ep10
            t, pos, quat = _reach(seed=i)
            g = f.create_group(f"ep{i}")
            g["time"], g["obs/eef"], g["quat"] = t, pos, quat
            g["label"] = "reach"
            demos.append((i, Demonstration.from_arrays(t, position=pos,
                                                       orientation=quat)))  # fmt: skip
    want = [d for _, d in sorted(demos, key=lambda x: x[0])]
    got, maps = read_demos(p, groups={"position": "obs/eef"}, return_mappings=True)
    assert got == want
    assert [m.source for m in maps] == [f"{p}:/ep{i}" for i in (1, 2, 10)]
    assert (
        str(maps[0]) == "time=time; position=obs/eef; orientation=quat; ignored label"
    )
    assert read_hdf5(p, groups={"position": "OBS/EEF"}) == want
    with pytest.raises(DataFileError, match=r"reach\.h5:/ep1: cannot tell the group"):
        read_hdf5(p)
    # datasets at the root: one episode
    q = tmp_path / "one.hdf5"
    t, pos, _ = _reach()
    with h5py.File(q, "w") as f:
        f["t"], f["pos"] = t, pos
    assert read_hdf5(q) == [Demonstration.from_arrays(t, position=pos)]


def test_hdf5_errors_and_missing_extra(tmp_path, monkeypatch):
    empty = tmp_path / "empty.h5"
    with h5py.File(empty, "w"):
        pass
    with pytest.raises(DataFileError, match="expected one HDF5 group per episode"):
        read_hdf5(empty)
    bad = tmp_path / "bad.h5"
    bad.write_text("t,x\n0,1\n")
    with pytest.raises(DataFileError, match=r"bad\.h5: expected an HDF5 file"):
        read_hdf5(bad)
    with pytest.raises(DataFileError, match=r"none\.h5: no such file"):
        read_hdf5(tmp_path / "none.h5")
    import sys

    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now fails
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[hdf5\]"'):
        read_hdf5(empty)


def test_read_demos_folder_takes_every_format_in_any_case(tmp_path):
    t, pos, _ = _reach()
    d = Demonstration.from_arrays(t, position=pos)
    write_csv(d, tmp_path / "a.CSV")
    np.savez(tmp_path / "b.NPZ", t=t, pos=pos)
    with h5py.File(tmp_path / "c.H5", "w") as f:
        f["e/t"], f["e/pos"] = t, pos
    (tmp_path / "d.tsv").write_text(
        "t\tx\ty\tz\n" + "\n".join("\t".join(map(repr, r)) for r in
                                   np.column_stack([t, pos]).tolist()) + "\n"
    )  # fmt: skip
    (tmp_path / "notes.txt").write_text("not data")
    demos, maps = read_demos(tmp_path, return_mappings=True)
    assert demos == [d] * 4
    assert [m.layout for m in maps] == [
        "comma-separated", "arrays", "arrays", "tab-separated"
    ]  # fmt: skip
    with pytest.raises(ValidationError, match=r"unexpected argument\(s\) \['group'\]"):
        read_demos(tmp_path, group={})


@pytest.mark.parametrize("compress", [False, True])
def test_write_npz_stores_or_deflates_and_reads_back_the_same(tmp_path, compress):
    import zipfile

    d = _rich_demo(40, 3)
    p = write_npz(d, tmp_path / "d.npz", compress=compress)
    assert read_npz(p) == d
    with zipfile.ZipFile(p) as z:
        kinds = {i.compress_type for i in z.infolist()}
    assert kinds == {zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED}
    if not compress:  # the default (the archive's time stamps differ: not bytes)
        with zipfile.ZipFile(write_npz(d, tmp_path / "default.npz")) as z:
            assert {i.compress_type for i in z.infolist()} == {zipfile.ZIP_STORED}
