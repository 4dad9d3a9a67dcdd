"""Saving and loading a fitted KeypointHMM: one reader per file-format version.

A model file is an ``.npz`` of numeric arrays plus JSON metadata with a
format version (:mod:`ndlfd._fileformat`), never pickle.

========  ===========================================================
version   what it holds
========  ===========================================================
1         scaler ranges, codebook levels, key points and the HMM
          (written before the blended generation: loads with
          ``generation="paper"``)
2         version 1 plus every demonstration's normalized values
3         the fit statistics (:class:`~ndlfd.learner.FitStats`) instead
          of the key points, HMM and values
4         version 3 plus the parameter ``match_window`` (older files load
          with 0: raw matching)
5         version 4 with states interned: the statistics hold each
          visited cell (``stats_centroid_cells``, its level index per
          column) and the key points' ids among them, no mixed-radix
          state numbers, so any number of columns fits (versions 3 and 4
          load into the same cells, ids in the same order)
========  ===========================================================

Version 4 files also carry the scaler's data extremes per group and its
sample count in their metadata (older ones load without them), and, when the
model knows it, how its training files were read: the ``input`` key, an
:class:`~ndlfd.io.ColumnMapping` as JSON (the file's time column, each group's
column names, the Euler convention). ``ndlfd fit`` records it (when every file
was read the same way) so that ``ndlfd generate`` writes the input's names
without ``--like``. A file without the key (older, or a model fitted from
:class:`~ndlfd.Demonstration` objects) loads with ``input_mapping_ = None``
and keeps the model's names; readers that predate the key ignore it.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from .. import hmm
from .._errors import ModelFormatError
from .._fileformat import load_npz, save_npz
from .._pose_groups import pose_dims
from .._poses import pose_size_ok
from ..codebook import Codebook, TimeBins
from ..io import ColumnMapping
from ..normalize import GroupScaler
from ._exact import scale_exponents
from ._params import jsonable
from ._spec import DemoSpec
from ._stats import FitStats

__all__ = [
    "FORMAT_VERSION",
    "Loaded",
    "input_from_json",
    "input_to_json",
    "load_model",
    "model_file_errors",
    "save_model",
]

FORMAT_KIND = "KeypointHMM"
#: The version :func:`save_model` writes.
FORMAT_VERSION = 5


@dataclass
class Loaded:
    """What a model file holds, checked: the estimator is built from it.

    Attributes
    ----------
    estimator : KeypointHMM
        Made from the file's parameters, checked, not fitted yet.
    columns, column_groups : tuple of str
    scaler : GroupScaler
    codebook : Codebook
    time_bins : TimeBins
    stats : FitStats or None
        The fit statistics (versions 2 to 4).
    v1 : dict
        Version 1 only: the estimator's ``model_``, ``keypoints_``,
        ``n_keypoints_``, ``n_demos_`` and ``symbols_seen_`` as stored.
    n_states_used, n_clipped : int
    """

    estimator: object
    columns: tuple
    column_groups: tuple
    scaler: GroupScaler
    codebook: Codebook
    time_bins: TimeBins
    n_states_used: int
    n_clipped: int
    stats: FitStats | None = None
    v1: dict = field(default_factory=dict)
    frames: tuple = ()

    def spec(self, groups: tuple) -> DemoSpec:
        """The demonstration spec of the file's model (its learned ``groups``)."""
        return DemoSpec(
            groups=groups,
            columns=self.columns,
            col_groups=self.column_groups,
            scaler=self.scaler,
            codebook=self.codebook,
            time_bins=self.time_bins,
            frames=self.frames,
        )


