"""What every command shares: flags, checks, reading and one-line reports.

The parser class (:class:`Parser`, one-line usage errors), the parsing of
comma-separated flags and the range checks (:func:`check_range`: one message for
every bounded setting), the output checks (:func:`check_output`), the column
mapping flags (:func:`add_column_options`, :func:`column_options`), reading
demonstrations with them (:func:`read_sources`) and the one-line reports
(:func:`say` on stderr unless ``-q``; :func:`noting` and :func:`tell`: one warning
line per kind of news), and the timing of a path from a model
(:func:`add_timing_options`, :func:`check_timing`, :func:`read_timing`:
``ndlfd generate`` and ``ndlfd sample``; where it goes is
:mod:`ndlfd.cli._conditions`). A command module uses these and adds its own
flags.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections import Counter
from pathlib import Path

import numpy as np

from .._errors import DataFileError, ValidationError
from .._pose_groups import hand_group, hand_name, is_orientation, kind
from .._repairs import repaired
from .._validation import check_times
from ..demonstration import with_velocity
from ..io import (
    BAD_FILES,
    BAD_ROWS,
    CLI_HINTS,
    TIME_NAMES,
    LeRobotEpisode,
    demo_files,
    parse_table,
    read_file,
    read_or_skip,
)
from ..io._hdf5 import HDF5_SUFFIXES
from ..orientation import QUATERNION_ORDERS, check_euler, check_representation
from ._news import noting, quiet_news, tell
from ._parsing import (
    check_output,
    check_range,
    parse_floats,
    parse_pairs,
    split_names,
)

__all__ = [
    "EXIT_USAGE",
    "GROUP_NAME",
    "MAX_SAMPLES",
    "Parser",
    "add_bad_data_options",
    "add_column_options",
    "add_timing_options",
    "bad_data_options",
    "check_datasets",
    "check_output",
    "check_range",
    "check_timing",
    "column_options",
    "dataset_options",
    "describe_mappings",
    "like_times",
    "noting",
    "parse_floats",
    "parse_pairs",
    "prepare_groups",
    "quiet_news",
    "read_one",
    "read_sources",
    "read_timing",
    "say",
    "split_names",
    "tell",
]

#: The exit status of every usage or data error.
EXIT_USAGE = 2
#: A name a group may have on the command line (``--group NAME=...``).
GROUP_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")
#: Most samples of a generated path's uniform time grid (80 MB per column).
MAX_SAMPLES = 10_000_000


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line, like every other error."""

    def error(self, message: str) -> None:  # type: ignore[override]
        """Print one line naming the command and exit with status 2.

        A flag left without its value because the value starts with ``-``
        (``--start -1,2`` reads ``-1,2`` as a flag) is told to use ``=``.
        """
        hint = f"see {self.prog} --help"
        flag = re.match(r"argument (--[\w-]+): expected one argument", message)
        if flag:
            hint = f"a value that starts with '-' takes '=': {flag[1]}=-...; {hint}"
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} ({hint})\n")


def say(args: argparse.Namespace, line: str) -> None:
    """Print one summary line on stderr unless ``-q``."""
    if not getattr(args, "quiet", False):
        print(line, file=sys.stderr)


