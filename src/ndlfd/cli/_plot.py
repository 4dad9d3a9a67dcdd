"""``ndlfd plot``: demonstrations, their key points and a generated path."""

from __future__ import annotations

import argparse
import json
import zipfile
from functools import partial
from pathlib import Path

import numpy as np

from .. import plot
from .._errors import DataFileError, MissingExtraError, NdlfdError, ValidationError
from .._fileformat import META_KEY
from .._pose_groups import hand_group, hand_name, hands, kind
from .._poses import check_frames
from ..demonstration import unit_time
from ..dp import simplify_many
from ..io import (
    CLI_HINTS,
    MAPPING_DEFAULTS,
    csv_header,
    parse_table,
    read_file,
    read_or_skip,
)
from ..learner import NORMALIZATIONS, KeypointHMM, demo_routes, resolve_groups
from ..learner._persist import FORMAT_KIND as MODEL_KIND
from ..normalize import GroupScaler
from ._conditions import flag_named, parse_task_frames
from ._options import (
    add_column_options,
    add_route_options,
    check_output,
    check_range,
    column_options,
    prepare_groups,
    quiet_news,
    read_sources,
    say,
    split_names,
)
from ._task_frames import parse_frame_columns, read_framed

__all__ = ["add_plot"]

#: Groups not drawn over time beside a position: every hand's position, its
#: velocity (its rate) and its orientation (quaternions; triads in 3-D).
_NOT_OVER_TIME = ("position", "velocity", "orientation")


def _over_time(group: str) -> bool:
    return kind(group) not in _NOT_OVER_TIME


def _sample_bounds(demos, maps) -> tuple[int, str, int, str]:
    """(fewest samples, its source, most samples, its source)."""
    n = [d.n_samples for d in demos]
    lo, hi = int(np.argmin(n)), int(np.argmax(n))
    return n[lo], maps[lo].source, n[hi], maps[hi].source


#: How ``--path`` is read, in turn, until one reading works (see :func:`_read_path`).
_PATH_READINGS = (
    ("with the demonstrations' column flags", None),
    ("with them but no --drop or --rate", {"drop": (), "rate": None}),
    ("by its own column names alone", "defaults"),
)  # fmt: skip


def _read_path(p: Path, args: argparse.Namespace, flag: str = "--path"):
    """The generated path of ``--path``: in the demonstrations' names or the model's.

    ``ndlfd generate`` writes the names, order and time column of the files
    the model was fitted on (:mod:`ndlfd.io._output`), never a column they
    left out: the path is read with the demonstrations' flags, else with
    them but no ``--drop`` or ``--rate`` (the dropped columns are not in the
    path; it has a time column), else by its own names alone (a model that
    did not record its files' names writes its own). When no reading works,
    the error says why each failed (the same reason once).
    """
    _refuse_model(p, flag)
    options = column_options(args)
    errors: dict[str, list[str]] = {}
    for label, how in _PATH_READINGS:
        if how == "defaults":
            mapping = dict(MAPPING_DEFAULTS)
        else:
            mapping = {**options, **(how or {})}
            if how and all(options.get(k) == v for k, v in how.items()):
                continue  # no --drop, no --rate: the same reading again
        try:
            return read_file(p, CLI_HINTS, **mapping)
        except MissingExtraError:
            raise
        except (NdlfdError, OSError) as exc:
            errors.setdefault(str(exc), []).append(label)
    if len(errors) == 1:
        raise DataFileError(f"{flag} {next(iter(errors))}")
    reasons = "; ".join(
        f"{' and '.join(ways)}: {text}" for text, ways in errors.items()
    )
    raise DataFileError(
        f"{flag} {p}: expected a path as 'ndlfd generate' writes it (the"
        f" demonstrations' column names, or the model's); no reading works: {reasons}"
    )


def _model_meta(p) -> dict | None:
    """The metadata of an ndlfd model file ``p`` (by its content), else None.

    Only the ``__ndlfd__`` entry of a zip archive is read, never pickled data.
    """
    if not isinstance(p, (str, Path)) or not Path(p).is_file():
        return None
    try:
        with open(p, "rb") as fh:
            if fh.read(4) not in (b"PK\x03\x04", b"PK\x05\x06"):
                return None
            fh.seek(0)
            with zipfile.ZipFile(fh) as z:
                if f"{META_KEY}.npy" not in z.namelist():
                    return None
                with z.open(f"{META_KEY}.npy") as m:
                    raw = np.lib.format.read_array(m, allow_pickle=False)
        meta = json.loads(str(raw))
    except (OSError, ValueError, zipfile.BadZipFile):
        return None
    if isinstance(meta, dict) and meta.get("kind") == MODEL_KIND:
        return meta
    return None


