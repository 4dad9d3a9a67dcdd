"""Delimited text: numeric tables and demonstrations in CSV files.

:func:`read_table` / :func:`write_table` move a header row and a numeric table
between a CSV file and numpy; :func:`read_csv` / :func:`write_csv` move a whole
:class:`~ndlfd.demonstration.Demonstration`, its columns mapped by
:func:`~ndlfd.io._mapping.map_arrays`. The dialect is described in
:mod:`ndlfd.io`.

Numbers are parsed by a compiled parser (:data:`ENGINES`: ``pyarrow.csv`` when
installed, else ``numpy.loadtxt``) on the rows below the header once a byte
scan shows they hold only numbers and delimiters; the careful line-by-line
parser (``"python"``) takes every other file (comments or blank lines among
the rows, non-ASCII text) and any file the compiled parser refuses, so that
its error names the file, the line and the column. Both give the same arrays.
"""

from __future__ import annotations

import functools
import io
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._errors import DataFileError, MissingExtraError, ValidationError
from .._fileformat import atomic_path
from .._registry import Registry
from .._validation import check_points
from ..demonstration import Demonstration
from ._mapping import (
    LIBRARY_HINTS,
    TIME_NAMES,
    ColumnMapping,
    euler_columns,
    map_arrays,
)
from ._output import output_columns

__all__ = [
    "ENGINES",
    "Table",
    "delimiter_name",
    "parse_table",
    "read_csv",
    "read_csv_mapped",
    "read_table",
    "write_csv",
    "write_table",
]

_DELIMITERS = ((",", "comma"), (";", "semicolon"), ("\t", "tab"))


def _delimiter_of(header_line: str) -> str | None:
    """The delimiter a header row uses: ``,``, ``;``, tab, or None (whitespace)."""
    for d, _ in _DELIMITERS:
        if d in header_line:
            return d
    if len(header_line.split()) > 1:
        return None
    return ","


def delimiter_name(delimiter: str | None) -> str:
    """How messages name a delimiter: comma, semicolon, tab or whitespace."""
    return dict(_DELIMITERS).get(delimiter, "whitespace") if delimiter else "whitespace"


