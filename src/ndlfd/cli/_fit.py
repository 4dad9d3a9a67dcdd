"""``ndlfd fit``: learn a model from demonstration files, read as a stream."""

from __future__ import annotations

import argparse
import re
import time
import warnings
from dataclasses import replace

import numpy as np

from .._errors import MissingExtraError, NdlfdWarning, ValidationError
from .._pose_groups import (
    frame_hands_problem,
    hand_group,
    hand_labels,
    hand_name,
    kind,
)
from .._repairs import collecting_repairs
from ..dp import DISTANCES
from ..io import CLI_HINTS, demo_files
from ..learner import (
    DECODERS,
    GENERATIONS,
    NORMALIZATIONS,
    STARTS,
    KeypointHMM,
    check_params,
    resolve_groups,
    route_columns,
)
from ..limits import path_peaks
from ._conditions import parse_named
from ._options import (
    add_column_options,
    add_route_options,
    check_datasets,
    check_output,
    check_range,
    column_options,
    dataset_options,
    describe_mappings,
    noting,
    parse_pairs,
    prepare_groups,
    say,
    split_names,
    tell,
)
from ._task_frames import FramedDemoFiles, parse_frame_columns, read_framed_or_skip

__all__ = ["add_fit"]


# ------------------------------------------------------------------ the command
def _parse_levels(text: str | None):
    if text is None:
        return None
    example = "position=20,velocity=10 (or one number for every group)"
    if re.fullmatch(r"\s*\d+\s*", text):
        levels = int(text)
        check_range(levels, "--levels", low=2)
        return levels
    levels = parse_pairs(text, "--levels", int, example)
    for g, v in levels.items():
        check_range(v, f"--levels {g}", low=2)
    return levels


#: What ``--frame-hands`` looks like.
_FRAME_HANDS_EXAMPLE = "FRAME=HAND[,HAND...] (e.g. socket=left or cube=left,right)"


def parse_frame_hands(texts: list[str] | None) -> dict | None:
    """Repeated ``--frame-hands`` flags as ``{frame: [hand, ...]}`` (or ``None``).

    ``KeypointHMM``'s ``frame_hands``: the hands each task frame may move, a
    hand by its name (``left`` for ``left_position``; ``position`` the
    unnamed one). A frame given twice, an empty hand or a hand named twice is
    an error naming the flag.

    Examples
    --------
    >>> parse_frame_hands(["socket=left", "peg=right"])
    {'socket': ['left'], 'peg': ['right']}
    >>> parse_frame_hands(None) is None
    True
    """
    if not texts:
        return None
    return parse_named(texts, "--frame-hands", _FRAME_HANDS_EXAMPLE, split_names)


def check_frame_hands(frame_hands: dict | None, frames, groups) -> None:
    """``--frame-hands`` against the frames and hands of the first file read.

    The checks of ``KeypointHMM.fit`` (a frame the demonstrations carry, a
    hand the model has), made before the files are read on the workers and
    worded for the flags.

    Parameters
    ----------
    frame_hands : dict of str to list of str, or None
    frames : iterable of str
        The task frames of the first demonstration (``--task-frame``).
    groups : sequence of str
        The groups learned.

    Raises
    ------
    ValidationError
        A frame the demonstrations do not carry, or a hand the groups have not.

    Examples
    --------
    >>> check_frame_hands({"cube": ["arm"]}, ["cube"], ["left_position", "gripper"])
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: --frame-hands cube names the hand 'arm'; ...
    """
    frames = list(frames)
    problem = frame_hands_problem(frame_hands, frames, list(groups))
    if problem is None:
        return
    name, h = problem
    if h is None:
        given = ", ".join(frames) if frames else "none (give them with --task-frame)"
        raise ValidationError(
            f"--frame-hands names the frame {name!r}, which the"
            f" demonstrations do not carry; their task frames: {given}"
        )
    labels = hand_labels(list(groups))
    have = ", ".join(map(repr, labels)) if labels else "none"
    raise ValidationError(
        f"--frame-hands {name} names the hand {h!r}; the learned"
        f" hands are {have} (a hand is a position group: position or"
        " <hand>_position, e.g. left_position)"
    )


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


