"""Reading and writing demonstrations: CSV tables, ``.npz`` and HDF5 files.

Two levels:

* :func:`read_table` / :func:`write_table` move a header row and a numeric
  table between a CSV file and numpy, nothing more.
* :func:`read_csv` / :func:`write_csv`, :func:`read_npz` / :func:`write_npz`,
  :func:`read_hdf5` and :func:`read_demos` move whole
  :class:`~ndlfd.demonstration.Demonstration` objects.

The CSV dialect is deliberately small: one header row, numbers only below it,
separated by commas, semicolons, tabs or whitespace (the header row decides
which). Spaces around names and values are stripped; blank lines and lines
whose first non-space character is ``#`` are skipped anywhere (so a file may
carry comments). Quoting is not supported. Every problem is reported as a
:class:`~ndlfd.DataFileError` naming the file and the 1-based line number.

**Column mapping.** Every reader of demonstrations maps the file's columns (or
the arrays of an ``.npz`` / HDF5 file) to a time vector and physical groups the
same way: a time column (``t`` or ``time`` unless named), explicit
``groups={"position": ["pos_x", "pos_y"]}`` (a 2-D array maps all its columns),
and every other column by its name (:func:`group_of_column`; 2-D arrays named
``position``/``pos``, ``velocity``/``vel``, ``orientation``/``quat``,
``force``). Names are matched case-insensitively (an exact match wins). The
mapping used is returned as a :class:`ColumnMapping` on request.

Every write goes to a temporary file beside the target and is renamed into place,
so a crash never leaves a partial file behind.
"""

from __future__ import annotations

import glob
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._errors import DataFileError, MissingExtraError, ModelFormatError, ValidationError
from ._fileformat import (
    _META_KEY,
    atomic_path,
    parse_metadata,
    read_archive,
    save_npz,
)
from ._validation import check_points
from .demonstration import Demonstration, default_columns
from .orientation import QUATERNION_ORDERS

__all__ = [
    "ARRAY_NAMES",
    "DEMO_SUFFIXES",
    "NAMING_CONVENTION",
    "TIME_NAMES",
    "ColumnMapping",
    "DemoFile",
    "DemoFiles",
    "demo_files",
    "group_of_column",
    "read_csv",
    "read_demos",
    "read_hdf5",
    "read_npz",
    "read_table",
    "write_csv",
    "write_npz",
    "write_table",
]

_NPZ_KIND = "Demonstration"
_NPZ_VERSION = 1

#: The file suffixes (any case) that a folder given to :func:`read_demos`
#: contributes.
DEMO_SUFFIXES = (".csv", ".tsv", ".npz", ".h5", ".hdf5")
_HDF5_SUFFIXES = (".h5", ".hdf5", ".he5")

#: The time column's names tried, in this order, when none is named.
TIME_NAMES = ("t", "time")

#: Names of 2-D arrays (``.npz`` keys, HDF5 datasets) that give their group.
ARRAY_NAMES: tuple[tuple[str, str], ...] = (
    ("position", "position"),
    ("pos", "position"),
    ("velocity", "velocity"),
    ("vel", "velocity"),
    ("orientation", "orientation"),
    ("quat", "orientation"),
    ("force", "force"),
)

# How error messages name the settings: library parameters or CLI flags.
_LIBRARY_HINTS = {
    "time": "time_column=",
    "time_hint": "pass time_column='NAME' (or None to use the row number)",
    "groups": "groups",
    "group_hint": "pass groups={'position': [...], ...}",
    "drop": "drop",
    "drop_hint": "drop=[...]",
}
_CLI_HINTS = {
    "time": "--time-column",
    "time_hint": "name it with --time-column NAME",
    "groups": "--group",
    "group_hint": "map them with --group GROUP=NAME[,NAME...]",
    "drop": "--drop",
    "drop_hint": "--drop NAME[,NAME...]",
}


# --------------------------------------------------------------------------- tables
_DELIMITERS = ((",", "comma"), (";", "semicolon"), ("\t", "tab"))


def _delimiter_of(header_line: str) -> str | None:
    """The delimiter a header row uses: ``,``, ``;``, tab, or None (whitespace)."""
    for d, _ in _DELIMITERS:
        if d in header_line:
            return d
    if len(header_line.split()) > 1:
        return None
    return ","


def _delimiter_name(delimiter: str | None) -> str:
    return dict(_DELIMITERS).get(delimiter, "whitespace") if delimiter else "whitespace"


