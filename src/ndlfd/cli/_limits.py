"""The limit flags of ``generate`` and ``sample``, and the peaks report.

``--max-velocity``, ``--max-acceleration`` and ``--max-jerk`` column by
column; ``--max-speed`` of a position group's norm, ``--max-angular-velocity``
and ``--max-angular-acceleration`` of an orientation's rotation, in radians
(or degrees: ``orientation=30deg``) per second (:mod:`ndlfd.limits`).
"""

from __future__ import annotations

import argparse

import numpy as np

from .._errors import ValidationError
from .._pose_groups import hand_group, hand_name, is_orientation
from .._pose_groups import kind as group_kind
from .._trajectory import rest_points
from ..demonstration import Demonstration
from ..limits import KINDS, NORM_KINDS, path_peaks, time_scale
from ._options import parse_floats, say

__all__ = [
    "add_limit_options",
    "apply_limits",
    "parse_limits",
    "peaks_line",
    "trajectory_peaks",
]


#: The norm flags: the kind each sets, its metavar, example and help.
_NORM_FLAGS = {
    "speed": ("NAME=V", "position=0.05",
              "the largest speed of the position group NAME: the norm of its"
              " velocity, in its units per second (not axis by axis)"),
    "angular_velocity": ("NAME=W[deg]", "orientation=0.5",
                         "the largest angular velocity of the orientation NAME"
                         " (quaternions), in rad/s (or deg/s: orientation=30deg)"),
    "angular_acceleration": ("NAME=A[deg]", "orientation=2",
                             "the largest angular acceleration of the"
                             " orientation NAME, in rad/s^2 (or deg/s^2: a"
                             " conservative bound, 0.89 to 1 times A)"),
}  # fmt: skip
_DEGREES = np.pi / 180.0


def _flag(kind: str) -> str:
    return "--max-" + kind.replace("_", "-")


def add_limit_options(p) -> None:
    """The limit flags (repeatable, one group or column each)."""
    g = p.add_argument_group(
        "a robot's limits",
        "Per second (squared, cubed), in the units of the demonstrations. A path"
        " that would exceed them is slowed down along the same route"
        " (TOPP-RA, needs ndlfd[limits]), starting and ending at rest;"
        " the output then lasts longer than the timing.",
    )
    for kind, example in (
        ("velocity", "90"),
        ("acceleration", "400"),
        ("jerk", "5000"),
    ):
        g.add_argument(
            f"--max-{kind}",
            action="append",
            metavar="NAME=V1[,V2,...]",
            help=f"the largest {kind} of each column of the group NAME (one value,"
            f" or one per column), or of the column NAME, e.g. --max-{kind}"
            f" joints={example}; repeatable"
            + (
                " (met by slowing the whole path down: not time-optimal)"
                if kind == "jerk"
                else ""
            ),
        )
    for kind, (metavar, example, text) in _NORM_FLAGS.items():
        g.add_argument(
            _flag(kind),
            action="append",
            metavar=metavar,
            help=f"{text}, e.g. {_flag(kind)} {example}; repeatable",
        )


def parse_limits(args: argparse.Namespace) -> dict | None:
    """The flags as ``limits=`` of :func:`ndlfd.limits.time_scale` (or ``None``).

    Examples
    --------
    >>> args = argparse.Namespace(max_velocity=["joints=90,80", "wrist.pos=30"],
    ...                           max_acceleration=["joints=400"], max_jerk=None)
    >>> limits = parse_limits(args)
    >>> limits["joints"], limits["wrist.pos"]
    ({'velocity': [90.0, 80.0], 'acceleration': [400.0]}, {'velocity': [30.0]})
    >>> args = argparse.Namespace(max_speed=["position=0.05"],
    ...                           max_angular_velocity=["orientation=90deg"])
    >>> limits = parse_limits(args)
    >>> limits["position"], limits["orientation"]
    ({'speed': 0.05}, {'angular_velocity': 1.5707963267948966})
    """
    out: dict[str, dict] = {}
    for kind in KINDS + NORM_KINDS:
        flag = _flag(kind)
        for text in getattr(args, f"max_{kind}", None) or []:
            name, eq, values = text.partition("=")
            name = name.strip()
            if not eq or not name:
                raise ValidationError(
                    f"{flag} must look like NAME=V1[,V2,...] (a group or a column);"
                    f" got {text!r}"
                )
            if kind in out.get(name, {}):
                raise ValidationError(f"{flag} gives {name} twice; give it once")
            if kind in NORM_KINDS:
                value = _norm_value(values, flag, name, kind)
            else:
                value = parse_floats(values, f"{flag} {name}")
            out.setdefault(name, {})[kind] = value
    return out or None


def _norm_value(text: str, flag: str, name: str, kind: str) -> float:
    """One number; an angular one in rad (per second...) or with ``deg``."""
    text = text.strip()
    factor = 1.0
    if kind != "speed" and text.lower().endswith("deg"):
        text, factor = text[:-3].strip(), _DEGREES
    values = parse_floats(text, f"{flag} {name}")
    if len(values) != 1:
        raise ValidationError(
            f"{flag} takes one value for the group {name} (of its norm, not per"
            f" column); got {len(values)}"
        )
    return values[0] * factor


