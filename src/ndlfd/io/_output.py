"""Output column names: a written path keeps the input's names, order and time.

A generated path's columns are the model's (its groups in the learned order,
each column named by the demonstration). Written with the
:class:`~ndlfd.io.ColumnMapping` of its input (the ``--like`` file, the
training files), the columns that input had keep its names and its order
and the time column its name; the others (a derived velocity) follow, named
``group.column`` unless the naming convention gives the group
(:func:`~ndlfd.io.group_of_column`). :func:`~ndlfd.io.write_csv` and the
Parquet writer (:mod:`ndlfd.io._parquet`) write through :func:`output_columns`.
"""

from __future__ import annotations

import numpy as np

from ..demonstration import Demonstration
from ._mapping import ColumnMapping, group_of_column

__all__ = ["csv_columns", "csv_header", "output_columns"]


def csv_header(demo: Demonstration, time_column: str) -> list[str]:
    """The header :func:`write_csv` writes for ``demo``.

    A column whose name does not give its group by the naming convention
    (:func:`~ndlfd.io.group_of_column`) is written as ``group.column``.

    Parameters
    ----------
    demo : Demonstration
    time_column : str
        The name of the time column (first).

    Returns
    -------
    header : list of str of length 1 + n_dims

    Examples
    --------
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]],
    ...                               grip=[0.25, 0.5])
    >>> csv_header(d, "t")
    ['t', 'x', 'y', 'grip.grip0']
    """
    return _header(demo.columns, demo.groups, time_column)


def csv_columns(
    demo: Demonstration, time_column: str = "t", mapping: ColumnMapping | None = None
) -> tuple[list[str], np.ndarray]:
    """The header :func:`write_csv` writes and which column of ``demo`` each is.

    With the ``mapping`` of a CSV file or a LeRobot dataset, the columns
    read from it keep the input's names and order and the time column its
    name; the other columns (a derived velocity) follow, as
    :func:`csv_header` names them. The orientation must not be one of Euler
    angles (:func:`write_csv` writes those as the input's three columns).

    Parameters
    ----------
    demo : Demonstration
    time_column : str, default="t"
        The time column's name when the mapping does not give one.
    mapping : ColumnMapping, optional
        How the input was read.

    Returns
    -------
    header : list of str of length 1 + n_dims
    index : ndarray of shape (n_dims,), dtype int64
        The column of ``demo`` written under ``header[1 + i]``.

    Examples
    --------
    >>> from ndlfd.io import ColumnMapping
    >>> d = Demonstration.from_arrays([0.0, 1.0], gripper=[0, 1],
    ...                               joints=[[0, 1], [2, 3]])
    >>> m = ColumnMapping("ds", "timestamp", (("joints", ("a.pos", "b.pos")),
    ...                   ("gripper", ("gripper.pos",))), layout="LeRobot v3.0",
    ...                   order=("a.pos", "b.pos", "gripper.pos"))
    >>> header, index = csv_columns(d, "t", m)
    >>> header, index.tolist()
    (['timestamp', 'a.pos', 'b.pos', 'gripper.pos'], [1, 2, 0])
    """
    return output_columns(demo.columns, demo.groups, time_column, mapping)


def output_columns(
    columns, groups, time_column: str, mapping: ColumnMapping | None
) -> tuple[list[str], np.ndarray]:
    """:func:`csv_columns` of the columns ``columns`` of groups ``groups``.

    The columns may hold an orientation as Euler angles
    (:func:`~ndlfd.io._mapping.euler_columns`).
    """
    own = _input_names(columns, groups, mapping)
    if any(n is not None for n in own) and mapping.time is not None:
        time_column = mapping.time
    header = _header(columns, groups, time_column, own)
    index = _input_order(own, mapping)
    return [header[0]] + [header[1 + j] for j in index], index


def _input_order(own: list, mapping: ColumnMapping | None) -> np.ndarray:
    """Columns with an input name in the input's order, then the others."""
    rank = {k: i for i, k in enumerate(mapping.order)} if mapping else {}
    key = [
        (0, rank[n]) if n in rank else (1, j) for j, n in enumerate(own)
    ]  # stable: the others keep their order
    return np.array(sorted(range(len(own)), key=key.__getitem__), dtype=np.int64)


def _keeps_names(layout: str) -> bool:
    """Whether a mapping of ``layout`` names the file's columns one by one."""
    return layout.endswith("-separated") or layout.startswith("LeRobot")


def _input_names(columns, groups, mapping: ColumnMapping | None) -> list:
    """The input's own name of each column that ``mapping`` read (else None).

    A group whose columns the mapping names one for one keeps those names;
    a group it lacks (a derived velocity) keeps the demonstration's.
    """
    names: list = [None] * len(columns)
    if mapping is None or not _keeps_names(mapping.layout):
        return names
    for g, ks in mapping.groups:
        idx = [j for j, h in enumerate(groups) if h == g]
        if len(idx) == len(ks):
            for j, k in zip(idx, ks, strict=True):
                names[j] = k
    return names


def _header(columns, groups, time_column: str, own=None) -> list[str]:
    header = [time_column]
    own = own or [None] * len(columns)
    for c, g, mine in zip(columns, groups, own, strict=True):
        if mine is not None:
            header.append(mine)
            continue
        hit = group_of_column(c)
        if hit == (g, c) and c.casefold() != time_column.casefold():
            header.append(c)
        else:
            header.append(f"{g}.{c}")
    return header