# ------------------------------------------------------------- data columns
def add_column_options(
    p,
    *,
    what: str = "demonstration files",
    bags: str | None = "",
    demonstrations: bool = True,
) -> None:
    """Add the column mapping flags to the parser ``p``.

    With ``bags`` (a flag prefix; ``None``: none), also a bag's topics; with
    ``demonstrations``, the flags of the readers of whole demonstrations
    (orientation conventions, LeRobot datasets).
    """
    g = p.add_argument_group(
        f"columns of the {what}",
        "CSV files are comma-, semicolon-, tab- or whitespace-separated (the header"
        " row decides); .npz files hold arrays and HDF5 files one group per"
        " episode, mapped like columns (a 2-D array is a whole group); .npy files"
        " one array whose columns --columns or a sidecar NAME.columns.txt names."
        " Names match in any case. Columns not named here go by their names: x,y,z"
        " position, vx,vy,vz velocity, qw,qx,qy,qz orientation, fx,fy,fz force,"
        " group.name a group of your own, or as labs export them: pos_x or"
        " PREFIX_pos_x, PREFIX_orientation_w..z or quat_w..z, force_x, torque_x,"
        " joint_1 or q1; of a measured and a commanded set (current_/actual_ beside"
        " goal_/desired_/cmd_/target_) the measured one is learned and the other"
        " left out with a warning. 2-D arrays named position/pos, velocity/vel,"
        " orientation/quat, force. The mapping used is reported on one line.",
    )
    g.add_argument(
        "--time-column",
        metavar="NAME",
        help="the time column (strictly increasing; default: 't', 'time' or"
        " 'timestamp')",
    )
    g.add_argument(
        "--group",
        action="append",
        metavar="GROUP=NAME[,NAME...][:REPR]",
        help="put these columns (or one 2-D array) in GROUP, e.g."
        " --group position=pos_x,pos_y or --group position=pos; names may be glob"
        " patterns (--group joints='joint_*'); repeatable. Orientation columns"
        " are listed in w,x,y,z order; three orientation columns need their"
        " representation after a colon: --group orientation=rx,ry,rz:rotvec (a"
        " rotation vector, axis times angle), :euler-xyz (Euler angles, any scipy"
        " sequence such as euler-ZYX); four may say :quat-wxyz or :quat-xyzw",
    )
    g.add_argument(
        "--drop",
        metavar="NAME[,NAME...]",
        help="columns to leave out of the data; names may be glob patterns, e.g."
        " --drop 'goal_*'",
    )
    if bags is not None:
        b = p.add_argument_group(
            f"ROS 2 bags among the {what}",
            "A bag is a folder with metadata.yaml or an .mcap/.db3 file (needs"
            " ndlfd[ros]). PoseStamped, PoseWithCovarianceStamped, TransformStamped,"
            " TFMessage (/tf) and Odometry give position x,y,z and orientation"
            " qw,qx,qy,qz; JointState the group joints (one column per joint);"
            " Float64/Float32 a group named after the topic. Time: the header stamps"
            " (the receive time without them), from 0.",
        )
        b.add_argument(
            f"--{bags}topic",
            dest="bag_topic",
            action="append",
            metavar="TOPIC",
            help="a topic to read (default: the bag's only readable one); repeat it"
            " to combine topics: the later ones are resampled onto the first one's"
            " stamps (linear, orientation by slerp)",
        )
        b.add_argument(
            f"--{bags}frame",
            dest="bag_frame",
            metavar="FRAME",
            help="the frame whose pose is read from /tf (implies --topic /tf):"
            " composed along the tf tree, /tf_static included, to --base-frame",
        )
        b.add_argument(
            f"--{bags}base-frame",
            dest="bag_base_frame",
            metavar="FRAME",
            help="the frame the pose of --frame is in (default: the root of its tf"
            " tree, e.g. base_link or world)",
        )
        if not bags:
            g.add_argument(
                "--rate",
                dest="read_rate",
                type=float,
                metavar="HZ",
                help="the sample rate of files without time stamps (fixed-rate logs:"
                " no time column, .npy arrays); row k is at k / HZ seconds",
            )
            b.add_argument(
                "--split-gap",
                type=float,
                metavar="SECONDS",
                help="one demonstration per stretch of a bag without a gap in the first"
                " topic's stamps longer than this (> 0)",
            )
            b.add_argument(
                "--split-still",
                type=float,
                metavar="SECONDS",
                help="one demonstration per stretch of a bag between rests of at"
                " least this long (> 0): the robot keeps publishing but nothing moves"
                " faster than 5 %% of the recording's typical moving speed (the 90th"
                " percentile of the speeds, every column scaled by its range); a"
                " warning when none is found or more than 50 pieces",
            )
    if demonstrations:
        _add_demonstration_options(p, g)
        add_bad_data_options(p)


