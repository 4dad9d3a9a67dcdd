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

import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from ._errors import DataFileError, ValidationError
from ._fileformat import atomic_path
from ._validation import check_points

__all__ = ["read_table", "write_table"]

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
