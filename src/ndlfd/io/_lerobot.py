"""LeRobot datasets: one demonstration per episode, read with pyarrow.

A LeRobot dataset is a folder recognized by its ``meta/info.json``. What ndlfd
relies on (LeRobot's ``lerobot/datasets/utils.py``, ``dataset_metadata.py``
and ``scripts/convert_dataset_v21_to_v30.py``):

* ``info.json`` keys: ``codebase_version`` (``"v2.0"``, ``"v2.1"``:
  layout 2.x; ``"v3.0"``: layout 3.0), ``features`` (each feature's
  ``dtype``, ``shape`` and ``names``: a list of component names, a list of
  one list of them (``[[...]]``), a dict of one or more lists such as
  ``{"motors": [...]}``, or ``null``), ``data_path``
  (the template of the data files), ``total_episodes``, ``chunks_size`` and
  ``fps`` (not used: time comes from the ``timestamp`` column).
* **2.x**: one Parquet file per episode, ``data_path`` =
  ``data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet`` with
  ``episode_chunk = episode_index // chunks_size``; the episodes are
  ``0 .. total_episodes - 1``.
* **3.0**: many episodes per file, ``data_path`` =
  ``data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet``; the
  episodes and their files are listed in ``meta/episodes/chunk-*/file-*.parquet``
  (columns ``episode_index``, ``data/chunk_index``, ``data/file_index``).
  LeRobot writes one row group per episode: an episode is read from the row
  groups whose ``episode_index`` statistics hold it (all of them in a file
  without statistics), then filtered on ``episode_index``. Each process keeps
  the footers of the last few files it read (a footer of 1,000 row groups
  takes ~10 ms to parse, a row group ~1 ms to read).
* Data files have the columns ``timestamp`` (seconds from the episode's
  start), ``episode_index``, ``frame_index``, ``index`` and one column per
  feature: a number for a feature of shape ``[1]``, else a (fixed-size) list.

One demonstration per episode: the time is ``timestamp`` (``time_column``
names another column, or ``None`` for the frame number), the values are the
components of one feature (``observation.state`` unless named: ``action``,
...), each a column named after ``names`` (``{short}_{i}`` without names,
``short`` being the feature's last dotted part) and mapped to groups by the
same rules as CSV columns (:mod:`ndlfd.io._mapping`): ``x, y, z`` position,
``roll, pitch, yaw`` orientation, ``gripper``, or ``groups=``.

**ALOHA** (``lerobot/aloha_sim_*``, ``robot_type`` ``aloha``): the 14 values
of ``observation.state`` and ``action`` are named per arm, ``left_waist``,
``left_shoulder``, ``left_elbow``, ``left_forearm_roll``,
``left_wrist_angle``, ``left_wrist_rotate``, ``left_gripper``, then
``right_...`` (:data:`~ndlfd.io._names.ALOHA_NAMES`, stored as
``{"motors": [...]}`` or ``[[...]]``): they are read as two arms, the groups
``left_joints``, ``gripper`` (both grippers) and ``right_joints``
(:mod:`ndlfd.io._names`). Fourteen values without names are an error that
gives ALOHA's mapping to pass, never a guess (some conversions put the right
arm first).

An episode is a :class:`LeRobotEpisode` (the dataset, the episode, the feature
and where its rows are), a small picklable item that reads its rows when
asked: :class:`~ndlfd.io.DemoFiles` of a dataset folder holds one per episode,
so a fit streams 10,000 episodes as it streams 10,000 files.
"""

from __future__ import annotations

import functools
import json
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._errors import DataFileError, MissingExtraError, ValidationError
from .._pose_groups import pose_dims
from ..demonstration import Demonstration
from ._frame_poses import check_frame_sources, feature_frame_poses, frame_flag
from ._mapping import LIBRARY_HINTS, TIME_NAMES, ColumnMapping, map_arrays

__all__ = [
    "BOOKKEEPING",
    "DATASET_DEFAULTS",
    "LEROBOT_INFO",
    "LeRobotEpisode",
    "feature_values",
    "is_lerobot_dataset",
    "layout_feature",
    "lerobot_episodes",
    "lerobot_layout",
    "parse_episodes",
    "read_episode_mapped",
    "read_lerobot",
]

