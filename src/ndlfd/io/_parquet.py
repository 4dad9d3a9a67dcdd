"""One episode as a Parquet file in LeRobot's layout: written, and read back.

``ndlfd generate -o path.parquet`` writes a generated path as LeRobot writes
an episode's rows (LeRobot's ``lerobot/datasets/utils.py``, its data files):
the columns ``timestamp`` (float32, seconds), ``frame_index``,
``episode_index``, ``index`` and ``task_index`` (int64), and the path as one
fixed-size list column of float32 named like the input's feature
(``observation.state``, ``action``). The components are in the input's order
under the input's names (:mod:`ndlfd.io._output`); the file's schema
metadata keeps them under the key ``ndlfd`` as LeRobot's ``info.json`` does
(``{"features": {FEATURE: {"dtype", "shape", "names"}}}``), so
:func:`read_parquet` (and ``ndlfd fit``/``plot``/``generate --like`` of a
``.parquet`` file) reads the path back with its names. A Parquet file
without that key is read when it has a single list column of numbers (its
components named ``{short}_{i}``).

Needs pyarrow: the extra ``lerobot`` (``pip install "ndlfd[lerobot]"``).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .._errors import DataFileError, MissingExtraError, ValidationError
from .._fileformat import atomic_path
from ..demonstration import Demonstration
from ._lerobot import BOOKKEEPING, feature_values, layout_feature, lerobot_layout
from ._mapping import (
    LIBRARY_HINTS,
    ColumnMapping,
    euler_columns,
    map_arrays,
)
from ._output import output_columns

__all__ = [
    "PARQUET_KEY",
    "read_parquet",
    "read_parquet_mapped",
    "write_parquet",
]

#: The schema metadata key holding the features' names (info.json's form).
PARQUET_KEY = b"ndlfd"
_TIME = BOOKKEEPING[0]
_LAYOUT_VERSION = "episode file"


def _pyarrow(what: str):
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise MissingExtraError(
            f"{what} Parquet files needs pyarrow; install it with: pip install"
            ' "ndlfd[lerobot]"'
        ) from None
    return pa, pq


def write_parquet(
    demo: Demonstration,
    path: str | os.PathLike,
    *,
    mapping: ColumnMapping | None = None,
    feature: str | None = None,
    episode_index: int = 0,
    task_index: int = 0,
) -> Path:
    """Write a demonstration as one LeRobot episode's rows in a Parquet file.

    Parameters
    ----------
    demo : Demonstration
        The path (a generated one, say).
    path : str or path-like
        Destination, written atomically.
    mapping : ColumnMapping, optional
        How the input was read: its columns keep their names and order
        (:func:`~ndlfd.io.csv_columns`; Euler angles written back as angles).
    feature : str, optional
        The list column's name; default the feature ``mapping`` read from a
        LeRobot dataset, else ``"observation.state"``.
    episode_index, task_index : int, default=0
        The values of those columns.

    Returns
    -------
    path : Path

    Raises
    ------
    ValidationError
        Time stamps that float32 (LeRobot's ``timestamp``) cannot keep apart.
    MissingExtraError
        pyarrow is not installed.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = Demonstration.from_arrays([0.0, 0.5, 1.0], joints=[[0, 1], [2, 3], [4, 5]])
    >>> p = write_parquet(d, pathlib.Path(tempfile.mkdtemp()) / "p.parquet")
    >>> back = read_parquet(p)
    >>> back.columns, back.X.tolist()
    (('joints0', 'joints1'), [[0.0, 1.0], [2.0, 3.0], [4.0, 5.0]])
    """
    pa, pq = _pyarrow("writing")
    if not isinstance(demo, Demonstration):
        raise ValidationError(
            f"demo must be a Demonstration; got {type(demo).__name__}"
        )
    if feature is None:
        feature = (mapping and layout_feature(mapping.layout)) or "observation.state"
    if not isinstance(feature, str) or not feature or feature in BOOKKEEPING:
        raise ValidationError(
            f"feature must name a feature, not one of {', '.join(BOOKKEEPING)};"
            f" got {feature!r}"
        )
    columns, groups, X = demo.columns, demo.groups, demo.X
    if mapping is not None:
        columns, groups, X = euler_columns(demo, mapping)
    header, index = output_columns(columns, groups, _TIME, mapping)
    names = header[1:]
    t32 = demo.t.astype(np.float32)
    close = np.flatnonzero(~(np.diff(t32) > 0))
    if close.size:
        i = int(close[0])
        raise ValidationError(
            f"the time stamps {demo.t[i]!r} and {demo.t[i + 1]!r} (samples {i}"
            f" and {i + 1}) are one float32 timestamp, as LeRobot stores time;"
            " expected stamps further apart"
        )
    n, k = X.shape[0], len(names)
    values = pa.FixedSizeListArray.from_arrays(
        pa.array(np.ascontiguousarray(X[:, index], dtype=np.float32).ravel()), k
    )
    counter = np.arange(n, dtype=np.int64)
    table = pa.table(
        {
            _TIME: pa.array(t32),
            "frame_index": pa.array(counter),
            "episode_index": pa.array(np.full(n, episode_index, dtype=np.int64)),
            "index": pa.array(counter),
            "task_index": pa.array(np.full(n, task_index, dtype=np.int64)),
            feature: values,
        }
    )
    info = {"features": {feature: {"dtype": "float32", "shape": [k], "names": names}}}
    table = table.replace_schema_metadata({PARQUET_KEY: json.dumps(info).encode()})
    final = Path(path)
    with atomic_path(final, suffix=".parquet") as tmp:
        pq.write_table(table, tmp)
    return final


def _feature_of(p: Path, schema, pa) -> tuple[str, tuple[str, ...]]:
    """The file's feature and its component names.

    From the ``ndlfd`` metadata, else the single list column of numbers.
    """
    meta = (schema.metadata or {}).get(PARQUET_KEY)
    if meta is not None:
        try:
            ((feature, spec),) = json.loads(meta)["features"].items()
            names = tuple(str(x) for x in spec["names"])
        except (ValueError, KeyError, TypeError, AttributeError):
            raise DataFileError(
                f"{p}: its {PARQUET_KEY.decode()} metadata must describe one"
                " feature as {'features': {NAME: {'names': [...]}}}; got"
                f" {meta[:200]!r}"
            ) from None
        return feature, names
    lists = [
        f.name
        for f in schema
        if (
            pa.types.is_list(f.type)
            or pa.types.is_fixed_size_list(f.type)
            or pa.types.is_large_list(f.type)
        )
        and (
            pa.types.is_floating(f.type.value_type)
            or pa.types.is_integer(f.type.value_type)
        )
    ]
    if len(lists) != 1:
        raise DataFileError(
            f"{p}: expected one list column of numbers (a LeRobot feature such"
            f" as observation.state) besides {', '.join(BOOKKEEPING)}; got"
            f" {len(lists)} ({', '.join(lists) or 'none'}) among the columns"
            f" {', '.join(schema.names)}"
        )
    field = schema.field(lists[0])
    k = getattr(field.type, "list_size", None)
    if k is None:
        raise DataFileError(
            f"{p}: feature {lists[0]!r} is a list of varying length and the file"
            f" does not name its components ({PARQUET_KEY.decode()} metadata)"
        )
    short = lists[0].rsplit(".", 1)[-1]
    return lists[0], tuple(f"{short}_{i}" for i in range(k))


def read_parquet_mapped(
    path, how, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """The demonstration of a Parquet episode file with the mapping used.

    The reader of :data:`~ndlfd.io._files.READERS` for ``.parquet``: ``how``
    is ``LIBRARY_HINTS`` or ``CLI_HINTS``, ``mapping`` the column mapping
    options (the time column by default ``timestamp``).
    """
    pa, pq = _pyarrow("reading")
    p = Path(path)
    try:
        schema = pq.read_schema(p)
        feature, names = _feature_of(p, schema, pa)
        time = [_TIME] if _TIME in schema.names else []
        table = pq.read_table(p, columns=[*time, feature])
    except (OSError, pa.ArrowInvalid) as exc:
        raise DataFileError(
            f"{p}: cannot be read as Parquet ({type(exc).__name__}: {exc})"
        ) from None
    if table.num_rows == 0:
        raise DataFileError(f"{p}: holds no rows")
    values = feature_values(table.column(feature), feature, names, p)
    arrays = {}
    if time:
        arrays[time[0]] = table.column(time[0]).to_numpy().astype(np.float64)
    arrays.update((name, values[:, j]) for j, name in enumerate(names))
    layout = lerobot_layout(_LAYOUT_VERSION, feature)
    return [map_arrays(p, arrays, how=how, layout=layout, **mapping)]


def read_parquet(
    path: str | os.PathLike,
    *,
    time_column: str | Sequence[str] | None = _TIME,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
    euler: str = "xyz",
    bad_rows: str = "error",
) -> Demonstration:
    """Read a Parquet episode file (as :func:`write_parquet` writes it).

    Time from ``timestamp``, values from the file's feature, its components
    named after the file's metadata and mapped to groups like CSV columns
    (``shoulder_pan.pos`` a joint, ...). Needs the ``lerobot`` extra.

    Parameters
    ----------
    path : str or path-like
    time_column, groups, quaternion_order, drop, euler, bad_rows
        As in :func:`~ndlfd.io.read_lerobot`.

    Returns
    -------
    demo : Demonstration
    """
    mapping = {
        "time_column": time_column,
        "groups": groups,
        "quaternion_order": quaternion_order,
        "drop": drop,
        "euler": euler,
        "bad_rows": bad_rows,
    }
    return read_parquet_mapped(path, LIBRARY_HINTS, **mapping)[0][0]
