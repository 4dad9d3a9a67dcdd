"""Demonstrations in HDF5 files: one HDF5 group per episode (needs h5py).

A file laid out as an ALOHA / ACT episode (``/action`` beside
``/observations/qpos``) is one demonstration of two arms: see
:mod:`ndlfd.io._aloha`.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .._errors import DataFileError, MissingExtraError
from ..demonstration import Demonstration
from ._aloha import is_aloha_episode, read_aloha_episode
from ._mapping import LIBRARY_HINTS, TIME_NAMES, ColumnMapping, map_arrays

__all__ = ["HDF5_SUFFIXES", "read_hdf5", "read_hdf5_mapped"]

#: The suffixes (any case) read as HDF5 files.
HDF5_SUFFIXES = (".h5", ".hdf5", ".he5")


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


def read_hdf5_mapped(
    p: Path, how, feature=None, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """Every episode of the HDF5 file ``p`` with the mapping used.

    Each episode is mapped by ``mapping`` (errors naming the settings by
    ``how`` and the episode as ``file:/episode``). An ALOHA episode file is
    one demonstration of ``feature`` (:mod:`ndlfd.io._aloha`; ``None``:
    ``/action``), which other files ignore.
    """
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
        if is_aloha_episode(fh):
            return read_aloha_episode(p, fh, how, feature, **mapping)
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
            out.append(map_arrays(source, arrays, how=how, source=source, **mapping))
    return out


def read_hdf5(
    path: str | os.PathLike,
    *,
    time_column: str | Sequence[str] | None = TIME_NAMES,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
    euler: str = "xyz",
    bad_rows: str = "error",
    feature: str | None = None,
) -> list[Demonstration]:
    """Read demonstrations from an HDF5 file: one HDF5 group per episode.

    Each group directly below the root is one episode (in natural order:
    ``ep2`` before ``ep10``); its datasets (those of its sub-groups as
    ``sub/name``) are mapped like the arrays of a plain ``.npz`` file (see
    :func:`read_npz`). A file with datasets at the root is one episode.
    An ALOHA / ACT episode file (``/action`` and ``/observations/qpos`` of
    14 values, as their ``record_episodes.py`` write it) is one
    demonstration of two arms, ``left_joints``, ``gripper`` and
    ``right_joints``, at 50 Hz, its images never read (see
    :mod:`ndlfd.io._aloha`). Needs the ``hdf5`` extra
    (``pip install "ndlfd[hdf5]"``).

    Parameters
    ----------
    path : str or path-like
        The file.
    time_column, groups, quaternion_order, drop, euler
        As in :func:`read_csv`, applied to every episode.
    bad_rows : {"error", "drop"}, default="error"
        A row with NaN or inf is an error naming it, or (``"drop"``) dropped
        with one :class:`~ndlfd.NdlfdWarning`, as in :func:`~ndlfd.io.read_csv`;
        at least 2 rows must remain in
        each episode.
    feature : str, optional
        What an ALOHA episode gives: the commanded ``"action"`` (the
        default) or the measured ``"observations/qpos"`` (also ``"qpos"``,
        or LeRobot's ``"observation.state"``); other files ignore it.

    Returns
    -------
    demos : list of Demonstration

    Raises
    ------
    DataFileError
        A missing or unreadable file, or an episode that cannot be mapped (the
        message names ``file:/episode``); an ALOHA episode whose ``qpos`` or
        ``action`` is not 14 wide, whose lengths differ, or that is empty.
    MissingExtraError
        h5py is not installed.
    """
    return [
        demo
        for demo, _ in read_hdf5_mapped(
            Path(path),
            LIBRARY_HINTS,
            time_column=time_column,
            groups=groups,
            quaternion_order=quaternion_order,
            drop=drop,
            euler=euler,
            bad_rows=bad_rows,
            feature=feature,
        )
    ]
