"""``ndlfd generate``: a path from a fitted model and a new timing."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .._errors import ValidationError
from ..io import (
    csv_columns,
    csv_header,
    write_csv,
    write_npz,
    write_parquet,
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
from ._rosout import (
    ROS_FORMATS,
    add_ros_output_options,
    check_ros_output,
    is_folder_output,
    write_ros_output,
)

__all__ = ["FLOAT_FORMAT", "FORMATS", "MAX_SAMPLES", "add_generate"]

#: Number format of computed values written by ``ndlfd generate``.
FLOAT_FORMAT = "%.10g"


#: What ``ndlfd generate -o`` writes, by ``--format`` or the output's suffix.
FORMATS = ("csv", "npz", "parquet", "bag", "joint-trajectory")
_FORMAT_OF_SUFFIX = {
    ".csv": "csv",
    ".txt": "csv",
    ".npz": "npz",
    ".parquet": "parquet",
    ".mcap": "bag",
    ".db3": "bag",
    ".yaml": "joint-trajectory",
    ".yml": "joint-trajectory",
}


def _output_format(args: argparse.Namespace, out: Path) -> str:
    suffix = out.suffix.lower()
    given = args.format or ("bag" if is_folder_output(args.output) else None)
    if given is None and suffix not in _FORMAT_OF_SUFFIX:
        known = ", ".join(sorted(_FORMAT_OF_SUFFIX))
        raise ValidationError(
            f"-o {out}: expected a file ending in {known} (or --format"
            f" {'/'.join(FORMATS)}); got {suffix or 'no suffix'}"
        )
    fmt = given or _FORMAT_OF_SUFFIX[suffix]
    check_ros_output(args, out, fmt)
    return fmt


def _cmd_generate(args: argparse.Namespace) -> int:
    out = check_output(args.output)
    fmt = _output_format(args, out)
    std_out = check_output(args.std, "--std") if args.std is not None else None
    n = check_timing(args)
    model, start, goal, via, frames = load_with_conditions(args)
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
        frames=frames,
    )
    path, std = result if std_out is not None else (result, None)
    dense = args.dense or prefix is not None  # a continuation: every time stamp
    exact_time = (
        (args.like is not None or args.rate is not None) and dense
    ) or prefix is not None
    scaled = apply_limits(args, path, dense=dense, std=std, prefix=prefix,
                          trajectory=fmt == "joint-trajectory")  # fmt: skip
    exact_time = exact_time and (
        scaled is path or args.rate is not None or prefix is not None
    )
    path = scaled
    if fmt in ROS_FORMATS:
        observed = 0 if prefix is None else prefix.n_samples
        note = write_ros_output(args, path, out, fmt, like, observed=observed)
        if note:
            say(args, note)
    elif fmt == "npz":
        write_npz(path, out)
    elif fmt == "parquet":
        write_parquet(path, out, mapping=like)
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
            " joints and a gripper, velocities and accelerations 0 at both ends;"
            " --format joint-trajectory -o NAME writes it into a bag for 'ros2 bag"
            " play'),"
            " or as a LeRobot episode's rows (-o PATH.parquet: timestamp,"
            " frame_index, episode_index, index, task_index and the path as one"
            " float32 list column named like the input's feature, e.g. action)."
            " The CSV and Parquet outputs keep the input's column names, order and"
            " time column. Bags need ndlfd[ros], Parquet ndlfd[lerobot]."
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
        help="output file (its folder must exist): .csv, .parquet (a LeRobot"
        " episode), .mcap (a ROS 2 bag), NAME/ (a bag folder) or .yaml (a joint"
        " trajectory)",
    )
    p.add_argument(
        "--format",
        choices=FORMATS,
        help="what -o holds (default: by its suffix: .csv/.txt csv, .npz an ndlfd"
        " .npz (t, X, columns, groups), .parquet parquet, .mcap/.db3 bag, .yaml/.yml"
        " joint-trajectory; another suffix is an error)",
    )
    p.add_argument(
        "--topic",
        metavar="TOPIC",
        help="the pose topic of a bag output (default /ndlfd/path), or the topic"
        " of a joint trajectory's bag (default"
        " /joint_trajectory_controller/joint_trajectory)",
    )
    add_ros_output_options(p)
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    add_column_options(p, what="--like file", bags="like-")
    p.set_defaults(func=_cmd_generate)