#: Where a LeRobot dataset describes itself, below its folder.
LEROBOT_INFO = Path("meta") / "info.json"
#: The options that choose what a dataset folder contributes, with defaults.
DATASET_DEFAULTS = {"feature": "observation.state", "episodes": None}
_TIME = "timestamp"
#: The columns every LeRobot data file has besides the features.
BOOKKEEPING = (_TIME, "frame_index", "episode_index", "index", "task_index")
_BOOKKEEPING = BOOKKEEPING
_V2_DATA_PATH = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"
_V3_DATA_PATH = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"


def _pyarrow():
    try:
        import pyarrow.parquet as pq
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            "reading LeRobot datasets needs pyarrow; install it with: pip install"
            ' "ndlfd[lerobot]"'
        ) from None
    return pq


def is_lerobot_dataset(path) -> bool:
    """Whether ``path`` is a folder with a ``meta/info.json`` (a LeRobot dataset).

    Examples
    --------
    >>> import tempfile
    >>> is_lerobot_dataset(tempfile.mkdtemp())
    False
    """
    p = Path(path)
    return p.is_dir() and (p / LEROBOT_INFO).is_file()


@dataclass(frozen=True)
class LeRobotEpisode:
    """One episode of a LeRobot dataset: an item read when used.

    Attributes
    ----------
    root : Path
        The dataset folder.
    episode : int
        The episode's ``episode_index``.
    feature : str
        The feature read (``observation.state``, ``action``, ...).
    data : str
        Its data file, relative to ``root``.
    names : tuple of str
        The feature's component names (the columns).
    version : str
        The dataset's ``codebase_version``.
    """

    root: Path
    episode: int
    feature: str
    data: str
    names: tuple[str, ...]
    version: str

    def __str__(self) -> str:
        """How messages name the episode: ``DATASET episode N``."""
        return f"{self.root} episode {self.episode}"

    @property
    def path(self) -> Path:
        """The data file holding the episode."""
        return self.root / self.data


def _load_info(root: Path) -> dict:
    p = root / LEROBOT_INFO
    try:
        info = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise DataFileError(f"{p}: cannot be read as JSON ({exc})") from None
    if not isinstance(info, dict):
        raise DataFileError(f"{p}: expected a JSON object; got {type(info).__name__}")
    missing = [k for k in ("codebase_version", "features") if k not in info]
    if missing:
        raise DataFileError(f"{p}: lacks {', '.join(missing)}")
    version = str(info["codebase_version"])
    if not re.match(r"^v?[23]\.", version):
        raise DataFileError(
            f"{p}: codebase_version {version!r} is not a LeRobot layout ndlfd"
            " reads; expected v2.x (one file per episode) or v3.0"
        )
    if not isinstance(info["features"], dict):
        raise DataFileError(f"{p}: features must be an object")
    return info


def _component_names(root: Path, feature: str, spec: Mapping) -> tuple[str, ...]:
    """The feature's component names from its ``shape`` and ``names``."""
    where = f"{root / LEROBOT_INFO}: feature {feature!r}"
    dtype = spec.get("dtype")
    if dtype in ("video", "image", "string", "language"):
        raise DataFileError(f"{where} is of dtype {dtype}, not numbers")
    shape = spec.get("shape")
    if not isinstance(shape, (list, tuple)) or len(shape) != 1:
        raise DataFileError(
            f"{where} must have a shape of one dimension, [k]; got {shape!r}"
        )
    k = int(shape[0])
    names = spec.get("names")
    if isinstance(names, Mapping):
        lists = [v for v in names.values() if isinstance(v, (list, tuple))]
        names = [n for v in lists for n in v] if lists else None
    elif (
        isinstance(names, (list, tuple))
        and names
        and all(isinstance(v, (list, tuple)) for v in names)
    ):  # [[...]]: LeRobot's ALOHA conversions write the motors' list in a list
        names = [n for v in names for n in v]
    if names is None or (k == 1 and len(names) != 1):
        short = feature.rsplit(".", 1)[-1]
        return (short,) if k == 1 else tuple(f"{short}_{i}" for i in range(k))
    names = [str(n) for n in names]
    if len(names) != k:
        raise DataFileError(f"{where} has shape [{k}] but {len(names)} names: {names}")
    if len(set(names)) != k:
        raise DataFileError(f"{where} names a component twice: {names}")
    return tuple(names)


