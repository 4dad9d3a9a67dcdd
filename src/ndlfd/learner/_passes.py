"""The two passes of :meth:`ndlfd.KeypointHMM.fit` and their map steps.

A fit reads its demonstrations twice (see :mod:`ndlfd.learner._stats`):

1. :func:`scan_ranges`: the groups and columns from the first demonstration,
   then per column the range over all (:class:`~ndlfd.learner.RangeStats`),
   from which the scaler is made;
2. :func:`collect_statistics`: per demonstration normalize, reduce to key
   points, encode them to codebook states and time bins, sum the centroids and
   keep the full values of the templates (:class:`~ndlfd.learner.FitStats`).

The passes take the estimator's parameters (a dict, ``get_params()``) and the
demonstration spec (:mod:`ndlfd.learner._spec`), never the estimator.

Each pass is :func:`ndlfd._parallel.map_reduce` of a map step over chunks of
*items* (a :class:`~ndlfd.Demonstration`, a file path, or a
:class:`~ndlfd.io.DemoFile`), in this thread, on threads, in processes or on
Dask. Errors name the item (``demos[i]``, with its file) they come from.
Only the statistics are kept, never all demonstrations at once (unless the
caller's list holds them), and the model is the same bit for bit serially, on
threads or processes (``n_jobs``: threads for long demonstrations, processes
for short ones, the calling thread for fewer than 256 short ones) or on Dask
(``client``). A worker process started with ``spawn`` imports your script:
guard it with ``if __name__ == "__main__":``.

The demonstrations may be any *re-iterable* (``__iter__`` starts over), for
example one that makes them on demand:

>>> from ndlfd import KeypointHMM, synth
>>> class Lazy:
...     def __iter__(self):
...         for seed in range(12):
...             yield synth.make_dataset("square", n_demos=1,
...                                      random_state=seed)[0][0]
>>> model = KeypointHMM(epsilon=0.1, n_time_bins=20, max_templates=5,
...                     random_state=0).fit(Lazy())
>>> model.n_demos_, model.template_indices_.size
(12, 5)
"""

from __future__ import annotations

import itertools
import os
import threading
from collections.abc import Callable, Iterable, Iterator, Mapping, Sized
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from .._errors import DataFileError, NdlfdError, ValidationError
from .._parallel import check_client, map_reduce
from .._repairs import collecting_repairs, summary_warnings
from ..demonstration import Demonstration
from ..io import DemoFile
from ._exact import scale_exponents
from ._spec import DemoSpec, first_quaternion, frame_spec, prepare, resolve_groups
from ._stats import DemoStats, FitStats, RangeStats, merge_repairs
from ._templates import template_mask

__all__ = ["Scan", "collect_statistics", "scan_ranges"]

_NOT_DEMOS = (
    "demos must be a Demonstration, a list (or any re-iterable) of them, or a list"
    " of file paths"
)


def _as_source(demos):
    """The training set as a re-iterable of items (Demonstrations or file paths)."""
    if isinstance(demos, Demonstration):
        return [demos]
    if isinstance(demos, (str, bytes, os.PathLike)):
        raise ValidationError(
            f"{_NOT_DEMOS}; got the single path {demos!r}. Pass [path] or a list of"
            " files, or read a folder with ndlfd.io.read_demos."
        )
    if isinstance(demos, (np.ndarray, Mapping)) or not isinstance(demos, Iterable):
        raise ValidationError(
            f"{_NOT_DEMOS}; got {type(demos).__name__}. Load files with"
            " ndlfd.io.read_demos."
        )
    if isinstance(demos, Iterator):
        raise ValidationError(
            f"demos is a one-shot iterator ({type(demos).__name__}), but fitting"
            " reads the demonstrations twice (their ranges, then their key"
            " points). Pass a list, a re-iterable (an object whose __iter__ starts"
            " over each time) or a list of file paths."
        )
    return demos


def _file(item):
    """A path or DemoFile item as a DemoFile; None for anything else."""
    if isinstance(item, (str, os.PathLike)):
        return DemoFile(Path(item))
    return item if isinstance(item, DemoFile) else None