def _split(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    return [f.strip() for f in line.split(delimiter)]


@dataclass(frozen=True)
class _Table:
    columns: list[str]
    data: np.ndarray
    lines: np.ndarray
    delimiter: str | None


def _parse_table(path) -> _Table:
    """Parse a CSV table; also give the 1-based file line of each data row."""
    p = Path(path)
    if not p.exists():
        raise DataFileError(f"{p}: no such file")
    if not p.is_file():
        raise DataFileError(f"{p}: expected a CSV file; got a directory or device")
    try:
        text = p.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise DataFileError(
            f"{p}: expected a UTF-8 text (CSV) file; got undecodable bytes at byte"
            f" {exc.start}"
        ) from None
    except OSError as exc:
        raise DataFileError(f"{p}: cannot be read ({exc.strerror})") from None

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
                f" {_delimiter_name(delimiter)}-separated values (one per column of"
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
            if not np.isfinite(v):
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
    return _Table(header, data, np.array(lines, dtype=np.int64), delimiter)


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
    table = _parse_table(path)
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
    if a.dtype.kind in "iu" and a.ndim == 2 and float_format is None:
        check_points(a, "data")  # shape and finiteness checks only
        rows = a.tolist()
        body_rows = [",".join(map(repr, row)) for row in rows]
        k = a.shape[1]
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
        fmt = [repr if f is None else f.__mod__ for f in formats]
        body_rows = [
            ",".join(fj(v) for fj, v in zip(fmt, row, strict=True))
            for row in values.tolist()
        ]
    names = _check_column_names(columns, k)
    final = Path(path)
    with atomic_path(final) as tmp:
        tmp.write_text("\n".join([",".join(names), *body_rows]) + "\n", "utf-8")
    return final


# --------------------------------------------------------------------------- mapping
#: How :func:`read_csv` tells a column's group from its name when no ``groups=``
#: mapping names it (case-insensitively). A name ``group.column`` puts
#: ``column`` in group ``group``.
NAMING_CONVENTION: tuple[tuple[str, str], ...] = (
    (r"x|y|z|p\d+", "position"),
    (r"vx|vy|vz|v\d+", "velocity"),
    (r"qw|qx|qy|qz", "orientation"),
    (r"fx|fy|fz|f\d+", "force"),
)
_CONVENTION = tuple(
    (re.compile(rf"^(?:{pat})$", re.IGNORECASE), g) for pat, g in NAMING_CONVENTION
)
_QUAT_NAMES = ("qw", "qx", "qy", "qz")


def group_of_column(name: str) -> tuple[str, str] | None:
    """Group and column name that the CSV naming convention gives a header name.

    ``x, y, z, p0, p1, ...`` → position; ``vx, vy, vz, v0, ...`` → velocity;
    ``qw, qx, qy, qz`` → orientation; ``fx, fy, fz, f0, ...`` → force (in any
    case); ``group.column`` → ``column`` in the user group ``group``; anything
    else → ``None``.

    Parameters
    ----------
    name : str
        A header name.

    Returns
    -------
    (group, column) : tuple of str, or None

    Examples
    --------
    >>> group_of_column("vy")
    ('velocity', 'vy')
    >>> group_of_column("X")
    ('position', 'X')
    >>> group_of_column("grip.width")
    ('grip', 'width')
    >>> group_of_column("speed") is None
    True
    """
    if "." in name:
        group, column = name.split(".", 1)
        if group and column:
            return group, column
        return None
    for pattern, group in _CONVENTION:
        if pattern.match(name):
            return group, name
    return None


def _group_of_array(name: str) -> str | None:
    low = name.casefold()
    for alias, group in ARRAY_NAMES:
        if low == alias:
            return group
    return None


@dataclass(frozen=True)
class ColumnMapping:
    """How one demonstration was read: its source, time column and groups.

    Attributes
    ----------
    source : str
        The file (``file.h5:/episode`` for an HDF5 episode).
    time : str or None
        The file's name of the time column (``None``: the row number).
    groups : tuple of (str, tuple of str)
        Each group with the file's names of its columns (or arrays), in the
        demonstration's column order.
    dropped : tuple of str
        Columns left out on request.
    ignored : tuple of str
        Arrays that are not data (scalars, text), left out by themselves.
    layout : str
        ``"comma-separated"`` (or semicolon, tab, whitespace) for a CSV file,
        ``"arrays"`` for plain ``.npz`` / HDF5 arrays, ``"ndlfd"`` for an ndlfd
        demonstration file (self-described, no mapping).

    Examples
    --------
    >>> m = ColumnMapping("a.csv", "time", (("position", ("X", "Y")),), ("id",))
    >>> str(m)
    'time=time; position=X,Y; dropped id'
    """

    source: str
    time: str | None
    groups: tuple[tuple[str, tuple[str, ...]], ...]
    dropped: tuple[str, ...] = ()
    ignored: tuple[str, ...] = ()
    layout: str = "comma-separated"

    def __str__(self) -> str:
        """The mapping in one line, as the command line reports it."""
        if self.layout == "ndlfd":
            return "ndlfd demonstration file"
        parts = [f"time={self.time if self.time is not None else '(row number)'}"]
        parts += [f"{g}={','.join(cols)}" for g, cols in self.groups]
        if self.dropped:
            parts.append("dropped " + ",".join(self.dropped))
        if self.ignored:
            parts.append("ignored " + ",".join(self.ignored))
        text = "; ".join(parts)
        if self.layout not in ("comma-separated", "arrays"):
            text += f" ({self.layout})"
        return text

    @property
    def group_names(self) -> tuple[str, ...]:
        """The groups read, in column order."""
        return tuple(g for g, _ in self.groups)


def _resolve(p, name: str, keys: Sequence[str], what: str) -> str:
    """The key ``name`` names: an exact match, else the one equal up to case."""
    if name in keys:
        return name
    hits = [k for k in keys if k.casefold() == name.casefold()]
    if len(hits) == 1:
        return hits[0]
    if hits:
        raise DataFileError(
            f"{p}: {what} {name!r} matches {hits}, which differ only in case; name"
            " one of them exactly"
        )
    raise DataFileError(
        f"{p}: {what} {name!r}, but there is no such column; got columns {list(keys)}"
    )


def _find_time(p, keys, time_column, how) -> str | None:
    if time_column is None:
        return None
    if isinstance(time_column, str):
        return _resolve(p, time_column, keys, f"{how['time']} names")
    candidates = list(time_column)
    for name in candidates:
        hits = [k for k in keys if k == name] or [
            k for k in keys if k.casefold() == name.casefold()
        ]
        if len(hits) == 1:
            return hits[0]
    names = " or ".join(repr(c) for c in candidates)
    raise DataFileError(
        f"{p}: expected a time column named {names} (any case); got columns"
        f" {list(keys)}; {how['time_hint']}"
    )


def _time_error(p, name, t, i, lines, layout) -> DataFileError:
    if lines is not None:
        return DataFileError(
            f"{p}, line {lines[i]}: time column {name!r} must be strictly"
            f" increasing; got {float(t[i])!r} after {float(t[i - 1])!r} on line"
            f" {lines[i - 1]}"
        )
    return DataFileError(
        f"{p}: time {layout} {name!r} must be strictly increasing; got"
        f" {float(t[i])!r} at row {i} after {float(t[i - 1])!r} at row {i - 1}"
    )


def _is_data(a: np.ndarray) -> bool:
    return a.dtype.kind in "biuf" and a.ndim >= 1


def _layout(
    p,
    arrays: Mapping[str, np.ndarray],
    *,
    time_column,
    groups,
    drop,
    quaternion_order: str,
    how: Mapping[str, str],
    lines: np.ndarray | None = None,
    layout: str = "arrays",
    source: str | None = None,
) -> tuple[Demonstration, ColumnMapping]:
    """Map named 1-D and 2-D arrays (CSV columns, npz keys) to a demonstration."""
    QUATERNION_ORDERS.get(quaternion_order)
    keys = list(arrays)
    table = lines is not None
    noun = "column" if table else "array"
    drop = [drop] if isinstance(drop, str) else list(drop)
    dropped = []
    unknown = []
    for c in drop:
        try:
            dropped.append(_resolve(p, c, keys, f"{how['drop']} names"))
        except DataFileError:
            unknown.append(c)
    if unknown:
        raise DataFileError(
            f"{p}: {how['drop']} names unknown column(s) {unknown}; the columns are"
            f" {keys}"
        )
    tname = _find_time(p, [k for k in keys if k not in dropped], time_column, how)
    if tname is None:
        n = None
        t = None
    else:
        t = np.asarray(arrays[tname])
        if not _is_data(t) or t.ndim > 2 or (t.ndim == 2 and t.shape[1] != 1):
            raise DataFileError(
                f"{p}: the time {noun} {tname!r} must hold one number per sample"
                f" (shape (n,)); got shape {t.shape} and dtype {t.dtype}"
            )
        t = t.reshape(-1).astype(np.float64)
        n = t.shape[0]
    # explicit groups
    layout_of: dict[str, list[str]] = {}
    owner: dict[str, str] = {}
    if groups is not None:
        if not isinstance(groups, Mapping):
            raise ValidationError(
                f"groups must be a mapping group -> column names; got {groups!r}"
            )
        for g, cols in groups.items():
            cols = [cols] if isinstance(cols, str) else list(cols)
            if not cols:
                raise DataFileError(f"{p}: {how['groups']} {g} names no column")
            for c in cols:
                k = _resolve(p, c, keys, f"{how['groups']} {g} names")
                if k == tname or k in dropped:
                    raise DataFileError(
                        f"{p}: {how['groups']} {g} names {noun} {k!r}, which is the"
                        " time column or dropped"
                    )
                if k in owner:
                    raise DataFileError(
                        f"{p}: {how['groups']} maps {noun} {k!r} to both"
                        f" {owner[k]!r} and {g!r}"
                    )
                owner[k] = g
                layout_of.setdefault(g, []).append(k)
    explicit = set(layout_of)
    # every other key by its name
    ignored, unassigned, conflicts = [], [], []
    by_name: dict[str, str] = {}  # key -> column name, for keys the convention put
    for k in keys:
        if k == tname or k in dropped or k in owner:
            continue
        a = np.asarray(arrays[k])
        if not _is_data(a):
            ignored.append(k)
            continue
        g = _group_of_array(k) if a.ndim >= 2 else None
        if g is None and a.ndim == 1:
            hit = group_of_column(k)
            if hit is not None:
                g, by_name[k] = hit
        if g is None:
            unassigned.append(k)
        elif g in explicit:
            conflicts.append((k, g))
        else:
            owner[k] = g
            layout_of.setdefault(g, []).append(k)
    if unassigned:
        raise DataFileError(
            f"{p}: cannot tell the group of {noun}(s) {unassigned} from their"
            " names; name them x, y, z / vx, vy, vz / qw, qx, qy, qz / fx, fy, fz /"
            f" group.column, or {how['group_hint']}, or leave them out with"
            f" {how['drop_hint']}"
        )
    if conflicts:
        k, g = conflicts[0]
        raise DataFileError(
            f"{p}: {noun} {k!r} belongs to group {g!r} by its name, but"
            f" {how['groups']} {g} does not list it; add it there or leave it out"
            f" with {how['drop_hint']}"
        )
    if not layout_of:
        raise DataFileError(
            f"{p}: expected value columns besides the time column; got none"
        )
    # shapes
    blocks, names, gnames, mapped = [], [], [], []
    for g, ks in layout_of.items():
        parts, cols = [], []
        for k in ks:
            a = np.asarray(arrays[k])
            if not _is_data(a) or a.ndim > 2:
                raise DataFileError(
                    f"{p}: {noun} {k!r} must hold numbers of shape (n,) or (n, k);"
                    f" got shape {a.shape} and dtype {a.dtype}"
                )
            a = a.astype(np.float64).reshape(a.shape[0], -1)
            if n is None:
                n = a.shape[0]
            if a.shape[0] != n:
                ref = f"the time {noun} {tname!r}" if tname else "the first array"
                hint = " (transposed?)" if a.shape[1] == n else ""
                raise DataFileError(
                    f"{p}: {noun} {k!r} has {a.shape[0]} rows{hint}; expected {n},"
                    f" like {ref}"
                )
            parts.append(a)
            if a.ndim == 2 and np.asarray(arrays[k]).ndim == 2:
                if len(ks) == 1:
                    cols.extend(default_columns(g, a.shape[1]))
                else:
                    cols.extend(f"{k}_{i}" for i in range(a.shape[1]))
            else:
                cols.append(by_name.get(k, k))
        block = np.hstack(parts)
        if g == "orientation" and block.shape[1] == 4:
            # four named columns qw, qx, qy, qz say their order; else the option
            low = [c.casefold() for c in ks]
            if len(ks) == 4 and sorted(low) == sorted(_QUAT_NAMES):
                order = [low.index(q) for q in _QUAT_NAMES]
            else:
                order = list(QUATERNION_ORDERS.get(quaternion_order))
            if len(ks) == 4:
                ks = [ks[i] for i in order]
                cols = [cols[i] for i in order]
            block = block[:, order]
        blocks.append(block)
        names.extend(cols)
        gnames.extend([g] * block.shape[1])
        mapped.append((g, tuple(ks)))
    if t is None:
        t = np.arange(n, dtype=np.float64)
    else:
        bad = np.flatnonzero(~(np.diff(t) > 0))
        if bad.size:
            raise _time_error(p, tname, t, int(bad[0]) + 1, lines, noun)
    mapping = ColumnMapping(
        source if source is not None else str(p),
        tname,
        tuple(mapped),
        tuple(dropped),
        tuple(ignored),
        layout,
    )
    try:
        demo = Demonstration(t, np.hstack(blocks), tuple(names), tuple(gnames))
    except ValidationError as exc:
        raise _wrap(p, exc, lines) from None
    return demo, mapping


def _wrap(p, exc: ValidationError, lines: np.ndarray | None = None):
    msg = str(exc)
    m = re.search(r"at row (\d+)", msg)
    if m and lines is not None and int(m.group(1)) < lines.size:
        msg += f" (line {lines[int(m.group(1))]})"
    return DataFileError(f"{p}: {msg}")


# --------------------------------------------------------------------------- CSV demos
def _read_csv(p: Path, how, **mapping) -> tuple[Demonstration, ColumnMapping]:
    table = _parse_table(p)
    columns = {name: table.data[:, j] for j, name in enumerate(table.columns)}
    return _layout(
        p,
        columns,
        lines=table.lines,
        layout=f"{_delimiter_name(table.delimiter)}-separated",
        how=how,
        **mapping,
    )


def read_csv(
    path: str | os.PathLike,
    *,
    time_column: str | Sequence[str] | None = TIME_NAMES,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
) -> Demonstration:
    r"""Read one demonstration from a CSV file.

    Every column except the time column and ``drop`` belongs to a group:
    the one ``groups`` maps it to, or else the one its name gives
    (:func:`group_of_column`): ``x, y, z`` (or ``p0, p1, ...``) position,
    ``vx, vy, vz`` (or ``v0, ...``) velocity, ``qw, qx, qy, qz`` orientation,
    ``fx, fy, fz`` (or ``f0, ...``) force, ``group.column`` a user group; any
    other name is an error asking for ``groups=``. Names are matched
    case-insensitively (an exact match wins). The groups of ``groups`` come
    first, in its order, then the others in the order their first column
    appears in the file.

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
    """
    return _read_csv(
        Path(path),
        _LIBRARY_HINTS,
        time_column=time_column,
        groups=groups,
        quaternion_order=quaternion_order,
        drop=drop,
    )[0]


def _csv_header(demo: Demonstration, time_column: str) -> list[str]:
    header = [time_column]
    for c, g in zip(demo.columns, demo.groups, strict=True):
        hit = group_of_column(c)
        if hit == (g, c) and c.casefold() != time_column.casefold():
            header.append(c)
        else:
            header.append(f"{g}.{c}")
    return header


def write_csv(
    demo: Demonstration,
    path: str | os.PathLike,
    *,
    time_column: str = "t",
    float_format: str | None = None,
    time_format: str | None = None,
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
    data = np.column_stack([demo.t, demo.X])
    formats = None
    if float_format is not None or time_format is not None:
        formats = [time_format] + [float_format] * demo.n_dims
    return write_table(path, _csv_header(demo, time_column), data, float_format=formats)


# --------------------------------------------------------------------------- NPZ demos
def write_npz(
    demo: Demonstration, path: str | os.PathLike, *, compress: bool = False
) -> Path:
    """Write a demonstration to an ndlfd ``.npz`` file (no pickle), atomically.

    The archive holds ``t`` and ``X`` and JSON metadata with the columns and
    groups (kind ``"Demonstration"``, format version 1).

    Parameters
    ----------
    demo : Demonstration
        The demonstration.
    path : str or path-like
        Destination (written as given).
    compress : bool, default=False
        Deflate the arrays. Recorded values compress little (a 1,000-sample
        noisy 3-D path: 29 kB instead of 33 kB), and an uncompressed file
        reads about twice as fast, which counts when a fit reads 100,000.

    Returns
    -------
    path : Path
    """
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )
    return save_npz(
        path,
        {"t": demo.t, "X": demo.X},
        kind=_NPZ_KIND,
        version=_NPZ_VERSION,
        metadata={"columns": list(demo.columns), "groups": list(demo.groups)},
        compress=compress,
    )


def _read_ndlfd_npz(p: Path, arrays: dict) -> Demonstration:
    try:
        arrays, meta = parse_metadata(arrays, p, kind=_NPZ_KIND, version=_NPZ_VERSION)
    except ModelFormatError as exc:
        raise DataFileError(str(exc)) from None
    missing = [k for k in ("t", "X") if k not in arrays]
    missing += [k for k in ("columns", "groups") if k not in meta]
    if missing:
        raise DataFileError(f"{p}: the Demonstration file lacks {missing}")
    cols, grps = meta["columns"], meta["groups"]
    if not isinstance(cols, list) or not isinstance(grps, list):
        raise DataFileError(f"{p}: columns and groups must be lists of names")
    try:
        return Demonstration(arrays["t"], arrays["X"], tuple(cols), tuple(grps))
    except ValidationError as exc:
        raise _wrap(p, exc) from None


def _read_npz(p: Path, how, **mapping) -> tuple[Demonstration, ColumnMapping]:
    """A Demonstration file (``write_npz``) or a plain archive of arrays."""
    arrays = read_archive(
        p, DataFileError, f"{p}: expected an .npz archive of numeric arrays"
    )
    if _META_KEY in arrays:
        demo = _read_ndlfd_npz(p, arrays)
        groups = tuple(
            (g, tuple(c for c, h in zip(demo.columns, demo.groups, strict=True)
                      if h == g))
            for g in demo.group_names
        )  # fmt: skip
        return demo, ColumnMapping(str(p), "t", groups, layout="ndlfd")
    return _layout(p, arrays, how=how, **mapping)


def read_npz(
    path: str | os.PathLike,
    *,
    time_column: str | Sequence[str] | None = TIME_NAMES,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
) -> Demonstration:
    """Read a demonstration from an ``.npz`` file: ndlfd's own or plain arrays.

    A file written by :func:`write_npz` describes itself (the other arguments
    are not used). A plain ``np.savez(f, t=..., pos=...)`` file is mapped like
    the columns of a CSV file (see :func:`read_csv`): ``t`` or ``time`` is the
    time, a 2-D array is a whole group (``position``/``pos``,
    ``velocity``/``vel``, ``orientation``/``quat``, ``force``, or mapped with
    ``groups={"position": "P"}``), a 1-D array one column (by its name, as in
    a CSV header). Arrays that hold no numbers (text, scalars) are ignored.
    Nothing is ever unpickled.

    Parameters
    ----------
    path : str or path-like
        The file.
    time_column, groups, quaternion_order, drop
        As in :func:`read_csv`, for a plain file.

    Returns
    -------
    demo : Demonstration

    Raises
    ------
    DataFileError
        A missing, truncated or tampered file, an ndlfd file of another kind
        or version, arrays that cannot be mapped, or contents that do not make
        a valid demonstration.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]])
    >>> p = write_npz(d, pathlib.Path(tempfile.mkdtemp()) / "d.npz")
    >>> read_npz(p) == d
    True
    >>> q = p.with_name("plain.npz")
    >>> np.savez(q, time=[0.0, 1.0], pos=[[0, 1], [2, 3]])
    >>> read_npz(q) == d
    True
    """
    return _read_npz(
        Path(path),
        _LIBRARY_HINTS,
        time_column=time_column,
        groups=groups,
        quaternion_order=quaternion_order,
        drop=drop,
    )[0]


# --------------------------------------------------------------------------- HDF5
def _h5py():
    try:
        import h5py
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            'reading HDF5 files needs h5py; install it with: pip install "ndlfd[hdf5]"'
        ) from None
    return h5py