def _add_demonstration_options(p, g) -> None:
    """Orientation conventions and LeRobot datasets (issue 19)."""
    g.add_argument(
        "--quaternion-order",
        default="wxyz",
        choices=QUATERNION_ORDERS.names,
        help="the order of four orientation columns not named qw,qx,qy,qz"
        " (default wxyz; xyzw is scipy's and ROS's)",
    )
    g.add_argument(
        "--euler",
        default=None,
        metavar="AXES",
        help="the convention of Euler angle columns (roll,pitch,yaw, or three"
        " columns of --group orientation=..., radians), which are learned as unit"
        " quaternions and written back as angles: xyz (the default for"
        " roll,pitch,yaw) is extrinsic (ROS's roll-pitch-yaw), XYZ intrinsic,"
        " e.g. ZYX",
    )
    g.add_argument(
        "--columns",
        metavar="NAME[,NAME...]",
        help="the names of the columns of .npy files (one 2-D array each), in"
        " order; without it, each file's sidecar NAME.columns.txt (the names"
        " separated by commas or new lines)",
    )
    d = p.add_argument_group(
        "LeRobot datasets",
        "A folder with meta/info.json is a LeRobot dataset (layout 2.x or 3.0): one"
        " demonstration per episode, time from 'timestamp', the columns named after"
        " the feature's components in info.json and mapped as above. Needs"
        " ndlfd[lerobot] (pyarrow).",
    )
    d.add_argument(
        "--feature",
        metavar="NAME",
        help="the feature read (default observation.state; e.g. action)",
    )
    d.add_argument(
        "--episodes",
        metavar="SELECTION",
        help="the episodes read: a slice such as 0:40 or -10: (Python syntax, over"
        " the episodes in order), an episode index, or a list such as 3,5,8"
        " (default all)",
    )


def dataset_options(args: argparse.Namespace) -> dict:
    """``demo_files`` keyword arguments from ``--feature/--episodes``."""
    out = {}
    if getattr(args, "feature", None) is not None:
        out["feature"] = args.feature.strip()
    if getattr(args, "episodes", None) is not None:
        out["episodes"] = args.episodes
    return out


def check_datasets(args: argparse.Namespace, items) -> None:
    """Refuse ``--feature/--episodes`` when no source is a LeRobot dataset.

    ``--feature`` also picks what ALOHA / ACT episode files (``.hdf5``) give
    (``/action`` or ``observations/qpos``), so an HDF5 source allows it.
    """
    given = [f"--{f}" for f in ("feature", "episodes")
             if getattr(args, f, None) is not None]  # fmt: skip
    if not given or any(isinstance(p, LeRobotEpisode) for p in items):
        return
    hdf5 = any(Path(str(p)).suffix.lower() in HDF5_SUFFIXES for p in items)
    if given == ["--feature"] and hdf5:
        return
    where = " or ALOHA episode files (.hdf5)" if given[0] == "--feature" else ""
    raise ValidationError(
        f"{given[0]} selects from a LeRobot dataset (a folder with"
        f" meta/info.json){where}; none of the sources is one"
    )


