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
        ("t,x\n0,1\n1,abc\n", r"bad\.csv, line 3, column 'x': expected a number;"
         " got 'abc'"),
        ("t,x\n0,\n", r"bad\.csv, line 2, column 'x': expected a number; got ''"),
        ("t,x\n0,1\n#c\n1,nan\n", r"bad\.csv, line 4, column 'x': expected a finite"
         " number; got 'nan'"),
        ("t,x\n0,inf\n", r"line 2, column 'x': expected a finite number; got 'inf'"),
        ("t,x,t\n0,1,2\n", r"bad\.csv, line 1: expected unique column names;"
         " got 't' in columns 1 and 3"),
        ("t,,y\n0,1,2\n", r"bad\.csv, line 1: expected a name for every"
         " column.*column 2 is empty"),
        ("0,1\n1,2\n", r"bad\.csv, line 1: expected a header row of"
         " column names; got only numbers"),
    ],
)  # fmt: skip
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
