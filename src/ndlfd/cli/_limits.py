"""The limit flags of ``generate`` and ``sample``, and the peaks report.

``--max-velocity`` and ``--max-acceleration`` (:mod:`ndlfd.limits`).
"""

from __future__ import annotations

import argparse

import numpy as np

from .._errors import ValidationError
from ..demonstration import Demonstration
from ..limits import KINDS, path_peaks, time_scale
from ._options import parse_floats, say

__all__ = ["add_limit_options", "apply_limits", "parse_limits", "peaks_line"]


def add_limit_options(p) -> None:
    """The three limit flags (repeatable, one group or column each)."""
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


def parse_limits(args: argparse.Namespace) -> dict | None:
    """The flags as ``limits=`` of :func:`ndlfd.limits.time_scale` (or ``None``).

    Examples
    --------
    >>> args = argparse.Namespace(max_velocity=["joints=90,80", "wrist.pos=30"],
    ...                           max_acceleration=["joints=400"], max_jerk=None)
    >>> limits = parse_limits(args)
    >>> limits["joints"], limits["wrist.pos"]
    ({'velocity': [90.0, 80.0], 'acceleration': [400.0]}, {'velocity': [30.0]})
    """
    out: dict[str, dict] = {}
    for kind in KINDS:
        flag = f"--max-{kind}"
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
            out.setdefault(name, {})[kind] = parse_floats(values, f"{flag} {name}")
    return out or None


def peaks_line(path: Demonstration) -> str:
    """The largest velocity and acceleration of each group, and where.

    Not of an orientation (quaternions), a velocity derived from the position,
    or a gripper on two values (it switches in one sample).

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> d = Demonstration.from_arrays(t, position=np.column_stack([2 * t, t * t]))
    >>> peaks_line(d)
    'peaks: position velocity 2 /s (x), acceleration 2 /s^2 (y)'
    """
    peaks = path_peaks(path)
    parts = []
    for g in path.group_names:
        cols = path.columns_of(g)
        if (
            g == "orientation"  # a quaternion
            or (g == "velocity" and path.has_group("position"))  # derived
            or (g == "gripper" and np.unique(path.X[:, cols]).size <= 2)  # switches
        ):
            continue
        v, a = peaks["velocity"][cols], peaks["acceleration"][cols]
        iv, ia = int(np.argmax(v)), int(np.argmax(a))
        parts.append(
            f"{g} velocity {v[iv]:.3g} /s ({path.columns[cols[iv]]}), "
            f"acceleration {a[ia]:.3g} /s^2 ({path.columns[cols[ia]]})"
        )
    return "peaks: " + "; ".join(parts)


def apply_limits(args, path: Demonstration, *, dense: bool, std, prefix, report=True):
    """The path time-scaled to the flags' limits (as it is without them).

    Says (``report``) the peaks, and the new duration when the path was slowed
    down.
    """
    limits = parse_limits(args)
    if limits is not None and (not dense or std is not None):
        raise ValidationError(
            "--max-velocity/-acceleration/-jerk time-scale a dense path: pass"
            " --dense, and no --std"
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
    if out.n_samples >= 3:
        say(args, peaks_line(out))
    return out