def _possible(n: int) -> str:
    """A count of possible cells: exact below a trillion, else about 1.02e+23."""
    return f"{n:,}" if n < 10**12 else f"about {float(n):.3g}"


def _cmd_fit(args: argparse.Namespace) -> int:
    out = check_output(args.output)
    groups = split_names(args.groups, "--groups")
    frames = parse_frame_columns(args.task_frame)
    frame_hands = parse_frame_hands(args.frame_hands)
    levels = _parse_levels(args.levels)
    weights = None
    if args.weights is not None:
        weights = parse_pairs(args.weights, "--weights", float, "velocity=0.5")
        for g, w in weights.items():
            check_range(w, f"--weights {g}", low=0)
    if args.epsilon is not None:
        check_range(args.epsilon, "--epsilon", low=0)
    if args.n_points is not None:
        check_range(args.n_points, "--n-points", low=2)
    if args.time_bins is not None:
        check_range(args.time_bins, "--time-bins", low=2)
    check_range(args.pseudo_emission, "--pseudo-emission", low=0)
    check_range(args.match_window, "--match-window", low=0, high=0.5)
    if args.n_jobs is not None:
        check_range(args.n_jobs, "--n-jobs", low=1)
    if args.random_state is not None:
        check_range(args.random_state, "--random-state", low=0)
    # the files are read as a stream (twice, on the workers): only the first
    # one here, for the groups and the checks that name the flags

    options = column_options(args)
    paths = demo_files(args.demos, **dataset_options(args))
    check_datasets(args, paths)
    news: list = []
    # the repairs of the data: one summary per kind at the end of the fit
    pairs, first_path = [], paths[0]
    with collecting_repairs():
        for first_path in paths:  # the first not skipped (--bad-files skip)
            with noting(first_path, news):
                pairs = read_framed_or_skip(first_path, CLI_HINTS, frames, **options)
            if pairs or options["bad_files"] != "skip":
                break
    tell(news)
    if not pairs:
        raise ValidationError(
            f"demos: {paths[0]} holds no demonstration"
            if options["bad_files"] != "skip"
            else "demos: every file was skipped (--bad-files skip); expected at"
            " least one readable file"
        )
    first, first_map = pairs[0]
    if groups is None:  # the library's groups="auto", resolved here to report it
        groups = list(resolve_groups("auto", first))
    for what, names in (("--levels", levels), ("--weights", weights)):
        if isinstance(names, dict):
            unknown = [g for g in names if g not in groups]
            if unknown:
                raise ValidationError(
                    f"{what} names {', '.join(unknown)}, which is not learned;"
                    f" the learned groups are {', '.join(groups)} (--groups)"
                )
    with collecting_repairs():
        _, derived = prepare_groups([first], [first_map], groups)
    check_frame_hands(frame_hands, first.frames, groups)
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
        n_routes=args.routes,
        route_groups=args.route_groups,
        frame_hands=frame_hands,
        random_state=args.random_state,
    )
    check_params(model.get_params())  # as fit does, before connecting
    files = FramedDemoFiles.for_cli(paths, frames, **options)
    scanned: dict = {}

    def after_scan(ranges):  # report the mappings, bound the time bins
        mappings = {text: n for text, _, n in ranges.notes}
        scanned["one_mapping"] = len(mappings) == 1
        say(args, describe_mappings(mappings, ranges.n_demos, paths))
        pieces = describe_pieces(first_path, [m for _, m in pairs], len(paths))
        if pieces:
            say(args, pieces)
        bins, note = _check_bounds(args, ranges, paths, defaults.n_time_bins)
        scanned.update(n_demos=ranges.n_demos, time_bins=bins, note=note)
        return dict(n_time_bins=bins, n_points=args.n_points)

    t0 = time.perf_counter()
    client = _connect(args.scheduler)
    try:
        with warnings.catch_warnings():
            if args.quiet:  # the summary warnings of the data's repairs
                warnings.simplefilter("ignore", NdlfdWarning)
            model.fit(files, client=client, after_scan=after_scan)
    finally:
        if client is not None:
            client.close()
    n_demos, time_bins, note = (scanned[k] for k in ("n_demos", "time_bins", "note"))
    elapsed = time.perf_counter() - t0
    # the input's names, for 'ndlfd generate' without --like (one mapping only)
    # (how the files read, not where the first piece of a split recording lay)
    one = replace(first_map, span=None) if scanned["one_mapping"] else None
    model.input_mapping_ = one
    model.save(out)
    k = model.n_keypoints_
    learned = ", ".join(groups) + (
        " (velocity derived from position)" if derived else ""
    )
    say(
        args,
        f"fitted {n_demos} demonstration(s) in {elapsed:.2f} s on {learned}:"
        f" key points {k.min()}-{k.max()} (median {int(np.median(k))}),"
        f" {model.n_states_used_} codebook cells visited (of"
        f" {_possible(model.codebook_.n_states)} possible),"
        f" {time_bins} time bins{note} -> {out}",
    )
    say(args, describe_routes(model))
    if model.task_frames_:
        say(args, describe_frames(model.task_frames_, frame_hands))
    peaks = demos_peaks_line([d for d, _ in pairs], groups)
    if peaks:  # of the first file only: the others are read on the workers
        whose = (
            ""
            if len(paths) == 1
            else f" (of {first_path} only, the first of {len(paths)})"
        )
        say(args, f"demonstrations' peaks{whose}: {peaks}")
    unused = [g for g in first.group_names if g not in groups]
    if unused:
        say(
            args,
            f"not learned: {', '.join(unused)} (in the files but not in --groups;"
            f" learn {'it' if len(unused) == 1 else 'them'} with --groups"
            f" {','.join([*groups, *unused])})",
        )
    return 0