def save_model(est, path: str | os.PathLike) -> None:
    """Write a fitted KeypointHMM (see :meth:`KeypointHMM.save`)."""
    scaler = est.scaler_
    arrays = {
        "scaler_min": scaler.data_min_,
        "scaler_max": scaler.data_max_,
        "levels": est.codebook_.levels,
    }
    if hasattr(est, "fit_stats_"):
        version = FORMAT_VERSION
        arrays.update(est.fit_stats_.to_arrays(prefix="stats_"))
    else:  # loaded from a version-1 file: no statistics to write
        version = 1
        arrays.update(
            keypoints=np.concatenate(est.keypoints_),
            keypoint_counts=est.n_keypoints_,
            symbols_seen=est.symbols_seen_,
        )
        arrays.update(est.model_.to_arrays(prefix="hmm_"))
    params = est.get_params()
    params["groups"] = list(est.groups_)
    meta = {
        "params": jsonable(params),
        "columns": list(est.columns_),
        "column_groups": list(est.column_groups_),
        "n_states_used": est.n_states_used_,
        "n_clipped": est.n_clipped_,
    }
    mapping = getattr(est, "input_mapping_", None)
    if mapping is not None:
        meta["input"] = input_to_json(mapping)
    frames = getattr(est, "task_frames_", None)
    if frames:
        meta["frames"] = [[name, int(a.shape[1])] for name, a in frames.items()]
    if version == FORMAT_VERSION:
        meta["scaler_seen"] = {
            "group_min": scaler.group_min_,
            "group_max": scaler.group_max_,
            "n_samples": int(scaler.n_samples_seen_),
        }
    save_npz(path, arrays, kind=FORMAT_KIND, version=version, metadata=meta)


def load_model(path: str | os.PathLike, make: Callable) -> Loaded:
    """Read a model file of any version (see :meth:`KeypointHMM.load`).

    Parameters
    ----------
    path : str or path-like
    make : callable
        ``make(params) -> estimator``: the unfitted estimator of the file's
        parameters, checked.

    Returns
    -------
    loaded : Loaded

    Raises
    ------
    ModelFormatError
        Not a KeypointHMM file, or an unknown version. Run it inside
        :func:`model_file_errors` so that inconsistent contents are one too.
    """
    arrays, meta = load_npz(
        path, kind=FORMAT_KIND, version=tuple(range(1, FORMAT_VERSION + 1))
    )
    return _READERS[meta["version"]](arrays, meta, path, make)


@contextmanager
def model_file_errors(path) -> Iterator[None]:
    """Any error reading a model file's contents as a :class:`ModelFormatError`."""
    try:
        yield
    except ModelFormatError:
        raise
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelFormatError(
            f"{path}: not a valid KeypointHMM file ({type(exc).__name__}: {exc})"
        ) from None


def _read_v1(arrays, meta, path, make) -> Loaded:
    """Version 1: written before the blended generation."""
    out = _common(arrays, meta, path, make, generation="paper", decoder="viterbi",
                  max_templates=None, match_window=0.0)  # fmt: skip
    out.v1 = _v1_arrays(arrays, out, path)
    return out


def _read_v2(arrays, meta, path, make) -> Loaded:
    """Version 2: version 1 plus every demonstration kept whole."""
    out = _common(arrays, meta, path, make, max_templates=None, match_window=0.0)
    v1 = _v1_arrays(arrays, out, path)
    counts = np.asarray(arrays["train_counts"], np.int64)
    n_demos = v1["n_demos_"]
    if counts.shape != (n_demos,) or np.any(counts < 1):
        raise ModelFormatError(f"{path}: train_counts do not match the key points")
    values = _split_rows(arrays, "train_values", counts, len(out.columns), path)
    tau = _split_rows(arrays, "train_tau", counts, None, path)
    for k, n in zip(v1["keypoints_"], counts, strict=True):
        if k.size == 0 or k.min() < 0 or k.max() >= n:
            raise ModelFormatError(f"{path}: key points out of range")
    exponents = scale_exponents(np.abs(np.concatenate(values)).max(axis=0))
    parts = []
    for j, (u, tq, idx) in enumerate(zip(values, tau, v1["keypoints_"], strict=True)):
        cells, clipped = out.codebook.cells(u[idx], return_n_clipped=True)
        bins = out.time_bins.transform(tq)[idx]  # tau is already normalized
        parts.append(
            FitStats.of_demo(
                j, u, tq, idx, cells, bins,
                exponents=exponents, n_clipped=clipped, template=True,
            )
        )  # fmt: skip
    out.stats = parts[0].merge(*parts[1:])
    return out


