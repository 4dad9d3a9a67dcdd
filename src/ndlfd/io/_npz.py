"""Demonstrations in ``.npz`` files: ndlfd's own or plain arrays (never pickle)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

from .._errors import DataFileError, ModelFormatError, ValidationError
from .._fileformat import META_KEY, parse_metadata, read_archive, save_npz
from ..demonstration import Demonstration
from ._mapping import LIBRARY_HINTS, TIME_NAMES, ColumnMapping, map_arrays, wrap_error

__all__ = ["read_npz", "read_npz_mapped", "write_npz"]

_NPZ_KIND = "Demonstration"
_NPZ_VERSION = 1


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
        raise wrap_error(p, exc) from None


def read_npz_mapped(
    p: Path, how, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """The demonstration of the ``.npz`` file ``p`` with the mapping used.

    A Demonstration file (:func:`write_npz`, self-described) or a plain archive
    of arrays (mapped by ``mapping``, errors naming the settings by ``how``).
    """
    arrays = read_archive(
        p, DataFileError, f"{p}: expected an .npz archive of numeric arrays"
    )
    if META_KEY in arrays:
        demo = _read_ndlfd_npz(p, arrays)
        groups = tuple(
            (g, tuple(c for c, h in zip(demo.columns, demo.groups, strict=True)
                      if h == g))
            for g in demo.group_names
        )  # fmt: skip
        return [(demo, ColumnMapping(str(p), "t", groups, layout="ndlfd"))]
    return [map_arrays(p, arrays, how=how, **mapping)]


def read_npz(
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
    time_column, groups, quaternion_order, drop, euler, representation
        As in :func:`read_csv`, for a plain file.
    bad_rows : {"error", "drop"}, default="error"
        A row with NaN or inf is an error naming it, or (``"drop"``) dropped
        with one :class:`~ndlfd.NdlfdWarning`, as in :func:`~ndlfd.io.read_csv`;
        at least 2 rows must remain. A file
        written by :func:`write_npz` holds no such row.

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
    >>> import numpy as np
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]])
    >>> p = write_npz(d, pathlib.Path(tempfile.mkdtemp()) / "d.npz")
    >>> read_npz(p) == d
    True
    >>> q = p.with_name("plain.npz")
    >>> np.savez(q, time=[0.0, 1.0], pos=[[0, 1], [2, 3]])
    >>> read_npz(q) == d
    True
    """
    return read_npz_mapped(
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
