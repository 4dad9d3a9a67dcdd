"""The ``ndlfd`` command line.

Every sub-command turns an :class:`~ndlfd.NdlfdError` (and a file-system error)
into one line on standard error and exit status 2; outputs are written
atomically, so a failed run never leaves a half-written file behind.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from . import __version__
from ._errors import NdlfdError, ValidationError

__all__ = ["main"]

EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line, like every other error."""

    def error(self, message: str) -> None:  # type: ignore[override]
        """Print one line naming the command and exit with status 2."""
        self.exit(
            EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n"
        )


def _split_names(text: str | None) -> list[str] | None:
    if text is None:
        return None
    names = [s.strip() for s in text.split(",") if s.strip()]
    if not names:
        raise ValidationError(f"expected a comma-separated list of names; got {text!r}")
    return names


def _parse_floats(text: str | None, what: str) -> list[float] | None:
    if text is None:
        return None
    try:
        return [float(s) for s in text.split(",")]
    except ValueError:
        raise ValidationError(
            f"{what} must be comma-separated numbers; got {text!r}"
        ) from None


# --------------------------------------------------------------------- simplify
def _cmd_simplify(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ._simplify import simplify
    from .io import _check_time_column, _read_table_lines, write_table

    columns, data, lines = _read_table_lines(args.input)
    index = {name: i for i, name in enumerate(columns)}
    time_col = args.time_column if args.time_column is not None else "t"
    if time_col not in index:
        if args.time_column is not None:
            raise ValidationError(
                f"{args.input}: time column {time_col!r} not found; the file has"
                f" columns {', '.join(columns)}"
            )
        time_col = None
    else:  # the same check and message as every other reader of a time column
        _check_time_column(Path(args.input), time_col, data[:, index[time_col]], lines)
    wanted = _split_names(args.columns)
    if wanted is None:
        wanted = [c for c in columns if c != time_col]
    missing = [c for c in wanted if c not in index]
    if missing:
        raise ValidationError(
            f"{args.input}: column(s) {', '.join(missing)} not found; the file has"
            f" columns {', '.join(columns)}"
        )
    if not wanted:
        raise ValidationError(
            f"{args.input}: no columns left to simplify besides the time column"
            f" {time_col!r}; pass --columns"
        )
    points = data[:, [index[c] for c in wanted]]
    times = data[:, index[time_col]] if time_col is not None else None
    if args.distance != "sed":
        times = None
    elif times is None:
        raise ValidationError(
            "--distance sed needs a time column; pass --time-column NAME"
        )
    result = simplify(
        points,
        args.epsilon,
        distance=args.distance,
        weights=_parse_floats(args.weights, "--weights"),
        times=times,
        n_points=args.n_points,
        return_mask=args.mask,
    )
    if args.mask:
        out = np.column_stack([data, result.astype(np.int64)])
        write_table(args.output, [*columns, args.mask_column], out)
        kept = int(result.sum())
    else:
        write_table(args.output, columns, data[result])
        kept = int(result.size)
    if not args.quiet:
        print(
            f"kept {kept} of {data.shape[0]} points"
            f" ({100.0 * kept / data.shape[0]:.1f} %) -> {args.output}",
            file=sys.stderr,
        )
    return 0


def _add_simplify(sub) -> None:
    from ._simplify import DISTANCES

    p = sub.add_parser(
        "simplify",
        help="keep the key points of one trajectory (n-D Douglas-Peucker)",
        description=(
            "Read a CSV file with a header row, keep the key points of the chosen"
            " columns by n-dimensional Douglas-Peucker, and write the original rows"
            " (all columns, time included) of the key points."
        ),
    )
    p.add_argument("input", help="CSV file with a header row")
    budget = p.add_mutually_exclusive_group(required=True)
    budget.add_argument(
        "--epsilon",
        type=float,
        help="tolerance: a point is kept when its distance exceeds it",
    )
    budget.add_argument(
        "--n-points",
        type=int,
        help="key-point budget instead of a tolerance (most significant first)",
    )
    p.add_argument(
        "--columns",
        help="comma-separated columns to simplify (default: all but the time column)",
    )
    p.add_argument(
        "--distance",
        default="line",
        choices=DISTANCES.names,
        help="distance to the chord (default: line, the exact perpendicular distance)",
    )
    p.add_argument(
        "--time-column",
        default=None,
        help="name of the time column, strictly increasing (default: 't' when"
        " present); used by 'sed'",
    )
    p.add_argument("--weights", help="comma-separated non-negative column weights")
    p.add_argument(
        "--mask",
        action="store_true",
        help="write every row with a 0/1 column saying whether it is a key point",
    )
    p.add_argument(
        "--mask-column", default="keep", help="name of the --mask column (keep)"
    )
    p.add_argument("-o", "--output", required=True, help="output CSV file")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    p.set_defaults(func=_cmd_simplify)


# ------------------------------------------------------------------ fit/generate
def _parse_mapping(text: str | None, what: str, cast) -> dict | None:
    """Parse ``name=value,name=value`` (a bare value applies to every group)."""
    if text is None:
        return None
    out = {}
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        if "=" not in part:
            raise ValidationError(
                f"{what} must look like position=20,velocity=10; got {text!r}"
            )
        key, _, value = part.partition("=")
        try:
            out[key.strip()] = cast(value.strip())
        except ValueError:
            raise ValidationError(
                f"{what}: {value.strip()!r} is not a valid number in {text!r}"
            ) from None
    return out


def _progress(iterable, total: int, desc: str):
    """Wrap ``iterable`` in a progress bar on a terminal (silent otherwise)."""
    from tqdm import tqdm

    bar = dict(desc=desc, unit="file", disable=None, leave=False)
    return tqdm(iterable, total=total, **bar)


def _cmd_fit(args: argparse.Namespace) -> int:
    import time

    from .io import demo_files, read_demos
    from .learner import KeypointHMM

    paths = demo_files(args.demos)
    demos = [read_demos(p)[0] for p in _progress(paths, len(paths), "reading demos")]
    levels = args.levels
    if levels is not None:
        levels = (
            int(levels)
            if levels.strip().isdigit()
            else _parse_mapping(levels, "--levels", int)
        )
    given = {"epsilon": args.epsilon, "n_time_bins": args.time_bins}
    model = KeypointHMM(
        groups=_split_names(args.groups),
        levels=levels,
        **{k: v for k, v in given.items() if v is not None},
        n_points=args.n_points,
        distance=args.distance,
        normalization=args.normalization,
        weights=_parse_mapping(args.weights, "--weights", float),
        pseudo_emission=args.pseudo_emission,
        start=args.start,
        generation=args.generation,
        decoder=args.decoder,
    )
    t0 = time.perf_counter()
    model.fit(demos)
    elapsed = time.perf_counter() - t0
    model.save(args.output)
    if not args.quiet:
        k = model.n_keypoints_
        print(
            f"fitted {len(demos)} demonstration(s) in {elapsed:.2f} s: key points"
            f" {k.min()}-{k.max()} (median {int(np.median(k))}),"
            f" {model.n_states_used_} of {model.codebook_.n_states} states used"
            f" -> {args.output}",
            file=sys.stderr,
        )
    return 0


def _cmd_generate(args: argparse.Namespace) -> int:
    from .io import read_demos, write_csv
    from .learner import KeypointHMM

    model = KeypointHMM.load(args.model)
    if args.like is not None:
        if args.duration is not None or args.samples is not None:
            raise ValidationError(
                "pass either --like or --duration/--samples, not both"
            )
        timing = read_demos(args.like)[0]
    else:
        if args.duration is None:
            raise ValidationError("pass --like FILE or --duration SECONDS")
        if not (args.duration > 0 and np.isfinite(args.duration)):
            raise ValidationError(f"--duration must be > 0; got {args.duration}")
        n = args.samples if args.samples is not None else 1000
        if n < 2:
            raise ValidationError(f"--samples must be >= 2; got {n}")
        timing = np.linspace(0.0, args.duration, n)
    start = _parse_floats(args.start, "--start")
    goal = _parse_floats(args.goal, "--goal")
    path = model.generate(
        timing,
        dense=args.dense,
        start=None if start is None else {"position": start},
        goal=None if goal is None else {"position": goal},
    )
    write_csv(path, args.output)
    if not args.quiet:
        print(
            f"generated {path.n_samples} {'samples' if args.dense else 'key points'}"
            f" -> {args.output}",
            file=sys.stderr,
        )
    return 0


def _add_fit(sub) -> None:
    from ._simplify import DISTANCES
    from .learner import DECODERS, GENERATIONS, NORMALIZATIONS, STARTS, KeypointHMM

    p = sub.add_parser(
        "fit",
        help="learn a model from demonstration files",
        description=(
            "Learn key points, codebook states and a discrete HMM from"
            " demonstration files (CSV or NPZ; a directory means all its files)."
        ),
    )
    p.add_argument("demos", nargs="+", help="CSV/NPZ files, directories or globs")
    p.add_argument("-o", "--output", required=True, help="model file to write")
    p.add_argument(
        "--groups",
        default="position,velocity",
        help="comma-separated groups to learn (default: position,velocity;"
        " a missing velocity is derived from position)",
    )
    budget = p.add_mutually_exclusive_group()
    defaults = KeypointHMM()
    budget.add_argument(
        "--epsilon",
        type=float,
        help=f"reduction tolerance (default {defaults.epsilon})",
    )
    budget.add_argument("--n-points", type=int, help="key points per demonstration")
    p.add_argument("--distance", default="line", choices=DISTANCES.names)
    p.add_argument(
        "--levels",
        help="codebook levels, e.g. position=20,velocity=10 or one number for all",
    )
    p.add_argument(
        "--time-bins",
        type=int,
        help=f"number of time symbols (default {defaults.n_time_bins})",
    )
    p.add_argument("--normalization", default="group", choices=NORMALIZATIONS.names)
    p.add_argument("--weights", help="per-group weights, e.g. velocity=0.5")
    p.add_argument(
        "--pseudo-emission", type=float, default=0.0, help="emission pseudo-count"
    )
    p.add_argument("--start", default="learned", choices=STARTS.names)
    p.add_argument(
        "--generation",
        default="blend",
        choices=GENERATIONS.names,
        help="blend (default: decoded key points, demonstrations aligned and"
        " blended) or paper (the paper's procedure)",
    )
    p.add_argument(
        "--decoder",
        default="viterbi",
        choices=DECODERS.names,
        help="viterbi (most likely sequence) or map (most likely state per step)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    p.set_defaults(func=_cmd_fit)


def _add_generate(sub) -> None:
    p = sub.add_parser(
        "generate",
        help="generate a path from a model and a new timing",
        description=(
            "Decode a new timing with a fitted model and write the generated path"
            " (key points, or every sample with --dense) as CSV."
        ),
    )
    p.add_argument("model", help="model file written by 'ndlfd fit'")
    p.add_argument("--like", help="a test demonstration whose timing is used")
    p.add_argument(
        "--start",
        metavar="X,Y[,Z]",
        help="where the robot starts (position): the path begins there and"
        " follows the demonstrations that start nearby",
    )
    p.add_argument(
        "--goal",
        metavar="X,Y[,Z]",
        help="where the path must end (position)",
    )
    p.add_argument("--duration", type=float, help="duration of a uniform time grid")
    p.add_argument(
        "--samples", type=int, help="samples of the uniform time grid (1000)"
    )
    p.add_argument(
        "--dense",
        action="store_true",
        help="interpolate to every time stamp instead of writing key points",
    )
    p.add_argument("-o", "--output", required=True, help="output CSV file")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    p.set_defaults(func=_cmd_generate)


def _cmd_demo(args: argparse.Namespace) -> int:
    from .experiments import run_demo

    run_demo(args.out, quick=args.quick, plot=not args.no_plot, echo=print)
    return 0


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from .reproduction import reproduce

    reproduce(args.out, quick=args.quick, echo=print)
    return 0


def _add_jobs(sub) -> None:
    p = sub.add_parser(
        "demo",
        help="learn and generate on built-in data, with a figure",
        description=(
            "The main job on built-in data: learn from the paper's synthetic 2-D"
            " square (100 noisy demonstrations with velocity) and, when the 'lasa'"
            " extra is installed, one LASA handwriting shape; generate the path for"
            " a test demonstration, write CSV files and a figure, print a summary."
        ),
    )
    p.add_argument("--out", default="demo-output", help="output folder")
    p.add_argument("--quick", action="store_true", help="fewer demonstrations")
    p.add_argument("--no-plot", action="store_true", help="write no figure")
    p.set_defaults(func=_cmd_demo)
    p = sub.add_parser(
        "reproduce",
        help="reproduce the paper's experiments (figures and report.md)",
        description=(
            "Re-run analogues of the paper's Fig. 2, 3, 5 and 6 and write one PNG"
            " per figure and report.md (our numbers beside the paper's)."
        ),
    )
    p.add_argument("--out", default="reproduction", help="output folder")
    p.add_argument("--quick", action="store_true", help="reduced sizes (tests)")
    p.set_defaults(func=_cmd_reproduce)


# --------------------------------------------------------------------- evaluate
def _cmd_evaluate(args: argparse.Namespace) -> int:
    from .evaluation import evaluate

    protocols = _split_names(args.protocols)
    result = evaluate(
        _split_names(args.shapes),
        generators=_split_names(args.generators),
        protocols=protocols if protocols is not None else ("time", "time+start"),
        folds=args.folds,
        n_jobs=args.n_jobs,
        progress=False if args.quiet else None,
    )
    plots = not args.no_plot
    if plots:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            plots = False
            print(
                "ndlfd evaluate: no figures (install them with: pip install"
                ' "ndlfd[plot]")',
                file=sys.stderr,
            )
    result.write_report(args.out, plots=plots)
    print(result.to_markdown())
    if not args.quiet:
        print(
            f"{len(result.rows)} rows, {len(result.failures)} failed, in"
            f" {result.seconds:.0f} s -> {args.out}",
            file=sys.stderr,
        )
    return 0


def _add_evaluate(sub) -> None:
    p = sub.add_parser(
        "evaluate",
        help="leave-one-out evaluation on LASA against ProMP, GMR, DMP and the mean",
        description=(
            "Hold out each demonstration of each LASA shape in turn, fit ndlfd and"
            " the baselines on the others, generate for the held-out timing (and"
            " start), and compare: DTW, Frechet, RMSE and endpoint error per shape"
            " range, path-length and turning ratios. Prints the summary tables and"
            " writes results.csv, summary.md and figures to --out. ProMP, GMR and"
            ' DMP need pip install "ndlfd[eval]".'
        ),
    )
    p.add_argument("--shapes", help="comma-separated LASA shapes (default: all 30)")
    p.add_argument(
        "--folds", type=int, help="held-out demonstrations per shape (default: 7)"
    )
    p.add_argument(
        "--protocols",
        help="comma-separated protocols: time, time+start (default: both)",
    )
    p.add_argument(
        "--generators",
        help="comma-separated generators: ndlfd, mean, promp, gmr, dmp (default: all)",
    )
    p.add_argument(
        "--n-jobs", type=int, help="worker processes (-1: one per CPU; default 1)"
    )
    p.add_argument("--out", default="evaluation", help="report folder (evaluation)")
    p.add_argument("--no-plot", action="store_true", help="write no figures")
    p.add_argument(
        "-q", "--quiet", action="store_true", help="no progress bar or closing line"
    )
    p.set_defaults(func=_cmd_evaluate)


# ------------------------------------------------------------------------ main
def build_parser() -> argparse.ArgumentParser:
    """Build the ``ndlfd`` argument parser with all sub-commands."""
    parser = _Parser(
        prog="ndlfd",
        description=(
            "Learn robot paths from demonstrations: n-dimensional Douglas-Peucker"
            " key points, a codebook of discrete states, a supervised discrete HMM"
            " and Viterbi generation."
        ),
    )
    parser.add_argument("--version", action="version", version=f"ndlfd {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    _add_simplify(sub)
    _add_fit(sub)
    _add_generate(sub)
    _add_jobs(sub)
    _add_evaluate(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``ndlfd`` command line; return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return EXIT_USAGE
    try:
        return int(args.func(args) or 0)
    except NdlfdError as exc:
        print(f"ndlfd {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        print(f"ndlfd {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"ndlfd {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