def parse_episodes(episodes, available: Sequence[int], where: str) -> list[int]:
    """The episode indices ``episodes`` selects from those ``available``.

    Parameters
    ----------
    episodes : None, int, slice, sequence of int or str
        ``None``: all; an int or a sequence of ints: those episode indices;
        a slice: that slice of the episodes in order (``slice(0, 40)``: the
        first 40). A string is the command line's form: ``"0:40"``,
        ``"-10:"``, ``"::2"`` (a slice), ``"7"`` or ``"3,5,8"``.
    available : sequence of int
        The dataset's episode indices, in order.
    where : str
        The dataset, for the messages.

    Returns
    -------
    selected : list of int

    Examples
    --------
    >>> parse_episodes("1:3", [0, 1, 2, 3], "ds")
    [1, 2]
    >>> parse_episodes("3,0", [0, 1, 2, 3], "ds")
    [3, 0]
    """
    if episodes is None:
        return list(available)
    if isinstance(episodes, str):
        episodes = _parse_text(episodes)
    if isinstance(episodes, slice):
        chosen = list(available)[episodes]
        if not chosen:
            raise DataFileError(
                f"{where}: the episodes {_slice_text(episodes)} select none of its"
                f" {len(available)} episodes"
            )
        return chosen
    if isinstance(episodes, (int, np.integer)):
        episodes = [episodes]
    if isinstance(episodes, Iterable):
        episodes = list(episodes)
    if not isinstance(episodes, list) or not all(
        isinstance(e, (int, np.integer)) and not isinstance(e, bool) for e in episodes
    ):
        raise ValidationError(
            "episodes must be None, an episode index, a list of them, a slice or"
            f" a string such as '0:40' or '3,5,8'; got {episodes!r}"
        )
    chosen = [int(e) for e in episodes]
    twice = next((e for e in chosen if chosen.count(e) > 1), None)
    if twice is not None:
        raise ValidationError(f"episodes names episode {twice} twice; got {episodes}")
    have = set(available)
    missing = [e for e in chosen if e not in have]
    if missing:
        span = f"{min(have)}-{max(have)}" if have else "none"
        raise DataFileError(
            f"{where}: has no episode {missing[0]}; its {len(have)} episodes are {span}"
        )
    return chosen


def _parse_text(text: str):
    s = text.strip()
    try:
        if ":" in s:
            parts = [p.strip() for p in s.split(":")]
            if len(parts) > 3:
                raise ValueError
            return slice(*(int(p) if p else None for p in parts))
        return [int(p) for p in s.split(",")]
    except ValueError:
        raise ValidationError(
            "episodes must look like 0:40 (a slice, Python syntax), 7 or 3,5,8;"
            f" got {text!r}"
        ) from None


def _slice_text(s: slice) -> str:
    parts = ["" if v is None else str(v) for v in (s.start, s.stop, s.step)]
    return ":".join(parts if s.step is not None else parts[:2])


def _episode_files_v3(root: Path, info: dict) -> dict[int, str]:
    """Episode index -> data file, from ``meta/episodes``."""
    pq = _pyarrow()
    folder = root / "meta" / "episodes"
    files = sorted(folder.glob("*/*.parquet")) if folder.is_dir() else []
    if not files:
        raise DataFileError(
            f"{root}: a LeRobot {info['codebase_version']} dataset lists its"
            " episodes in meta/episodes/chunk-*/file-*.parquet; found none"
        )
    template = info.get(
        "data_path", "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
    )
    keys = ["episode_index", "data/chunk_index", "data/file_index"]
    out: dict[int, str] = {}
    for f in files:
        try:
            table = pq.read_table(f, columns=keys)
        except (OSError, ValueError, KeyError) as exc:
            raise DataFileError(
                f"{f}: cannot read the columns {keys} ({type(exc).__name__}: {exc})"
            ) from None
        cols = [table.column(k).to_pylist() for k in keys]
        for ep, chunk, file in zip(*cols, strict=True):
            out[int(ep)] = _format_path(
                root, template, chunk_index=int(chunk), file_index=int(file)
            )
    return dict(sorted(out.items()))


