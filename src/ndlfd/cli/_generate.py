"""``ndlfd generate``: a path from a fitted model and a new timing."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from .._errors import ValidationError
from ..io import (
    csv_header,
    write_bag,
    write_csv,
    write_joint_trajectory,
    write_table,
)
from ..learner import KeypointHMM
from ._options import (
    add_column_options,
    check_output,
    check_range,
    parse_floats,
    read_sources,
    say,
)

__all__ = ["FLOAT_FORMAT", "FORMATS", "MAX_SAMPLES", "add_generate"]

#: Most samples ``ndlfd generate --samples`` writes (80 MB per column).
MAX_SAMPLES = 10_000_000
#: Number format of computed values written by ``ndlfd generate``.
FLOAT_FORMAT = "%.10g"


#: What ``ndlfd generate -o`` writes, by ``--format`` or the output's suffix.
FORMATS = ("csv", "bag", "joint-trajectory")
_FORMAT_OF_SUFFIX = {
    ".mcap": "bag",
    ".db3": "bag",
    ".yaml": "joint-trajectory",
    ".yml": "joint-trajectory",
}


def _output_format(args: argparse.Namespace, out: Path) -> str:
    fmt = args.format or _FORMAT_OF_SUFFIX.get(out.suffix.lower(), "csv")
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
        check_range(n, "--samples", low=2, high=MAX_SAMPLES)
    start = parse_floats(args.start, "--start")
    goal = parse_floats(args.goal, "--goal")
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
        demos, maps = read_sources(args, args.like, flag="--like")
        if len(demos) != 1:
            raise ValidationError(
                f"--like must name one demonstration; {args.like} holds"
                f" {len(demos)} ({maps[0].source}, {maps[1].source}, ...)"
            )
        timing, like = demos[0], maps[0]
    else:
        timing, like = np.linspace(0.0, args.duration, n), None
    result = model.generate(
        timing,
        dense=args.dense,
        start=None if start is None else {"position": start},
        goal=None if goal is None else {"position": goal},
        return_std=std_out is not None,
    )
    path, std = result if std_out is not None else (result, None)
    exact_time = args.like is not None and args.dense
    if fmt == "bag":
        write_bag(path, out, topic=args.topic or "/ndlfd/path")
    elif fmt == "joint-trajectory":
        write_joint_trajectory(path, out)
    else:
        _write_path(path, out, exact_time=exact_time, like=like)
    if std is not None:  # the path's columns (std of a quaternion is no quaternion)
        formats = [None if exact_time else FLOAT_FORMAT]
        formats += [FLOAT_FORMAT] * path.n_dims
        write_table(std_out, csv_header(path, "t"),
                    np.column_stack([path.t, std]), float_format=formats)  # fmt: skip
    what = "samples" if args.dense else "key points"
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
    p.add_argument(
        "--like",
        help="a test demonstration whose timing is used (one file, or one episode"
        " of a LeRobot dataset with --episodes N); when it gives the orientation"
        " as Euler angles, the output does too, under its names",
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
        "-o",
        "--output",
        required=True,
        help="output file (its folder must exist): .csv, .mcap (a ROS 2 bag) or"
        " .yaml (a joint trajectory)",
    )
    p.add_argument(
        "--format",
        choices=FORMATS,
        help="what -o holds (default: by its suffix: .mcap/.db3 bag,"
        " .yaml/.yml joint-trajectory, else csv)",
    )
    p.add_argument(
        "--topic",
        metavar="TOPIC",
        help="the pose topic of a bag output (default /ndlfd/path)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    add_column_options(p, what="--like file", bags="like-")
    p.set_defaults(func=_cmd_generate)