def _natural_key(name: str):
    return [int(s) if s.isdigit() else s.casefold() for s in re.split(r"(\d+)", name)]


def _read_hdf5(p: Path, how, **mapping) -> list[tuple[Demonstration, ColumnMapping]]:
    if not p.is_file():
        raise DataFileError(f"{p}: no such file")
    h5py = _h5py()
    try:
        fh = h5py.File(p, "r")
    except OSError as exc:
        raise DataFileError(
            f"{p}: expected an HDF5 file; the file is not readable as one ({exc})"
        ) from None
    out = []
    with fh:
        datasets = [k for k in fh if isinstance(fh[k], h5py.Dataset)]
        if datasets:
            episodes = [("/", fh)]
        else:
            names = sorted(
                (k for k in fh if isinstance(fh[k], h5py.Group)), key=_natural_key
            )
            episodes = [(f"/{k}", fh[k]) for k in names]
        if not episodes:
            raise DataFileError(
                f"{p}: expected one HDF5 group per episode (or datasets at the"
                " root); got an empty file"
            )
        for name, group in episodes:
            arrays: dict[str, np.ndarray] = {}

            def visit(key, obj, arrays=arrays):
                if isinstance(obj, h5py.Dataset):
                    if obj.dtype.kind in "biuf":
                        arrays[key] = obj[()]
                    else:  # text, compound, references: not data, never decoded
                        arrays[key] = np.empty(0, dtype=object)

            group.visititems(visit)
            source = f"{p}:{name}"
            if not arrays:
                raise DataFileError(f"{source}: the episode holds no datasets")
            out.append(_layout(source, arrays, how=how, source=source, **mapping))
    return out