def _refuse_model(p, flag: str | None) -> None:
    """A clear error when ``p`` (a demonstration, or ``flag``'s file) is a model."""
    if _model_meta(p) is None:
        return
    head = f"{flag} {p}" if flag else f"{p}"
    takes = (
        f"{flag} takes a generated path"
        if flag
        else "ndlfd plot draws demonstrations (files or folders, read as 'ndlfd"
        " fit' reads them) and a generated path (--path FILE.csv)"
    )
    raise ValidationError(
        f"{head}: is an ndlfd model (written by 'ndlfd fit'), which ndlfd plot"
        f" does not draw; {takes}. Make a path from the model with 'ndlfd"
        f" generate {p} --duration SECONDS -o path.csv' (or --like"
        " DEMONSTRATION), then draw it with 'ndlfd plot DEMOS --path path.csv -o"
        " FIGURE'"
    )


def _read_demo(p, how, *, frames, **mapping) -> list:
    """One demonstration source as ``ndlfd fit`` reads it; a model refused.

    :func:`~ndlfd.cli._task_frames.read_framed_or_skip` with a model file
    refused by its content (``--bad-files skip`` skips it, with the reason).
    """

    def read(q, h, **m):
        _refuse_model(q, None)
        return read_framed(q, h, frames=frames, **m) if frames else read_file(q, h, **m)

    return read_or_skip(p, how, read=read, **mapping)


def _sample_files(args: argparse.Namespace) -> list[Path]:
    """The CSV files of ``--samples DIR`` (``ndlfd sample -o DIR``), checked."""
    if args.samples is None:
        return []
    folder = Path(args.samples)
    if not folder.is_dir():
        raise ValidationError(
            f"--samples {folder}: expected the folder 'ndlfd sample -o' writes"
        )
    files = sorted(folder.glob("*.csv"))
    if not files:
        raise ValidationError(f"--samples {folder}: the folder holds no .csv file")
    return files


def _read_samples(args, files: list[Path], group: str, k: int) -> list:
    """The sampled paths of ``files``, each with the ``k`` columns of ``group``."""
    out = []
    for p in files:
        pairs = _read_path(p, args, "--samples")
        d = pairs[0][0]
        if len(pairs) != 1 or not d.has_group(group) or d.columns_of(group).size != k:
            raise ValidationError(
                f"--samples {p} must be one path with the {k} {group} column(s) of"
                f" the demonstrations; got {', '.join(d.columns)}"
            )
        out.append(d)
    return out


def _shared_axes(ax, dims: int) -> None:
    """Label the axes x, y (, z): several hands' positions share them."""
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    if dims == 3:
        ax.set_zlabel("z")


def _draw_triads(ax, args, group: str, k: int, path, demos, maps) -> str:
    """Orientation triads along the generated path (else the first demonstration).

    Only for a 3-D position with an orientation (a hand's: ``position`` and
    ``orientation``, ``left_position`` and ``left_orientation``); returns the
    summary's words.
    """
    source = path if path is not None else demos[0]
    orient = hand_group(hand_name(group) or "", "orientation")
    if (
        args.triads == 0
        or kind(group) != "position"
        or k != 3
        or not source.has_group(group)
        or not source.has_group(orient)
        or source.columns_of(orient).size != 4
    ):
        return ""
    idx = plot.plot_triads(
        ax, source.get(group), source.get(orient), n_triads=args.triads
    )
    where = "the generated path" if path is not None else maps[0].source
    named = f" ({orient})" if hand_name(group) else ""  # one of several hands
    return f", {idx.size} orientation triads{named} on {where}"


def _path_frames(args: argparse.Namespace, dims: int | None = None) -> dict | None:
    """``--path-frame NAME=X,Y,Z[,QW,QX,QY,QZ]``: the poses the path was made for.

    Parsed (``dims`` None), else also checked against the position's ``dims``.
    """
    if not args.path_frame:
        return None
    if args.path is None:
        raise ValidationError(
            "--path-frame marks the task frames of --path FILE.csv; pass --path"
        )
    try:  # as 'ndlfd generate --task-frame' reads them
        frames = parse_task_frames(args.path_frame)
        if dims is None:
            return frames
        return dict(check_frames(frames, dims, what="--task-frame"))
    except ValidationError as exc:
        text = flag_named(exc).replace("--task-frame", "--path-frame")
        raise ValidationError(text) from None


