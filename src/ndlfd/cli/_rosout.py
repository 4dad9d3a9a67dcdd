"""What ``ndlfd generate`` writes for ROS 2: bags and joint trajectories.

A bag is ``-o NAME.mcap`` / ``NAME.db3`` (one storage file) or a bag folder:
``-o NAME/`` (a trailing slash), or ``--format bag`` with a name without a
suffix. ``--format joint-trajectory`` writes a ``JointTrajectory`` as YAML
(``.yaml``/``.yml``) or, for any other name, a bag of that one message for
``ros2 bag play``. The flags here set the frame, the stamps and the joints of
those outputs.
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

from .._errors import ValidationError
from ..io import write_bag, write_joint_trajectory
from ..io._bag import BAG_SUFFIXES, bag_frame_id
from ..io._bagout import JOINT_UNITS, TRAJECTORY_TOPIC
from ..io._lerobot import layout_feature
from ..io._mapping import is_so_arm_joint
from ._options import split_names

__all__ = [
    "ROS_FORMATS",
    "add_ros_output_options",
    "check_ros_output",
    "is_folder_output",
    "joint_units",
    "write_ros_output",
]

#: The ``--format`` values written here.
ROS_FORMATS = ("bag", "joint-trajectory")
#: The frame of a bag's poses when neither ``--frame-id`` nor the input says.
DEFAULT_FRAME = "world"


def is_folder_output(raw: str) -> bool:
    """Whether ``-o`` names a folder to write (it ends with a slash)."""
    return raw.endswith(("/", os.sep))


def add_ros_output_options(p) -> None:
    """Add ``--frame-id``, ``--start-time``, ``--joint-names``, ``--units``."""
    g = p.add_argument_group(
        "ROS 2 outputs (bags, joint trajectories)",
        "ROS wants joint angles in radians: joints in degrees need --units deg"
        " (LeRobot's SO-100/101 arms need --units: degrees or -100..100)."
        " The joint trajectory comes to rest at its ends (a path still moving"
        " there is eased to a stop along its route), and its velocities and"
        " accelerations are those of the one curve through its positions that"
        " a joint_trajectory_controller follows.",
    )
    g.add_argument(
        "--frame-id",
        metavar="FRAME",
        help="the headers' frame of a bag's poses (default: the frame the input"
        f" bag's poses were in, its base frame for --frame; else {DEFAULT_FRAME})",
    )
    g.add_argument(
        "--start-time",
        type=float,
        metavar="SECONDS",
        help="stamp the output from this time, in seconds since 1970 (default 0:"
        " stamps from 0)",
    )
    g.add_argument(
        "--joint-names",
        metavar="NAME[,NAME...]",
        help="the joints' names in the JointState / JointTrajectory (the URDF's),"
        " one per joint column, gripper last (default: the columns' names)",
    )
    g.add_argument(
        "--units",
        choices=tuple(JOINT_UNITS),
        default=None,
        help="the units of the joint columns; deg is converted to radians for"
        " ROS (default rad; required for a LeRobot dataset's SO-100/101 joints,"
        " NAME.pos or main_NAME: degrees with use_degrees=True, else -100..100)",
    )


def check_ros_output(args: argparse.Namespace, out: Path, fmt: str) -> None:
    """Refuse ROS flags for another output, and a bag that cannot be written."""
    ros = fmt in ROS_FORMATS
    given = [
        flag
        for flag, value in (
            ("--topic", args.topic),
            ("--frame-id", args.frame_id),
            ("--start-time", args.start_time),
            ("--joint-names", args.joint_names),
        )
        if value is not None
    ]
    if given and not ros:
        raise ValidationError(
            f"{given[0]} sets a ROS 2 output (-o PATH.mcap, a bag folder PATH/, or"
            f" PATH.yaml); -o {out} writes {fmt}"
        )
    yaml = out.suffix.lower() in (".yaml", ".yml")
    if fmt == "bag" and (
        yaml or (out.suffix and out.suffix.lower() not in BAG_SUFFIXES)
    ):
        raise ValidationError(
            f"--format bag writes one .mcap (or .db3) file or a bag folder (a name"
            f" without a suffix, or ending in /); got -o {out} (e.g. -o"
            f" {out.with_suffix('.mcap')})"
        )
    if yaml and (args.topic is not None or args.start_time is not None):
        raise ValidationError(
            f"{'--topic' if args.topic is not None else '--start-time'} sets a bag;"
            f" -o {out} writes YAML"
        )
    if args.frame_id is not None and fmt != "bag":
        raise ValidationError(
            f"--frame-id sets the poses' frame of a bag (-o PATH.mcap); -o {out}"
            " writes a joint trajectory, which has no frame"
        )
    if args.start_time is not None and not (
        math.isfinite(args.start_time) and args.start_time >= 0
    ):
        raise ValidationError(
            f"--start-time must be seconds since 1970, >= 0; got {args.start_time:g}"
        )
    if fmt == "bag" and out.suffix.lower() not in BAG_SUFFIXES and out.exists():
        raise ValidationError(f"-o {out}: exists; a bag folder is written new")


def joint_units(units: str | None, mapping) -> tuple[str, str]:
    """The joints' units: ``units`` (``--units``) if given, else radians.

    A LeRobot dataset's SO-100/101 joints are refused without ``--units``:
    LeRobot records those arms in degrees only when the robot was configured
    with ``use_degrees=True``; by default each joint is normalized to
    -100..100 of its calibrated range (``MotorNormMode.RANGE_M100_100``), which
    no unit converts to radians. Only the user knows which.

    Parameters
    ----------
    units : {"rad", "deg"} or None
        As ``--units`` gave them (``None``: not given).
    mapping : ColumnMapping or None
        How the output's data were read (``--like``, ``--observed`` or the
        model's training files).

    Returns
    -------
    units : str
    note : str
        For the summary: what the joints were written as, else ``""``.

    Raises
    ------
    ValidationError
        SO-100/101 joints from LeRobot without ``units``.

    Examples
    --------
    >>> from ndlfd.io import ColumnMapping
    >>> m = ColumnMapping("so101 episode 0", "timestamp",
    ...                   (("joints", ("shoulder_pan.pos", "elbow_flex.pos")),),
    ...                   layout="LeRobot v3.0, action")
    >>> joint_units("deg", m)[0], joint_units("rad", m)[0], joint_units(None, None)
    ('deg', 'rad', ('rad', ''))
    """
    if units is not None:
        return units, ""
    joints = dict(mapping.groups).get("joints", ()) if mapping is not None else ()
    if (
        joints
        and layout_feature(mapping.layout) is not None
        and all(map(is_so_arm_joint, joints))
    ):
        raise ValidationError(
            f"the joints ({joints[0]}, ...) come from a LeRobot SO-100/101 dataset,"
            " recorded in degrees (a robot configured with use_degrees=True) or"
            " in -100..100 of each joint's calibrated range (LeRobot's default),"
            " and ROS wants radians: say --units deg (converted) or --units rad"
            " (written as they are), after converting -100..100 with the arm's"
            " calibration"
        )
    return "rad", ""


def write_ros_output(args, path, out: Path, fmt: str, mapping, *, observed=0) -> str:
    """Write ``path`` as ``fmt`` to ``out``; a note on its units for the summary.

    The note (else ``""``) says that the joints were taken for degrees
    (:func:`joint_units`). After ``observed`` executed samples (``--observed``),
    a JointTrajectory is the rest only, from the last of them (where the robot
    is now, moving: its velocity not 0) on; a bag holds the whole path.
    """
    joint_names = split_names(args.joint_names, "--joint-names")
    start = args.start_time or 0.0
    units, note = joint_units(args.units, mapping)
    if not path.has_group("joints"):
        note = ""
    try:
        if fmt == "bag":
            frame = args.frame_id or bag_frame_id(mapping) or DEFAULT_FRAME
            write_bag(
                path,
                out,
                topic=args.topic or "/ndlfd/path",
                frame_id=frame,
                start_time=start,
                joint_names=joint_names,
                units=units,
            )
            return note
        if observed:  # the past is not sent: from where the robot is now
            path = path.take(list(range(observed - 1, path.n_samples)))
            now = "the trajectory starts at the last observed sample"
            note = f"{note}; {now}" if note else now
        write_joint_trajectory(
            path,
            out,
            joint_names=joint_names,
            units=units,
            topic=args.topic or TRAJECTORY_TOPIC,
            start_time=start,
            moving_start=observed > 0,
        )
    except ValidationError as exc:
        text = str(exc).replace("joint_names", "--joint-names")
        raise ValidationError(text.replace("units='deg'", "--units deg")) from None
    return note
