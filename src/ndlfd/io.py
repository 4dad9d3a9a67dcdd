"""Reading and writing demonstrations: CSV tables and ``.npz`` files.

Two levels:

* :func:`read_table` / :func:`write_table` move a header row and a numeric
  table between a CSV file and numpy, nothing more.
* :func:`read_csv` / :func:`write_csv`, :func:`read_npz` / :func:`write_npz` and
  :func:`read_demos` move whole :class:`~ndlfd.demo.Demonstration` objects.

The CSV dialect is deliberately small: comma-separated values, one header row,
numbers only below it. Spaces around names and values are stripped; blank lines
and lines whose first non-space character is ``#`` are skipped anywhere (so a
file may carry comments). Quoting is not supported. Every problem is reported as
a :class:`~ndlfd.DataFileError` naming the file and the 1-based line number.

Every write goes to a temporary file beside the target and is renamed into place,
so a crash never leaves a partial file behind.
"""

from __future__ import annotations

import glob
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np

from ._errors import DataFileError, ModelFormatError, ValidationError
from ._fileformat import atomic_path, load_npz, save_npz
from ._validation import check_points
from .demo import Demonstration
from .orientation import QUATERNION_ORDERS

__all__ = [
    "NAMING_CONVENTION",
    "demo_files",
    "group_of_column",
    "read_csv",
    "read_demos",
    "read_npz",
    "read_table",
    "write_csv",
    "write_npz",
    "write_table",
]

_NPZ_KIND = "Demonstration"
_NPZ_VERSION = 1


# --------------------------------------------------------------------------- tables
def _read_table_lines(path) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Parse a CSV table; also return the 1-based file line of each data row."""
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
    rows: list[list[float]] = []
    lines: list[int] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if not s or s.startswith("#"):
            continue
        fields = [f.strip() for f in s.split(",")]
        if header is None:
            header, header_line = fields, lineno
            _check_header(p, header, lineno)
            continue
        if len(fields) != len(header):
            raise DataFileError(
                f"{p}, line {lineno}: expected {len(header)} comma-separated values"
                f" (one per column of the header on line {header_line}); got"
                f" {len(fields)}"
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
    return header, data, np.array(lines, dtype=np.int64)


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
        comma-separated. Blank lines and ``#`` comment lines are skipped.

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
    """
    columns, data, _ = _read_table_lines(path)
    return columns, data


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


def write_table(path: str | os.PathLike, columns: Sequence[str], data) -> Path:
    """Write a header row and a numeric table to a CSV file, atomically.

    Floats are written in Python's shortest round-trip form (``repr``), so
    :func:`read_table` gives back exactly the same numbers; an integer array is
    written as integers.

    Parameters
    ----------
    path : str or path-like
        Destination; its folder is created if needed.
    columns : sequence of str of length n_columns
        Unique names without commas, newlines or ``#``.
    data : array-like of shape (n_rows, n_columns)
        Finite real numbers, at least one row.

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
    """
    a = np.asarray(data)
    if a.dtype.kind in "iu" and a.ndim == 2:
        check_points(a, "data")  # shape and finiteness checks only
        rows = a.tolist()
    else:
        rows = check_points(data, "data").tolist()
        a = np.asarray(rows)
    names = _check_column_names(columns, a.shape[1])
    body = [",".join(names)]
    body.extend(",".join(map(repr, row)) for row in rows)
    final = Path(path)
    with atomic_path(final) as tmp:
        tmp.write_text("\n".join(body) + "\n", encoding="utf-8")
    return final


# --------------------------------------------------------------------------- CSV demos
#: How :func:`read_csv` tells a column's group from its name when no ``groups=``
#: mapping is given. A name ``group.column`` puts ``column`` in group ``group``.
NAMING_CONVENTION: tuple[tuple[str, str], ...] = (
    (r"x|y|z|p\d+", "position"),
    (r"vx|vy|vz|v\d+", "velocity"),
    (r"qw|qx|qy|qz", "orientation"),
    (r"fx|fy|fz|f\d+", "force"),
)
_CONVENTION = tuple((re.compile(rf"^(?:{pat})$"), g) for pat, g in NAMING_CONVENTION)
_QUAT_NAMES = ("qw", "qx", "qy", "qz")