def describe_frames(frames: dict, frame_hands: dict | None = None) -> str:
    """One line: the task frames learned, and how to give new poses of them.

    Parameters
    ----------
    frames : dict of str to ndarray of shape (n_demos, n_values)
        The model's ``task_frames_``.
    frame_hands : dict of str to list of str, optional
        The hands each frame may move (``--frame-hands``), said per frame.

    Examples
    --------
    >>> poses = np.zeros((6, 3))
    >>> poses[1, 0] = 0.1
    >>> print(describe_frames({"object": poses}))
    task frames of the 6 demonstrations: object (3 values; moved over 0.1); new
    poses: ndlfd generate --task-frame object=X,Y,Z
    >>> print(describe_frames({"object": poses}, {"object": ["right"]}))
    task frames of the 6 demonstrations: object (3 values; moved over 0.1; moves
    right only); new poses: ndlfd generate --task-frame object=X,Y,Z
    """
    values = {2: "X,Y", 3: "X,Y,Z", 7: "X,Y,Z,QW,QX,QY,QZ"}
    each, example = [], []
    for name, poses in frames.items():
        size = poses.shape[1]
        quat = ", position and unit quaternion w,x,y,z" if size == 7 else ""
        moves = ""
        if frame_hands and name in frame_hands:
            moves = f"; moves {', '.join(frame_hands[name])} only"
        each.append(f"{name} ({size} values{quat}; {_frame_spread(poses)}{moves})")
        example.append(f"--task-frame {name}={values.get(size, 'V1,...')}")
    n_demos = next(iter(frames.values())).shape[0]
    return (
        f"task frames of the {n_demos} demonstrations: {', '.join(each)}; new"
        f" poses: ndlfd generate {' '.join(example)}"
    )


def _frame_spread(poses: np.ndarray) -> str:
    """How far a frame moved (and turned) over the demonstrations.

    The largest distance between two of its origins, and for a pose with a
    quaternion the largest angle between two of its orientations: how far a
    new pose is inside what was demonstrated.
    """
    from scipy.spatial.distance import pdist

    size = poses.shape[1]
    k = 3 if size == 7 else size
    moved = float(pdist(poses[:, :k]).max(initial=0.0)) if len(poses) > 1 else 0.0
    text = f"moved over {moved:.3g}"
    if size == 7 and len(poses) > 1:
        dots = np.clip(np.abs(poses[:, 3:] @ poses[:, 3:].T), 0.0, 1.0)
        text += f", turned over {np.degrees(2 * np.arccos(dots.min())):.3g} deg"
    return text