def _read_v3(arrays, meta, path, make) -> Loaded:
    """Version 3: the fit statistics."""
    out = _common(arrays, meta, path, make, match_window=0.0)
    return _with_stats(out, arrays, path)


def _read_v4(arrays, meta, path, make) -> Loaded:
    """Version 4: version 3 plus ``match_window`` and the scaler's data extremes.

    Version 5 (interned states) reads alike: :meth:`FitStats.from_arrays`
    reads either form of the states.
    """
    return _with_stats(_common(arrays, meta, path, make), arrays, path)


_READERS = {1: _read_v1, 2: _read_v2, 3: _read_v3, 4: _read_v4, 5: _read_v4}


def _common(arrays, meta, path, make, **older) -> Loaded:
    """The parameters, columns, scaler, codebook and time bins of any version.

    ``older`` holds the parameters a version predates, with the values that
    make it load and generate as it did.
    """
    params = dict(meta["params"])
    params.update(older)
    if isinstance(params.get("groups"), list):
        params["groups"] = tuple(params["groups"])
    est = make(params)
    # how the training files were read (None: not recorded), for the output
    est.input_mapping_ = input_from_json(meta.get("input"), path)
    columns = tuple(meta["columns"])
    col_groups = tuple(meta["column_groups"])
    d = len(columns)
    mins = np.asarray(arrays["scaler_min"], np.float64)
    maxs = np.asarray(arrays["scaler_max"], np.float64)
    levels = np.asarray(arrays["levels"])
    if (
        len(col_groups) != d
        or mins.shape != (d,)
        or maxs.shape != (d,)
        or levels.shape != (d,)
        or not (np.all(np.isfinite(mins)) and np.all(np.isfinite(maxs)))
    ):
        raise ModelFormatError(
            f"{path}: inconsistent KeypointHMM arrays (tampered file?)"
        )
    seen = meta.get("scaler_seen") or {}
    scaler = GroupScaler.from_ranges(
        mins,
        maxs,
        col_groups,
        columns=columns,
        mode=est.normalization,
        weights=est.weights,
        group_min=seen.get("group_min"),
        group_max=seen.get("group_max"),
        n_samples_seen=seen.get("n_samples", 0),
    )
    return Loaded(
        estimator=est,
        columns=columns,
        column_groups=col_groups,
        scaler=scaler,
        codebook=Codebook([int(x) for x in levels]),
        time_bins=TimeBins(est.n_time_bins),
        n_states_used=int(meta["n_states_used"]),
        n_clipped=int(meta["n_clipped"]),
        frames=_frames_of(meta.get("frames", []), col_groups, path),
    )


def _frames_of(obj, col_groups, path) -> tuple:
    """The task frames' names and pose sizes of a model file, checked."""
    dims = pose_dims(col_groups)
    ok = isinstance(obj, list) and all(
        isinstance(e, list)
        and len(e) == 2
        and isinstance(e[0], str)
        and isinstance(e[1], int)
        and pose_size_ok(e[1], dims)
        for e in obj
    )
    if not ok or len({e[0] for e in obj}) != len(obj):
        raise ModelFormatError(
            f"{path}: malformed task frames {obj!r} (tampered file?); expected"
            f" [[name, size], ...] with poses of {dims or '2, 3'} or 7 values"
        )
    return tuple((name, size) for name, size in obj)


def input_to_json(mapping: ColumnMapping) -> dict:
    """A :class:`~ndlfd.io.ColumnMapping` as a JSON object (:func:`input_from_json`).

    Examples
    --------
    >>> m = ColumnMapping("a.csv", "time", (("position", ("X", "Y")),), ("id",))
    >>> input_from_json(input_to_json(m), "m.ndlfd") == m
    True
    """
    if not isinstance(mapping, ColumnMapping):
        raise TypeError(
            f"input_mapping_ must be a ColumnMapping or None; got"
            f" {type(mapping).__name__}"
        )
    return {
        "source": mapping.source,
        "time": mapping.time,
        "groups": [[g, list(ks)] for g, ks in mapping.groups],
        "dropped": list(mapping.dropped),
        "ignored": list(mapping.ignored),
        "layout": mapping.layout,
        "euler": mapping.euler,
        "order": list(mapping.order),
    }