def group_of_column(name: str) -> tuple[str, str] | None:
    """Group and column name that the CSV naming convention gives a header name.

    ``x, y, z, p0, p1, ...`` → position; ``vx, vy, vz, v0, ...`` → velocity;
    ``qw, qx, qy, qz`` → orientation; ``fx, fy, fz, f0, ...`` → force;
    ``group.column`` → ``column`` in the user group ``group``; anything else
    → ``None``.

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


def _wrap(p: Path, exc: ValidationError, lines: np.ndarray | None = None):
    msg = str(exc)
    m = re.search(r"at row (\d+)", msg)
    if m and lines is not None and int(m.group(1)) < lines.size:
        msg += f" (line {lines[int(m.group(1))]})"
    return DataFileError(f"{p}: {msg}")


def _check_time_column(p: Path, name: str, t: np.ndarray, lines: np.ndarray) -> None:
    """Refuse a time column that repeats or decreases, naming the file's line.

    Every reader of a time column (:func:`read_csv`, ``ndlfd simplify``) uses
    this, so they refuse the same files with the same message.
    """
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise DataFileError(
            f"{p}, line {lines[i]}: time column {name!r} must be strictly"
            f" increasing; got {float(t[i])!r} after {float(t[i - 1])!r} on line"
            f" {lines[i - 1]}"
        )


def read_csv(
    path: str | os.PathLike,
    *,
    time_column: str | None = "t",
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
) -> Demonstration:
    r"""Read one demonstration from a CSV file.

    Without ``groups`` every column except the time column is assigned by its
    name (:func:`group_of_column`): ``x, y, z`` (or ``p0, p1, ...``) position,
    ``vx, vy, vz`` (or ``v0, ...``) velocity, ``qw, qx, qy, qz`` orientation,
    ``fx, fy, fz`` (or ``f0, ...``) force, ``group.column`` a user group; any
    other name is an error asking for ``groups=``. Groups are laid out in the
    order their first column appears in the file.

    Parameters
    ----------
    path : str or path-like
        The CSV file (dialect: see :func:`read_table`).
    time_column : str or None, default="t"
        The column holding the time stamps (strictly increasing). ``None`` uses
        the row number ``0, 1, 2, ...`` as time.
    groups : mapping of str to sequence of str, optional
        Explicit assignment ``{"position": ["X", "Y"], "grip": ["w"]}``. Every
        column except the time column and ``drop`` must be mapped; the columns
        keep their names and the groups the mapping's order.
    quaternion_order : {"wxyz", "xyzw"}, default="wxyz"
        The order of the four orientation columns in the file. When they are
        named ``qw, qx, qy, qz`` the names decide and this is not used.
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
    """
    p = Path(path)
    QUATERNION_ORDERS.get(quaternion_order)
    header, data, lines = _read_table_lines(p)
    drop = [drop] if isinstance(drop, str) else list(drop)
    unknown = [c for c in drop if c not in header]
    if unknown:
        raise DataFileError(
            f"{p}: drop names unknown column(s) {unknown}; the columns are {header}"
        )
    if time_column is None:
        t = np.arange(data.shape[0], dtype=np.float64)
        tj = None
    else:
        if time_column not in header:
            raise DataFileError(
                f"{p}: expected a time column {time_column!r}; got columns {header}"
                " (pass time_column= to name another one, or None to use the row"
                " number)"
            )
        tj = header.index(time_column)
        t = data[:, tj]
        _check_time_column(p, time_column, t, lines)
    free = [j for j, c in enumerate(header) if j != tj and c not in drop]
    layout: dict[str, list[tuple[int, str]]] = {}
    if groups is None:
        unassigned = []
        for j in free:
            hit = group_of_column(header[j])
            if hit is None:
                unassigned.append(header[j])
            else:
                layout.setdefault(hit[0], []).append((j, hit[1]))
        if unassigned:
            raise DataFileError(
                f"{p}: cannot tell the group of column(s) {unassigned} from their"
                " names; name them x, y, z / vx, vy, vz / qw, qx, qy, qz / fx, fy,"
                " fz / group.column, or pass groups={'position': [...], ...}"
            )
    else:
        if not isinstance(groups, Mapping):
            raise ValidationError(
                f"groups must be a mapping group -> column names; got {groups!r}"
            )
        seen: dict[str, str] = {}
        for g, cols in groups.items():
            cols = [cols] if isinstance(cols, str) else list(cols)
            for c in cols:
                if c not in header:
                    raise DataFileError(
                        f"{p}: groups maps column {c!r} to {g!r}, but the file has"
                        f" no such column; got columns {header}"
                    )
                if c == time_column or c in drop:
                    raise DataFileError(
                        f"{p}: groups maps column {c!r}, which is the time column"
                        " or dropped"
                    )
                if c in seen:
                    raise DataFileError(
                        f"{p}: groups maps column {c!r} to both {seen[c]!r} and {g!r}"
                    )
                seen[c] = g
                layout.setdefault(g, []).append((header.index(c), c))
        rest = [header[j] for j in free if header[j] not in seen]
        if rest:
            raise DataFileError(
                f"{p}: groups does not map column(s) {rest}; map them or pass"
                f" drop={rest!r} to ignore them"
            )
    if not layout:
        raise DataFileError(
            f"{p}: expected value columns besides the time column; got none"
        )
    blocks, names, gnames = [], [], []
    for g, items in layout.items():
        idx = [j for j, _ in items]
        cols = [c for _, c in items]
        if g == "orientation" and len(idx) == 4:
            if sorted(cols) == sorted(_QUAT_NAMES):
                order = [cols.index(q) for q in _QUAT_NAMES]
            else:
                order = list(QUATERNION_ORDERS.get(quaternion_order))
            idx = [idx[k] for k in order]
            cols = [cols[k] for k in order]
        blocks.append(data[:, idx])
        names.extend(cols)
        gnames.extend([g] * len(idx))
    try:
        return Demonstration(t, np.hstack(blocks), tuple(names), tuple(gnames))
    except ValidationError as exc:
        raise _wrap(p, exc, lines) from None


def _csv_header(demo: Demonstration, time_column: str) -> list[str]:
    header = [time_column]
    for c, g in zip(demo.columns, demo.groups, strict=True):
        hit = group_of_column(c)
        if hit == (g, c) and c != time_column:
            header.append(c)
        else:
            header.append(f"{g}.{c}")
    return header


def write_csv(
    demo: Demonstration, path: str | os.PathLike, *, time_column: str = "t"
) -> Path:
    """Write a demonstration to a CSV file that :func:`read_csv` reads back exactly.

    The first column is the time; a column whose name does not already give
    its group by the naming convention is written as ``group.column``.
    Numbers are written in shortest round-trip form, atomically.

    Parameters
    ----------
    demo : Demonstration
        The demonstration.
    path : str or path-like
        Destination.
    time_column : str, default="t"
        Name of the time column.

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
    return write_table(path, _csv_header(demo, time_column), data)