def _format_path(root: Path, template: str, **keys) -> str:
    try:
        return template.format(**keys)
    except (KeyError, IndexError, ValueError) as exc:
        raise DataFileError(
            f"{root / LEROBOT_INFO}: data_path {template!r} names {exc}, which ndlfd"
            f" does not know; expected the keys {', '.join(keys)}"
        ) from None


def lerobot_episodes(
    root, feature: str = "observation.state", episodes=None
) -> list[LeRobotEpisode]:
    """The episodes of a LeRobot dataset, as items to read when used.

    Reads ``meta/info.json`` (and, for layout 3.0, the episode index in
    ``meta/episodes``), not the data.

    Parameters
    ----------
    root : str or path-like
        The dataset folder (holding ``meta/info.json``).
    feature : str, default="observation.state"
        The feature to read.
    episodes : None, int, slice, sequence of int or str, optional
        Which episodes (see :func:`parse_episodes`); default all.

    Returns
    -------
    episodes : list of LeRobotEpisode

    Raises
    ------
    DataFileError
        No ``meta/info.json``, an unknown layout, a feature the dataset does
        not have (the message lists those it has), unknown episodes.
    """
    root = Path(root)
    if not is_lerobot_dataset(root):
        raise DataFileError(
            f"{root}: not a LeRobot dataset (expected a folder with {LEROBOT_INFO})"
        )
    info = _load_info(root)
    features = info["features"]
    if not isinstance(feature, str) or feature not in features:
        there = ", ".join(k for k in features if k not in _BOOKKEEPING)
        raise DataFileError(
            f"{root}: has no feature {feature!r}; its features are {there}"
        )
    names = _component_names(root, feature, features[feature])
    version = str(info["codebase_version"])
    if version.lstrip("v").startswith("2."):
        total = info.get("total_episodes")
        if not isinstance(total, int) or total < 0:
            raise DataFileError(
                f"{root / LEROBOT_INFO}: total_episodes must be a count; got {total!r}"
            )
        template = info.get("data_path", _V2_DATA_PATH)
        chunk = int(info.get("chunks_size", 1000))
        where = {
            e: _format_path(root, template, episode_chunk=e // chunk, episode_index=e)
            for e in parse_episodes(episodes, range(total), str(root))
        }
    else:
        files = _episode_files_v3(root, info)
        where = {e: files[e] for e in parse_episodes(episodes, list(files), str(root))}
    if not where:
        raise DataFileError(f"{root}: the dataset holds no episode")
    return [
        LeRobotEpisode(root, e, feature, data, names, version)
        for e, data in where.items()
    ]


def lerobot_layout(version: str, feature: str) -> str:
    """The :attr:`~ndlfd.io.ColumnMapping.layout` of a LeRobot feature read.

    Examples
    --------
    >>> lerobot_layout("v3.0", "action")
    'LeRobot v3.0, action'
    >>> layout_feature(lerobot_layout("v2.1", "observation.state"))
    'observation.state'
    """
    return f"LeRobot {version}, {feature}"


def layout_feature(layout: str) -> str | None:
    """The feature a mapping of :func:`lerobot_layout` read (else ``None``)."""
    if not layout.startswith("LeRobot ") or ", " not in layout:
        return None
    return layout.split(", ", 1)[1]


def feature_values(column, feature: str, names: Sequence[str], where) -> np.ndarray:
    """A feature's Parquet column as an ``(n, k)`` float array (lists or numbers).

    Parameters
    ----------
    column : pyarrow.Array or pyarrow.ChunkedArray
        Fixed-size or variable lists of ``k = len(names)`` numbers, or one
        number per row when ``k == 1``.
    feature : str
        The feature's name, for the messages.
    names : sequence of str
        Its component names (from ``info.json``).
    where : object
        The episode or file, for the messages.

    Returns
    -------
    values : ndarray of shape (n, k), float64
    """
    import pyarrow as pa

    col = column.combine_chunks() if hasattr(column, "combine_chunks") else column
    k = len(names)
    n = len(col)
    if col.null_count:
        row = int(np.flatnonzero(np.asarray(col.is_null()))[0])
        raise DataFileError(
            f"{where}: feature {feature!r} is empty (null) at row {row}"
        )
    if (
        pa.types.is_list(col.type)
        or pa.types.is_large_list(col.type)
        or (pa.types.is_fixed_size_list(col.type))
    ):
        values = col.flatten()
        if len(values) != n * k:
            import pyarrow.compute as pc

            lengths = np.asarray(pc.list_value_length(col))
            row = int(np.flatnonzero(lengths != k)[0])
            raise DataFileError(
                f"{where}: feature {feature!r} has {int(lengths[row])} values at"
                f" row {row}; info.json gives it {k} ({', '.join(names)})"
            )
        return values.to_numpy(zero_copy_only=False).astype(np.float64).reshape(n, k)
    if k != 1:
        raise DataFileError(
            f"{where}: feature {feature!r} holds one number per row; info.json"
            f" gives it {k} components"
        )
    return col.to_numpy(zero_copy_only=False).astype(np.float64).reshape(n, 1)


@functools.lru_cache(maxsize=4)
def _row_groups(path: str, mtime_ns: int, size: int):
    """A data file's footer and each row group's episode range (per process).

    Parsing the footer of a file of 1,000 row groups takes ~10 ms, reading
    one row group ~1 ms: a worker reading the episodes of a file one by one
    parses it once. The file's time and size are part of the key.
    """
    pq = _pyarrow()
    meta = pq.read_metadata(path)
    schema = meta.schema
    col = next(
        (
            i
            for i in range(meta.num_columns)
            if schema.column(i).path == "episode_index"
        ),
        None,
    )
    n = meta.num_row_groups
    lo = np.full(n, np.iinfo(np.int64).min)
    hi = np.full(n, np.iinfo(np.int64).max)  # no statistics: may hold any episode
    if col is not None:
        for i in range(n):
            stats = meta.row_group(i).column(col).statistics
            if stats is not None and stats.has_min_max:
                lo[i], hi[i] = int(stats.min), int(stats.max)
    return meta, lo, hi


def _read_episode_rows(p: Path, episode: int, columns: list[str]):
    """The rows of ``episode`` of a 3.0 file: only the row groups that hold it."""
    import pyarrow.compute as pc

    pq = _pyarrow()
    st = p.stat()
    meta, lo, hi = _row_groups(str(p), st.st_mtime_ns, st.st_size)
    groups = np.flatnonzero((lo <= episode) & (episode <= hi)).tolist()
    table = pq.ParquetFile(p, metadata=meta).read_row_groups(
        groups, columns=[*columns, "episode_index"]
    )
    table = table.filter(pc.equal(table.column("episode_index"), episode))
    return table.select(columns)


def _read_rows(item: LeRobotEpisode, columns: list[str]):
    """The episode's rows of ``columns``: a whole 2.x file, filtered in 3.0."""
    pq = _pyarrow()
    p = item.path
    if not p.is_file():
        raise DataFileError(f"{item}: its data file {p} does not exist")
    try:
        if item.version.lstrip("v").startswith("2."):
            return pq.read_table(p, columns=columns)
        return _read_episode_rows(p, item.episode, columns)
    except (OSError, ValueError, KeyError) as exc:
        import pyarrow as pa

        if isinstance(exc, (pa.ArrowInvalid, KeyError)):
            schema = pq.read_schema(p)
            missing = [c for c in columns if c not in schema.names]
            if missing:
                raise DataFileError(
                    f"{item}: {p} has no column {missing[0]!r}; its columns are"
                    f" {', '.join(schema.names)}"
                ) from None
        raise DataFileError(
            f"{item}: cannot read {p} ({type(exc).__name__}: {exc})"
        ) from None


def read_episode_mapped(
    item: LeRobotEpisode, how, frames=None, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """The demonstration of one episode with the mapping used.

    The reader of :data:`~ndlfd.io._files.READERS` for episodes: ``how`` is
    ``LIBRARY_HINTS`` or ``CLI_HINTS``, ``mapping`` the column mapping options
    (``time_column`` at its default means ``timestamp``), ``frames`` the task
    frames' features (see :func:`read_lerobot`).
    """
    cli = how.get("groups", "").startswith("--")
    example = "{'object': 'observation.object_pose'}"
    sources = check_frame_sources(frames, "--task-frame" if cli else "frames", example)
    extra = [f for f in dict.fromkeys((sources or {}).values()) if f != item.feature]
    try:
        table = _read_rows(item, [_TIME, item.feature, *extra])
    except DataFileError as exc:  # a frame's feature missing: name the frame
        text = str(exc)
        for name, feature in (sources or {}).items():
            text = text.replace(
                f"has no column {feature!r}",
                f"has no column {feature!r} ({frame_flag(how, name)})",
            )
        raise DataFileError(text) from None
    if table.num_rows == 0:
        raise DataFileError(f"{item}: the episode has no rows in {item.path}")
    values = feature_values(table.column(item.feature), item.feature, item.names, item)
    arrays = {_TIME: table.column(_TIME).to_numpy().astype(np.float64)}
    arrays.update((name, values[:, j]) for j, name in enumerate(item.names))
    mapping = dict(mapping)
    tc = mapping.get("time_column", TIME_NAMES)
    if tc is not None and not isinstance(tc, str) and tuple(tc) == TIME_NAMES:
        mapping["time_column"] = _TIME  # the default names: LeRobot's column
    layout = lerobot_layout(item.version, item.feature)
    demo, m = map_arrays(
        item, arrays, how=how, layout=layout, source=str(item), **mapping
    )
    if sources:  # each constant over the episode
        dims = pose_dims(demo.groups)
        demo = demo.with_frames(feature_frame_poses(item, table, sources, dims, how))
    return [(demo, m)]


def read_lerobot(
    root: str | os.PathLike,
    feature: str = "observation.state",
    episodes=None,
    *,
    time_column: str | Sequence[str] | None = _TIME,
    groups: Mapping[str, Sequence[str] | str] | None = None,
    quaternion_order: str = "wxyz",
    drop: Sequence[str] = (),
    euler: str = "xyz",
    bad_rows: str = "error",
    frames: Mapping[str, str] | None = None,
) -> list[Demonstration]:
    """Read the episodes of a LeRobot dataset (layout 2.x or 3.0).

    One demonstration per episode: time from ``timestamp``, values from the
    components of ``feature``, named after ``info.json`` and mapped to groups
    like CSV columns (see :mod:`ndlfd.io._lerobot`). This reads every selected
    episode into memory; to fit from a large dataset, pass
    ``DemoFiles(root, feature=..., episodes=...)`` instead, which reads each
    episode when the fit uses it. Needs the ``lerobot`` extra
    (``pip install "ndlfd[lerobot]"``: pyarrow, not the ``lerobot`` package).

    Parameters
    ----------
    root : str or path-like
        The dataset folder (holding ``meta/info.json``).
    feature : str, default="observation.state"
        The feature read: ``observation.state``, ``action``, ...
    episodes : None, int, slice, sequence of int or str, optional
        Which episodes: all (default), an episode index or a list of them, a
        slice of the episodes in order, or the command line's form ``"0:40"``.
    time_column, groups, quaternion_order, drop, euler
        As in :func:`~ndlfd.io.read_csv` (the time column defaults to
        ``timestamp``).
    bad_rows : {"error", "drop"}, default="error"
        A row with NaN or inf is an error naming it, or (``"drop"``) dropped
        with one :class:`~ndlfd.NdlfdWarning`, as in :func:`~ndlfd.io.read_csv`;
        at least 2 rows must remain in
        each episode.
    frames : mapping of str to str, optional
        Task frames (:attr:`~ndlfd.Demonstration.frames`: where the object or
        the place was), each named after the feature that holds it, e.g.
        ``{"object": "observation.object_pose"}``: a vector of the position
        group's dimension (in 3-D optionally followed by a unit quaternion
        w, x, y, z) that stays within 0.005 (and 3 degrees) of its first row
        over each episode; the frame is its mean.

    Returns
    -------
    demos : list of Demonstration

    Raises
    ------
    DataFileError
        Not a LeRobot dataset, a missing feature (the message lists the
        features there), unknown episodes, an episode that cannot be mapped,
        a frame's feature that is missing, of the wrong size or not constant
        over an episode (the message says how far it moved).
    MissingExtraError
        pyarrow is not installed.
    """
    mapping = {
        "time_column": time_column,
        "groups": groups,
        "quaternion_order": quaternion_order,
        "drop": drop,
        "euler": euler,
        "bad_rows": bad_rows,
        "frames": frames,
    }
    return [
        demo
        for item in lerobot_episodes(root, feature, episodes)
        for demo, _ in read_episode_mapped(item, LIBRARY_HINTS, **mapping)
    ]
