"""The ``ndlfd`` command line.

Every sub-command turns an :class:`~ndlfd.NdlfdError` (and a file-system error)
into one line on standard error and exit status 2, naming the command-line flag
at fault; an :class:`~ndlfd.NdlfdWarning` is one line too. Settings are checked
against their documented ranges before any work starts (and against the data
as soon as it is read), output paths before anything is computed. Outputs are
written atomically, so a failed run never leaves a half-written file behind.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import sys
import warnings
from collections import Counter
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from . import __version__
from ._errors import MissingExtraError, NdlfdError, NdlfdWarning, ValidationError

__all__ = ["main"]

EXIT_USAGE = 2
#: Most samples ``ndlfd generate --samples`` writes (80 MB per column).
MAX_SAMPLES = 10_000_000
#: Number format of computed values written by ``ndlfd generate``.
FLOAT_FORMAT = "%.10g"
_GROUP_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line, like every other error."""

    def error(self, message: str) -> None:  # type: ignore[override]
        """Print one line naming the command and exit with status 2."""
        self.exit(
            EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n"
        )


def _say(args: argparse.Namespace, line: str) -> None:
    """Print one summary line on stderr unless ``-q``."""
    if not getattr(args, "quiet", False):
        print(line, file=sys.stderr)


# ------------------------------------------------------------------ parsing
def _split_names(text: str | None, flag: str) -> list[str] | None:
    """``a,b,c`` strictly: no empty entry (a trailing comma is an error)."""
    if text is None:
        return None
    names = [s.strip() for s in text.split(",")]
    if not text.strip() or any(not s for s in names):
        raise ValidationError(
            f"{flag} must be a comma-separated list of names without empty entries;"
            f" got {text!r}"
        )
    dup = next((s for s in names if names.count(s) > 1), None)
    if dup is not None:
        raise ValidationError(f"{flag} names {dup!r} twice; got {text!r}")
    return names


def _parse_floats(text: str | None, flag: str) -> list[float] | None:
    if text is None:
        return None
    try:
        values = [float(s) for s in text.split(",")]
    except ValueError:
        raise ValidationError(
            f"{flag} must be comma-separated numbers; got {text!r}"
        ) from None
    if not all(math.isfinite(v) for v in values):
        raise ValidationError(f"{flag} must be finite numbers; got {text!r}")
    return values


def _parse_pairs(text: str, flag: str, cast, example: str) -> dict:
    """``name=value,name=value`` strictly (no empty entry, no repeated name)."""
    out: dict = {}
    for part in text.split(","):
        part = part.strip()
        if not part:
            raise ValidationError(
                f"{flag} must look like {example}; got {text!r} (an empty entry:"
                " a trailing or doubled comma)"
            )
        if "=" not in part:
            raise ValidationError(f"{flag} must look like {example}; got {text!r}")
        key, _, value = part.partition("=")
        key, value = key.strip(), value.strip()
        if not key:
            raise ValidationError(
                f"{flag} must look like {example}; got {part!r} without a name"
            )
        if key in out:
            raise ValidationError(f"{flag} names {key!r} twice; got {text!r}")
        try:
            out[key] = cast(value)
        except ValueError:
            raise ValidationError(
                f"{flag}: {value!r} is not a valid number in {text!r}"
            ) from None
    return out


def _check_range(value, flag: str, low=None, high=None) -> None:
    """One message for every bounded setting: ``FLAG must be ... ; got V``."""
    ok = value is not None and math.isfinite(value)
    if ok and low is not None:
        ok = value >= low
    if ok and high is not None:
        ok = value <= high
    if ok:
        return
    noun = "an integer" if isinstance(value, int) else "a finite number"
    if low is not None and high is not None:
        bound = f"between {low} and {high}"
    elif low is not None:
        bound = f"{noun} >= {low}"
    else:
        bound = f"{noun} <= {high}"
    raise ValidationError(f"{flag} must be {bound}; got {value}")