def _label(i: int, item) -> str:
    """How errors name an item: ``demos[i]``, with its file; the CLI: the file."""
    f = _file(item)
    if f is None:
        return f"demos[{i}]"
    return str(f.path) if f.hints == "cli" else f"demos[{i}] ({f.path})"


def _read_item(item, i: int, notes: list | None = None) -> list[Demonstration]:
    """The demonstrations of one input item (a Demonstration or a file).

    ``notes`` gets how each demonstration of a file read for the command line
    was read (its :class:`~ndlfd.io.ColumnMapping`).
    """
    if isinstance(item, Demonstration):
        return [item]
    f = _file(item)
    if f is None:
        raise ValidationError(
            f"demos[{i}] must be a Demonstration or a file path; got"
            f" {type(item).__name__}"
        )
    head = "" if f.hints == "cli" else f"demos[{i}]: "
    try:
        pairs = f.read_with_mappings()
    except NdlfdError as exc:  # the message names the file
        raise type(exc)(f"{head}{exc}") from exc
    except (OSError, ValueError) as exc:
        raise DataFileError(
            f"{head}{f.path}: cannot be read ({type(exc).__name__}: {exc})"
        ) from exc
    if not pairs:
        if f.mapping.get("bad_files") == "skip":
            return []  # skipped, and reported as a repair
        raise DataFileError(f"{head}{f.path}: holds no demonstration")
    if notes is not None and f.hints == "cli":
        notes.extend(str(m) for _, m in pairs)
    return [d for d, _ in pairs]


def _where(i: int, item, k: int, n: int) -> str:
    """The label of demonstration ``k`` of the ``n`` of item ``i``."""
    return _label(i, item) + ("" if n == 1 else f", demonstration {k}")


def _located(where: str | Callable[[], str], fn, *args):
    """``fn(*args)``, with errors naming the demonstration they come from.

    ``where`` may be a callable that makes the name: it is called only on an
    error, so the per-demonstration hot path builds no label.
    """
    try:
        return fn(*args)
    except NdlfdError as exc:
        label = where() if callable(where) else where
        raise type(exc)(f"{label}: {exc}") from exc
    except (ValueError, TypeError, ArithmeticError, LookupError) as exc:
        label = where() if callable(where) else where
        raise ValidationError(f"{label}: {type(exc).__name__}: {exc}") from exc


def _changed(what: str) -> ValidationError:
    return ValidationError(
        f"the demonstrations changed between the two passes of fit ({what}); fit"
        " needs a re-iterable that yields the same demonstrations each time"
    )


#: A local fit maps on threads when demonstrations have at least this many
#: samples on average, and on processes otherwise. The per-demonstration work
#: of shorter ones is mostly Python (holding the GIL): on 1,000-sample
#: demonstrations two threads were slower than one and two processes 1.7 to 1.9
#: times faster (benchmarks/RESULTS.md); on 20,000-sample ones threads were 1.3
#: times faster.
_THREAD_MIN_SAMPLES = 5000

#: Bytes of prepared demonstrations (groups selected, velocity derived) that a
#: local fit keeps from the first pass for the second, for the Demonstration
#: objects the caller's list holds anyway (never for files or re-iterables).
_CACHE_BYTES = 256 * 2**20


class _PreparedCache:
    """Prepared demonstrations of pass 1 kept for pass 2, up to a byte budget."""

    def __init__(self, budget: int) -> None:
        self._left = budget
        self._items: dict = {}
        self._lock = threading.Lock()

    def put(self, i: int, demo: Demonstration) -> None:
        size = demo.X.nbytes + demo.t.nbytes
        with self._lock:
            if size <= self._left:
                self._left -= size
                self._items[i] = demo

    def get(self, i: int) -> Demonstration | None:
        with self._lock:
            return self._items.get(i)

    def pop(self, i: int) -> Demonstration | None:
        with self._lock:
            return self._items.pop(i, None)


@dataclass(frozen=True)
class _PassSpec:
    """What the per-demonstration map steps need (sent to the workers)."""

    params: dict  # the estimator's parameters
    demo: DemoSpec = field(default_factory=DemoSpec)
    exponents: np.ndarray | None = None
    templates: np.ndarray | None = None
    cache: _PreparedCache | None = None