def read_hdf5(
    path: str | os.PathLike,
    *,
    time_column: str | Sequence[str] | None = TIME_NAMES,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
) -> list[Demonstration]:
    """Read demonstrations from an HDF5 file: one HDF5 group per episode.

    Each group directly below the root is one episode (in natural order:
    ``ep2`` before ``ep10``); its datasets (those of its sub-groups as
    ``sub/name``) are mapped like the arrays of a plain ``.npz`` file (see
    :func:`read_npz`). A file with datasets at the root is one episode.
    Needs the ``hdf5`` extra (``pip install "ndlfd[hdf5]"``).

    Parameters
    ----------
    path : str or path-like
        The file.
    time_column, groups, quaternion_order, drop
        As in :func:`read_csv`, applied to every episode.

    Returns
    -------
    demos : list of Demonstration

    Raises
    ------
    DataFileError
        A missing or unreadable file, or an episode that cannot be mapped (the
        message names ``file:/episode``).
    MissingExtraError
        h5py is not installed.
    """
    return [
        demo
        for demo, _ in _read_hdf5(
            Path(path),
            _LIBRARY_HINTS,
            time_column=time_column,
            groups=groups,
            quaternion_order=quaternion_order,
            drop=drop,
        )
    ]


# --------------------------------------------------------------------------- many
def demo_files(source) -> list[Path]:
    """The files :func:`read_demos` reads from ``source``, in that order.

    Parameters
    ----------
    source : str, path-like or list of them
        A folder (its ``.csv``, ``.tsv``, ``.npz``, ``.h5`` and ``.hdf5``
        files, in any case, sorted), a glob pattern (its matches, sorted), a
        file, or a list of these.

    Returns
    -------
    paths : list of Path

    Examples
    --------
    >>> demo_files(["a.csv", "b.npz"])
    [PosixPath('a.csv'), PosixPath('b.npz')]
    """
    return _expand(source)