def _split(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    return [f.strip() for f in line.split(delimiter)]


@dataclass(frozen=True)
class Table:
    r"""A parsed CSV table, with where each row came from.

    Attributes
    ----------
    columns : list of str
        The header names.
    data : ndarray of shape (n_rows, n_columns), dtype float64
    lines : ndarray of shape (n_rows,), dtype int64
        The 1-based file line of each data row (for error messages).
    delimiter : str or None
        ``","``, ``";"``, ``"\t"``, or None for whitespace.
    """

    columns: list[str]
    data: np.ndarray
    lines: np.ndarray
    delimiter: str | None


def parse_table(path, *, finite: bool = True, engine: str = "auto") -> Table:
    """Parse a CSV table; also give the 1-based file line of each data row.

    Parameters
    ----------
    path : str or path-like
        The CSV file (dialect: see :func:`read_table`).
    finite : bool, default=True
        Refuse NaN and inf (``False``: keep them, for ``bad_rows="drop"``).
    engine : {"auto", "pyarrow", "numpy", "python"}, default="auto"
        The parser of the numbers (:data:`ENGINES`): ``"auto"`` is
        ``"pyarrow"`` when pyarrow is installed and the delimiter is not
        whitespace, else ``"numpy"``; ``"python"`` is the careful parser
        alone. Every engine gives the same table (a file a compiled parser
        cannot take goes to the careful one).

    Returns
    -------
    table : Table

    Raises
    ------
    DataFileError
        As :func:`read_table`.
    """
    p = Path(path)
    rows = ENGINES.get(engine)
    if not p.exists():
        raise DataFileError(f"{p}: no such file")
    if not p.is_file():
        raise DataFileError(f"{p}: expected a CSV file; got a directory or device")
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise DataFileError(f"{p}: cannot be read ({exc.strerror})") from None
    if rows is not None:
        table = _parse_compiled(p, raw, finite, rows)
        if table is not None:
            return table
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise DataFileError(
            f"{p}: expected a UTF-8 text (CSV) file; got undecodable bytes at byte"
            f" {exc.start}"
        ) from None
    return _parse_careful(p, text, finite)


def _parse_careful(p: Path, text: str, finite: bool) -> Table:
    """The line-by-line parser: every check, every message names the line."""
    header: list[str] | None = None
    header_line = 0
    delimiter: str | None = ","
    rows: list[list[float]] = []
    lines: list[int] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        if header is None:
            delimiter = _delimiter_of(s)
            header, header_line = _split(s, delimiter), lineno
            _check_header(p, header, lineno)
            continue
        fields = _split(s, delimiter)
        if len(fields) != len(header):
            raise DataFileError(
                f"{p}, line {lineno}: expected {len(header)}"
                f" {delimiter_name(delimiter)}-separated values (one per column of"
                f" the header on line {header_line}); got {len(fields)}"
            )
        try:
            values = [float(f) for f in fields]
        except ValueError:
            for name, f in zip(header, fields, strict=True):
                try:
                    float(f)
                except ValueError:
                    raise DataFileError(
                        f"{p}, line {lineno}, column {name!r}: expected a number;"
                        f" got {f!r}"
                    ) from None
            raise  # pragma: no cover - one of the fields must have failed
        for name, f, v in zip(header, fields, values, strict=True):
            if finite and not np.isfinite(v):
                raise DataFileError(
                    f"{p}, line {lineno}, column {name!r}: expected a finite number;"
                    f" got {f!r}"
                )
        rows.append(values)
        lines.append(lineno)
    if header is None:
        raise DataFileError(
            f"{p}: expected a header row and data rows; got an empty file"
        )
    if not rows:
        raise DataFileError(
            f"{p}: expected data rows below the header on line {header_line}; got"
            " none (header only)"
        )
    data = np.array(rows, dtype=np.float64).reshape(len(rows), len(header))
    return Table(header, data, np.array(lines, dtype=np.int64), delimiter)


# ------------------------------------------------------------- compiled parsers
#: Engines that parse the rows of numbers below the header (``"python"``: none,
#: the careful parser takes the whole file): each takes the
#: bytes of the rows (ASCII, ``\n`` line ends, no blank or comment line in
#: between), the delimiter and the number of columns, and returns the
#: ``(n_rows, n_columns)`` float64 array or raises ``ValueError``.
ENGINES: Registry = Registry("CSV engine")
_BOM = b"\xef\xbb\xbf"
#: bytes that rows of numbers hold besides their delimiter
_NUMBER_BYTES = b"0123456789.eE+- \t\n"
#: the letters of nan, inf and infinity (in any case), for ``finite=False``
_NONFINITE_BYTES = b"nNaAiIfFtTyY"
#: line breaks of ``str.splitlines`` (and a space of ``str.strip``) beyond ``\n``
#: and ``\r``, which the compiled parsers do not know
_ODD_BYTES = b"\x0b\x0c\x1c\x1d\x1e\x1f"


@ENGINES.register("pyarrow")
def _rows_pyarrow(body: bytes, delimiter: str | None, k: int) -> np.ndarray:
    """The rows by ``pyarrow.csv`` (extra ``lerobot``): no quoting, no nulls."""
    try:
        import pyarrow as pa
        import pyarrow.csv as pc
    except ImportError:
        raise MissingExtraError(
            'engine "pyarrow" needs pyarrow; install it with: pip install'
            ' "ndlfd[lerobot]"'
        ) from None
    if delimiter is None:
        raise ValueError("pyarrow does not split on runs of whitespace")
    names = [f"c{j}" for j in range(k)]
    table = pc.read_csv(
        pa.py_buffer(body),
        read_options=pc.ReadOptions(column_names=names, use_threads=False),
        parse_options=pc.ParseOptions(
            delimiter=delimiter,
            quote_char=False,
            escape_char=False,
            newlines_in_values=False,
            ignore_empty_lines=True,
        ),
        convert_options=pc.ConvertOptions(
            column_types=dict.fromkeys(names, pa.float64()),
            null_values=[],
            strings_can_be_null=False,
            quoted_strings_can_be_null=False,
        ),
    )
    data = np.empty((table.num_rows, k), dtype=np.float64)
    for j, column in enumerate(table.columns):
        data[:, j] = column.to_numpy()
    return data


@ENGINES.register("numpy")
def _rows_numpy(body: bytes, delimiter: str | None, k: int) -> np.ndarray:
    """The rows by ``numpy.loadtxt`` (any delimiter, whitespace too)."""
    data = np.loadtxt(
        io.BytesIO(body), delimiter=delimiter, comments=None, ndmin=2, encoding=None
    )
    return np.ascontiguousarray(data, dtype=np.float64)


@functools.cache
def _has_pyarrow() -> bool:
    try:
        import pyarrow.csv  # noqa: F401
    except ImportError:
        return False
    return True


@ENGINES.register("auto")
def _rows_auto(body: bytes, delimiter: str | None, k: int) -> np.ndarray:
    """By pyarrow when installed and the delimiter is not whitespace, else numpy."""
    if delimiter is not None and _has_pyarrow():
        return _rows_pyarrow(body, delimiter, k)
    return _rows_numpy(body, delimiter, k)


ENGINES.add("python", None)  # the careful parser alone


def _parse_compiled(p: Path, raw: bytes, finite: bool, rows) -> Table | None:
    """The table by a compiled parser, or None where the careful one must go.

    None for a file that is not plain ASCII, holds a comment, blank line or
    anything but numbers and delimiters below the header, or that the compiled
    parser refuses (then the careful parser names the bad row).
    """
    if raw.startswith(_BOM):
        raw = raw[len(_BOM) :]
    if not raw.isascii():
        return None
    if b"\r" in raw:  # \r\n and \r end lines as \n does (str.splitlines)
        raw = raw.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    start, lineno = 0, 1
    while True:  # the header: the first line neither blank nor a comment
        end = raw.find(b"\n", start)
        if end < 0:
            return None  # no data row: the careful parser says what is missing
        line = raw[start:end].strip()
        if line and not line.startswith(b"#"):
            break
        start, lineno = end + 1, lineno + 1
    if any(b in raw[:end] for b in _ODD_BYTES):
        return None
    header = line.decode()
    delimiter = _delimiter_of(header)
    names = _split(header, delimiter)
    _check_header(p, names, lineno)
    body = raw[end + 1 :].rstrip()
    allowed = _NUMBER_BYTES + (delimiter or "").encode()
    if not finite:
        allowed += _NONFINITE_BYTES
    if not body or body.translate(None, allowed):
        return None
    try:
        data = rows(body, delimiter, len(names))
    except MissingExtraError:
        raise
    except ValueError:  # pyarrow's ArrowInvalid too
        return None
    n = body.count(b"\n") + 1
    if data.shape != (n, len(names)) or (finite and not np.isfinite(data).all()):
        return None  # a row skipped or a value not finite: the careful parser
    lines = np.arange(lineno + 1, lineno + 1 + n, dtype=np.int64)
    return Table(names, data, lines, delimiter)


def _check_header(p: Path, header: list[str], lineno: int) -> None:
    for j, name in enumerate(header):
        if not name:
            raise DataFileError(
                f"{p}, line {lineno}: expected a name for every column of the header;"
                f" column {j + 1} is empty"
            )
    seen: dict[str, int] = {}
    for j, name in enumerate(header):
        if name in seen:
            raise DataFileError(
                f"{p}, line {lineno}: expected unique column names; got {name!r} in"
                f" columns {seen[name] + 1} and {j + 1}"
            )
        seen[name] = j
    if all(_is_number(name) for name in header):
        raise DataFileError(
            f"{p}, line {lineno}: expected a header row of column names; got only"
            f" numbers ({', '.join(header[:4])}{', ...' if len(header) > 4 else ''})"
        )


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


def read_table(path: str | os.PathLike) -> tuple[list[str], np.ndarray]:
    r"""Read a CSV file with a header row into column names and a float array.

    Parameters
    ----------
    path : str or path-like
        The CSV file: one header row of unique names, then rows of numbers,
        separated by commas, semicolons, tabs or whitespace (whichever the
        header row uses, in that order of preference). Blank lines and ``#``
        comment lines are skipped.

    Returns
    -------
    columns : list of str
        The header names, stripped of surrounding spaces.
    data : ndarray of shape (n_rows, n_columns), dtype float64
        The values; all finite.

    Raises
    ------
    DataFileError
        Missing or empty file, header only, duplicate or empty column names,
        a row with the wrong number of values, text where a number is expected,
        NaN or inf. The message names the file and the line.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "demo.csv"
    >>> _ = p.write_text("t, x\n0, 1.5\n0.1, 2\n")
    >>> read_table(p)
    (['t', 'x'], array([[0. , 1.5],
           [0.1, 2. ]]))
    >>> _ = p.write_text("t;x\n0;1.5\n")
    >>> read_table(p)
    (['t', 'x'], array([[0. , 1.5]]))
    """
    table = parse_table(path)
    return table.columns, table.data


def _check_column_names(columns, k: int | None = None) -> list[str]:
    if isinstance(columns, str) or not isinstance(columns, Iterable):
        raise ValidationError("columns must be a sequence of str; got " + repr(columns))
    names = list(columns)
    for name in names:
        if not isinstance(name, str) or not name.strip() or name != name.strip():
            raise ValidationError(
                "columns must be non-empty str without surrounding spaces; got"
                f" {name!r}"
            )
        if re.search(r"[,\r\n#]", name):
            raise ValidationError(
                "columns must not contain commas, newlines or '#' (they would break"
                f" the CSV file); got {name!r}"
            )
    if len(set(names)) != len(names):
        dup = next(n for n in names if names.count(n) > 1)
        raise ValidationError(f"columns must be unique; got {dup!r} twice")
    if k is not None and len(names) != k:
        raise ValidationError(
            f"columns must name every column of data ({k}); got {len(names)} names"
        )
    return names


def _check_formats(float_format, k: int) -> list[str | None]:
    if float_format is None or isinstance(float_format, str):
        formats = [float_format] * k
    elif isinstance(float_format, Sequence):
        formats = list(float_format)
        if len(formats) != k:
            raise ValidationError(
                f"float_format must be one format or one per column ({k}); got"
                f" {len(formats)}"
            )
    else:
        raise ValidationError(
            "float_format must be None, a %-format such as '%.10g' or a sequence of"
            f" them; got {float_format!r}"
        )
    for f in formats:
        if f is None:
            continue
        try:
            f % 1.0
        except (TypeError, ValueError):
            raise ValidationError(
                f"float_format must be a %-format for one number such as '%.10g';"
                f" got {f!r}"
            ) from None
    return formats


def write_table(
    path: str | os.PathLike, columns: Sequence[str], data, *, float_format=None
) -> Path:
    """Write a header row and a numeric table to a CSV file, atomically.

    By default floats are written in Python's shortest round-trip form
    (``repr``), so :func:`read_table` gives back exactly the same numbers; an
    integer array is written as integers.

    Parameters
    ----------
    path : str or path-like
        Destination; its folder is created if needed.
    columns : sequence of str of length n_columns
        Unique names without commas, newlines or ``#``.
    data : array-like of shape (n_rows, n_columns)
        Finite real numbers, at least one row.
    float_format : str, sequence of (str or None), or None, default=None
        A %-format for the numbers (``"%.10g"``: ten significant digits), or
        one per column (``None`` keeps the exact form for that column). A
        column formatted with ``"%d"`` must hold whole numbers.

    Returns
    -------
    path : Path

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "out.csv"
    >>> _ = write_table(p, ["t", "x"], [[0.0, 0.1], [1.0, 1 / 3]])
    >>> print(p.read_text(), end="")
    t,x
    0.0,0.1
    1.0,0.3333333333333333
    >>> _ = write_table(p, ["t", "x"], [[0.0, 0.1], [1.0, 1 / 3]],
    ...                 float_format=["%d", "%.10g"])
    >>> print(p.read_text(), end="")
    t,x
    0,0.1
    1,0.3333333333
    """
    a = np.asarray(data)
    formats: list = [None]
    if a.dtype.kind in "iu" and a.ndim == 2 and float_format is None:
        check_points(a, "data")  # shape and finiteness checks only
        rows, k = a.tolist(), a.shape[1]
    else:
        values = check_points(data, "data")
        k = values.shape[1]
        formats = _check_formats(float_format, k)
        for j, f in enumerate(formats):
            if f is not None and f.rstrip().endswith(("d", "i")):
                col = values[:, j]
                bad = np.flatnonzero(col != np.round(col))
                if bad.size:
                    raise ValidationError(
                        f"column {j} is written with {f!r} and must hold whole"
                        f" numbers; got {col[bad[0]]!r} at row {bad[0]}"
                    )
        rows = values.tolist()
    if all(f is None for f in formats):  # shortest round-trip form (ints as ints)
        body_rows = [",".join(map(repr, row)) for row in rows]
    else:
        fmt = [repr if f is None else f.__mod__ for f in formats]
        body_rows = [
            ",".join(fj(v) for fj, v in zip(fmt, row, strict=True)) for row in rows
        ]
    names = _check_column_names(columns, k)
    final = Path(path)
    with atomic_path(final) as tmp:
        tmp.write_text("\n".join([",".join(names), *body_rows]) + "\n", "utf-8")
    return final


# ---------------------------------------------------------------- demonstrations
def read_csv_mapped(
    p: Path, how, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """The demonstration of the CSV file ``p`` with the mapping used.

    A reader of :data:`~ndlfd.io._files.READERS`: ``how`` is
    :data:`~ndlfd.io._mapping.LIBRARY_HINTS` or ``CLI_HINTS``, ``mapping`` the
    options of :func:`read_csv`.
    """
    table = parse_table(p, finite=mapping.get("bad_rows", "error") == "error")
    columns = {name: table.data[:, j] for j, name in enumerate(table.columns)}
    pair = map_arrays(
        p,
        columns,
        lines=table.lines,
        layout=f"{delimiter_name(table.delimiter)}-separated",
        how=how,
        **mapping,
    )
    return [pair]


def read_csv(
    path: str | os.PathLike,
    *,
    time_column: str | Sequence[str] | None = TIME_NAMES,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
    euler: str | None = None,
    representation: str | None = None,
    bad_rows: str = "error",
) -> Demonstration:
    r"""Read one demonstration from a CSV file.

    Every column except the time column and ``drop`` belongs to a group:
    the one ``groups`` maps it to, or else the one its name gives
    (:func:`group_of_column`): ``x, y, z`` (or ``p0, p1, ...``) position,
    ``vx, vy, vz`` (or ``v0, ...``) velocity, ``qw, qx, qy, qz`` orientation
    (or Euler angles ``roll, pitch, yaw``), ``fx, fy, fz`` (or ``f0, ...``)
    force, ``gripper``, ``group.column`` a user group; or the names labs
    export (:mod:`ndlfd.io._names`): ``pos_x``/``<prefix>_pos_x`` position,
    ``<prefix>_orientation_w..z``/``quat_w..z``/``q_w..z`` orientation,
    ``force_x`` force, ``torque_x`` torque, ``joint_1``/``joint1``/``q1``
    joints; where a log holds a measured and a commanded set of one kind
    (``current_``/``actual_``/``measured_`` beside
    ``goal_``/``desired_``/``cmd_``/``target_``), the measured one is learned
    and the commanded one left out with a warning. Any other name is an
    error giving ``groups=`` and ``drop=`` to paste. Names are matched
    case-insensitively (an exact match wins); ``groups`` and ``drop`` take
    glob patterns (``drop=["goal_*"]``). The groups of ``groups`` come
    first, in its order, then the others in the order their first column
    appears in the file.

    Two arms: names of a ``left_`` and a ``right_`` hand (``left_x``,
    ``right_pos_x``, ``right_ee_x``, ``left_qw``, ``left_roll``,
    ``left_joint_1``, ALOHA's ``left_waist``) are each hand's groups,
    ``left_position`` (3 columns), ``left_orientation``, ``left_joints`` ...,
    and ``left_gripper``, ``right_gripper`` the one group ``gripper``;
    ``euler`` and ``representation`` apply to every hand's orientation.

    Three orientation columns are Euler angles or a rotation vector, never
    guessed: columns named ``roll, pitch, yaw`` are Euler angles (``euler``,
    default ``"xyz"``); any other three need ``representation`` (or
    ``euler``), e.g. Universal Robots' axis-angle ``rx, ry, rz``:
    ``groups={"orientation": ["rx", "ry", "rz"]}, representation="rotvec"``.
    All conversions are scipy's :class:`~scipy.spatial.transform.Rotation`.

    Parameters
    ----------
    path : str or path-like
        The CSV file (dialect: see :func:`read_table`; comma, semicolon, tab or
        whitespace separated).
    time_column : str, sequence of str or None, default=("t", "time")
        The column holding the time stamps (strictly increasing), or names to
        try in order. ``None`` uses the row number ``0, 1, 2, ...`` as time.
    groups : mapping of str to sequence of str, optional
        Explicit assignment ``{"position": ["X", "Y"], "grip": ["w"]}``; the
        columns keep their names. A group named here gets only the columns
        listed (a column that its name would put there is an error unless
        dropped).
    quaternion_order : {"wxyz", "xyzw"}, default="wxyz"
        The order of the four orientation columns in the file (or in
        ``groups["orientation"]``). When they are named ``qw, qx, qy, qz`` the
        names decide and this is not used.
    drop : sequence of str, default=()
        Columns to ignore.
    euler : str, optional
        The convention of Euler angle columns (``roll, pitch, yaw``, or three
        columns of ``groups["orientation"]``, in radians), which become unit
        quaternions: ``"xyz"`` extrinsic (ROS's roll-pitch-yaw; the default
        for ``roll, pitch, yaw``), ``"ZYX"`` intrinsic, ... (see
        :mod:`ndlfd.io._mapping`).
    representation : str, optional
        How the orientation columns hold it
        (:data:`~ndlfd.orientation.REPRESENTATIONS`): ``"rotvec"`` (three
        columns: axis times angle), ``"euler-SEQ"`` (three Euler angles,
        ``SEQ`` any scipy convention: ``"euler-xyz"``, ``"euler-ZYX"``),
        ``"quat-wxyz"`` or ``"quat-xyzw"`` (four). Written paths give it back
        in the same representation (:func:`write_csv` with the mapping).
    bad_rows : {"error", "drop"}, default="error"
        A row with NaN or inf is an error naming it, or (``"drop"``) dropped
        with one :class:`~ndlfd.NdlfdWarning` (one summary per fit); at least
        2 rows must remain.

    Returns
    -------
    demo : Demonstration

    Raises
    ------
    DataFileError
        Any problem with the file, naming the file and, where it applies, the
        line: see :func:`read_table`, plus a missing or non-increasing time
        column, unassignable or unknown column names, invalid quaternions.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "demo.csv"
    >>> _ = p.write_text("t,x,y,vx,vy\n0,0,0,1,0\n1,1,0,1,0\n")
    >>> read_csv(p)
    Demonstration(n_samples=2, duration=1, position=(x, y), velocity=(vx, vy))
    >>> _ = p.write_text("Time;Pos_X;Pos_Y\n0;0;0\n1;1;0\n")
    >>> read_csv(p, groups={"position": ["pos_x", "pos_y"]})
    Demonstration(n_samples=2, duration=1, position=(Pos_X, Pos_Y))
    >>> _ = p.write_text("t,x,y,z,rx,ry,rz\n0,0,0,0,0,0,1.5\n1,1,0,0,0,0,1.6\n")
    >>> read_csv(p, representation="rotvec").get("orientation").round(3)
    array([[0.732, 0.   , 0.   , 0.682],
           [0.697, 0.   , 0.   , 0.717]])
    """
    return read_csv_mapped(
        Path(path),
        LIBRARY_HINTS,
        time_column=time_column,
        groups=groups,
        quaternion_order=quaternion_order,
        drop=drop,
        euler=euler,
        representation=representation,
        bad_rows=bad_rows,
    )[0][0]


def write_csv(
    demo: Demonstration,
    path: str | os.PathLike,
    *,
    time_column: str = "t",
    float_format: str | None = None,
    time_format: str | None = None,
    mapping: ColumnMapping | None = None,
) -> Path:
    """Write a demonstration to a CSV file that :func:`read_csv` reads back.

    The first column is the time; a column whose name does not already give
    its group by the naming convention is written as ``group.column``.
    Numbers are written in shortest round-trip form (read back exactly)
    unless a format is given, atomically.

    Parameters
    ----------
    demo : Demonstration
        The demonstration.
    path : str or path-like
        Destination.
    time_column : str, default="t"
        Name of the time column.
    float_format : str, optional
        %-format of the values, e.g. ``"%.10g"`` (ten significant digits).
    time_format : str, optional
        %-format of the time stamps.
    mapping : ColumnMapping, optional
        How the input was read: when it had Euler angles or a rotation
        vector, the orientation is written back as those columns, in that
        representation (see
        :func:`~ndlfd.io._mapping.euler_columns`); when it was a CSV file
        or a LeRobot dataset, its time column and the columns of its groups
        keep its names and its order (a group it did not have, such as a
        derived velocity, keeps the demonstration's names, after them; see
        :func:`~ndlfd.io.csv_columns`).

    Returns
    -------
    path : Path

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = Demonstration.from_arrays([0.0, 0.5], position=[[0, 1], [2, 3]],
    ...                               grip=[0.25, 0.5])
    >>> p = write_csv(d, pathlib.Path(tempfile.mkdtemp()) / "d.csv")
    >>> print(p.read_text(), end="")
    t,x,y,grip.grip0
    0.0,0.0,1.0,0.25
    0.5,2.0,3.0,0.5
    >>> read_csv(p) == d
    True
    """
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )
    columns, groups, X = demo.columns, demo.groups, demo.X
    if mapping is not None:
        columns, groups, X = euler_columns(demo, mapping)
    header, index = output_columns(columns, groups, time_column, mapping)
    data = np.column_stack([demo.t, X[:, index]])
    formats = None
    if float_format is not None or time_format is not None:
        formats = [time_format] + [float_format] * X.shape[1]
    return write_table(path, header, data, float_format=formats)