#: The pieces of a split recording listed by :func:`describe_pieces`.
MAX_PIECES_LISTED = 12


def describe_pieces(source, mappings, n_files: int) -> str:
    """One line: each piece of a split recording and where it lies in it.

    Parameters
    ----------
    source : path-like
        The recording (the first file read).
    mappings : list of ColumnMapping
        Its demonstrations' mappings; the pieces have a ``span``.
    n_files : int
        The files read in all (the others' pieces are read on the workers).

    Returns
    -------
    line : str
        Empty when the recording was not split.

    Examples
    --------
    >>> from ndlfd.io import ColumnMapping
    >>> m = [ColumnMapping("s:0", "t", (), span=(0.5, 9.25)),
    ...      ColumnMapping("s:1", "t", (), span=(12.0, 20.0))]
    >>> describe_pieces("s", m, 1)
    'pieces of s, in seconds from its first stamp: 0.50-9.25, 12.00-20.00'
    """
    spans = [m.span for m in mappings if m.span is not None]
    if not spans:
        return ""
    shown = ", ".join(f"{a:.2f}-{b:.2f}" for a, b in spans[:MAX_PIECES_LISTED])
    if len(spans) > MAX_PIECES_LISTED:
        shown += f", ... ({len(spans) - MAX_PIECES_LISTED} more)"
    of = f" (the first of {n_files} files)" if n_files > 1 else ""
    return f"pieces of {source}{of}, in seconds from its first stamp: {shown}"


def demos_peaks_line(demos, groups) -> str:
    """The largest velocity and acceleration of each learned group, and where.

    The largest over ``demos`` of :func:`ndlfd.limits.path_peaks`, column by
    column, as ``generate`` reports a path's peaks: not of an orientation
    (quaternions, of any hand), a hand's velocity beside its position
    (derived from it when learned), or a gripper on two values (it switches
    in one sample).
    Demonstrations of fewer than 3 samples have no peaks; the line is empty
    when no group has any.

    Parameters
    ----------
    demos : list of Demonstration
    groups : sequence of str
        The learned groups (others are left out).

    Returns
    -------
    line : str
        ``GROUP velocity V /s (COLUMN), acceleration A /s^2 (COLUMN); ...``

    Examples
    --------
    >>> from ndlfd.demonstration import Demonstration
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> a = Demonstration.from_arrays(t, joints=np.column_stack([2 * t, t * t]))
    >>> b = Demonstration.from_arrays(t, joints=np.column_stack([t, 3 * t * t]))
    >>> demos_peaks_line([a, b], ["joints"])
    'joints velocity 6 /s (joints1), acceleration 6 /s^2 (joints1)'
    """
    top: dict[str, dict[str, np.ndarray]] = {}  # group -> column -> (v, a)
    for d in demos:
        if d.n_samples < 3:
            continue
        peaks = path_peaks(d)
        for c, (g, name) in enumerate(zip(d.groups, d.columns, strict=True)):
            was = top.setdefault(g, {}).get(name, np.zeros(2))
            now = np.array([peaks["velocity"][c], peaks["acceleration"][c]])
            top[g][name] = np.maximum(was, now)
    parts = []
    for g in groups:
        if (
            g not in top
            or kind(g) == "orientation"  # a quaternion (any hand's)
            or (kind(g) == "velocity" and _position_of(g) in top)  # derived
            or (g == "gripper" and _two_valued(demos, g))  # switches
        ):
            continue
        names = list(top[g])
        va = np.array([top[g][n] for n in names])
        iv, ia = int(np.argmax(va[:, 0])), int(np.argmax(va[:, 1]))
        parts.append(
            f"{g} velocity {va[iv, 0]:.3g} /s ({names[iv]}), "
            f"acceleration {va[ia, 1]:.3g} /s^2 ({names[ia]})"
        )
    return "; ".join(parts)