def _draw_frames(ax, demos, routes, path_frames) -> str:
    """Each demonstration's task frames in its line's colour, the path's in black.

    One marker style per frame name (the path's alike); returns the summary's
    words.
    """
    names = list(dict.fromkeys(n for d in demos for n in d.frames))
    own = [n for n in path_frames or () if n not in names]
    words = ""
    if names:
        several = np.unique(routes).size > 1
        route = [plot.ROUTE_COLORS[int(r) % len(plot.ROUTE_COLORS)] for r in routes]
        colors = route if several else plot.DEMO_COLOR
        plot.plot_frames(
            ax, [d.frames for d in demos], colors=colors, names=names + own
        )
        words = f", each demonstration's task frames ({', '.join(names)})"
    if path_frames:
        plot.plot_frames(
            ax, [path_frames], names=names + own, label="{name} of the path"
        )
        words += f", the path's ({', '.join(path_frames)})"
    return words


def _cmd_plot(args: argparse.Namespace) -> int:
    out = check_output(args.output)
    fig0, _ = plot.new_figure(1)  # matplotlib is there (or a one-line error)
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
    groups = split_names(args.groups, "--groups")  # None: those of fit
    epsilon = args.epsilon if args.epsilon is not None else KeypointHMM().epsilon
    check_range(epsilon, "--epsilon", low=0)
    if args.n_points is not None:
        check_range(args.n_points, "--n-points", low=2)
    check_range(args.triads, "--triads", low=0, high=1000)
    sample_files = _sample_files(args)
    frames = parse_frame_columns(args.task_frame)  # read as 'ndlfd fit' reads them
    _path_frames(args)  # its words, before the files are read
    read = partial(_read_demo, frames=frames)
    demos, maps = read_sources(args, args.demos, flag="demos", read=read)
    fewest, fewest_src, _, _ = _sample_bounds(demos, maps)
    if args.n_points is not None and args.n_points > fewest:
        raise ValidationError(
            f"--n-points must be between 2 and {fewest} (the number of samples of"
            f" the shortest demonstration, {fewest_src}); got {args.n_points}"
        )
    if groups is None:  # the library's groups="auto", as ndlfd fit resolves it
        groups = list(resolve_groups("auto", demos[0]))
    prepared, _ = prepare_groups(demos, maps, groups)
    # the key points 'ndlfd fit' finds with the same settings
    scaler = GroupScaler(mode=args.normalization).fit(prepared)
    keypoints = simplify_many(
        [scaler.transform(d) for d in prepared],
        None if args.n_points is not None else epsilon,
        n_points=args.n_points,
        n_jobs=1,
    )
    # each demonstration's route, as 'ndlfd fit' finds them (colours)
    routes = demo_routes(
        [scaler.transform(d, weighted=False) for d in prepared],
        [unit_time(d.t) for d in prepared],
        prepared[0].groups,
        route_groups=args.route_groups,
        n_routes=args.routes,
    )
    hand_groups = [hand_group(h.name, "position") for h in hands(prepared[0].groups)]
    if not hand_groups or prepared[0].columns_of(hand_groups[0]).size == 1:
        # joints, a gripper, a position of one column: each channel over time
        if args.path_frame:
            raise ValidationError(
                "--path-frame marks frames on a position's axes; the"
                " demonstrations have no position of 2 or 3 columns"
            )
        return _plot_over_time(args, out, prepared, keypoints, routes, sample_files,
                               demos[0].columns)  # fmt: skip
    group = hand_groups[0]  # the first hand; the others drawn on the same axes
    k = demos[0].columns_of(group).size
    path = S = None
    if args.path is not None:
        pairs = _read_path(Path(args.path), args)
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
    samples = _read_samples(args, sample_files, group, k)
    path_frames = _path_frames(args, k)
    S_all = None
    if args.std is not None:
        S_all = _std_of(args, path, path_map)
        S = S_all[:, path.columns_of(group)]
    dims = 3 if k >= 3 else 2
    # the other learned groups (joints, a gripper, a force) over time, beside
    first = prepared[0]
    others = {c for c, g in zip(first.columns, first.groups, strict=True)
              if _over_time(g)}  # fmt: skip
    beside = [c for c in demos[0].columns if c in others]
    beside += [c for c in first.columns if c in others and c not in beside]
    if beside:
        fig, ax, side = plot.new_figure_beside(len(beside), dims=dims)
    else:
        fig, (ax,) = plot.new_figure(1, dims=dims)
    band = ""
    if S is not None:
        if dims == 2:
            plot.plot_band(
                ax, path.get(group)[:, :2], S[:, :2], label="generated ±1 sd"
            )
            band = " and its ±1 sd band"
        else:
            band = (
                " and its ±1 sd band over time (none in 3-D)"
                if beside
                else " (no band in 3-D)"
            )
    plot.plot_demos(
        demos,
        group=group,
        keypoints=keypoints,
        ax=ax,
        title=args.title,
        max_demos=None,
        routes=routes,
    )
    for more in hand_groups[1:]:  # every other hand on the same axes
        plot.plot_demos(demos, group=more, keypoints=keypoints, ax=ax,
                        max_demos=None, routes=routes)  # fmt: skip
    for g in hand_groups:
        if samples:
            plot.plot_samples(ax, [d.get(g) for d in samples if d.has_group(g)])
        if path is not None and path.has_group(g):  # a line, not dots
            plot.plot_path(
                ax, path.get(g), color=plot.GEN_COLOR, lw=2.0,
                label="generated" if g == group else None,
            )  # fmt: skip
    triads = "".join(
        _draw_triads(ax, args, g, k, path, demos, maps) for g in hand_groups
    )
    marks = _draw_frames(ax, demos, routes, path_frames)
    if len(hand_groups) > 1:  # the axes are every hand's, not the last one's
        _shared_axes(ax, dims)
    if path is not None or samples or triads or marks or len(hand_groups) > 1:
        handles, labels = ax.get_legend_handles_labels()
        once = dict(zip(labels, handles, strict=True))  # one entry per label
        ax.legend(once.values(), once.keys(), loc="best", fontsize="small")
    if beside:
        plot.plot_channels(prepared, columns=beside, keypoints=keypoints,
                           generated=path, std=S_all, routes=routes,
                           samples=samples, fig=side)  # fmt: skip
    plot.save_figure(fig, out)
    counts = np.array([len(i) for i in keypoints])
    budget = (
        f"--n-points {args.n_points}"
        if args.n_points is not None
        else f"--epsilon {epsilon:g}"
    )
    drawn = f", the generated path{band}" if path is not None else ""
    drawn += f", {len(samples)} sample(s)" if samples else ""
    drawn += triads + marks
    n_routes = int(routes.max()) + 1
    if n_routes > 1:
        sizes = ", ".join(str(int(c)) for c in np.bincount(routes))
        drawn += f", coloured by route ({n_routes} routes: {sizes} demonstrations)"
    also = ""
    if beside:
        names = dict.fromkeys(first.groups[first.columns.index(c)] for c in beside)
        also = f" and over time ({', '.join(names)}: {len(beside)} channel(s))"
    say(
        args,
        f"drew {len(demos)} demonstration(s) in {dims}-D"
        f" ({', '.join(hand_groups)}){also} with"
        f" their key points ({counts.min()}-{counts.max()} at {budget}){drawn} ->"
        f" {out}",
    )
    return 0