def _probe(spec: _PassSpec, unit):
    """Groups and learned columns, from the first demonstration of the first item."""
    i, item = unit
    with collecting_repairs() as log:
        groups, columns, col_groups, n, frames, ref = _probe_item(spec, i, item)
    return groups, columns, col_groups, n, frames, ref, _records(log, i, item)


def _probe_item(spec: _PassSpec, i: int, item):
    demos = _read_item(item, i)
    if not demos:  # a skipped file
        return None, None, None, 0, (), ()
    p = spec.params
    groups = resolve_groups(p["groups"], demos[0], derive_velocity=p["derive_velocity"])
    where = partial(_where, i, item, 0, len(demos))
    d = _located(
        where,
        partial(prepare, derive_velocity=p["derive_velocity"], cli=spec.demo.cli),
        demos[0],
        groups,
    )
    frames = frame_spec(demos[0])
    if spec.cache is not None and isinstance(item, Demonstration):
        spec.cache.put(i, d)
    return groups, d.columns, d.groups, d.n_samples, frames, first_quaternion(d)


def _map_ranges(spec: _PassSpec, chunk) -> RangeStats:
    """Pass 1: per-column min and max of the demonstrations of some items."""
    entries, parts = [], []
    with collecting_repairs() as log:  # one log; each item's part of it
        for i, item in chunk:
            notes: list[str] = []
            seen = len(log)
            arrays = _ranges_of(spec, i, item, notes)
            repairs = _records(log[seen:], i, item)
            if arrays:
                entries.append((i, arrays, notes, repairs))
            else:  # a skipped file
                parts.append(_skipped(i, len(spec.demo.columns), repairs))
    if entries:  # all items read at once: the merge of each one's RangeStats
        parts.append(RangeStats.of_items(entries))
    return parts[0].merge(*parts[1:])


def _ranges_of(spec: _PassSpec, i: int, item, notes: list) -> list[np.ndarray]:
    """The prepared value arrays of item ``i`` (cached or read)."""
    if isinstance(item, Demonstration) and spec.cache is not None:
        d = spec.cache.get(i)  # the first one, from the probe
        if d is None:
            d = _located(f"demos[{i}]", spec.demo.prepared, item)
            spec.cache.put(i, d)
        return [d.X]
    demos = _read_item(item, i, notes)
    return [
        _located(partial(_where, i, item, k, len(demos)), spec.demo.prepared, d).X
        for k, d in enumerate(demos)
    ]


def _skipped(i: int, k: int, repairs: tuple) -> RangeStats:
    """The pass-1 statistics of a skipped file: nothing, in a mergeable form."""
    return RangeStats(
        np.full(k, np.inf),
        np.full(k, -np.inf),
        0,
        np.array([i], dtype=np.int64),
        np.zeros(1, dtype=np.int64),
        min_samples=np.iinfo(np.int64).max,
        shortest_item=i,
        longest_item=i,
        repairs=repairs,
    )


def _records(log: list, i: int, item) -> tuple:
    """An item's repairs (kind, item, label, count), one per kind."""
    if not log:
        return ()
    f = _file(item)
    label = f"demos[{i}]" if f is None else str(f.path)
    counts: dict[str, list] = {}
    for kind, n, detail in log:
        seen = counts.setdefault(kind, [0, detail or label])
        seen[0] += n
    return tuple((kind, i, text, n) for kind, (n, text) in counts.items())


def _stats_of_one(spec: _PassSpec, demo: Demonstration, j: int, d=None) -> DemoStats:
    """Normalize, reduce and encode demonstration ``j``: its part of the statistics."""
    if d is None:
        d = spec.demo.prepared(demo)
    r = spec.demo.encode(d, n_jobs=1)
    template = bool(spec.templates[j])
    return DemoStats(
        j,
        r.values,
        r.tau if template else None,  # read for a template only
        r.keypoints,
        r.key_cells,
        r.key_bins,
        r.n_clipped,
        template,
        spec.demo.frame_values(d),
    )


def _map_statistics(spec: _PassSpec, chunk) -> FitStats:
    """Pass 2: key points, states, bins, centroid sums and templates of some items.

    The repairs of the data are those of pass 1, which reported them.
    """
    with collecting_repairs():
        return _statistics_of(spec, chunk)