def _expand(source) -> list[Path]:
    if isinstance(source, (str, os.PathLike)):
        p = Path(source)
        if p.is_dir():
            found = sorted(
                q
                for q in p.iterdir()
                if q.is_file() and q.suffix.lower() in DEMO_SUFFIXES
            )
            if not found:
                raise DataFileError(
                    f"{p}: expected .csv, .tsv, .npz, .h5 or .hdf5 files in the"
                    " folder (any case); found none"
                )
            return found
        s = os.fspath(source)
        if glob.has_magic(s):
            found = sorted(Path(q) for q in glob.glob(s) if Path(q).is_file())
            if not found:
                raise DataFileError(f"{s}: the pattern matched no files")
            return found
        return [p]
    if isinstance(source, Iterable):
        out: list[Path] = []
        for item in source:
            if not isinstance(item, (str, os.PathLike)):
                raise ValidationError(
                    f"paths must be str or path-like; got {type(item).__name__}"
                )
            out.extend(_expand(item))
        if not out:
            raise DataFileError("expected at least one file; got an empty list")
        return out
    raise ValidationError(
        "source must be a file, a folder, a glob pattern or a list of paths; got"
        f" {type(source).__name__}"
    )


def _read_file(
    p: Path, how=_LIBRARY_HINTS, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """Every demonstration of one file with the mapping used, by its suffix."""
    suffix = p.suffix.lower()
    if suffix == ".npz":
        return [_read_npz(p, how, **mapping)]
    if suffix in _HDF5_SUFFIXES:
        return _read_hdf5(p, how, **mapping)
    return [_read_csv(p, how, **mapping)]


_MAPPING_DEFAULTS = {
    "time_column": TIME_NAMES,
    "groups": None,
    "quaternion_order": "wxyz",
    "drop": (),
}


def read_demos(source, *, return_mappings: bool = False, **kwargs):
    """Read many demonstrations: a folder, a glob pattern, a file or a list.

    A folder gives its ``.csv``, ``.tsv``, ``.npz``, ``.h5`` and ``.hdf5``
    files (any case) in sorted order; a glob pattern its matches, sorted.
    ``.npz`` files are read with :func:`read_npz`, ``.h5``/``.hdf5`` with
    :func:`read_hdf5` (one demonstration per episode), everything else with
    :func:`read_csv`; each gets the same column mapping (``kwargs``).

    Parameters
    ----------
    source : str, path-like or list of them
        Where the demonstrations are.
    return_mappings : bool, default=False
        Also return the :class:`ColumnMapping` of each demonstration.
    **kwargs
        ``time_column``, ``groups``, ``quaternion_order``, ``drop``: see
        :func:`read_csv`.

    Returns
    -------
    demos : list of Demonstration
    mappings : list of ColumnMapping
        Only with ``return_mappings=True``.

    Raises
    ------
    DataFileError
        No file found, or a file that cannot be read.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]])
    >>> _ = write_csv(d, folder / "a.csv"); _ = write_npz(d, folder / "b.npz")
    >>> [x == d for x in read_demos(folder)]
    [True, True]
    >>> _, maps = read_demos(folder / "a.csv", return_mappings=True)
    >>> print(maps[0])
    time=t; position=x,y
    """
    mapping = _mapping("read_demos", kwargs, "or return_mappings")
    pairs = [pair for p in _expand(source) for pair in _read_file(p, **mapping)]
    demos = [d for d, _ in pairs]
    if return_mappings:
        return demos, [m for _, m in pairs]
    return demos


def _mapping(who: str, kwargs: dict, more: str = "") -> dict:
    """The column mapping options with their defaults; unknown names refused."""
    unknown = sorted(set(kwargs) - set(_MAPPING_DEFAULTS))
    if unknown:
        raise ValidationError(
            f"{who} got unexpected argument(s) {unknown}; expected"
            f" {', '.join(_MAPPING_DEFAULTS)} {more}".rstrip()
        )
    return {**_MAPPING_DEFAULTS, **kwargs}


@dataclass(frozen=True)
class DemoFile:
    """One data file and how to read it: an item of :class:`DemoFiles`.

    It is read only when :meth:`read` is called (on whichever worker maps it
    in :meth:`KeypointHMM.fit <ndlfd.KeypointHMM.fit>`).

    Attributes
    ----------
    path : Path
    mapping : dict
        ``time_column``, ``groups``, ``quaternion_order`` and ``drop`` (see
        :func:`read_csv`).
    """

    path: Path
    mapping: dict = field(default_factory=lambda: dict(_MAPPING_DEFAULTS))
    #: How error messages name the settings: ``"library"`` (parameters) or
    #: ``"cli"`` (the command line's flags).
    hints: str = field(default="library", repr=False)

    def read(self) -> list[Demonstration]:
        """The file's demonstrations (several for an HDF5 file of episodes)."""
        return [d for d, _ in self.read_with_mappings()]

    def read_with_mappings(self) -> list[tuple[Demonstration, ColumnMapping]]:
        """The file's demonstrations, each with the :class:`ColumnMapping` used."""
        how = _CLI_HINTS if self.hints == "cli" else _LIBRARY_HINTS
        return _read_file(self.path, how, **self.mapping)


class DemoFiles(Sequence):
    """The data files of a folder, glob pattern or list, read lazily.

    A sequence of :class:`DemoFile` (a file and the column mapping to read it
    with) that holds no data: pass it to :meth:`KeypointHMM.fit
    <ndlfd.KeypointHMM.fit>` to fit from files that do not fit in memory
    together; each pass reads each file once, on the worker that maps it.

    Parameters
    ----------
    source : str, path-like or list of them
        As :func:`read_demos` takes it (a folder, a glob pattern, files).
    **mapping
        ``time_column``, ``groups``, ``quaternion_order``, ``drop``: see
        :func:`read_csv`.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from ndlfd import KeypointHMM, synth
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> demos, _ = synth.make_dataset("square", n_demos=4, random_state=0)
    >>> for i, d in enumerate(demos):
    ...     _ = write_csv(d, folder / f"demo_{i}.csv")
    >>> files = DemoFiles(folder)
    >>> len(files), files[0].path.name, files[0].read()[0] == demos[0]
    (4, 'demo_0.csv', True)
    >>> KeypointHMM(epsilon=0.1, n_time_bins=20).fit(files).n_demos_
    4
    """

    def __init__(self, source, **mapping) -> None:
        self._mapping = _mapping("DemoFiles", mapping)
        self._hints = "library"
        self.paths = tuple(_expand(source))

    @classmethod
    def _for_cli(cls, paths, **mapping) -> DemoFiles:
        files = cls.__new__(cls)
        files._mapping = _mapping("DemoFiles", mapping)
        files._hints = "cli"
        files.paths = tuple(paths)
        return files

    def __len__(self) -> int:
        return len(self.paths)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return DemoFile(self.paths[i], dict(self._mapping), self._hints)

    def __repr__(self) -> str:
        return f"DemoFiles({len(self)} files, first {str(self.paths[0])!r})"
