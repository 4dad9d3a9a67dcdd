"""``ndlfd generate``: a path from a fitted model and a new timing."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .._errors import ValidationError
from ..io import (
    csv_columns,
    csv_header,
    write_bag,
    write_csv,
    write_joint_trajectory,
    write_npz,
    write_table,
)
from ._conditions import (
    add_condition_options,
    load_with_conditions,
    output_mapping,
    read_observed,
)
from ._limits import add_limit_options, apply_limits
from ._options import (
    MAX_SAMPLES,
    add_column_options,
    add_timing_options,
    check_output,
    check_timing,
    read_timing,
    say,
)

__all__ = ["FLOAT_FORMAT", "FORMATS", "MAX_SAMPLES", "add_generate"]

#: Number format of computed values written by ``ndlfd generate``.
FLOAT_FORMAT = "%.10g"


#: What ``ndlfd generate -o`` writes, by ``--format`` or the output's suffix.
FORMATS = ("csv", "npz", "bag", "joint-trajectory")
_FORMAT_OF_SUFFIX = {
    ".csv": "csv",
    ".txt": "csv",
    ".npz": "npz",
    ".mcap": "bag",
    ".db3": "bag",
    ".yaml": "joint-trajectory",
    ".yml": "joint-trajectory",
}


def _output_format(args: argparse.Namespace, out: Path) -> str:
    suffix = out.suffix.lower()
    if args.format is None and suffix not in _FORMAT_OF_SUFFIX:
        known = ", ".join(sorted(_FORMAT_OF_SUFFIX))
        later = " (Parquet and LeRobot output are not written yet)"
        raise ValidationError(
            f"-o {out}: expected a file ending in {known} (or --format"
            f" {'/'.join(FORMATS)}); got {suffix or 'no suffix'}"
            + (later if suffix == ".parquet" else "")
        )
    fmt = args.format or _FORMAT_OF_SUFFIX[suffix]
    if fmt == "bag" and out.suffix.lower() not in (".mcap", ".db3"):
        raise ValidationError(
            f"--format bag writes one .mcap (or .db3) file; got -o {out}"
            f" (e.g. -o {out.with_suffix('.mcap')})"
        )
    if args.topic is not None and fmt != "bag":
        raise ValidationError(
            f"--topic names the topic of a bag output (-o PATH.mcap); -o {out}"
            f" writes {fmt}"
        )
    return fmt


def _cmd_generate(args: argparse.Namespace) -> int:
    out = check_output(args.output)
    fmt = _output_format(args, out)
    std_out = check_output(args.std, "--std") if args.std is not None else None
    n = check_timing(args)
    model, start, goal, via = load_with_conditions(args)
    if std_out is not None and model.generation != "blend":
        raise ValidationError(
            "--std needs a model fitted with --generation blend; this one uses"
            f" {model.generation}"
        )
    timing, like = read_timing(args, n, times_only=model.generation != "paper")
    prefix, timing, observed_map = read_observed(args, timing)
    like = output_mapping(model, like, observed_map)
    result = model.generate(
        timing,
        dense=args.dense,
        start=start,
        goal=goal,
        via=via,
        observed=prefix,
        return_std=std_out is not None,
    )
    path, std = result if std_out is not None else (result, None)
    dense = args.dense or prefix is not None  # a continuation: every time stamp
    exact_time = (
        (args.like is not None or args.rate is not None) and dense
    ) or prefix is not None
    scaled = apply_limits(args, path, dense=dense, std=std, prefix=prefix)
    exact_time = exact_time and (scaled is path or args.rate is not None)
    path = scaled
    if fmt == "bag":
        write_bag(path, out, topic=args.topic or "/ndlfd/path")
    elif fmt == "joint-trajectory":
        write_joint_trajectory(path, out)
    elif fmt == "npz":
        write_npz(path, out)
    else:
        _write_path(path, out, exact_time=exact_time, like=like)
    if std is not None:  # the path's columns (std of a quaternion is no quaternion)
        formats = [None if exact_time else FLOAT_FORMAT]
        formats += [FLOAT_FORMAT] * path.n_dims
        header, index = csv_header(path, "t"), np.arange(path.n_dims)
        if fmt == "csv" and (like is None or like.euler is None):
            header, index = csv_columns(path, "t", like)  # as the path's CSV
        data = np.column_stack([path.t, std[:, index]])
        write_table(std_out, header, data, float_format=formats)
    what = "samples" if dense else "key points"
    if prefix is not None:
        what += f" (the first {prefix.n_samples} observed)"
    also = f" and its standard deviation -> {std_out}" if std_out is not None else ""
    say(args, f"generated {path.n_samples} {what} -> {out}{also}")
    return 0


def _write_path(demo, path: Path, *, exact_time: bool, like=None) -> None:
    """Computed values with ten significant digits; given time stamps exactly.

    When the ``--like`` file gave the orientation as Euler angles (its mapping
    ``like`` says so), the orientation is written back as those columns.
    """
    write_csv(
        demo,
        path,
        float_format=FLOAT_FORMAT,
        time_format=None if exact_time else FLOAT_FORMAT,
        mapping=like,
    )


def add_generate(sub) -> None:
    p = sub.add_parser(
        "generate",
        help="generate a path from a model and a new timing",
        description=(
            "Decode a new timing with a fitted model and write the generated path"
            " (key points, or every sample with --dense) as CSV, numbers with ten"
            " significant digits (the time stamps of --like exactly); or as a ROS 2"
            " bag (-o PATH.mcap: a PoseStamped per sample on --topic for position"
            " and orientation, a JointState on TOPIC/joint_states for joints, a"
            " topic TOPIC/GROUP for each other group such as a gripper; replay it"
            " with 'ros2 bag play PATH.mcap'), or as a"
            " trajectory_msgs/msg/JointTrajectory in YAML (-o PATH.yaml: the group"
            " joints, velocities by numpy.gradient; send it with 'ros2 topic pub')."
            " Bags need ndlfd[ros]."
        ),
    )
    p.add_argument("model", help="model file written by 'ndlfd fit'")
    add_timing_options(p)
    add_condition_options(p)
    add_limit_options(p)
    p.add_argument(
        "--dense",
        action="store_true",
        help="interpolate to every time stamp instead of writing key points"
        " (always with --observed)",
    )
    p.add_argument(
        "--std",
        metavar="FILE.csv",
        help="also write the path's standard deviation (same columns) there, for"
        " 'ndlfd plot --std' (models fitted with --generation blend)",
    )
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="output file (its folder must exist): .csv, .mcap (a ROS 2 bag) or"
        " .yaml (a joint trajectory)",
    )
    p.add_argument(
        "--format",
        choices=FORMATS,
        help="what -o holds (default: by its suffix: .csv/.txt csv, .npz an ndlfd"
        " .npz (t, X, columns, groups), .mcap/.db3 bag, .yaml/.yml"
        " joint-trajectory; another suffix is an error)",
    )
    p.add_argument(
        "--topic",
        metavar="TOPIC",
        help="the pose topic of a bag output (default /ndlfd/path)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    add_column_options(p, what="--like file", bags="like-")
    p.set_defaults(func=_cmd_generate)