def peaks_line(path: Demonstration, peaks: dict | None = None) -> str:
    """The largest velocity and acceleration of each group, and where.

    A position group's speed too (the norm of its velocity); an orientation
    (quaternions) by its angular velocity and acceleration. Not a velocity
    derived from the position, or a gripper on two values (it switches in one
    sample). ``peaks``: the path's (:func:`~ndlfd.limits.path_peaks`) unless
    given (:func:`trajectory_peaks`).

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> d = Demonstration.from_arrays(t, position=np.column_stack([2 * t, t * t]))
    >>> peaks_line(d)
    'peaks: position velocity 2 /s (x), acceleration 2 /s^2 (y), speed 2.83 /s'
    """
    peaks = path_peaks(path) if peaks is None else peaks
    parts = []
    for g in path.group_names:
        cols = path.columns_of(g)
        if is_orientation(g) and cols.size == 4:
            w = peaks["angular_velocity"][cols[0]]
            a = peaks["angular_acceleration"][cols[0]]
            parts.append(
                f"{g} angular velocity {w:.3g} rad/s ({np.degrees(w):.3g} deg/s),"
                f" angular acceleration {a:.3g} rad/s^2"
            )
            continue
        if (
            is_orientation(g)
            or (
                group_kind(g) == "velocity"  # derived from its hand's position
                and path.has_group(hand_group(hand_name(g), "position"))
            )
            or (g == "gripper" and np.unique(path.X[:, cols]).size <= 2)  # switches
        ):
            continue
        v, a = peaks["velocity"][cols], peaks["acceleration"][cols]
        iv, ia = int(np.argmax(v)), int(np.argmax(a))
        part = (
            f"{g} velocity {v[iv]:.3g} /s ({path.columns[cols[iv]]}), "
            f"acceleration {a[ia]:.3g} /s^2 ({path.columns[cols[ia]]})"
        )
        if peaks["speed"][cols[0]] > 0 and cols.size > 1:
            part += f", speed {peaks['speed'][cols[0]]:.3g} /s"
        parts.append(part)
    return "peaks: " + "; ".join(parts)


def trajectory_peaks(path: Demonstration, *, moving_start: bool = False):
    """What a JointTrajectory of ``path`` carries, in the path's units, and its peaks.

    The groups ``joints`` and ``gripper`` as
    :func:`~ndlfd.io.write_joint_trajectory` writes them: eased to rest
    where they move at an end (the first one left moving after a prefix),
    with the velocities and accelerations of the curve through them
    (:func:`ndlfd._trajectory.rest_points`). Those are the peaks, not the
    samples' differences.

    Parameters
    ----------
    path : Demonstration
        With the group ``joints``.
    moving_start : bool, default=False

    Returns
    -------
    sent : Demonstration
    peaks : dict of str to ndarray
        As :func:`~ndlfd.limits.path_peaks` of ``sent``, its velocity and
        acceleration those written.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> d = Demonstration.from_arrays(t, joints=np.column_stack([t, 2 * t]))
    >>> sent, peaks = trajectory_peaks(d)  # moving at both ends: eased
    >>> sent.n_samples, peaks["velocity"].round(2).tolist()
    (111, [1.0, 2.0])
    """
    groups = [g for g in ("joints", "gripper") if path.has_group(g)]
    cols = np.concatenate([path.columns_of(g) for g in groups])
    Q = path.X[:, cols]
    held = np.array([np.unique(Q[:, j]).size == 2 for j in range(Q.shape[1])])
    t, Q, V, A = rest_points(path.t - path.t[0], Q, moving_start=moving_start,
                             held=held)  # fmt: skip
    sent = Demonstration(
        path.t[0] + t, Q, tuple(path.columns[c] for c in cols),
        tuple(path.groups[c] for c in cols),
    )  # fmt: skip
    peaks = path_peaks(sent)
    peaks["velocity"], peaks["acceleration"] = np.abs(V).max(0), np.abs(A).max(0)
    return sent, peaks


def apply_limits(
    args, path: Demonstration, *, dense: bool, std, prefix, report=True,
    trajectory=False,
):  # fmt: skip
    """The path time-scaled to the flags' limits (as it is without them).

    Says (``report``) the peaks, and the new duration when the path was slowed
    down. After an observed ``prefix`` the peaks are of what follows it (from
    its last sample, what a JointTrajectory sends): the executed samples are
    history, their peaks the robot's. For a JointTrajectory (``trajectory``),
    the peaks of what it is written with: its joints and gripper eased to
    rest, the curve's velocities and accelerations (:func:`trajectory_peaks`).
    """
    limits = parse_limits(args)
    if limits is not None and (not dense or std is not None):
        raise ValidationError(
            "--max-velocity/-acceleration/-jerk/-speed/-angular-* time-scale a"
            " dense path: pass --dense, and no --std"
        )
    keep = 0 if prefix is None else prefix.n_samples  # kept, with their stamps
    out = (
        path if limits is None else time_scale(path, limits, rate=args.rate, keep=keep)
    )
    if not report:
        return out
    if out is not path:
        say(
            args,
            f"slowed down to the limits: {path.duration:.4g} s -> "
            f"{out.duration:.4g} s, {out.n_samples} samples",
        )
    # of what is sent on: after an executed prefix, from its last sample
    sent = out if keep <= 1 else out.take(np.arange(keep - 1, out.n_samples))
    if sent.n_samples >= 3:
        peaks = None
        if trajectory and sent.has_group("joints"):
            sent, peaks = trajectory_peaks(sent, moving_start=keep > 0)
        line = peaks_line(sent, peaks)
        if keep > 1:
            line += f" (from the last of the {keep} observed samples on)"
        say(args, line)
    return out