def _std_of(args, path, path_map) -> np.ndarray:
    """``--std`` as an array of ``path``'s columns (matched by the file's names)."""
    if path_map.layout in ("arrays", "ndlfd"):
        raise ValidationError(
            f"--std goes with a CSV --path (as 'ndlfd generate' writes it); got"
            f" {args.path}"
        )
    header = parse_table(Path(args.path)).columns
    table = parse_table(Path(args.std))
    if table.columns not in (header, csv_header(path, "t")) or (
        table.data.shape[0] != path.n_samples
    ):
        raise ValidationError(
            f"--std {args.std} must have the columns and rows of --path"
            f" {args.path} ({', '.join(header)}; {path.n_samples} rows); got"
            f" {', '.join(table.columns)}; {table.data.shape[0]} rows"
        )
    if table.columns != header:  # the model's own names, in the path's order
        return table.data[:, 1:]
    names = [k for _, ks in path_map.groups for k in ks]
    if len(names) != path.n_dims:  # Euler angles: the file's order as read
        return table.data[:, 1:]
    return table.data[:, [1 + header[1:].index(k) for k in names]]


def _plot_over_time(args, out, demos, keypoints, routes, files, order) -> int:
    """Each learned channel over time (no position): small multiples."""
    columns = [c for c in order if c in demos[0].columns]
    columns += [c for c in demos[0].columns if c not in columns]  # derived
    path = S = None
    if args.path is not None:
        pairs = _read_path(Path(args.path), args)
        path, path_map = pairs[0]
        if len(pairs) != 1 or not set(columns) & set(path.columns):
            raise ValidationError(
                f"--path {args.path} must be one path with columns of the"
                f" demonstrations ({', '.join(columns)}); got {len(pairs)} path(s)"
                f" with {', '.join(path.columns)}"
            )
        if args.std is not None:
            S = _std_of(args, path, path_map)
    samples = [_read_path(p, args, "--samples")[0][0] for p in files]
    fig, _ = plot.plot_channels(demos, columns=columns, keypoints=keypoints,
                                generated=path, std=S, routes=routes,
                                samples=samples, title=args.title)  # fmt: skip
    plot.save_figure(fig, out)
    counts = np.array([len(i) for i in keypoints])
    epsilon = KeypointHMM().epsilon if args.epsilon is None else args.epsilon
    budget = (
        f"--n-points {args.n_points}"
        if args.n_points is not None
        else f"--epsilon {epsilon:g}"
    )
    drawn = ""
    if path is not None:
        drawn = ", the generated path" + (
            " and its ±1 sd band" if S is not None else ""
        )
    drawn += f", {len(samples)} sample(s)" if samples else ""
    groups = ", ".join(dict.fromkeys(demos[0].groups[demos[0].columns.index(c)]
                                     for c in columns))  # fmt: skip
    say(
        args,
        f"drew {len(demos)} demonstration(s) over time, one axis per channel"
        f" ({len(columns)}: {groups}), with their key points"
        f" ({counts.min()}-{counts.max()} at {budget}){drawn} -> {out}",
    )
    return 0


