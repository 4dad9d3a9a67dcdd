"""The compiled CSV engines against the careful parser (``engine="python"``)."""

import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import ndlfd.io._csv as csv_module
from ndlfd._errors import DataFileError, MissingExtraError, OptionError
from ndlfd.io import parse_table, write_table
from ndlfd.io._csv import ENGINES

COMPILED = [e for e in ENGINES.names if e != "python"]
NAMES = ["t", "x", "y", "z", "vx", "qw", "Time", "grip", "pos_x", "f0"]
SEPARATORS = {",": ",", ";": ";", "\t": "\t", "ws": " "}


def _outcome(path, engine, finite):
    """The table as plain values, or the error's message."""
    try:
        t = parse_table(path, finite=finite, engine=engine)
    except DataFileError as exc:
        return ("error", str(exc))
    assert t.data.dtype == np.float64 and t.data.flags.c_contiguous
    return ("table", t.columns, t.data, t.lines, t.delimiter)


def _same(a, b):
    if a[0] != b[0] or (a[0] == "error" and a != b):
        return False
    if a[0] == "error":
        return True
    _, ca, da, la, sa = a
    _, cb, db, lb, sb = b
    return (
        ca == cb
        and sa == sb
        and np.array_equal(la, lb)
        and da.shape == db.shape
        and np.array_equal(da, db, equal_nan=True)
        and np.array_equal(np.signbit(da), np.signbit(db))  # -0.0 stays -0.0
    )


def _number(draw, finite):
    """One number as text, in one of the forms a file may hold."""
    v = draw(
        st.floats(allow_nan=not finite, allow_infinity=not finite, width=64)
        | st.integers(-(10**20), 10**20).map(float)
        | st.sampled_from([0.0, -0.0, 1e-300, 5e-324, 1e300, 0.1, 2.5])
    )
    form = draw(st.sampled_from(["repr", "%.17g", "%e", "%E", "%.3f", "%g", "int"]))
    if not np.isfinite(v):
        text = draw(st.sampled_from([repr(v), str(v).upper(), f"{v:e}"]))
        return text.replace("inf", draw(st.sampled_from(["inf", "Infinity", "INF"])))
    if form == "repr":
        text = repr(v)
    elif form == "int":
        text = str(int(v)) if v == int(v) and abs(v) < 1e25 else repr(v)
    else:
        text = form % v
    if draw(st.booleans()) and not text.startswith("-"):
        text = "+" + text
    if text.startswith(("0.", "-0.")) and draw(st.booleans()):
        text = text.replace("0.", ".", 1)  # .5 and -.5
    return text


BREAKAGES = ['"quoted"', "abc", "", "1_0", "1e", "1,2", "nan", "inf", "# c", "1 2"]


@st.composite
def csv_files(draw):
    """Text of a CSV file of the dialect, with the variations it allows.

    Returns the bytes and ``finite`` (whether NaN and inf are refused).
    """
    finite = draw(st.booleans())
    sep_key = draw(st.sampled_from(sorted(SEPARATORS)))
    sep = SEPARATORS[sep_key]
    k = draw(st.integers(1, 4))
    names = draw(st.lists(st.sampled_from(NAMES), min_size=k, max_size=k, unique=True))
    if sep_key == "ws" and k == 1:
        sep_key, sep = ",", ","  # one name without a delimiter is a comma file
    pad = st.sampled_from(["", "", " ", "  ", "\t"] if sep != "\t" else ["", " "])
    n = draw(st.integers(1, 12))
    rows = []
    for _ in range(n):
        fields = [draw(pad) + _number(draw, finite) + draw(pad) for _ in range(k)]
        rows.append(sep.join(fields))
    if draw(st.integers(0, 4)) == 0:  # one field made invalid (or odd)
        i, j = draw(st.integers(0, n - 1)), draw(st.integers(0, k - 1))
        fields = rows[i].split(sep) if sep != " " else rows[i].split()
        fields[j] = draw(st.sampled_from(BREAKAGES))
        rows[i] = sep.join(fields)
    header = sep.join(draw(pad) + nm + draw(pad) for nm in names)
    lines = [header, *rows]
    if draw(st.booleans()):  # comments and blank lines, anywhere
        for _ in range(draw(st.integers(1, 3))):
            at = draw(st.integers(0, len(lines)))
            lines.insert(at, draw(st.sampled_from(["", "  ", "# note", " #x,1"])))
    eol = draw(st.sampled_from(["\n", "\r\n", "\r"]))
    text = eol.join(lines) + draw(st.sampled_from(["", eol, eol + eol + "  "]))
    bom = b"\xef\xbb\xbf" if draw(st.booleans()) else b""
    return bom + text.encode(), finite


