"""Many demonstrations: folders, glob patterns and lists; dispatch by suffix."""

from __future__ import annotations

import glob
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

from .._errors import DataFileError, ValidationError
from .._repairs import collecting_repairs, repaired, summary_warnings
from ..demonstration import Demonstration
from ._bag import BAG_OPTIONS, BAG_SUFFIXES, is_bag_folder, read_bag_mapped
from ._csv import read_csv_mapped
from ._hdf5 import HDF5_SUFFIXES, read_hdf5_mapped
from ._lerobot import (
    DATASET_DEFAULTS,
    LeRobotEpisode,
    is_lerobot_dataset,
    lerobot_episodes,
    read_episode_mapped,
)
from ._mapping import (
    CLI_HINTS,
    LIBRARY_HINTS,
    MAPPING_DEFAULTS,
    TIME_NAMES,
    ColumnMapping,
    RateMapping,
    check_bad_rows,
)
from ._npy import NPY_OPTIONS, read_npy_mapped
from ._npz import read_npz_mapped
from ._parquet import read_parquet_mapped

__all__ = [
    "BAD_FILES",
    "DEMO_SUFFIXES",
    "RATE_OPTIONS",
    "READERS",
    "READER_OPTIONS",
    "READ_DEFAULTS",
    "DemoFile",
    "DemoFiles",
    "RateMapping",
    "demo_files",
    "read_demos",
    "read_file",
    "read_or_skip",
]

#: The file suffixes (any case) that a folder given to :func:`read_demos`
#: contributes (besides its sub-folders that are ROS 2 bags).
DEMO_SUFFIXES = (".csv", ".tsv", ".npz", ".npy", ".h5", ".hdf5", *BAG_SUFFIXES)


def demo_files(source, **dataset) -> list[Path | LeRobotEpisode]:
    """The files :func:`read_demos` reads from ``source``, in that order.

    Parameters
    ----------
    source : str, path-like or list of them
        A folder (its ``.csv``, ``.tsv``, ``.npz``, ``.npy``, ``.h5``, ``.hdf5``,
        ``.mcap`` and ``.db3`` files, in any case, and its sub-folders that are
        ROS 2 bags, sorted), a ROS 2 bag folder (one source), a LeRobot dataset
        folder (one item per episode), a glob pattern (its matches, sorted), a
        file, or a list of these.
    **dataset
        ``feature`` and ``episodes``: what a LeRobot dataset contributes (see
        :func:`~ndlfd.io.read_lerobot`).

    Returns
    -------
    paths : list of Path or LeRobotEpisode

    Examples
    --------
    >>> demo_files(["a.csv", "b.npz"])
    [PosixPath('a.csv'), PosixPath('b.npz')]
    """
    return _expand(source, _checked_dataset("demo_files", dataset))


def _checked_dataset(who: str, dataset: dict) -> dict:
    unknown = sorted(set(dataset) - set(DATASET_DEFAULTS))
    if unknown:
        raise ValidationError(
            f"{who} got unexpected argument(s) {unknown}; expected"
            f" {', '.join(DATASET_DEFAULTS)}"
        )
    return {**DATASET_DEFAULTS, **dataset}


def _expand(source, dataset=DATASET_DEFAULTS) -> list:
    if isinstance(source, (str, os.PathLike)):
        p = Path(source)
        if is_lerobot_dataset(p):
            return lerobot_episodes(p, **dataset)
        if p.is_dir() and not is_bag_folder(p):
            found = sorted(
                q
                for q in p.iterdir()
                if (q.is_file() and q.suffix.lower() in DEMO_SUFFIXES)
                or is_bag_folder(q)
            )
            if not found:
                raise DataFileError(
                    f"{p}: expected .csv, .tsv, .npz, .npy, .h5, .hdf5, .mcap or .db3"
                    " files or ROS 2 bag folders in the folder (any case); found"
                    " none"
                )
            return found
        s = os.fspath(source)
        if glob.has_magic(s):
            found = sorted(
                Path(q)
                for q in glob.glob(s)
                if Path(q).is_file() or is_bag_folder(Path(q))
            )
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
            out.extend(_expand(item, dataset))
        if not out:
            raise DataFileError("expected at least one file; got an empty list")
        return out
    raise ValidationError(
        "source must be a file, a folder, a glob pattern or a list of paths; got"
        f" {type(source).__name__}"
    )