def column_options(args: argparse.Namespace) -> dict:
    """``read_demos`` keyword arguments from ``--time-column/--group/--drop``.

    ``--group orientation=A,B,C:REPR`` gives the orientation's
    representation (``representation``).
    """
    groups: dict[str, list[str]] | None = None
    representation = None
    for entry in args.group or ():
        if "=" not in entry:
            raise ValidationError(
                f"--group must look like GROUP=NAME[,NAME...], e.g."
                f" position=pos_x,pos_y; got {entry!r}"
            )
        name, _, cols = entry.partition("=")
        name = name.strip()
        if not GROUP_NAME.match(name):
            raise ValidationError(
                "--group GROUP must be a name of letters, digits, '_' and '-'"
                f" (starting with a letter or '_'); got {name!r} in {entry!r}"
            )
        groups = groups if groups is not None else {}
        if name in groups:
            raise ValidationError(f"--group {name} is given twice")
        cols, rep = _representation_suffix(name, cols, entry)
        if rep is not None and representation not in (None, rep):
            raise ValidationError(
                f"--group {entry}: every orientation of a file is in one"
                f" representation; got {representation} and {rep}"
            )
        if rep is not None:
            representation = rep
        groups[name] = split_names(cols, f"--group {name}")
    time_column = args.time_column
    if time_column is not None and not time_column.strip():
        raise ValidationError("--time-column must name a column; got ''")
    euler = getattr(args, "euler", None)
    if euler is not None:
        try:
            euler = check_euler(euler)
        except ValidationError as exc:
            raise ValidationError("--" + str(exc)) from None
    options = {
        "time_column": TIME_NAMES if time_column is None else time_column.strip(),
        "groups": groups,
        "drop": split_names(args.drop, "--drop") or (),
        "quaternion_order": getattr(args, "quaternion_order", "wxyz"),
        "euler": euler,
    }
    if representation is not None:
        options["representation"] = representation
    if getattr(args, "feature", None) is not None:  # an ALOHA episode file's
        options["feature"] = args.feature.strip()
    columns = split_names(getattr(args, "columns", None), "--columns")
    if columns is not None:
        options["columns"] = columns
    split_gap = getattr(args, "split_gap", None)
    split_still = getattr(args, "split_still", None)
    for flag, value in (("--split-gap", split_gap), ("--split-still", split_still)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise ValidationError(
                f"{flag} must be a number of seconds > 0; got {value:g}"
            )
    bag = {
        "topic": getattr(args, "bag_topic", None),
        "frame": getattr(args, "bag_frame", None),
        "base_frame": getattr(args, "bag_base_frame", None),
        "split_gap": split_gap,
        "split_still": split_still,
        "rate": getattr(args, "read_rate", None),
    }
    options.update({k: v for k, v in bag.items() if v is not None})
    options.update(bad_data_options(args))
    return options


def _representation_suffix(name: str, cols: str, entry: str):
    """``A,B,C:REPR`` split into the names and the representation (or None)."""
    head, sep, rep = cols.rpartition(":")
    if not sep:
        return cols, None
    rep = rep.strip()
    try:
        check_representation(rep)
    except ValidationError as exc:
        raise ValidationError(f"--group {entry}: {exc}") from None
    if not is_orientation(name):
        raise ValidationError(
            f"--group {entry}: a representation ({rep}) is for an orientation"
            f" group (orientation, <hand>_orientation); got it on {name!r}"
        )
    return head, rep


# --------------------------------------- bad rows and files (every reading command)
def add_bad_data_options(p, *, files: bool = True) -> None:
    """Add ``--bad-rows`` (and with ``files``, ``--bad-files``) to the parser ``p``.

    :func:`add_column_options` adds both for every command that reads whole
    demonstrations (``fit``, ``plot``, ``generate``/``sample --like``);
    ``ndlfd simplify`` reads one file and adds ``--bad-rows`` alone.
    """
    g = p.add_argument_group(
        "bad data",
        "what to do with rows of NaN or inf and files that cannot be read;"
        " what is dropped or skipped is reported in one warning per kind",
    )
    g.add_argument(
        "--bad-rows",
        choices=BAD_ROWS,
        default="error",
        help="a row with NaN or inf: an error naming it (default), or dropped"
        " (a file must keep at least 2 rows)",
    )
    if files:
        g.add_argument(
            "--bad-files",
            choices=BAD_FILES,
            default="error",
            help="a file that cannot be read: an error (default), or skipped with"
            " the reason",
        )


def bad_data_options(args) -> dict:
    """``bad_rows`` and ``bad_files`` of the flags (the defaults without them)."""
    return {
        "bad_rows": getattr(args, "bad_rows", "error"),
        "bad_files": getattr(args, "bad_files", "error"),
    }


def describe_mappings(texts: dict[str, int], n_demos: int, items) -> str:
    """One line: how the files were read (the distinct mappings, with counts)."""
    n_eps = sum(isinstance(p, LeRobotEpisode) for p in items)
    parts = [f"{len(items) - n_eps} file(s)"] if len(items) > n_eps else []
    parts += [f"{n_eps} LeRobot episode(s)"] if n_eps else []
    head = f"read {n_demos} demonstration(s) from {' and '.join(parts)}"
    if len(texts) == 1:
        return f"{head}: {next(iter(texts))}"
    return f"{head}: " + " | ".join(f"{k} as {t}" for t, k in texts.items())


def read_sources(args, sources, *, flag: str, progress: bool = False, read=None):
    """Read demonstrations with the column options; report the mapping.

    ``read`` reads one file as :func:`~ndlfd.io.read_or_skip` does (its
    default), e.g. with task frames (``ndlfd plot --task-frame``).
    """
    read = read_or_skip if read is None else read
    options = column_options(args)
    paths = demo_files(sources, **dataset_options(args))
    check_datasets(args, paths)
    if progress:
        paths_iter = _progress(paths, len(paths), "reading demos")
    else:
        paths_iter = paths
    pairs, news = [], []
    for p in paths_iter:
        with noting(p, news):
            pairs.extend(read(p, CLI_HINTS, **options))
    tell(news)
    if not pairs:
        skipped = options["bad_files"] == "skip"
        raise ValidationError(
            f"{flag}: every file was skipped (--bad-files skip); expected at least"
            " one readable file"
            if skipped
            else f"{flag}: the files hold no demonstration"
        )
    demos = [d for d, _ in pairs]
    maps = [m for _, m in pairs]
    texts = Counter(str(m) for m in maps)
    say(args, describe_mappings(texts, len(maps), paths))
    return demos, maps


def _progress(iterable, total: int, desc: str):
    """Wrap ``iterable`` in a progress bar on a terminal (silent otherwise)."""
    from tqdm import tqdm

    bar = dict(desc=desc, unit="file", disable=None, leave=False)
    return tqdm(iterable, total=total, **bar)


def prepare_groups(demos, maps, groups: list[str]):
    """Each demonstration's learned groups (velocity derived when missing).

    Errors name ``--groups`` and the file, like every check of the data.
    """
    out, news = [], []
    derived = False
    for d, m in zip(demos, maps, strict=True):
        for vel in [g for g in groups if kind(g) == "velocity"]:  # every hand's
            if d.has_group(vel):
                continue
            hand = hand_name(vel)
            if not d.has_group(hand_group(hand, "position")):
                raise ValidationError(
                    f"--groups asks for {vel}, but {m.source} has neither"
                    f" {vel} nor {hand_group(hand, 'position')} to derive it from;"
                    f" it has {', '.join(d.group_names)}"
                )
            with noting(m.source, news):
                d = with_velocity(d, hand=hand)
            derived = True
        missing = [g for g in groups if not d.has_group(g)]
        if missing:
            raise ValidationError(
                f"--groups asks for {', '.join(missing)}, but {m.source} has only"
                f" {', '.join(d.group_names)} ({m}); map its columns with --group"
                f" {missing[0]}=NAME,... or leave it out of --groups"
            )
        out.append(d.select(*groups))
    tell(news)
    first = out[0]
    for d, m in zip(out[1:], maps[1:], strict=True):
        if d.columns != first.columns or d.groups != first.groups:
            raise ValidationError(
                f"every demonstration must have the same columns; {maps[0].source}"
                f" has {', '.join(first.columns)} and {m.source} has"
                f" {', '.join(d.columns)}"
            )
    return out, derived


# ------------------------------------------------------- a path from a model


def add_route_options(p) -> None:
    """``--routes N`` and ``--route-groups`` (fit; plot colours by route)."""
    p.add_argument(
        "--routes",
        type=int,
        default=None,
        metavar="N",
        help="how many routes the demonstrations take (default: found from the"
        " gaps between them on the route groups)",
    )
    p.add_argument(
        "--route-groups",
        type=lambda text: [g.strip() for g in text.split(",") if g.strip()],
        default=None,
        metavar="G1,G2",
        help="the groups routes are judged on (default: position, else every"
        " group but velocity, orientation, force and gripper)",
    )


def add_timing_options(p) -> None:
    """``--like``, ``--duration``, ``--samples`` and ``--rate``."""
    p.add_argument(
        "--like",
        help="a test demonstration whose timing is used (one file, or one episode"
        " of a LeRobot dataset with --episodes N); when it gives the orientation"
        " as Euler angles, the output does too, under its names",
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
        "--rate",
        type=float,
        metavar="HZ",
        help="the time grid's sample rate instead of --samples: stamps k / HZ"
        " exactly, from 0 to the last at or before --duration",
    )


def check_timing(args: argparse.Namespace) -> int | None:
    """Check ``--like`` against ``--duration``/``--samples``.

    Returns
    -------
    n : int or None
        The samples of the uniform grid (``None`` with ``--like``).
    """
    rate = getattr(args, "rate", None)
    if args.like is not None:
        if args.duration is not None or args.samples is not None:
            raise ValidationError(
                "pass either --like or --duration/--samples, not both (--rate with"
                " --like gives the stamps of a file without a time column)"
            )
        if rate is not None and not (rate > 0 and math.isfinite(rate)):
            raise ValidationError(f"--rate must be a finite number > 0; got {rate}")
        return None
    if args.duration is None:
        raise ValidationError("pass --like FILE or --duration SECONDS")
    if not (args.duration > 0 and math.isfinite(args.duration)):
        raise ValidationError(
            f"--duration must be a finite number > 0; got {args.duration}"
        )
    if rate is not None:
        if args.samples is not None:
            raise ValidationError("pass either --samples or --rate, not both")
        if not (rate > 0 and math.isfinite(rate)):
            raise ValidationError(f"--rate must be a finite number > 0; got {rate}")
        # the stamps k / rate up to the duration (a rounding of the product
        # just under an integer counts as that integer)
        n = math.floor(args.duration * rate * (1.0 + 1e-12)) + 1
        if not 2 <= n <= MAX_SAMPLES:
            raise ValidationError(
                f"--duration {args.duration:g} at --rate {rate:g} gives {n:,}"
                f" samples; expected 2 to {MAX_SAMPLES:,}"
            )
        return n
    n = args.samples if args.samples is not None else 1000
    check_range(n, "--samples", low=2, high=MAX_SAMPLES)
    return n


def read_timing(args: argparse.Namespace, n: int | None, *, times_only=False):
    """The timing and its column mapping (``None`` for a uniform grid).

    The ``--like`` demonstration (its mapping says how to write the output:
    Euler angles, the file's names), or ``n`` uniform time stamps. With
    ``times_only`` (a model that uses only the timing), a CSV file whose
    columns the flags do not map gives its time column alone, without a
    mapping (:func:`like_times`).
    """
    if args.like is None:
        if getattr(args, "rate", None) is not None:
            return np.arange(n) / args.rate, None
        return np.linspace(0.0, args.duration, n), None
    rate = getattr(args, "rate", None)
    if times_only:
        got = like_times(args)
        if got is not None:
            return got
    if rate is None:
        return read_one(args, args.like, "--like")
    try:  # a file without time stamps: row k at k / rate
        return read_one(_with_read_rate(args, rate), args.like, "--like")
    except DataFileError as exc:
        if "has a time column" not in str(exc):
            raise
    demo, mapping = read_one(args, args.like, "--like")
    _check_like_rate(args, demo.t, mapping.time)
    return demo, mapping


def _with_read_rate(args: argparse.Namespace, rate) -> argparse.Namespace:
    """``args`` with ``rate`` as the sample rate of files without time stamps."""
    return argparse.Namespace(**{**vars(args), "read_rate": rate})


def _check_like_rate(args, t: np.ndarray, name) -> None:
    """Refuse a ``--like`` file whose own stamps disagree with ``--rate``."""
    want = np.arange(t.size) / args.rate
    tol = 1e-6 / args.rate
    if not np.allclose(t - t[0], want, rtol=0, atol=tol):
        k = int(np.argmax(np.abs(t - t[0] - want) > tol))
        raise ValidationError(
            f"--like {args.like} has its own time stamps (column {name!r}), which"
            f" are not k / {args.rate:g} Hz: {float(t[k] - t[0])!r} s at sample {k},"
            f" not {float(want[k])!r}; pass --rate only for a file without a time"
            " column"
        )


def read_one(args: argparse.Namespace, source, flag: str):
    """The one demonstration ``source`` holds, read with the column flags.

    Returns
    -------
    demo : Demonstration
    mapping : ColumnMapping
        How its columns were read (the output may write them back so).
    """
    demos, maps = read_sources(args, source, flag=flag)
    if len(demos) != 1:
        raise ValidationError(
            f"{flag} must name one demonstration; {source} holds"
            f" {len(demos)} ({maps[0].source}, {maps[1].source}, ...)"
        )
    return demos[0], maps[0]


def like_times(args: argparse.Namespace):
    """The time stamps of a ``--like`` CSV file, and its mapping when it maps.

    Only the time column is needed for the timing: when the file's other
    columns cannot be mapped by the flags (names that need ``--group``), its
    time column alone is read, and the mapping is ``None`` (the output keeps
    the model's names). ``None`` for anything but one CSV file.

    A NaN or inf among the values does not matter (only the time is used):
    the time column alone is read then. ``--bad-rows drop`` drops the rows
    whose time stamp is NaN or inf (reported); by default they are an error.
    """
    paths = demo_files(args.like, **dataset_options(args))
    p = paths[0]
    if len(paths) != 1 or not isinstance(p, Path) or not p.is_file():
        return None
    if p.suffix.lower() in (".npz", ".npy", ".h5", ".hdf5", ".mcap", ".db3"):
        return None
    rate = getattr(args, "rate", None)
    if rate is not None:
        return _like_times_at_rate(args, p, paths)
    options = column_options(args)
    news: list = []
    try:
        with noting(p, news):  # values with NaN: the time column alone
            pairs = read_file(p, CLI_HINTS, **{**options, "bad_rows": "error"})
    except DataFileError:
        pairs = None
    if pairs:
        tell(news)
        demo, mapping = pairs[0]
        if len(pairs) != 1:
            return None  # several demonstrations: read_timing says so
        say(args, describe_mappings(Counter([str(mapping)]), 1, paths))
        return demo, mapping
    table = parse_table(p, finite=False)
    tc = options["time_column"]
    if tc is None:
        return np.arange(table.data.shape[0], dtype=np.float64), None
    for name in [tc] if isinstance(tc, str) else list(tc):
        hits = [c for c in table.columns if c == name] or [
            c for c in table.columns if c.casefold() == name.casefold()
        ]
        if len(hits) == 1:
            t = table.data[:, table.columns.index(hits[0])]
            bad = ~np.isfinite(t)
            if bad.any() and options["bad_rows"] == "drop":
                repaired(
                    "rows",
                    int(bad.sum()),
                    f"--like {p}: dropped {int(bad.sum())} of {t.size} row(s) with"
                    f" NaN or inf in the time column {hits[0]!r}",
                )
                t = t[~bad]
            t = check_times(t, name=f"--like {p}: time column {hits[0]!r}")
            say(args, f"--like {p}: time={hits[0]} (its time stamps only)")
            return t, None
    raise DataFileError(
        f"--like {p}: expected a time column named {tc!r} (any case); got columns"
        f" {table.columns}; {CLI_HINTS['time_hint']}"
    )


def _like_times_at_rate(args, p: Path, paths):
    """:func:`like_times` with ``--rate``: the file's rows at that rate.

    A file with its own time column keeps its stamps when they are
    ``k / rate`` (else an error); one whose columns the flags do not map
    gives its rows' times alone.
    """
    options = column_options(_with_read_rate(args, args.rate))
    news: list = []
    try:
        with noting(p, news):
            pairs = read_file(p, CLI_HINTS, **{**options, "bad_rows": "error"})
    except DataFileError as exc:
        if "has a time column" in str(exc):
            return None  # read with its stamps, checked against the rate
        pairs = None
    if pairs and len(pairs) == 1:
        tell(news)
        say(args, describe_mappings(Counter([str(pairs[0][1])]), 1, paths))
        return pairs[0]
    table = parse_table(p, finite=False)
    low = [c.casefold() for c in table.columns]
    if any(name in low for name in TIME_NAMES):
        return None
    n = table.data.shape[0]
    say(args, f"--like {p}: {n} rows at {args.rate:g} Hz (its length only)")
    return np.arange(n, dtype=np.float64) / args.rate, None
