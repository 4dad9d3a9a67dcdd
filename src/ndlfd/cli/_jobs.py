"""The built-in jobs: ``ndlfd demo``, ``ndlfd reproduce`` and ``ndlfd evaluate``."""

from __future__ import annotations

import argparse
import sys

from ..jobs import evaluate, reproduce, run_demo
from ._options import split_names

__all__ = ["add_evaluate", "add_jobs"]


def _cmd_demo(args: argparse.Namespace) -> int:
    run_demo(args.out, quick=args.quick, plot=not args.no_plot, echo=print)
    return 0


def _cmd_reproduce(args: argparse.Namespace) -> int:
    reproduce(args.out, quick=args.quick, echo=print)
    return 0


def add_jobs(sub) -> None:
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


def _cmd_tasks(args: argparse.Namespace) -> int:
    from ..jobs._tasks import evaluate_tasks

    try:
        demos = [int(n) for n in split_names(args.demos, "--demos")]
    except ValueError:
        print(f"ndlfd evaluate: --demos must be whole numbers; got {args.demos!r}",
              file=sys.stderr)  # fmt: skip
        return 2
    result = evaluate_tasks(
        split_names(args.tasks, "--tasks"),
        demos=demos,
        episodes=args.episodes,
        methods=split_names(args.methods, "--methods") if args.methods else None,
        seed=args.seed,
        echo=None if args.quiet else (lambda line: print(line, file=sys.stderr)),
    )
    plots = not args.no_plot
    if plots:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            plots = False
            print('ndlfd evaluate: no figures (install them with: pip install'
                  ' "ndlfd[plot]")', file=sys.stderr)  # fmt: skip
    out = "tasks-evaluation" if args.out == "evaluation" else args.out
    result.write_report(out, plots=plots)
    print(result.to_markdown())
    if not args.quiet:
        print(f"{len(result.rows)} episodes in {result.seconds:.0f} s -> {out}",
              file=sys.stderr)  # fmt: skip
    return 0


def _cmd_evaluate(args: argparse.Namespace) -> int:
    if args.tasks:
        return _cmd_tasks(args)
    protocols = split_names(args.protocols, "--protocols")
    result = evaluate(
        split_names(args.shapes, "--shapes"),
        generators=split_names(args.generators, "--generators"),
        protocols=protocols,
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


def add_evaluate(sub) -> None:
    p = sub.add_parser(
        "evaluate",
        help="leave-one-out evaluation on LASA against ProMP, GMR, DMP and the mean",
        description=(
            "Hold out each demonstration of each LASA shape in turn, fit ndlfd and"
            " the baselines on the others, generate for the held-out timing (time),"
            " also its start (time+start), also its start and middle position as a"
            " via point (via), or with its first 30%% observed (prefix), and"
            " compare: DTW, on-route distance, Frechet, RMSE and endpoint error per"
            " shape range, path-length and turning ratios, via error, prefix jump."
            " Prints the summary tables and"
            " writes results.csv, summary.md and figures to --out. ProMP, GMR and"
            ' DMP need pip install "ndlfd[eval]".'
        ),
    )
    p.add_argument(
        "--shapes",
        help="comma-separated LASA shapes (default: all 30), or the pick-and-place"
        " sets PickPlace, PickPlaceTurned (protocol task: the start, the grasp and"
        " the goal given)",
    )
    p.add_argument(
        "--folds", type=int, help="held-out demonstrations per shape (default: 7)"
    )
    p.add_argument(
        "--protocols",
        help="comma-separated protocols: time, time+start, via, prefix, task,"
        " frames (default: all, task and frames only with a pick-and-place set)",
    )
    p.add_argument(
        "--generators",
        help="comma-separated generators: ndlfd, mean, promp, gmr, dmp (default: all)",
    )
    p.add_argument(
        "--n-jobs", type=int, help="worker processes (-1: one per CPU; default 1)"
    )
    p.add_argument(
        "--tasks",
        help="comma-separated simulated tasks: transfer-cube, insertion (the"
        ' ALOHA scenes of gym-aloha, pip install "ndlfd[sim]"): task success'
        " over held-out object poses instead of the LASA protocols",
    )
    p.add_argument(
        "--demos",
        default="5,10,20,50",
        help="with --tasks: comma-separated numbers of demonstrations (5,10,20,50)",
    )
    p.add_argument(
        "--episodes",
        type=int,
        default=200,
        help="with --tasks: held-out object poses per task (200)",
    )
    p.add_argument(
        "--methods",
        help="with --tasks: comma-separated methods: ndlfd-ee, ndlfd-joint,"
        " object-mean, promp, nearest, promp-joint, nearest-joint (default: all)",
    )
    p.add_argument(
        "--seed", type=int, default=0, help="with --tasks: the seed streams' root (0)"
    )
    p.add_argument(
        "--out",
        default="evaluation",
        help="report folder (evaluation; tasks-evaluation with --tasks)",
    )
    p.add_argument("--no-plot", action="store_true", help="write no figures")
    p.add_argument(
        "-q", "--quiet", action="store_true", help="no progress bar or closing line"
    )
    p.set_defaults(func=_cmd_evaluate)
