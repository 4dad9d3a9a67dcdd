"""Demonstrations in ``.npy`` files: one ``(n_samples, n_columns)`` array each.

An ``.npy`` file holds a bare array without names. Its columns are named by
``columns=["x", "y", ...]`` (``--columns x,y,...`` on the command line) or,
for each file, by a sidecar text file beside it, ``NAME.columns.txt`` for
``NAME.npy``: the names separated by commas or new lines (``#`` starts a
comment). Then the columns are mapped like a CSV file's (groups by name or
``groups=``, a time column among them, or ``rate=`` for a log without time
stamps). The array is loaded with ``allow_pickle=False``, always: an object
array is refused, never unpickled.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .._errors import DataFileError, ValidationError
from ..demonstration import Demonstration
from ._mapping import LIBRARY_HINTS, TIME_NAMES, ColumnMapping, map_arrays

__all__ = ["NPY_OPTIONS", "SIDECAR_SUFFIX", "read_npy", "read_npy_mapped"]

#: The sidecar beside ``NAME.npy`` that names its columns: ``NAME.columns.txt``.
SIDECAR_SUFFIX = ".columns.txt"

#: The option only this reader takes: the columns' names.
NPY_OPTIONS = {"columns": None}


def _sidecar(p: Path) -> Path:
    return p.with_name(p.name[: -len(p.suffix)] + SIDECAR_SUFFIX)


def _names_of(p: Path, columns, how) -> tuple[list[str], str]:
    """The column names (given, else the sidecar's) and where they came from."""
    flag = "--columns" if how["groups"].startswith("--") else "columns="
    if columns is not None:
        if isinstance(columns, str) or not isinstance(columns, Sequence):
            raise ValidationError(
                f"columns must be a sequence of column names; got {columns!r}"
            )
        return [str(c) for c in columns], flag
    side = _sidecar(p)
    if not side.is_file():
        raise DataFileError(
            f"{p}: an .npy file holds no column names; name its columns with"
            f" {flag} a,b,c or in a sidecar file {side.name} beside it (the names"
            " separated by commas or new lines)"
        )
    try:
        text = side.read_text("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise DataFileError(f"{side}: cannot be read as UTF-8 text ({exc})") from None
    names = []
    for line in text.splitlines():
        line = line.split("#", 1)[0]
        names += [s.strip() for s in line.split(",") if s.strip()]
    return names, side.name


def _load(p: Path) -> np.ndarray:
    if not p.exists():
        raise DataFileError(f"{p}: no such file")
    try:
        a = np.load(p, allow_pickle=False, mmap_mode=None)
    except ValueError as exc:  # an object array (pickled) or a damaged header
        raise DataFileError(
            f"{p}: expected an .npy array of numbers (loaded without pickle); got {exc}"
        ) from None
    except (OSError, EOFError) as exc:
        raise DataFileError(f"{p}: not a readable .npy file ({exc})") from None
    if not isinstance(a, np.ndarray):  # an .npz archive under an .npy name
        raise DataFileError(
            f"{p}: expected one .npy array; got an .npz archive (name it .npz)"
        )
    if a.dtype.kind not in "iuf":
        raise DataFileError(
            f"{p}: expected an array of real numbers (float or integer); got dtype"
            f" {a.dtype}"
        )
    if a.ndim != 2:
        hint = " (one column: save a.reshape(-1, 1))" if a.ndim == 1 else ""
        raise DataFileError(
            f"{p}: expected an array of shape (n_samples, n_columns); got shape"
            f" {a.shape}{hint}"
        )
    if a.shape[0] < 1 or a.shape[1] < 1:
        raise DataFileError(
            f"{p}: expected at least one sample and one column; got shape {a.shape}"
        )
    return a


def read_npy_mapped(
    p: Path, how, *, columns=None, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """The demonstration of the ``.npy`` file ``p`` with the mapping used.

    A reader of :data:`~ndlfd.io._files.READERS`: ``columns`` names the
    columns (else the sidecar ``NAME.columns.txt``), ``mapping`` maps them as
    :func:`~ndlfd.io.read_csv` does.
    """
    a = _load(p)
    names, origin = _names_of(p, columns, how)
    if len(names) != a.shape[1]:
        raise DataFileError(
            f"{p}: the array has {a.shape[1]} columns (shape {a.shape}); {origin}"
            f" names {len(names)}: {names}"
        )
    seen: dict[str, int] = {}
    for name in names:
        if name in seen:
            raise DataFileError(f"{p}: {origin} names the column {name!r} twice")
        seen[name] = 1
    arrays = {name: a[:, j] for j, name in enumerate(names)}
    return [map_arrays(p, arrays, how=how, layout="npy", **mapping)]


def read_npy(
    path: str | os.PathLike,
    *,
    columns: Sequence[str] | None = None,
    time_column: str | Sequence[str] | None = TIME_NAMES,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
    euler: str | None = None,
    representation: str | None = None,
    bad_rows: str = "error",
) -> Demonstration:
    """Read a demonstration from an ``.npy`` file of shape (n_samples, n_columns).

    Parameters
    ----------
    path : str or path-like
        The file (loaded with ``allow_pickle=False``: real numbers only).
    columns : sequence of str, optional
        The name of each column; without it, the sidecar ``NAME.columns.txt``
        beside ``NAME.npy`` (names separated by commas or new lines).
    time_column, groups, quaternion_order, drop, euler, representation, bad_rows
        As in :func:`~ndlfd.io.read_csv`. A log without a time column is read
        at its sample rate by :func:`~ndlfd.io.read_demos` (``rate=``).

    Returns
    -------
    demo : Demonstration

    Raises
    ------
    DataFileError
        A missing file, an array that is not 2-D real numbers (an object
        array is never unpickled), names missing or not one per column, or
        columns that cannot be mapped.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "d.npy"
    >>> np.save(p, np.array([[0.0, 1.0, 2.0], [0.5, 2.0, 3.0]]))
    >>> read_npy(p, columns=["t", "x", "y"])
    Demonstration(n_samples=2, duration=0.5, position=(x, y))
    """
    return read_npy_mapped(
        Path(path),
        LIBRARY_HINTS,
        columns=columns,
        time_column=time_column,
        groups=groups,
        quaternion_order=quaternion_order,
        drop=drop,
        euler=euler,
        representation=representation,
        bad_rows=bad_rows,
    )[0][0]