def _statistics_of(spec: _PassSpec, chunk) -> FitStats:
    parts = []
    for i, start, expected, item in chunk:
        if spec.cache is not None and isinstance(item, Demonstration):
            d = spec.cache.pop(i)  # prepared in pass 1
            if d is not None:
                where = f"demos[{i}]"
                parts.append(_located(where, _stats_of_one, spec, item, start, d))
                continue
        demos = _read_item(item, i)
        if len(demos) != expected:
            raise _changed(
                f"demos[{i}] held {expected} demonstration(s), now {len(demos)}"
            )
        for k, d in enumerate(demos):
            where = partial(_where, i, item, k, len(demos))
            parts.append(_located(where, _stats_of_one, spec, d, start + k))
    return FitStats.of_demos(parts, exponents=spec.exponents)


def _numbered_items(source, counts: np.ndarray):
    start = 0
    n = 0
    for i, item in enumerate(source):
        if i >= counts.size:
            raise _changed(f"{counts.size} item(s) in the first, more in the second")
        if counts[i] == 0:  # a file skipped in the first pass
            n = i + 1
            continue
        yield i, start, int(counts[i]), item
        start += int(counts[i])
        n = i + 1
    if n != counts.size:
        raise _changed(f"{counts.size} item(s) in the first, {n} in the second")


#: With ``n_jobs=None`` a local fit of short demonstrations (below
#: :data:`_THREAD_MIN_SAMPLES`) uses worker processes only from this many
#: input items on: fewer take well under a second serially.
_PROCESS_MIN_ITEMS = 256


def _workers(n_jobs, mean_length: float, total: int | None) -> tuple[int, str]:
    """(workers, backend) of a local map: threads for long demonstrations.

    The kernels release the GIL, so long demonstrations scale on threads; the
    per-demonstration work of short ones is mostly Python, so they go to
    processes (:mod:`ndlfd._parallel`).
    """
    cpus = os.cpu_count() or 1
    if mean_length >= _THREAD_MIN_SAMPLES:
        return (n_jobs if n_jobs is not None else cpus), "threads"
    if n_jobs is not None:
        return n_jobs, "processes"
    if total is not None and total < _PROCESS_MIN_ITEMS:
        return 1, "threads"
    return cpus, "processes"


@dataclass
class Scan:
    """What pass 1 of a fit found (see :func:`scan_ranges`).

    Attributes
    ----------
    source : iterable
        The training items, to be read again by :func:`collect_statistics`.
    spec : _PassSpec
        The groups and columns, and the parameters of the map steps.
    ranges : RangeStats
        Per-column ranges, demonstrations per item, fewest and most samples.
    total : int or None
        Number of items, when the source is sized.
    run : dict
        ``client`` and ``progress`` of the fit.
    """

    source: Iterable
    spec: _PassSpec
    ranges: RangeStats
    total: int | None
    run: dict[str, Any]


