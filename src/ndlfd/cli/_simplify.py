"""``ndlfd simplify``: the key points of one trajectory in a CSV file."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .._errors import ValidationError
from ..demonstration import KNOWN_GROUPS
from ..dp import DISTANCES, simplify
from ..io import CLI_HINTS, TIME_NAMES, group_of_column, parse_table, write_table
from ..io._csv import delimiter_name
from ..io._mapping import map_arrays, resolve_column
from ..learner import NORMALIZATIONS
from ..normalize import GroupScaler
from ._options import (
    GROUP_NAME,
    add_bad_data_options,
    add_column_options,
    check_output,
    check_range,
    column_options,
    parse_floats,
    quiet_news,
    say,
    split_names,
)

__all__ = ["add_simplify"]


def _own_group(name: str, j: int, taken) -> str:
    g = name if GROUP_NAME.match(name) else f"column_{j + 1}"
    return g if g not in taken else f"column_{j + 1}"


def _cmd_simplify(args: argparse.Namespace) -> int:
    out = check_output(args.output)
    if args.epsilon is not None:
        check_range(args.epsilon, "--epsilon", low=0)
    if args.n_points is not None:
        check_range(args.n_points, "--n-points", low=2)
    options = column_options(args)
    p = Path(args.input)
    drop_rows = options["bad_rows"] == "drop"
    table = parse_table(p, finite=not drop_rows)
    columns = table.columns
    # the time column: named, else 't' or 'time' when present, else the row number
    if args.time_column is not None:
        time_col = resolve_column(
            p, options["time_column"], columns, "--time-column names"
        )
    else:
        low = [c.casefold() for c in columns]
        time_col = next((columns[low.index(c)] for c in TIME_NAMES if c in low), None)
    drop = [resolve_column(p, c, columns, "--drop names") for c in options["drop"]]
    wanted = split_names(args.columns, "--columns")
    if wanted is None:
        wanted = [c for c in columns if c != time_col and c not in drop]
    else:
        wanted = [resolve_column(p, c, columns, "--columns names") for c in wanted]
        if time_col in wanted:
            raise ValidationError(
                f"--columns names {time_col!r}, the time column; leave it out (or"
                " name another with --time-column)"
            )
        wanted = [c for c in wanted if c not in drop]
    if not wanted:
        raise ValidationError(
            f"{p}: no columns left to simplify besides the time column"
            f" {time_col!r}; pass --columns"
        )
    # groups: --group, then the naming convention, then a column on its own
    groups = {}
    for g, cols in (options["groups"] or {}).items():
        names = [resolve_column(p, c, columns, f"--group {g} names") for c in cols]
        outside = [c for c in names if c not in wanted]
        if outside:
            raise ValidationError(
                f"--group {g} names {', '.join(outside)}, which is not among the"
                f" simplified columns ({', '.join(wanted)})"
            )
        groups[g] = names
    mapped = {c for cols in groups.values() for c in cols}
    alone = set()
    for j, c in enumerate(columns):
        if c in wanted and c not in mapped and group_of_column(c) is None:
            g = _own_group(c, j, {*groups, *KNOWN_GROUPS})
            alone.add(g)
            groups[g] = [c]
    used = [columns.index(c) for c in (*wanted, *([time_col] if time_col else []))]
    # the rows read (those --bad-rows drop keeps): the output's rows index them
    rows = np.flatnonzero(np.isfinite(table.data[:, used]).all(axis=1))
    arrays = {c: table.data[:, columns.index(c)] for c in wanted}
    if time_col is not None:
        arrays[time_col] = table.data[:, columns.index(time_col)]
    demo, mapping = map_arrays(
        p,
        arrays,
        time_column=time_col,
        groups=groups,
        drop=(),
        quaternion_order="wxyz",
        how=CLI_HINTS,
        lines=table.lines,
        bad_rows=options["bad_rows"],
    )
    n = demo.n_samples
    order = [k for _, keys in mapping.groups for k in keys]  # the demo's columns
    if args.n_points is not None and args.n_points > n:
        raise ValidationError(
            f"--n-points must be between 2 and {n} (the file's number of samples);"
            f" got {args.n_points}"
        )
    weights = parse_floats(args.weights, "--weights")
    if weights is not None:
        if len(weights) != len(wanted):
            raise ValidationError(
                f"--weights must give one weight per simplified column"
                f" ({len(wanted)}: {', '.join(wanted)}); got {len(weights)}"
            )
        if min(weights) < 0:
            raise ValidationError(f"--weights must be >= 0; got {args.weights!r}")
        weights = [weights[wanted.index(k)] for k in order]
    if args.distance == "sed" and time_col is None:
        raise ValidationError(
            "--distance sed needs a time column; pass --time-column NAME"
        )
    U = GroupScaler(mode=args.normalization).fit(demo).transform(demo)
    result = simplify(
        U,
        args.epsilon,
        distance=args.distance,
        weights=weights,
        times=demo.t if args.distance == "sed" else None,
        n_points=args.n_points,
        return_mask=args.mask,
    )
    if args.mask:
        if any(c.casefold() == args.mask_column.casefold() for c in columns):
            raise ValidationError(
                f"--mask-column {args.mask_column!r} is already a column of"
                f" {p}; name another"
            )
        # every row read (--bad-rows drop leaves the dropped ones out)
        data = np.column_stack([table.data[rows], result.astype(np.float64)])
        formats = [None] * len(columns) + ["%d"]
        write_table(out, [*columns, args.mask_column], data, float_format=formats)
        kept = int(result.sum())
    else:
        write_table(out, columns, table.data[rows[result]])
        kept = int(result.size)
    say(args, _simplify_mapping(p, time_col, mapping.groups, alone, table, args))
    say(args, f"kept {kept} of {n} points ({100.0 * kept / n:.1f} %) -> {out}")
    return 0


def _simplify_mapping(p, time_col, groups, alone, table, args) -> str:
    """The one line saying how ``ndlfd simplify`` read and scaled the file."""
    parts = [f"time={time_col if time_col is not None else '(row number)'}"]
    parts += [f"{g}={','.join(keys)}" for g, keys in groups if g not in alone]
    single = [keys[0] for g, keys in groups if g in alone]
    if single:
        parts.append(
            f"each in a group of its own: {','.join(single)} (group them with"
            " --group GROUP=NAME,...)"
        )
    sep = ""
    if table.delimiter != ",":
        sep = f" ({delimiter_name(table.delimiter)}-separated)"
    return f"read {p}: {'; '.join(parts)}{sep}; normalization {args.normalization}"


def add_simplify(sub) -> None:
    p = sub.add_parser(
        "simplify",
        help="keep the key points of one trajectory (n-D Douglas-Peucker)",
        description=(
            "Read a CSV file with a header row, keep the key points of the chosen"
            " columns by n-dimensional Douglas-Peucker on their normalized values"
            " (like 'ndlfd fit'), and write the original rows (all columns, time"
            " included, values unchanged) of the key points."
        ),
    )
    p.add_argument("input", help="CSV file with a header row")
    budget = p.add_mutually_exclusive_group(required=True)
    budget.add_argument(
        "--epsilon",
        type=float,
        help="tolerance on the normalized values (>= 0; with the default"
        " normalization a fraction of each group's range): a point is kept when"
        " its distance exceeds it",
    )
    budget.add_argument(
        "--n-points",
        type=int,
        help="key-point budget instead of a tolerance, most significant first"
        " (2 <= N <= the file's number of samples)",
    )
    p.add_argument(
        "--columns",
        help="comma-separated columns to simplify (default: all but the time column)",
    )
    p.add_argument(
        "--normalization",
        default="group",
        choices=NORMALIZATIONS.names,
        help="how columns are scaled before reduction, as in 'ndlfd fit' (default:"
        " group, one range per group so quaternions and positions count alike;"
        " per-dimension: each column its own range; none: raw values). Columns"
        " whose group their name does not give are a group of their own",
    )
    p.add_argument(
        "--distance",
        default="line",
        choices=DISTANCES.names,
        help="distance to the chord (default: line, the exact perpendicular distance)",
    )
    p.add_argument(
        "--weights",
        help="comma-separated column weights >= 0, one per simplified column",
    )
    p.add_argument(
        "--mask",
        action="store_true",
        help="write every row with a 0/1 column saying whether it is a key point",
    )
    p.add_argument(
        "--mask-column", default="keep", help="name of the --mask column (keep)"
    )
    p.add_argument(
        "-o", "--output", required=True, help="output CSV file (its folder must exist)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    add_column_options(p, what="input file", bags=None, demonstrations=False)
    add_bad_data_options(p, files=False)
    p.set_defaults(func=quiet_news(_cmd_simplify))