def _check_output(path: str, flag: str = "-o") -> Path:
    """Refuse an output that is a folder or lies in a missing folder."""
    p = Path(path)
    if p.is_dir():
        raise ValidationError(
            f"{flag} {path}: is a folder; expected a file name (e.g."
            f" {p / ('out' + (p.suffix or '.csv'))})"
        )
    parent = p.parent
    if not parent.exists():
        raise ValidationError(
            f"{flag} {path}: the folder {parent} does not exist; create it first"
        )
    if not parent.is_dir():
        raise ValidationError(f"{flag} {path}: {parent} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValidationError(f"{flag} {path}: the folder {parent} is not writable")
    return p


# ------------------------------------------------------------- data columns
def _add_column_options(p, *, what: str = "demonstration files") -> None:
    g = p.add_argument_group(
        f"columns of the {what}",
        "CSV files are comma-, semicolon-, tab- or whitespace-separated (the header"
        " row decides); .npz files hold arrays and HDF5 files one group per"
        " episode, mapped like columns (a 2-D array is a whole group). Names match"
        " in any case. Columns not named here go by their names: x,y,z position,"
        " vx,vy,vz velocity, qw,qx,qy,qz orientation, fx,fy,fz force,"
        " group.name a group of your own; 2-D arrays named position/pos,"
        " velocity/vel, orientation/quat, force. The mapping used is reported on"
        " one line.",
    )
    g.add_argument(
        "--time-column",
        metavar="NAME",
        help="the time column (strictly increasing; default: 't' or 'time')",
    )
    g.add_argument(
        "--group",
        action="append",
        metavar="GROUP=NAME[,NAME...]",
        help="put these columns (or one 2-D array) in GROUP, e.g."
        " --group position=pos_x,pos_y or --group position=pos; repeatable."
        " Orientation columns are listed in w,x,y,z order",
    )
    g.add_argument(
        "--drop", metavar="NAME[,NAME...]", help="columns to leave out of the data"
    )


def _column_options(args: argparse.Namespace) -> dict:
    """``read_demos`` keyword arguments from ``--time-column/--group/--drop``."""
    from .io import TIME_NAMES

    groups: dict[str, list[str]] | None = None
    for entry in args.group or ():
        if "=" not in entry:
            raise ValidationError(
                f"--group must look like GROUP=NAME[,NAME...], e.g."
                f" position=pos_x,pos_y; got {entry!r}"
            )
        name, _, cols = entry.partition("=")
        name = name.strip()
        if not _GROUP_NAME.match(name):
            raise ValidationError(
                "--group GROUP must be a name of letters, digits, '_' and '-'"
                f" (starting with a letter or '_'); got {name!r} in {entry!r}"
            )
        groups = groups if groups is not None else {}
        if name in groups:
            raise ValidationError(f"--group {name} is given twice")
        groups[name] = _split_names(cols, f"--group {name}")
    time_column = args.time_column
    if time_column is not None and not time_column.strip():
        raise ValidationError("--time-column must name a column; got ''")
    return {
        "time_column": TIME_NAMES if time_column is None else time_column.strip(),
        "groups": groups,
        "drop": _split_names(args.drop, "--drop") or (),
        "quaternion_order": "wxyz",
    }


def _describe_mappings(texts: dict[str, int], n_demos: int, n_files: int) -> str:
    """One line: how the files were read (the distinct mappings, with counts)."""
    head = f"read {n_demos} demonstration(s) from {n_files} file(s)"
    if len(texts) == 1:
        return f"{head}: {next(iter(texts))}"
    return f"{head}: " + " | ".join(f"{k} as {t}" for t, k in texts.items())


def _read_sources(args, sources, *, flag: str, progress: bool = False):
    """Read demonstrations with the column options; report the mapping."""
    from .io import _CLI_HINTS, _read_file, demo_files

    options = _column_options(args)
    paths = demo_files(sources)
    if progress:
        paths_iter = _progress(paths, len(paths), "reading demos")
    else:
        paths_iter = paths
    pairs, news = [], []
    for p in paths_iter:
        with _noting(p, news):
            pairs.extend(_read_file(p, _CLI_HINTS, **options))
    _tell(news)
    if not pairs:
        raise ValidationError(f"{flag}: the files hold no demonstration")
    demos = [d for d, _ in pairs]
    maps = [m for _, m in pairs]
    texts = Counter(str(m) for m in maps)
    _say(args, _describe_mappings(texts, len(maps), len(paths)))
    return demos, maps


@contextlib.contextmanager
def _noting(source, news: list):
    """Collect the NdlfdWarnings raised while ``source`` is handled."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", NdlfdWarning)
        yield
    for w in caught:
        if issubclass(w.category, NdlfdWarning):
            news.append((str(source), " ".join(str(w.message).split())))
        else:  # pragma: no cover - not ndlfd's news: as it came
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def _tell(news: list) -> None:
    """One warning line per kind of news, naming the first file and the count."""
    kinds: dict[str, list] = {}
    for source, text in news:
        kinds.setdefault(re.sub(r"[\d.]+", "#", text), []).append((source, text))
    for items in kinds.values():
        source, text = items[0]
        more = ""
        if len(items) > 1:
            others = [s for s, _ in items[1:]]
            shown = ", ".join(others[:3]) + (", ..." if len(others) > 3 else "")
            more = f" (likewise in {len(others)} more: {shown})"
        warnings.warn(f"{source}: {text}{more}", NdlfdWarning, stacklevel=2)


def _progress(iterable, total: int, desc: str):
    """Wrap ``iterable`` in a progress bar on a terminal (silent otherwise)."""
    from tqdm import tqdm

    bar = dict(desc=desc, unit="file", disable=None, leave=False)
    return tqdm(iterable, total=total, **bar)


def _prepare_groups(demos, maps, groups: list[str]):
    """Each demonstration's learned groups (velocity derived when missing).

    Errors name ``--groups`` and the file, like every check of the data.
    """
    from .demonstration import with_velocity

    out, news = [], []
    derived = False
    for d, m in zip(demos, maps, strict=True):
        if "velocity" in groups and not d.has_group("velocity"):
            if not d.has_group("position"):
                raise ValidationError(
                    f"--groups asks for velocity, but {m.source} has neither"
                    f" velocity nor position to derive it from; it has"
                    f" {', '.join(d.group_names)}"
                )
            with _noting(m.source, news):
                d = with_velocity(d)
            derived = True
        missing = [g for g in groups if not d.has_group(g)]
        if missing:
            raise ValidationError(
                f"--groups asks for {', '.join(missing)}, but {m.source} has only"
                f" {', '.join(d.group_names)} ({m}); map its columns with --group"
                f" {missing[0]}=NAME,... or leave it out of --groups"
            )
        out.append(d.select(*groups))
    _tell(news)
    first = out[0]
    for d, m in zip(out[1:], maps[1:], strict=True):
        if d.columns != first.columns or d.groups != first.groups:
            raise ValidationError(
                f"every demonstration must have the same columns; {maps[0].source}"
                f" has {', '.join(first.columns)} and {m.source} has"
                f" {', '.join(d.columns)}"
            )
    return out, derived


def _sample_bounds(demos, maps) -> tuple[int, str, int, str]:
    """(fewest samples, its source, most samples, its source)."""
    n = [d.n_samples for d in demos]
    lo, hi = int(np.argmin(n)), int(np.argmax(n))
    return n[lo], maps[lo].source, n[hi], maps[hi].source


def _check_bounds(args, ranges, paths, default_bins: int) -> tuple[int, str]:
    """``--n-points`` and ``--time-bins`` against the demonstrations' lengths.

    Returns the time bins (the default lowered to the longest demonstration's
    samples) and a note saying so.
    """
    fewest, most = ranges.min_samples, ranges.max_samples
    if args.n_points is not None and args.n_points > fewest:
        raise ValidationError(
            f"--n-points must be between 2 and {fewest} (the number of samples of"
            f" the shortest demonstration, {paths[ranges.shortest_item]}); got"
            f" {args.n_points}"
        )
    time_bins, note = args.time_bins, ""
    if time_bins is None:
        time_bins = min(default_bins, most)
        if time_bins < default_bins:
            note = (
                f" (the default {default_bins} lowered to the longest"
                f" demonstration's {most} samples)"
            )
    elif time_bins > most:
        raise ValidationError(
            f"--time-bins must be between 2 and {most} (the number of samples of"
            f" the longest demonstration, {paths[ranges.longest_item]}); got"
            f" {time_bins}"
        )
    return time_bins, note


# --------------------------------------------------------------------- simplify
def _own_group(name: str, j: int, taken) -> str:
    g = name if _GROUP_NAME.match(name) else f"column_{j + 1}"
    return g if g not in taken else f"column_{j + 1}"


def _cmd_simplify(args: argparse.Namespace) -> int:
    from ._simplify import simplify
    from .demonstration import KNOWN_GROUPS
    from .io import (
        _CLI_HINTS,
        TIME_NAMES,
        _layout,
        _parse_table,
        _resolve,
        group_of_column,
        write_table,
    )
    from .normalize import GroupScaler

    out = _check_output(args.output)
    if args.epsilon is not None:
        _check_range(args.epsilon, "--epsilon", low=0)
    if args.n_points is not None:
        _check_range(args.n_points, "--n-points", low=2)
    options = _column_options(args)
    p = Path(args.input)
    table = _parse_table(p)
    columns = table.columns
    n = table.data.shape[0]
    # the time column: named, else 't' or 'time' when present, else the row number
    if args.time_column is not None:
        time_col = _resolve(p, options["time_column"], columns, "--time-column names")
    else:
        low = [c.casefold() for c in columns]
        time_col = next((columns[low.index(c)] for c in TIME_NAMES if c in low), None)
    drop = [_resolve(p, c, columns, "--drop names") for c in options["drop"]]
    wanted = _split_names(args.columns, "--columns")
    if wanted is None:
        wanted = [c for c in columns if c != time_col and c not in drop]
    else:
        wanted = [_resolve(p, c, columns, "--columns names") for c in wanted]
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
        names = [_resolve(p, c, columns, f"--group {g} names") for c in cols]
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
    arrays = {c: table.data[:, columns.index(c)] for c in wanted}
    if time_col is not None:
        arrays[time_col] = table.data[:, columns.index(time_col)]
    demo, mapping = _layout(
        p,
        arrays,
        time_column=time_col,
        groups=groups,
        drop=(),
        quaternion_order="wxyz",
        how=_CLI_HINTS,
        lines=table.lines,
    )
    order = [k for _, keys in mapping.groups for k in keys]  # the demo's columns
    if args.n_points is not None and args.n_points > n:
        raise ValidationError(
            f"--n-points must be between 2 and {n} (the file's number of samples);"
            f" got {args.n_points}"
        )
    weights = _parse_floats(args.weights, "--weights")
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
        data = np.column_stack([table.data, result.astype(np.float64)])
        formats = [None] * len(columns) + ["%d"]
        write_table(out, [*columns, args.mask_column], data, float_format=formats)
        kept = int(result.sum())
    else:
        write_table(out, columns, table.data[result])
        kept = int(result.size)
    _say(args, _simplify_mapping(p, time_col, mapping.groups, alone, table, args))
    _say(args, f"kept {kept} of {n} points ({100.0 * kept / n:.1f} %) -> {out}")
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
    sep = {",": "", ";": " (semicolon-separated)", "\t": " (tab-separated)"}
    return (
        f"read {p}: {'; '.join(parts)}"
        f"{sep.get(table.delimiter, ' (whitespace-separated)')};"
        f" normalization {args.normalization}"
    )


def _add_simplify(sub) -> None:
    from ._simplify import DISTANCES
    from .learner import NORMALIZATIONS

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
    _add_column_options(p, what="input file")
    p.set_defaults(func=_cmd_simplify)


# ------------------------------------------------------------------ fit/generate
def _parse_levels(text: str | None):
    if text is None:
        return None
    example = "position=20,velocity=10 (or one number for every group)"
    if re.fullmatch(r"\s*\d+\s*", text):
        levels = int(text)
        _check_range(levels, "--levels", low=2)
        return levels
    levels = _parse_pairs(text, "--levels", int, example)
    for g, v in levels.items():
        _check_range(v, f"--levels {g}", low=2)
    return levels


def _connect(address: str | None):
    """A Dask client of the scheduler at ``address`` (None: no client)."""
    if address is None:
        return None
    try:
        from distributed import Client
    except ImportError:
        raise MissingExtraError(
            '--scheduler needs Dask; install it with: pip install "ndlfd[dask]"'
        ) from None
    try:
        return Client(address, timeout=10)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ValidationError(
            f"--scheduler {address}: cannot connect to a Dask scheduler there"
            f" ({type(exc).__name__}: {exc}); start one with: dask scheduler"
        ) from None


def _cmd_fit(args: argparse.Namespace) -> int:
    import time

    from .learner import DEFAULT_LEVELS, KeypointHMM

    out = _check_output(args.output)
    groups = _split_names(args.groups, "--groups")
    levels = _parse_levels(args.levels)
    weights = None
    if args.weights is not None:
        weights = _parse_pairs(args.weights, "--weights", float, "velocity=0.5")
        for g, w in weights.items():
            _check_range(w, f"--weights {g}", low=0)
    if args.epsilon is not None:
        _check_range(args.epsilon, "--epsilon", low=0)
    if args.n_points is not None:
        _check_range(args.n_points, "--n-points", low=2)
    if args.time_bins is not None:
        _check_range(args.time_bins, "--time-bins", low=2)
    _check_range(args.pseudo_emission, "--pseudo-emission", low=0)
    _check_range(args.match_window, "--match-window", low=0, high=0.5)
    if args.n_jobs is not None:
        _check_range(args.n_jobs, "--n-jobs", low=1)
    # the files are read as a stream (twice, on the workers): only the first
    # one here, for the groups and the checks that name the flags
    from . import _fitmap
    from ._parallel import keep_workers
    from .io import _CLI_HINTS, DemoFiles, _read_file, demo_files

    options = _column_options(args)
    paths = demo_files(args.demos)
    news: list = []
    with _noting(paths[0], news):
        pairs = _read_file(paths[0], _CLI_HINTS, **options)
    _tell(news)
    if not pairs:
        raise ValidationError(f"demos: {paths[0]} holds no demonstration")
    first, first_map = pairs[0]
    if groups is None:  # the library's groups="auto", resolved here to report it
        groups = list(KeypointHMM()._wanted_groups(first))
    for what, names in (("--levels", levels), ("--weights", weights)):
        if isinstance(names, dict):
            unknown = [g for g in names if g not in groups]
            if unknown:
                raise ValidationError(
                    f"{what} names {', '.join(unknown)}, which is not learned;"
                    f" the learned groups are {', '.join(groups)} (--groups)"
                )
    if not isinstance(levels, int):
        lacking = [
            g for g in groups if g not in (levels or {}) and g not in DEFAULT_LEVELS
        ]
        if lacking:
            raise ValidationError(
                f"--levels must give the codebook levels of group {lacking[0]!r},"
                f" which has no default (e.g. --levels {lacking[0]}=10)"
            )
    _, derived = _prepare_groups([first], [first_map], groups)
    defaults = KeypointHMM()
    model = KeypointHMM(
        groups=groups,
        levels=levels,
        epsilon=args.epsilon if args.epsilon is not None else defaults.epsilon,
        n_time_bins=args.time_bins or defaults.n_time_bins,
        n_points=None,  # checked against the shortest demonstration first
        distance=args.distance,
        normalization=args.normalization,
        weights=weights,
        pseudo_emission=args.pseudo_emission,
        start=args.start,
        generation=args.generation,
        decoder=args.decoder,
        n_jobs=args.n_jobs,
        match_window=args.match_window,
    )
    model._check_params()  # as fit does: the passes below are fit's
    files = DemoFiles._for_cli(paths, **options)
    t0 = time.perf_counter()
    client = _connect(args.scheduler)
    try:
        with keep_workers():  # one pool for both passes, ended after them
            scanned = _fitmap.scan(model, files, client=client)
            ranges = scanned.ranges
            n_demos = ranges.n_demos
            mappings = {text: n for text, _, n in ranges.notes}
            _say(args, _describe_mappings(mappings, n_demos, len(paths)))
            time_bins, note = _check_bounds(args, ranges, paths, defaults.n_time_bins)
            model.set_params(n_time_bins=time_bins, n_points=args.n_points)
            spec, stats = _fitmap.count(model, scanned)
    finally:
        if client is not None:
            client.close()
    model._set_from_spec(spec, stats)
    elapsed = time.perf_counter() - t0
    model.save(out)
    k = model.n_keypoints_
    learned = ", ".join(groups) + (
        " (velocity derived from position)" if derived else ""
    )
    _say(
        args,
        f"fitted {n_demos} demonstration(s) in {elapsed:.2f} s on {learned}:"
        f" key points {k.min()}-{k.max()} (median {int(np.median(k))}),"
        f" {model.n_states_used_} of {model.codebook_.n_states} states used,"
        f" {time_bins} time bins{note} -> {out}",
    )
    unused = [g for g in first.group_names if g not in groups]
    if unused:
        _say(
            args,
            f"not learned: {', '.join(unused)} (in the files but not in --groups;"
            f" learn {'it' if len(unused) == 1 else 'them'} with --groups"
            f" {','.join([*groups, *unused])})",
        )
    return 0


def _cmd_generate(args: argparse.Namespace) -> int:
    from .learner import KeypointHMM

    out = _check_output(args.output)
    std_out = _check_output(args.std, "--std") if args.std is not None else None
    if args.like is not None:
        if args.duration is not None or args.samples is not None:
            raise ValidationError(
                "pass either --like or --duration/--samples, not both"
            )
    else:
        if args.duration is None:
            raise ValidationError("pass --like FILE or --duration SECONDS")
        if not (args.duration > 0 and math.isfinite(args.duration)):
            raise ValidationError(
                f"--duration must be a finite number > 0; got {args.duration}"
            )
        n = args.samples if args.samples is not None else 1000
        _check_range(n, "--samples", low=2, high=MAX_SAMPLES)
    start = _parse_floats(args.start, "--start")
    goal = _parse_floats(args.goal, "--goal")
    model = KeypointHMM.load(args.model)
    n_pos = model.column_groups_.count("position")
    for flag, values in (("--start", start), ("--goal", goal)):
        if values is None:
            continue
        if n_pos == 0:
            raise ValidationError(
                f"{flag} needs a model that learned position; it learned"
                f" {', '.join(model.groups_)}"
            )
        if len(values) != n_pos:
            pairs = zip(model.columns_, model.column_groups_, strict=True)
            names = ", ".join(c for c, g in pairs if g == "position")
            raise ValidationError(
                f"{flag} must give {n_pos} position values (one per column: {names});"
                f" got {len(values)}"
            )
    if std_out is not None and model.generation != "blend":
        raise ValidationError(
            "--std needs a model fitted with --generation blend; this one uses"
            f" {model.generation}"
        )
    if args.like is not None:
        demos, maps = _read_sources(args, args.like, flag="--like")
        if len(demos) != 1:
            raise ValidationError(
                f"--like must name one demonstration; {args.like} holds"
                f" {len(demos)} ({maps[0].source}, {maps[1].source}, ...)"
            )
        timing = demos[0]
    else:
        timing = np.linspace(0.0, args.duration, n)
    result = model.generate(
        timing,
        dense=args.dense,
        start=None if start is None else {"position": start},
        goal=None if goal is None else {"position": goal},
        return_std=std_out is not None,
    )
    path, std = result if std_out is not None else (result, None)
    exact_time = args.like is not None and args.dense
    _write_path(path, out, exact_time=exact_time)
    if std is not None:  # the path's columns (std of a quaternion is no quaternion)
        from .io import _csv_header, write_table

        formats = [None if exact_time else FLOAT_FORMAT]
        formats += [FLOAT_FORMAT] * path.n_dims
        write_table(std_out, _csv_header(path, "t"),
                    np.column_stack([path.t, std]), float_format=formats)  # fmt: skip
    what = "samples" if args.dense else "key points"
    also = f" and its standard deviation -> {std_out}" if std_out is not None else ""
    _say(args, f"generated {path.n_samples} {what} -> {out}{also}")
    return 0


def _write_path(demo, path: Path, *, exact_time: bool) -> None:
    """Computed values with ten significant digits; given time stamps exactly."""
    from .io import write_csv

    write_csv(
        demo,
        path,
        float_format=FLOAT_FORMAT,
        time_format=None if exact_time else FLOAT_FORMAT,
    )


def _add_fit(sub) -> None:
    from ._simplify import DISTANCES
    from .learner import DECODERS, GENERATIONS, NORMALIZATIONS, STARTS, KeypointHMM

    p = sub.add_parser(
        "fit",
        help="learn a model from demonstration files",
        description=(
            "Learn key points, codebook states and a discrete HMM from"
            " demonstration files (CSV, .npz or HDF5; a folder means all its"
            " .csv/.tsv/.npz/.h5/.hdf5 files, in any case). The summary names the"
            " learned groups and the groups in the files that are not learned."
        ),
    )
    p.add_argument("demos", nargs="+", help="files, folders or glob patterns")
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="model file to write (its folder must exist)",
    )
    p.add_argument(
        "--groups",
        default=None,
        help="comma-separated groups to learn (default: position, velocity,"
        " orientation and force, those the files have; a missing velocity is"
        " derived from position). Name your own groups to learn them too",
    )
    budget = p.add_mutually_exclusive_group()
    defaults = KeypointHMM()
    budget.add_argument(
        "--epsilon",
        type=float,
        help=f"reduction tolerance on the normalized values, >= 0 (default"
        f" {defaults.epsilon})",
    )
    budget.add_argument(
        "--n-points",
        type=int,
        help="key points per demonstration (2 <= N <= the shortest demonstration's"
        " number of samples)",
    )
    p.add_argument("--distance", default="line", choices=DISTANCES.names)
    p.add_argument(
        "--levels",
        help="codebook levels >= 2, e.g. position=20,velocity=10 or one number for"
        " all groups (default: 20 for position, 10 for velocity, orientation and"
        " force; groups of your own need one)",
    )
    p.add_argument(
        "--time-bins",
        type=int,
        help=f"number of time symbols, 2 <= N <= the longest demonstration's number"
        f" of samples (default {defaults.n_time_bins}, or that number if smaller)",
    )
    p.add_argument("--normalization", default="group", choices=NORMALIZATIONS.names)
    p.add_argument(
        "--weights", help="per-group weights >= 0 in the reduction, e.g. velocity=0.5"
    )
    p.add_argument(
        "--pseudo-emission",
        type=float,
        default=0.0,
        help="emission pseudo-count >= 0 (default 0)",
    )
    p.add_argument("--start", default="learned", choices=STARTS.names)
    p.add_argument(
        "--match-window",
        type=float,
        default=defaults.match_window,
        help="the blend matches key points on each demonstration's moving average"
        " over this fraction of its samples each side, 0 to 0.5 (default"
        f" {defaults.match_window}; 0: raw samples, which spike on noisy data)",
    )
    p.add_argument(
        "--n-jobs",
        type=int,
        default=None,
        help="workers reading and reducing the files: processes for short"
        " demonstrations, threads for long ones (>= 5,000 samples); default one"
        " per CPU from 256 files on, else 1; the model is the same",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="fit on a Dask cluster, e.g. tcp://127.0.0.1:8786 (start one with"
        " 'dask scheduler' and 'dask worker ADDRESS'; needs ndlfd[dask]); the"
        " model is the same as a local fit's",
    )
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
    _add_column_options(p)
    p.set_defaults(func=_cmd_fit)


def _add_generate(sub) -> None:
    p = sub.add_parser(
        "generate",
        help="generate a path from a model and a new timing",
        description=(
            "Decode a new timing with a fitted model and write the generated path"
            " (key points, or every sample with --dense) as CSV, numbers with ten"
            " significant digits (the time stamps of --like exactly)."
        ),
    )
    p.add_argument("model", help="model file written by 'ndlfd fit'")
    p.add_argument(
        "--like", help="a test demonstration whose timing is used (one file)"
    )
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
    p.add_argument(
        "--duration", type=float, help="duration (> 0) of a uniform time grid"
    )
    p.add_argument(
        "--samples",
        type=int,
        help=f"samples of the uniform time grid, 2 <= N <= {MAX_SAMPLES:,}"
        " (default 1000)",
    )
    p.add_argument(
        "--dense",
        action="store_true",
        help="interpolate to every time stamp instead of writing key points",
    )
    p.add_argument(
        "--std",
        metavar="FILE.csv",
        help="also write the path's standard deviation (same columns) there, for"
        " 'ndlfd plot --std' (models fitted with --generation blend)",
    )
    p.add_argument(
        "-o", "--output", required=True, help="output CSV file (its folder must exist)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    _add_column_options(p, what="--like file")
    p.set_defaults(func=_cmd_generate)


# ------------------------------------------------------------------------- plot
def _cmd_plot(args: argparse.Namespace) -> int:
    from ._simplify import simplify_many
    from .demonstration import Demonstration
    from .io import _CLI_HINTS, _MAPPING_DEFAULTS, _parse_table, _read_file
    from .learner import KeypointHMM
    from .normalize import GroupScaler
    from .plot import (
        GEN_COLOR,
        new_figure,
        plot_band,
        plot_demos,
        plot_path,
        save_figure,
    )

    out = _check_output(args.output)
    fig0, _ = new_figure(1)  # matplotlib is there (or a one-line error)
    formats = fig0.canvas.get_supported_filetypes()
    suffix = out.suffix.lower().lstrip(".")
    if suffix not in formats:
        raise ValidationError(
            f"-o {args.output}: expected a figure file ending in"
            f" {', '.join('.' + f for f in sorted(formats))}; got"
            f" {out.suffix or 'no suffix'}"
        )
    if args.std is not None and args.path is None:
        raise ValidationError("--std draws the band of --path FILE.csv; pass --path")
    groups = _split_names(args.groups, "--groups")
    epsilon = args.epsilon if args.epsilon is not None else KeypointHMM().epsilon
    _check_range(epsilon, "--epsilon", low=0)
    if args.n_points is not None:
        _check_range(args.n_points, "--n-points", low=2)

    demos, maps = _read_sources(args, args.demos, flag="demos")
    fewest, fewest_src, _, _ = _sample_bounds(demos, maps)
    if args.n_points is not None and args.n_points > fewest:
        raise ValidationError(
            f"--n-points must be between 2 and {fewest} (the number of samples of"
            f" the shortest demonstration, {fewest_src}); got {args.n_points}"
        )
    prepared, _ = _prepare_groups(demos, maps, groups)
    # the key points 'ndlfd fit' finds with the same settings
    scaler = GroupScaler(mode=args.normalization).fit(prepared)
    keypoints = simplify_many(
        [scaler.transform(d) for d in prepared],
        None if args.n_points is not None else epsilon,
        n_points=args.n_points,
        n_jobs=1,
    )
    group = "position" if demos[0].has_group("position") else demos[0].group_names[0]
    k = demos[0].columns_of(group).size
    path = S = None
    if args.path is not None:
        pairs = _read_file(Path(args.path), _CLI_HINTS, **_MAPPING_DEFAULTS)
        path, path_map = pairs[0]
        if (
            len(pairs) != 1
            or not path.has_group(group)
            or (path.columns_of(group).size != k)
        ):
            raise ValidationError(
                f"--path {args.path} must be one path with the {k} {group}"
                f" column(s) of the demonstrations; got {len(pairs)} path(s) with"
                f" {', '.join(path.columns)}"
            )
    if args.std is not None:
        if path_map.layout == "arrays" or path_map.layout == "ndlfd":
            raise ValidationError(
                f"--std goes with a CSV --path (as 'ndlfd generate' writes it); got"
                f" {args.path}"
            )
        header = _parse_table(Path(args.path)).columns
        table = _parse_table(Path(args.std))
        if table.columns != header or table.data.shape[0] != path.n_samples:
            raise ValidationError(
                f"--std {args.std} must have the columns and rows of --path"
                f" {args.path} ({', '.join(header)}; {path.n_samples} rows); got"
                f" {', '.join(table.columns)}; {table.data.shape[0]} rows"
            )
        keys = dict(path_map.groups)[group]
        S = table.data[:, [header.index(c) for c in keys]]
    if k == 1:  # one column: draw it over time, with no spread in time

        def over_time(d):
            c = d.columns[d.columns_of(group)[0]]
            X = np.column_stack([d.t, d.get(group)])
            return Demonstration(d.t, X, ("time", c), (group, group))

        demos = [over_time(d) for d in demos]
        if path is not None:
            path = over_time(path)
        if S is not None:
            S = np.column_stack([np.zeros(len(S)), S])
    dims = 3 if k >= 3 else 2
    fig, (ax,) = new_figure(1, dims=dims)
    band = ""
    if S is not None:
        if dims == 2:
            plot_band(ax, path.get(group)[:, :2], S[:, :2], label="generated ±1 sd")
            band = " and its ±1 sd band"
        else:
            band = " (no band in 3-D)"
    plot_demos(
        demos,
        group=group,
        keypoints=keypoints,
        ax=ax,
        title=args.title,
        max_demos=None,
    )
    if path is not None:  # a line (a dense path would drown in dots)
        plot_path(ax, path.get(group), color=GEN_COLOR, lw=2.0, label="generated")
        ax.legend(loc="best", fontsize="small")
    save_figure(fig, out)
    counts = np.array([len(i) for i in keypoints])
    budget = (
        f"--n-points {args.n_points}"
        if args.n_points is not None
        else f"--epsilon {epsilon:g}"
    )
    drawn = f", the generated path{band}" if path is not None else ""
    _say(
        args,
        f"drew {len(demos)} demonstration(s) in {dims}-D ({group}) with their key"
        f" points ({counts.min()}-{counts.max()} at {budget}){drawn} -> {out}",
    )
    return 0


def _add_plot(sub) -> None:
    from .learner import NORMALIZATIONS, KeypointHMM

    p = sub.add_parser(
        "plot",
        help="draw demonstrations, their key points and a generated path",
        description=(
            "Draw demonstrations (files or folders, read like 'ndlfd fit' reads"
            " them) with their key points as 'ndlfd fit' finds them, and"
            " optionally a generated path (--path, e.g. from 'ndlfd generate') with"
            " its band (--std). Positions are drawn in 2-D or 3-D by their number"
            " of columns (one column: over time; more than three: the first"
            ' three). Needs matplotlib (pip install "ndlfd[plot]").'
        ),
    )
    p.add_argument("demos", nargs="+", help="files, folders or glob patterns")
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="figure file, e.g. demos.png (.pdf, .svg; its folder must exist)",
    )
    budget = p.add_mutually_exclusive_group()
    budget.add_argument(
        "--epsilon",
        type=float,
        help=f"key-point tolerance, >= 0 (default {KeypointHMM().epsilon}, as fit)",
    )
    budget.add_argument(
        "--n-points",
        type=int,
        help="key points per demonstration (2 <= N <= the shortest demonstration's"
        " number of samples)",
    )
    p.add_argument(
        "--groups",
        default="position,velocity",
        help="groups the key points are found on, as in fit (position,velocity)",
    )
    p.add_argument("--normalization", default="group", choices=NORMALIZATIONS.names)
    p.add_argument("--path", metavar="FILE.csv", help="a generated path to draw")
    p.add_argument(
        "--std",
        metavar="FILE.csv",
        help="the path's standard deviation (from 'ndlfd generate --std'), drawn"
        " as a band of one standard deviation (2-D only)",
    )
    p.add_argument("--title", help="title of the figure")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    _add_column_options(p)
    p.set_defaults(func=_cmd_plot)


# ------------------------------------------------------------------ jobs
def _cmd_demo(args: argparse.Namespace) -> int:
    from .jobs import run_demo

    run_demo(args.out, quick=args.quick, plot=not args.no_plot, echo=print)
    return 0


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from .jobs import reproduce

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
    from .jobs import evaluate

    protocols = _split_names(args.protocols, "--protocols")
    result = evaluate(
        _split_names(args.shapes, "--shapes"),
        generators=_split_names(args.generators, "--generators"),
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
    _add_plot(sub)
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
    command = args.command

    def one_line(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        print(f"ndlfd {command}: warning: {text}", file=sys.stderr)

    try:
        with warnings.catch_warnings():
            # repairs of the data are news for the user, one line each
            warnings.simplefilter("always", NdlfdWarning)
            warnings.showwarning = one_line
            return int(args.func(args) or 0)
    except NdlfdError as exc:
        print(f"ndlfd {command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        print(f"ndlfd {command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"ndlfd {command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