#: Which reader takes a file, by its suffix (any case); a file of any other
#: suffix is read as CSV, a ROS 2 bag folder as a bag. A reader is called
#: ``reader(path, hints, **mapping)`` and gives a list of (Demonstration,
#: ColumnMapping): see :mod:`ndlfd.io`.
READERS = {
    ".npz": read_npz_mapped,
    ".npy": read_npy_mapped,
    ".parquet": read_parquet_mapped,
    **dict.fromkeys(HDF5_SUFFIXES, read_hdf5_mapped),
    **dict.fromkeys(BAG_SUFFIXES, read_bag_mapped),
}

#: The options that only some readers take (a bag's ``topic``, ``frame`` and
#: ``split_gap``; the ``frames`` of a bag or a LeRobot episode: topics or
#: features, see :func:`~ndlfd.io.read_bag`), with their defaults, by reader.
#: :class:`DemoFiles` and :func:`read_demos` accept them besides the column
#: mapping and give each reader those it takes (a CSV file in the same folder
#: as a bag ignores them).
READER_OPTIONS = {
    read_bag_mapped: BAG_OPTIONS,
    read_episode_mapped: {"frames": None},
    read_npy_mapped: NPY_OPTIONS,
    read_hdf5_mapped: {"feature": None},  # an ALOHA episode's (given, not default)
}

#: Mapping options that readers with a fixed signature (a bag's) do not take:
#: given to a reader only when set.
_WHEN_SET = ("representation",)


#: What ``bad_files`` may be: ``"error"`` (a file that cannot be read stops
#: the reading with its error) or ``"skip"`` (it is left out, with a warning
#: saying which and why: one summary per fit).
BAD_FILES = ("error", "skip")

#: The options of reading many files (not given to the readers).
READ_DEFAULTS = {"bad_files": "error"}

#: The option of files without time stamps: their sample rate in Hz (the
#: time of row ``k`` is ``k / rate``); given to no reader.
RATE_OPTIONS = {"rate": None}


def _rate_flag(how) -> str:
    return "--rate" if how.get("time", "").startswith("--") else "rate="


def _at_rate(p, how, reader, options: dict, rate) -> list:
    """Read ``p`` without a time column; row ``k`` at ``k / rate`` seconds."""
    flag = _rate_flag(how)
    if not (
        isinstance(rate, (int, float))
        and not isinstance(rate, bool)
        and math.isfinite(rate)
        and rate > 0
    ):
        raise ValidationError(f"{flag} must be a sample rate in Hz > 0; got {rate!r}")
    if reader in (read_bag_mapped, read_episode_mapped, read_parquet_mapped):
        raise DataFileError(
            f"{p}: {flag} gives the time of files without time stamps (a fixed-rate"
            " log); this one has its own stamps"
        )
    if options.get("bad_rows") == "drop":
        raise ValidationError(
            f"{flag} times the rows by their number, and dropping a bad row would"
            " shift every later row's time; pass bad_rows='error' (--bad-rows"
            " error) and repair the file"
        )
    if isinstance(options.get("time_column"), str):
        raise ValidationError(
            f"{flag} and {how['time']} both give the time; pass one of them"
        )

    def timed(name):
        return DataFileError(
            f"{p}: {flag} gives the time of files without time stamps; this one"
            f" has a time column {name!r} (name it with {how['time']} instead of"
            f" {flag}, or drop it)"
        )

    try:
        pairs = reader(p, how, **{**options, "time_column": None})
    except DataFileError:
        try:  # a time column the mapping could not place?
            with collecting_repairs():
                found = reader(p, how, **options)
        except (DataFileError, ValidationError):
            found = []
        if found:
            raise timed(found[0][1].time) from None
        raise
    out = []
    for demo, m in pairs:
        names = [c for _, cols in m.groups for c in cols]
        clock = [c for c in names if c.casefold() in TIME_NAMES]
        if clock:
            raise timed(clock[0])
        demo = Demonstration(demo.t / rate, demo.X, demo.columns, demo.groups)
        out.append((demo, RateMapping(**asdict(m), rate=float(rate))))
    return out