def scan_ranges(params: dict, demos, *, client=None, progress=None) -> Scan:
    """Pass 1 of a fit: groups, columns and per-column ranges.

    Parameters
    ----------
    params : dict
        The estimator's parameters (``KeypointHMM.get_params()``).
    demos : Demonstration, re-iterable of them, or sequence of paths
        As :meth:`KeypointHMM.fit <ndlfd.KeypointHMM.fit>` takes them.
    client, progress
        As in :meth:`KeypointHMM.fit <ndlfd.KeypointHMM.fit>`.

    Returns
    -------
    scan : Scan
    """
    source = _as_source(demos)
    if client is not None:
        client = check_client(client)
    total = len(source) if isinstance(source, Sized) else None
    run = dict(client=client, progress=progress)

    # the groups and columns, from the first demonstration
    items = iter(source)
    try:
        first = next(items)
    except StopIteration:
        raise ValidationError(
            "demos must hold at least one demonstration; got none"
        ) from None
    # the Demonstrations of an in-memory list: keep them prepared between the
    # passes (local fits on threads only; they are in memory anyway)
    local_list = client is None and isinstance(source, (list, tuple))
    spec = _PassSpec(
        params=dict(params),
        demo=DemoSpec(cli=getattr(source, "hints", None) == "cli"),
        cache=_PreparedCache(_CACHE_BYTES) if local_list else None,
    )
    head, probed = [], ()
    while True:  # the first item that is not a skipped file
        at = len(head)
        if client is not None and not isinstance(first, Demonstration):
            probe = client.submit(_probe, spec, (at, first), pure=False).result()
        else:
            probe = _probe(spec, (at, first))
        groups, columns, col_groups, first_length, frames, ref, found = probe
        probed = merge_repairs(probed, found)
        if groups is not None:
            break
        head.append((at, first))
        try:
            first = next(items)
        except StopIteration:
            raise DataFileError(
                f"demos: every one of the {len(head)} file(s) was skipped"
                " (bad_files='skip'); expected at least one readable file"
            ) from None
    workers, backend = _workers(params["n_jobs"], first_length, total)
    spec = replace(
        spec,
        demo=replace(
            spec.demo,
            groups=groups,
            columns=columns,
            col_groups=col_groups,
            derive_velocity=params["derive_velocity"],
            frames=frames,
            quat_ref=ref,
        ),
        cache=None if backend == "processes" and workers > 1 else spec.cache,
    )
    units = itertools.chain(
        head, [(len(head), first)], enumerate(items, start=len(head) + 1)
    )
    del first
    ranges = map_reduce(
        _map_ranges,
        spec,
        units,
        total=total,
        desc="fit 1/2 ranges",
        n_jobs=workers,
        backend=backend,
        **run,
    )
    ranges = replace(ranges, repairs=merge_repairs(probed, ranges.repairs))
    return Scan(source, spec, ranges, total, run)


def collect_statistics(params: dict, done: Scan) -> tuple[DemoSpec, FitStats]:
    """Pass 2 of a fit: the fit statistics, with the scaler of pass 1.

    Parameters
    ----------
    params : dict
        The estimator's parameters. They may differ from those
        :func:`scan_ranges` had only in parameters that pass 1 does not use
        (``n_time_bins``, ``epsilon``, ``n_points``).
    done : Scan
        What pass 1 found.

    Returns
    -------
    spec : DemoSpec
        The learned groups and columns, the scaler, codebook and time bins.
    stats : FitStats
    """
    first, ranges = done.spec, done.ranges
    n_points = params["n_points"]
    if n_points is not None and n_points > ranges.min_samples:
        raise ValidationError(
            f"n_points must be between 2 and {ranges.min_samples}, the number of"
            " samples of the shortest demonstration"
            f" (demos[{ranges.shortest_item}]); got {n_points}"
        )
    demo = first.demo
    spec = DemoSpec.fitted(
        params,
        ranges,
        demo.groups,
        demo.columns,
        demo.col_groups,
        cli=demo.cli,
        frames=demo.frames,
        quat_ref=demo.quat_ref,
    )
    # |u| <= 2**E per column: u is monotone in x, so the extremes bound it
    ends = spec.scaler.transform(
        np.vstack([ranges.data_min, ranges.data_max]), weighted=False
    )
    pass_spec = replace(
        first,
        params=dict(params),
        demo=spec,
        exponents=scale_exponents(np.abs(ends).max(axis=0)),
        templates=template_mask(
            ranges.n_demos, params["max_templates"], params["random_state"]
        ),
    )
    counts = ranges.demos_per_item
    workers, backend = _workers(
        params["n_jobs"], ranges.n_samples / ranges.n_demos, counts.size
    )
    if backend == "processes" and workers > 1:
        pass_spec = replace(
            pass_spec, cache=None
        )  # prepared again there (a lock: local)
    stats = map_reduce(
        _map_statistics,
        pass_spec,
        _numbered_items(done.source, counts),
        total=counts.size,
        desc="fit 2/2 key points",
        n_jobs=workers,
        backend=backend,
        **done.run,
    )
    if stats.n_demos != ranges.n_demos or (
        int(stats.n_samples.sum()) != ranges.n_samples
    ):
        raise _changed(
            f"{ranges.n_demos} demonstration(s) of {ranges.n_samples} samples"
            f" in the first, {stats.n_demos} of {int(stats.n_samples.sum())} in"
            " the second"
        )
    # one warning per kind of repair of the data, at the end of the fit
    summary_warnings([(k, label, n) for k, _, label, n in ranges.repairs])
    return spec, stats
