import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from io_samples import reach, rich_demo

from ndlfd._errors import DataFileError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import (
    read_csv,
    read_demos,
    read_table,
    write_csv,
    write_npz,
    write_table,
)


def _reference_parse(text):
    """Obviously-correct parser of the dialect: strip, skip blanks and comments."""
    lines = [ln.strip() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln and not ln.startswith("#")]
    header = [h.strip() for h in lines[0].split(",")]
    rows = [[float(v) for v in ln.split(",")] for ln in lines[1:]]
    return header, np.array(rows)


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


def test_csv_round_trip_exact(tmp_path):
    d = rich_demo()
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


@pytest.mark.parametrize(
    ("text", "kwargs", "match"),
    [
        (
            "x,y\n0,1\n",
            {},
            r"d\.csv: expected a time column named 't' or 'time' or 'timestamp'"
            r" \(any case\); got columns \['x', 'y'\]; pass time_column=",
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


@pytest.mark.parametrize("sep", [",", ";", "\t", " ", "  \t "])
def test_read_csv_detects_the_delimiter(tmp_path, sep):
    t, pos, _ = reach()
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