def _position_of(velocity: str) -> str:
    """The position group a hand's velocity group is derived from."""
    return hand_group(hand_name(velocity), "position")


def _two_valued(demos, group: str) -> bool:
    """Whether every column of ``group`` takes at most two values in all demos."""
    values: dict[str, set] = {}
    for d in demos:
        for c in d.columns_of(group) if d.has_group(group) else ():
            values.setdefault(d.columns[c], set()).update(np.unique(d.X[:, c]))
    return all(len(v) <= 2 for v in values.values())


def describe_routes(model) -> str:
    """One line: the routes found, their demonstrations, the groups judged."""
    sizes = np.bincount(model.routes_)
    judged = sorted({model.column_groups_[c] for c in route_columns(
        model.column_groups_, model.route_groups)})  # fmt: skip
    how = "asked for (--routes)" if model.n_routes is not None else "found"
    if sizes.size == 1:
        return (
            f"routes: 1 {how} on {', '.join(judged)}: every demonstration"
            " blended (--routes N to ask for more)"
        )
    each = ", ".join(f"route {r}: {n}" for r, n in enumerate(sizes))
    return (
        f"routes: {sizes.size} {how} on {', '.join(judged)} ({each}"
        " demonstrations); a path follows one (the largest unless a start, goal,"
        " via point or prefix selects another)"
    )


def add_fit(sub) -> None:
    p = sub.add_parser(
        "fit",
        help="learn a model from demonstration files",
        description=(
            "Learn key points, codebook states and a discrete HMM from"
            " demonstration files (CSV, .npz, HDF5 or ROS 2 bags; a folder means"
            " all its .csv/.tsv/.npz/.h5/.hdf5/.mcap/.db3 files, in any case, and"
            " its bag folders). The summary names the learned groups and the"
            " groups in the files that are not learned."
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
        help="comma-separated groups to learn (default: every group the files"
        " have, position, velocity, orientation, force and gripper first, then"
        " the others such as joints; a missing velocity is derived from"
        " position)",
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
        " all groups (default: 20 for position and joints, 10 for velocity,"
        " orientation, force, joint_velocity, joint_effort and any group of your"
        " own, 2 for a gripper)",
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
    add_route_options(p)
    p.add_argument(
        "--random-state",
        type=int,
        default=None,
        metavar="SEED",
        help="which demonstrations are kept whole as templates when there are"
        " more than 200 (default: a fixed choice, the same every run)",
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
    p.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="print no summary and no warnings of repaired data (errors still print)",
    )
    add_column_options(p)
    p.add_argument(
        "--task-frame",
        action="append",
        metavar="NAME=COLUMN,COLUMN,...",
        help="these columns of each file are where its task frame NAME was (the"
        " object, the place): constant over the demonstration, a position of the"
        " position group's dimension, in 3-D optionally followed by a unit"
        " quaternion w,x,y,z (7 columns); they are not learned as data, and"
        " 'ndlfd generate --task-frame NAME=...' gives the frame a new pose;"
        " repeatable, one frame each, e.g. --task-frame"
        " object=obj_x,obj_y,obj_z; of a ROS 2 bag, a topic (PoseStamped, Pose,"
        " TransformStamped, PointStamped: object=/object_pose) or a tf frame"
        " (object=tf:object_frame, in the demonstrations' base frame); of a"
        " LeRobot dataset, a feature (object=observation.object_pose); it must"
        " stay within 5 mm and 3 degrees over each demonstration",
    )
    p.add_argument(
        "--frame-hands",
        action="append",
        metavar="FRAME=HAND[,HAND...]",
        help="the hands task frame FRAME may move (a hand by its name: left for"
        " left_position, position for the unnamed one); the others ignore it;"
        " by default a frame may move every hand, each phase as the"
        " demonstrations agree; repeatable, one frame each, e.g."
        " --frame-hands socket=left --frame-hands peg=right",
    )
    p.set_defaults(func=_cmd_fit)