# --------------------------------------------------------------------------- NPZ demos
def write_npz(demo: Demonstration, path: str | os.PathLike) -> Path:
    """Write a demonstration to an ndlfd ``.npz`` file (no pickle), atomically.

    The archive holds ``t`` and ``X`` and JSON metadata with the columns and
    groups (kind ``"Demonstration"``, format version 1).

    Parameters
    ----------
    demo : Demonstration
        The demonstration.
    path : str or path-like
        Destination (written as given).

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
    )


def read_npz(path: str | os.PathLike) -> Demonstration:
    """Read a demonstration written by :func:`write_npz`.

    Parameters
    ----------
    path : str or path-like
        The file.

    Returns
    -------
    demo : Demonstration

    Raises
    ------
    DataFileError
        A missing, foreign, truncated or tampered file, another format version,
        or contents that do not make a valid demonstration.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]])
    >>> p = write_npz(d, pathlib.Path(tempfile.mkdtemp()) / "d.npz")
    >>> read_npz(p) == d
    True
    """
    p = Path(path)
    try:
        arrays, meta = load_npz(p, kind=_NPZ_KIND, version=_NPZ_VERSION)
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


# --------------------------------------------------------------------------- many
def demo_files(source) -> list[Path]:
    """The files :func:`read_demos` reads from ``source``, in that order.

    Parameters
    ----------
    source : str, path-like or list of them
        A folder (its ``*.csv`` and ``*.npz`` files, sorted), a glob pattern
        (its matches, sorted), a file, or a list of these.

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
                q for q in p.iterdir() if q.is_file() and q.suffix in (".csv", ".npz")
            )
            if not found:
                raise DataFileError(
                    f"{p}: expected .csv or .npz files in the folder; found none"
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


def read_demos(source, **kwargs) -> list[Demonstration]:
    """Read many demonstrations: a folder, a glob pattern, a file or a list.

    A folder gives its ``*.csv`` and ``*.npz`` files in sorted order; a glob
    pattern its matches, sorted. ``.npz`` files are read with :func:`read_npz`,
    everything else with :func:`read_csv` (which gets ``kwargs``).

    Parameters
    ----------
    source : str, path-like or list of them
        Where the demonstrations are.
    **kwargs
        Passed to :func:`read_csv`.

    Returns
    -------
    demos : list of Demonstration

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
    """
    return [
        read_npz(p) if p.suffix == ".npz" else read_csv(p, **kwargs)
        for p in _expand(source)
    ]