@settings(max_examples=120, deadline=None)
@given(csv_files())
@example((b"t,x\n0,1\n1,2\n", True))
@example((b"t x\n0 1\n1\t2\n", True))
@example((b"t;x\r\n0;1e5\r\n1;-.5E-3\r\n", True))
@example((b"t,x\n0,1\n\n1,2\n", True))  # a blank line: the row lines shift
@example((b"t,x\n0,1\n1,nan\n", False))
@example((b"t,x\n0,1\n1,nan\n", True))
@example((b"t,x\n0,1\n1,1_0\n", True))  # Python's float takes underscores
@example((b"t,x\n0,1\n1,\x0c2\n", True))  # \x0c ends a line for str.splitlines
@example((b"t\n1\n2\n", True))
@example(("t,x\n0,1\n1,\u00a02\n".encode(), True))  # non-ASCII space
@example((b'"t","x"\n"0","1"\n', True))
def test_engines_equal_the_careful_parser(case):
    content, finite = case
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "f.csv"
        path.write_bytes(content)
        want = _outcome(path, "python", finite)
        for engine in COMPILED:
            got = _outcome(path, engine, finite)
            assert _same(got, want), (engine, content, got, want)


def _spiral_table(path, n=1000, seed=0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 3.0, n)
    data = np.column_stack([t, np.cumsum(rng.normal(size=(n, 3)), axis=0)])
    write_table(path, ["t", "x", "y", "z"], data)
    return data


@pytest.mark.parametrize("engine", COMPILED)
def test_plain_files_never_reach_the_careful_parser(tmp_path, monkeypatch, engine):
    """A file of plain rows is parsed by the compiled engine alone, exactly."""
    p = tmp_path / "a.csv"
    data = _spiral_table(p)
    for sep in (";", "\t"):  # and as the other delimiters write it
        text = p.read_text().replace(",", sep)
        (tmp_path / f"b{ord(sep)}.csv").write_text(text.replace("\n", "\r\n"))

    def careful(*args):
        raise AssertionError("the careful parser was used")

    monkeypatch.setattr(csv_module, "_parse_careful", careful)
    for f in sorted(tmp_path.glob("*.csv")):
        table = parse_table(f, engine=engine)
        np.testing.assert_array_equal(table.data, data)  # shortest repr: exact
        np.testing.assert_array_equal(table.lines, np.arange(2, 1002))


def test_bad_row_is_named_after_the_compiled_parser_refuses(tmp_path):
    p = tmp_path / "a.csv"
    _spiral_table(p, n=50)
    lines = p.read_text().splitlines()
    lines[31] = lines[31].replace(",", ",x", 1)
    p.write_text("\n".join(lines))
    for engine in ENGINES.names:
        with pytest.raises(DataFileError, match=r"a\.csv, line 32, column 'x':"):
            parse_table(p, engine=engine)


def test_unknown_engine_lists_the_choices(tmp_path):
    p = tmp_path / "a.csv"
    p.write_text("t,x\n0,1\n")
    with pytest.raises(OptionError, match="expected one of: 'pyarrow', 'numpy'"):
        parse_table(p, engine="fast")


def test_pyarrow_engine_without_pyarrow_names_the_extra(tmp_path, monkeypatch):
    p = tmp_path / "a.csv"
    p.write_text("t,x\n0,1\n")
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow fails
    monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    with pytest.raises(MissingExtraError, match=r"pip install .*ndlfd\[lerobot\]"):
        parse_table(p, engine="pyarrow")
    np.testing.assert_array_equal(parse_table(p, engine="numpy").data, [[0, 1]])