def read_or_skip(
    p: Path | LeRobotEpisode, how=LIBRARY_HINTS, *, read=None, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """:func:`read_file`, or nothing for a bad file with ``bad_files="skip"``.

    A skipped file is reported as a repair (:mod:`ndlfd._repairs`): which file
    and why. ``read`` (``read(p, how, **mapping)``) reads instead of
    :func:`read_file` (the CLI's task-frame columns).
    """
    read = read_file if read is None else read
    if mapping.get("bad_files", "error") != "skip":
        return read(p, how, **mapping)
    try:
        pairs = read(p, how, **mapping)
    except (DataFileError, ValidationError, OSError, ValueError) as exc:
        why = str(exc)
        text = why if why.startswith(str(p)) else f"{p}: {why}"
        repaired("files", 1, f"skipped {text}", detail=text, stacklevel=3)
        return []
    if not pairs:
        repaired(
            "files",
            1,
            f"skipped {p}: holds no demonstration",
            detail=f"{p}: holds no demonstration",
            stacklevel=3,
        )
    return pairs


def read_file(
    p: Path | LeRobotEpisode, how=LIBRARY_HINTS, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """Every demonstration of one file with the mapping used, by its suffix.

    Parameters
    ----------
    p : Path or LeRobotEpisode
        The file (or an episode of a LeRobot dataset).
    how : dict, default=LIBRARY_HINTS
        How error messages name the settings (``CLI_HINTS``: the flags).
    **mapping
        ``time_column``, ``groups``, ``quaternion_order``, ``drop``: see
        :func:`~ndlfd.io.read_csv` (all of them: see ``MAPPING_DEFAULTS``).

    Returns
    -------
    pairs : list of (Demonstration, ColumnMapping)
    """
    if isinstance(p, LeRobotEpisode):
        reader = read_episode_mapped
    elif is_bag_folder(p):
        reader = read_bag_mapped
    else:
        reader = READERS.get(p.suffix.lower(), read_csv_mapped)
    own = READER_OPTIONS.get(reader, {})
    options = {
        k: v
        for k, v in mapping.items()
        if (k in MAPPING_DEFAULTS or k in own) and not (k in _WHEN_SET and v is None)
    }
    if reader is read_bag_mapped and options.get("representation") is not None:
        raise DataFileError(
            f"{p}: a representation of the orientation is for files of columns;"
            " a bag gives its orientation as quaternions"
        )
    if mapping.get("rate") is not None:
        return _at_rate(p, how, reader, options, mapping["rate"])
    return reader(p, how, **options)


def read_demos(source, *, return_mappings: bool = False, **kwargs):
    """Read many demonstrations: a folder, a glob pattern, a file or a list.

    A folder gives its ``.csv``, ``.tsv``, ``.npz``, ``.npy``, ``.h5``,
    ``.hdf5``, ``.mcap`` and ``.db3`` files (any case) and its ROS 2 bag
    folders in sorted order, a LeRobot dataset folder its episodes
    (``feature=``, ``episodes=``: see :func:`read_lerobot`); a glob pattern
    its matches, sorted. ``.npz`` files are read with :func:`read_npz`,
    ``.npy`` with :func:`read_npy` (``columns=``, else each file's sidecar
    ``NAME.columns.txt``), ``.h5``/``.hdf5`` with :func:`read_hdf5` (one
    demonstration per episode), bags with :func:`~ndlfd.io.read_bag`,
    everything else with :func:`read_csv`; each gets the same column mapping
    (``kwargs``).

    Parameters
    ----------
    source : str, path-like or list of them
        Where the demonstrations are.
    return_mappings : bool, default=False
        Also return the :class:`ColumnMapping` of each demonstration.
    **kwargs
        ``time_column``, ``groups``, ``quaternion_order``, ``drop``, ``euler``,
        ``representation``: see :func:`read_csv`; ``columns``: the names of
        the columns of ``.npy`` files (:func:`read_npy`); for bags also
        ``topic``, ``frame``, ``base_frame``, ``split_gap``, ``split_still``,
        ``frames`` (see :func:`~ndlfd.io.read_bag`); ``feature``,
        ``episodes``, and ``frames`` of a dataset: see :func:`read_lerobot`;
        ``rate``: the sample rate in Hz of files without time stamps
        (fixed-rate logs: CSV, ``.npz``, ``.npy`` or HDF5 without a time
        column), row ``k`` at ``k / rate`` seconds; an error for a file with
        a time column or its own stamps (a bag, a LeRobot episode), and with
        ``bad_rows="drop"`` (a dropped row would shift the later rows' times).

    Returns
    -------
    demos : list of Demonstration
    mappings : list of ColumnMapping
        Only with ``return_mappings=True`` (a :class:`RateMapping` with
        ``rate``).

    Raises
    ------
    DataFileError
        No file found, or a file that cannot be read.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> from ndlfd.io import write_csv, write_npz
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]])
    >>> _ = write_csv(d, folder / "a.csv"); _ = write_npz(d, folder / "b.npz")
    >>> [x == d for x in read_demos(folder)]
    [True, True]
    >>> _, maps = read_demos(folder / "a.csv", return_mappings=True)
    >>> print(maps[0])
    time=t; position=x,y
    """
    dataset = {k: kwargs.pop(k) for k in DATASET_DEFAULTS if k in kwargs}
    mapping = _with_feature(
        _checked_mapping("read_demos", kwargs, "or return_mappings"), dataset
    )
    items = _expand(source, _checked_dataset("read_demos", dataset))
    pairs, records = [], []
    for p in items:
        with collecting_repairs() as log:
            pairs.extend(read_or_skip(p, **mapping))
        records.extend(_summed(log, p))
    summary_warnings(records)
    if not pairs:
        raise DataFileError(
            f"{source}: expected at least one readable demonstration; every file"
            " was skipped (bad_files='skip')"
        )
    demos = [d for d, _ in pairs]
    if return_mappings:
        return demos, [m for _, m in pairs]
    return demos


def _summed(log, p) -> list[tuple[str, str, int]]:
    """The repairs made reading file ``p``: one summary record per kind."""
    counts: dict[str, list] = {}
    for kind, n, detail in log:
        counts.setdefault(kind, [0, detail or str(p)])[0] += n
    return [(kind, text, n) for kind, (n, text) in counts.items()]


def _checked_mapping(who: str, kwargs: dict, more: str = "") -> dict:
    """The column mapping options with their defaults; unknown names refused."""
    known = {**MAPPING_DEFAULTS, **READ_DEFAULTS, **RATE_OPTIONS}
    for options in READER_OPTIONS.values():
        known.update(options)
    unknown = sorted(set(kwargs) - set(known))
    if unknown:
        raise ValidationError(
            f"{who} got unexpected argument(s) {unknown}; expected"
            f" {', '.join([*known, *DATASET_DEFAULTS])} {more}".rstrip()
        )
    if kwargs.get("bad_files", "error") not in BAD_FILES:
        raise ValidationError(
            f"bad_files must be one of {', '.join(map(repr, BAD_FILES))}; got"
            f" {kwargs['bad_files']!r}"
        )
    check_bad_rows(kwargs.get("bad_rows", "error"))
    return {**MAPPING_DEFAULTS, **READ_DEFAULTS, **RATE_OPTIONS, **kwargs}


def _with_feature(mapping: dict, dataset: dict) -> dict:
    """``mapping`` with the ``feature`` given: an ALOHA HDF5 episode's too.

    A LeRobot dataset's default (``observation.state``) is not passed on: an
    ALOHA episode file gives its action unless a feature is named.
    """
    if dataset.get("feature") is not None:
        return {**mapping, "feature": dataset["feature"]}
    return mapping


@dataclass(frozen=True)
class DemoFile:
    """One data file and how to read it: an item of :class:`DemoFiles`.

    It is read only when :meth:`read` is called (on whichever worker maps it
    in :meth:`KeypointHMM.fit <ndlfd.KeypointHMM.fit>`).

    Attributes
    ----------
    path : Path or LeRobotEpisode
        The file, or an episode of a LeRobot dataset.
    mapping : dict
        ``time_column``, ``groups``, ``quaternion_order`` and ``drop`` (see
        :func:`read_csv`).
    """

    path: Path | LeRobotEpisode
    mapping: dict = field(default_factory=lambda: dict(MAPPING_DEFAULTS))
    #: How error messages name the settings: ``"library"`` (parameters) or
    #: ``"cli"`` (the command line's flags).
    hints: str = field(default="library", repr=False)

    def read(self) -> list[Demonstration]:
        """The file's demonstrations (several for an HDF5 file of episodes)."""
        return [d for d, _ in self.read_with_mappings()]

    def read_with_mappings(self) -> list[tuple[Demonstration, ColumnMapping]]:
        """The file's demonstrations, each with the :class:`ColumnMapping` used."""
        how = CLI_HINTS if self.hints == "cli" else LIBRARY_HINTS
        return read_or_skip(self.path, how, **self.mapping)


class DemoFiles(Sequence):
    """The data files of a folder, glob pattern or list, read lazily.

    A sequence of :class:`DemoFile` (a file and the column mapping to read it
    with) that holds no data: pass it to :meth:`KeypointHMM.fit
    <ndlfd.KeypointHMM.fit>` to fit from files that do not fit in memory
    together; each pass reads each file once, on the worker that maps it.

    Parameters
    ----------
    source : str, path-like or list of them
        As :func:`read_demos` takes it (a folder, a glob pattern, files, a
        LeRobot dataset: one item per episode).
    **mapping
        ``time_column``, ``groups``, ``quaternion_order``, ``drop``,
        ``euler``: see :func:`read_csv`; ``feature``, ``episodes``: what a
        LeRobot dataset contributes (see :func:`read_lerobot`).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from ndlfd import KeypointHMM, synth
    >>> from ndlfd.io import write_csv
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
        dataset = {k: mapping.pop(k) for k in DATASET_DEFAULTS if k in mapping}
        self._mapping = _with_feature(_checked_mapping("DemoFiles", mapping), dataset)
        self.hints = "library"
        self.paths = tuple(_expand(source, _checked_dataset("DemoFiles", dataset)))

    @classmethod
    def for_cli(cls, paths, **mapping) -> DemoFiles:
        """The files ``paths`` as given (not expanded), read for the command line.

        Error messages name the command line's flags (``--group``, ...)
        instead of the parameters.

        Parameters
        ----------
        paths : sequence of path-like
            The files (as :func:`demo_files` gives them).
        **mapping
            As for :class:`DemoFiles`.

        Returns
        -------
        files : DemoFiles
        """
        files = cls.__new__(cls)
        files._mapping = _checked_mapping("DemoFiles", mapping)
        files.hints = "cli"
        files.paths = tuple(paths)
        return files

    def __len__(self) -> int:
        return len(self.paths)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return DemoFile(self.paths[i], dict(self._mapping), self.hints)

    def __repr__(self) -> str:
        return f"DemoFiles({len(self)} files, first {str(self.paths[0])!r})"
