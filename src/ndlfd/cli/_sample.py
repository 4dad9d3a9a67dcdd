"""``ndlfd sample``: paths drawn from a fitted model, one CSV each."""

from __future__ import annotations

import argparse
from pathlib import Path

from .._errors import ValidationError
from ..io import write_csv
from ._conditions import (
    add_condition_options,
    load_with_conditions,
    output_mapping,
    read_observed,
)
from ._generate import FLOAT_FORMAT
from ._limits import add_limit_options, apply_limits, parse_limits
from ._options import (
    add_column_options,
    add_timing_options,
    check_range,
    check_timing,
    read_timing,
    say,
)

__all__ = ["MAX_DRAWS", "add_sample"]

#: Most paths one ``ndlfd sample`` draws.
MAX_DRAWS = 100_000


def _cmd_sample(args: argparse.Namespace) -> int:
    folder = Path(args.output)
    if folder.exists() and not folder.is_dir():
        raise ValidationError(f"-o {folder}: is a file; expected a folder")
    if not folder.parent.exists():
        raise ValidationError(
            f"-o {folder}: its parent folder {folder.parent} does not exist"
        )
    check_range(args.n, "-n", low=1, high=MAX_DRAWS)
    n = check_timing(args)
    model, start, goal, via, frames = load_with_conditions(args)
    timing, like = read_timing(args, n)
    prefix, timing, observed_map = read_observed(args, timing)
    like = output_mapping(model, like, observed_map)
    paths = model.sample(
        timing,
        args.n,
        dense=not args.key_points,
        start=start,
        goal=goal,
        via=via,
        observed=prefix,
        random_state=args.random_state,
        frames=frames,
    )
    folder.mkdir(exist_ok=True)
    dense = not args.key_points or prefix is not None  # a continuation: all
    exact_time = (
        (args.like is not None or args.rate is not None) and dense
    ) or prefix is not None
    drawn = paths
    paths = [apply_limits(args, path, dense=dense, std=None, prefix=prefix,
                          report=False) for path in drawn]  # fmt: skip
    slowed = sum(a is not b for a, b in zip(paths, drawn, strict=True))
    if parse_limits(args) is not None:
        exact_time = exact_time and (
            slowed == 0 or args.rate is not None or prefix is not None
        )
        say(args, f"slowed down {slowed} of {len(paths)} path(s) to the limits")
    digits = max(3, len(str(args.n - 1)))
    for k, path in enumerate(paths):
        write_csv(
            path,
            folder / f"sample_{k:0{digits}d}.csv",
            float_format=FLOAT_FORMAT,
            time_format=None if exact_time else FLOAT_FORMAT,
            mapping=like,
        )
    what = "samples" if dense else "key points"
    if prefix is not None:
        what += f", each continuing the {prefix.n_samples} observed"
    say(args, f"drew {len(paths)} path(s) of {what} -> {folder}/sample_*.csv")
    return 0


def add_sample(sub) -> None:
    p = sub.add_parser(
        "sample",
        help="draw paths from a model: one CSV per path",
        description=(
            "Draw paths from a fitted model for a new timing (KeypointHMM.sample):"
            " each on one route of the demonstrations, routes in proportion to"
            " their weight, varying within a route about as the demonstrations"
            " do. Writes FOLDER/sample_000.csv, ... (every time stamp, numbers"
            " with ten significant digits, the time stamps of --like exactly)."
        ),
    )
    p.add_argument("model", help="model file written by 'ndlfd fit'")
    p.add_argument(
        "-n", type=int, default=1, help=f"paths to draw, 1 <= N <= {MAX_DRAWS:,}"
    )
    add_timing_options(p)
    add_condition_options(p)
    add_limit_options(p)
    p.add_argument(
        "--key-points",
        action="store_true",
        help="write each path's key points instead of every time stamp (with"
        " --observed every time stamp: a continuation is dense)",
    )
    p.add_argument(
        "--random-state",
        type=int,
        metavar="SEED",
        help="seed of the draws: the same seed and input give the same paths",
    )
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="output folder (made if missing; its parent must exist)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    add_column_options(p, what="--like file", bags="like-")
    p.set_defaults(func=_cmd_sample)