def input_from_json(obj, path) -> ColumnMapping | None:
    """The :class:`~ndlfd.io.ColumnMapping` of a model file's ``input`` key.

    ``None`` without the key; a :class:`~ndlfd.ModelFormatError` naming
    ``path`` for a malformed one.
    """
    if obj is None:
        return None

    def names(x) -> bool:
        return isinstance(x, list) and all(isinstance(s, str) for s in x)

    def text(x, optional=False) -> bool:
        return isinstance(x, str) or (optional and x is None)

    ok = (
        isinstance(obj, dict)
        and text(obj.get("source"))
        and text(obj.get("time"), optional=True)
        and isinstance(obj.get("groups"), list)
        and all(
            isinstance(e, list) and len(e) == 2 and text(e[0]) and names(e[1])
            for e in obj["groups"]
        )
        and names(obj.get("dropped"))
        and names(obj.get("ignored"))
        and text(obj.get("layout"))
        and text(obj.get("euler"), optional=True)
        and names(obj.get("order", []))
    )
    if not ok:
        raise ModelFormatError(
            f"{path}: the 'input' metadata must describe how the training files"
            f" were read (source, time, groups, dropped, ignored, layout, euler);"
            f" got {obj!r:.200}"
        )
    return ColumnMapping(
        obj["source"],
        obj["time"],
        tuple((g, tuple(ks)) for g, ks in obj["groups"]),
        tuple(obj["dropped"]),
        tuple(obj["ignored"]),
        obj["layout"],
        obj["euler"],
        tuple(obj.get("order", [])),  # absent in files before it was kept
    )


def _with_stats(out: Loaded, arrays, path) -> Loaded:
    stats = FitStats.from_arrays(arrays, prefix="stats_", levels=out.codebook.levels)
    if stats.n_dims != len(out.columns):
        raise ModelFormatError(
            f"{path}: the fit statistics have {stats.n_dims} columns,"
            f" the model {len(out.columns)} (tampered file?)"
        )
    want = sum(size for _, size in out.frames)
    if stats.frames.shape[1] != want:
        raise ModelFormatError(
            f"{path}: the fit statistics hold {stats.frames.shape[1]} task-frame"
            f" values per demonstration, the task frames {list(out.frames)} need"
            f" {want} (tampered file?)"
        )
    out.stats = stats
    return out


def _v1_arrays(arrays, out: Loaded, path) -> dict:
    """The key points and the HMM as format versions 1 and 2 store them."""
    counts = np.asarray(arrays["keypoint_counts"], np.int64)
    flat = np.asarray(arrays["keypoints"], np.int64)
    seen = np.asarray(arrays["symbols_seen"], bool)
    if counts.sum() != flat.size or seen.shape != (out.time_bins.n_bins,):
        raise ModelFormatError(
            f"{path}: inconsistent KeypointHMM arrays (tampered file?)"
        )
    model = hmm.DiscreteHMM.from_arrays(arrays, prefix="hmm_")
    if (
        model.n_states != out.codebook.n_states
        or model.n_symbols != out.time_bins.n_bins
    ):
        raise ModelFormatError(
            f"{path}: the HMM does not match the codebook (tampered file?)"
        )
    return {  # the estimator's attributes
        "model_": model,
        "keypoints_": np.split(flat, np.cumsum(counts)[:-1]),
        "n_keypoints_": counts,
        "n_demos_": int(counts.size),
        "symbols_seen_": seen,
    }


def _split_rows(arrays, key, counts, width, path):
    a = np.asarray(arrays[key], np.float64)
    shape = (int(counts.sum()),) + (() if width is None else (width,))
    if a.shape != shape or not np.all(np.isfinite(a)):
        raise ModelFormatError(
            f"{path}: {key} has shape {a.shape}, expected {shape} with finite"
            " values (tampered file?)"
        )
    return np.split(a, np.cumsum(counts)[:-1])