def add_plot(sub) -> None:
    p = sub.add_parser(
        "plot",
        help="draw demonstrations, their key points and a generated path",
        description=(
            "Draw demonstrations (files or folders, read like 'ndlfd fit' reads"
            " them) with their key points as 'ndlfd fit' finds them, and"
            " optionally a generated path (--path, e.g. from 'ndlfd generate') with"
            " its band (--std), sampled paths (--samples DIR, from 'ndlfd"
            " sample'), orientation triads along a 3-D path and each"
            " demonstration's task frames (--task-frame, read as 'ndlfd fit'"
            " reads them; --path-frame for the path's). Positions are"
            " drawn in 2-D or 3-D by their number of columns (more than three: the"
            " first three), and the other learned groups (joints, a gripper, a"
            " force; not a velocity or an orientation) beside, over time."
            " Data without a position (joints, a gripper) or with a"
            " position of one column are drawn over time, one axis per learned"
            " channel, with the path's band."
            ' Needs matplotlib (pip install "ndlfd[plot]").'
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
        default=None,
        help="groups the key points are found on (default: those fit learns:"
        " position, velocity, orientation, force and gripper, those the files"
        " have; a missing velocity is derived from position)",
    )
    p.add_argument("--normalization", default="group", choices=NORMALIZATIONS.names)
    p.add_argument(
        "--path",
        metavar="FILE.csv",
        help="a generated path to draw, as 'ndlfd generate' writes it (read with"
        " the column flags, else without --drop and --rate, else by its own"
        " names; not a model: make a path from one with 'ndlfd generate')",
    )
    p.add_argument(
        "--std",
        metavar="FILE.csv",
        help="the path's standard deviation (from 'ndlfd generate --std'), drawn"
        " as a band of one standard deviation (2-D positions, and every"
        " channel drawn over time)",
    )
    p.add_argument(
        "--samples",
        metavar="DIR",
        help="a folder of sampled paths ('ndlfd sample -o DIR'), drawn as thin lines",
    )
    p.add_argument(
        "--triads",
        type=int,
        default=8,
        metavar="N",
        help="orientation triads (x red, y green, z blue) drawn at equal steps of"
        " arc length along the generated path, else the first demonstration, when"
        " the position is 3-D with an orientation (default 8; 0: none)",
    )
    p.add_argument(
        "--task-frame",
        action="append",
        metavar="NAME=COLUMN,COLUMN,...",
        help="the columns (of a ROS 2 bag, a topic or tf:FRAME; of a LeRobot"
        " dataset, a feature) that are each demonstration's task frame NAME,"
        " read as 'ndlfd fit --task-frame' reads them, not as data; drawn at"
        " its position in the demonstration's colour, one marker per frame,"
        " with an arrow along its x axis when it has an orientation; repeatable",
    )
    p.add_argument(
        "--path-frame",
        action="append",
        metavar="NAME=X,Y,Z[,QW,QX,QY,QZ]",
        help="where the task frame NAME of --path was (the values given to"
        " 'ndlfd generate --task-frame'), drawn in black; repeatable",
    )
    p.add_argument("--title", help="title of the figure")
    add_route_options(p)
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    add_column_options(p)
    p.set_defaults(func=quiet_news(_cmd_plot))
