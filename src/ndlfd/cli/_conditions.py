"""Where a path from a model goes: ``--start``, ``--goal``, ``--via``, ``--observed``.

``ndlfd generate`` and ``ndlfd sample`` share these flags
(:func:`add_condition_options`), and ``--task-frame`` (new poses of the
model's task frames). They are parsed before the model is read, so
a typo is reported first (:func:`parse_condition`, :func:`parse_via`,
:func:`parse_task_frames`), then checked against the model's groups, task
frames and generation (:func:`model_conditions`, :func:`model_frames`,
:func:`check_condition_flags`; the steps: :func:`load_with_conditions`).
An executed prefix is read like ``--like`` (:func:`read_observed`; but
``--episodes`` selects from the ``--like`` dataset only) and its
time stamps become the first of the output (:func:`observed_timing`). Every
error is one line naming the flag.
"""

from __future__ import annotations

import argparse
import math
import re

import numpy as np

from .._errors import ValidationError
from .._poses import check_frames
from ..demonstration import Demonstration
from ..io._lerobot import is_lerobot_dataset
from ..learner import KeypointHMM
from ._options import GROUP_NAME, parse_floats, read_one

__all__ = [
    "add_condition_options",
    "check_condition_flags",
    "flag_named",
    "load_with_conditions",
    "model_conditions",
    "model_frames",
    "observed_timing",
    "output_mapping",
    "parse_condition",
    "parse_named",
    "parse_task_frames",
    "parse_via",
    "read_observed",
]


def add_condition_options(p) -> None:
    """``--start``, ``--goal`` and ``--via`` (repeatable) and ``--observed``."""
    g = p.add_argument_group(
        "where the path goes",
        "Values in the units of the demonstrations, one per column of the group"
        " (orientation as a unit quaternion w,x,y,z); a bare X,Y[,Z] is a"
        " position. A value that starts with '-' takes '=': --start=-0.5,0."
        " 'ndlfd fit' reports the groups a model learned.",
    )
    g.add_argument(
        "--start",
        action="append",
        metavar="[GROUP=]V1,V2,...",
        help="where the robot starts: the path begins there and follows the"
        " demonstrations that start nearby; repeatable, one group each, e.g."
        " --start 0.5,0 or --start position=0.4,0.1,0.3 --start"
        " orientation=1,0,0,0 --start gripper=1",
    )
    g.add_argument(
        "--goal",
        action="append",
        metavar="[GROUP=]V1,V2,...",
        help="where the path must end, as --start",
    )
    g.add_argument(
        "--via",
        action="append",
        metavar="TIME:GROUP=V1,V2,...",
        help="a via point: the path passes through these values of GROUP at"
        " TIME (on the timing's clock) and follows the route through them;"
        " repeatable, e.g. --via 2.5:position=0.6,0.1,0.3",
    )
    g.add_argument(
        "--task-frame",
        action="append",
        metavar="NAME=X,Y[,Z[,QW,QX,QY,QZ]]",
        help="a new pose of a task frame the model learned ('ndlfd fit"
        " --task-frame'): its position (the position group's dimension), in 3-D"
        " optionally followed by a unit quaternion w,x,y,z, as many values as"
        " the demonstrations' frames had; each part of the path follows the"
        " frame in which the demonstrations agree; repeatable, one frame each,"
        " e.g. --task-frame object=0.5,0.1,0.02,0,1,0,0 (models fitted with"
        " --generation blend)",
    )
    g.add_argument(
        "--observed",
        metavar="FILE",
        help="what the robot executed so far (one demonstration, read like"
        " --like, from the start of this execution): its time stamps are the"
        " output's first, then the timing's after them; the path is these"
        " samples, then continues from the last one on the route they are on"
        " (not with --start or --via)",
    )


def parse_condition(texts: list[str] | None, flag: str) -> dict | None:
    """Repeated ``--start``/``--goal`` flags as ``{group: values}`` (or ``None``).

    Examples
    --------
    >>> parse_condition(["0.5,0", "gripper=1"], "--start")
    {'position': [0.5, 0.0], 'gripper': [1.0]}
    """
    if not texts:
        return None
    out: dict[str, list[float]] = {}
    for text in texts:
        group, eq, values = text.partition("=")
        group = group.strip()
        if not eq:
            group, values = "position", text
        elif not GROUP_NAME.match(group):
            raise ValidationError(
                f"{flag} must look like GROUP=V1,V2,... or V1,V2,... (a"
                f" position); got {text!r}"
            )
        if group in out:
            raise ValidationError(
                f"{flag} gives {group} twice ({text!r}); give each group once"
            )
        out[group] = parse_floats(values, flag if not eq else f"{flag} {group}")
    return out


def parse_via(texts: list[str] | None) -> list | None:
    """``--via`` flags as ``[(time, {group: values})]`` (or ``None``).

    Examples
    --------
    >>> parse_via(["2.5:position=0.6,0.1"])
    [(2.5, {'position': [0.6, 0.1]})]
    """
    if not texts:
        return None
    out = []
    example = "TIME:GROUP=V1,V2,... (e.g. 2.5:position=0.6,0.1,0.3)"
    for text in texts:
        time, colon, rest = text.partition(":")
        group, eq, values = rest.partition("=")
        if not (colon and eq and group.strip()):
            raise ValidationError(f"--via must look like {example}; got {text!r}")
        try:
            t = float(time)
        except ValueError:
            raise ValidationError(
                f"--via: the time {time!r} is not a number in {text!r}"
            ) from None
        if not math.isfinite(t):
            raise ValidationError(f"--via: the time must be finite; got {text!r}")
        out.append((t, {group.strip(): parse_floats(values, f"--via {text}")}))
    return out


def parse_named(texts, flag: str, example: str, parse) -> dict:
    """Repeated ``NAME=VALUES`` flags as ``{name: parse(values, label)}``.

    A missing ``=`` or value, a bad name or a name given twice is an error
    naming ``flag`` and showing ``example``.

    Examples
    --------
    >>> parse_named(["a=1,2", "b=3"], "--f", "NAME=V,...", parse_floats)
    {'a': [1.0, 2.0], 'b': [3.0]}
    """
    out: dict = {}
    for text in texts:
        name, eq, values = text.partition("=")
        name = name.strip()
        if not eq or not values.strip():
            raise ValidationError(f"{flag} must look like {example}; got {text!r}")
        if not GROUP_NAME.match(name):
            raise ValidationError(
                f"{flag} NAME must be a name of letters, digits, '_' and '-'"
                f" (starting with a letter or '_'); got {name!r} in {text!r}"
            )
        if name in out:
            raise ValidationError(
                f"{flag} gives {name} twice ({text!r}); give each frame once"
            )
        out[name] = parse(values, f"{flag} {name}")
    return out


#: What ``--task-frame`` looks like (generate, sample).
_FRAME_EXAMPLE = "NAME=X,Y,Z[,QW,QX,QY,QZ] (e.g. object=0.5,0.1,0.02)"


def parse_task_frames(texts: list[str] | None) -> dict | None:
    """Repeated ``--task-frame`` flags as ``{name: pose}`` (or ``None``).

    Examples
    --------
    >>> parse_task_frames(["object=0.5,0.1,0.02", "place=0.2,-0.3,0"])
    {'object': [0.5, 0.1, 0.02], 'place': [0.2, -0.3, 0.0]}
    """
    if not texts:
        return None
    return parse_named(texts, "--task-frame", _FRAME_EXAMPLE, parse_floats)


def model_frames(model, frames: dict | None) -> dict | None:
    """Check parsed ``--task-frame`` poses against the model's task frames.

    Parameters
    ----------
    model : KeypointHMM
        Fitted.
    frames : dict of str to list of float, or None
        From :func:`parse_task_frames`.

    Returns
    -------
    frames : dict or None
        As given, for :meth:`KeypointHMM.generate` and ``sample``.
    """
    if not frames:
        return None
    learned = getattr(model, "task_frames_", None) or {}
    if not learned:
        raise ValidationError(
            "--task-frame gives a new pose of a task frame, but this model learned"
            " none (fit it with --task-frame NAME=COLUMN,... to learn where each"
            " demonstration's frame was)"
        )
    for name, pose in frames.items():
        if name not in learned:
            raise ValidationError(
                f"--task-frame names frame {name!r}, which the model did not"
                f" learn; it learned {', '.join(learned)}"
            )
        size = learned[name].shape[1]
        if len(pose) != size:
            what = (
                "x, y, z, then a unit quaternion qw, qx, qy, qz"
                if size == 7
                else "a position"
            )
            raise ValidationError(
                f"--task-frame {name} must give {size} values ({what}), as the"
                f" demonstrations' frames had; got {len(pose)}"
            )
    dims = model.column_groups_.count("position") or None
    try:  # a quaternion's length
        check_frames(frames, dims, what="--task-frame")
    except ValidationError as exc:
        raise ValidationError(flag_named(exc)) from None
    return frames


def flag_named(exc: Exception) -> str:
    """A message of :func:`~ndlfd._poses.check_frames` naming ``--task-frame NAME``.

    Examples
    --------
    >>> flag_named(ValidationError("--task-frame['object'] must be finite"))
    '--task-frame object must be finite'
    """
    return re.sub(r"--task-frame\['([^']*)'\]", r"--task-frame \1", str(exc))


def model_conditions(model, start: dict | None, goal: dict | None) -> tuple:
    """Check parsed ``--start`` and ``--goal`` against the model's groups.

    Parameters
    ----------
    model : KeypointHMM
        Fitted.
    start, goal : dict of str to list of float, or None
        From :func:`parse_condition`.

    Returns
    -------
    start, goal : dict or None
        As given, for :meth:`KeypointHMM.generate`.
    """
    pairs = list(zip(model.columns_, model.column_groups_, strict=True))
    for flag, cond in (("--start", start), ("--goal", goal)):
        for group, values in (cond or {}).items():
            names = [c for c, g in pairs if g == group]
            if not names:
                raise ValidationError(
                    f"{flag} names group {group!r}, which the model did not"
                    f" learn; it learned {', '.join(model.groups_)} (e.g."
                    f" {flag} {model.groups_[0]}=V1,...)"
                )
            if len(values) != len(names):
                raise ValidationError(
                    f"{flag} must give {len(names)} {group} values (one per"
                    f" column: {', '.join(names)}); got {len(values)}"
                )
    return start, goal


def check_condition_flags(args: argparse.Namespace, model) -> None:
    """Refuse flags the model or each other exclude, naming the flags.

    ``--observed`` takes the place of ``--start`` (its first sample is where
    the robot started) and cannot be combined with ``--via``; both need a
    model fitted with ``--generation blend``.
    """
    if args.observed is not None and (args.start or args.via):
        raise ValidationError(
            "--observed continues an execution from its last sample; it cannot"
            " be combined with --start or --via (--goal is fine)"
        )
    if model.generation != "blend":
        for flag in ("via", "observed", "task_frame"):
            if getattr(args, flag, None):
                raise ValidationError(
                    f"--{flag.replace('_', '-')} needs a model fitted with"
                    f" --generation blend; this one uses {model.generation}"
                )


def load_with_conditions(args: argparse.Namespace) -> tuple:
    """The model of ``args.model``, the start, goal and via points and frames.

    The flags are parsed before the model is read (a typo is reported
    first), then checked against its groups, task frames and generation.

    Returns
    -------
    model : KeypointHMM
    start, goal : dict or None
    via : list or None
    frames : dict or None
        New poses of its task frames (``--task-frame``).
    """
    start = parse_condition(args.start, "--start")
    goal = parse_condition(args.goal, "--goal")
    via = parse_via(args.via)
    frames = parse_task_frames(getattr(args, "task_frame", None))
    model = KeypointHMM.load(args.model)
    start, goal = model_conditions(model, start, goal)
    check_condition_flags(args, model)
    return model, start, goal, via, model_frames(model, frames)


def read_observed(args: argparse.Namespace, timing) -> tuple:
    """The ``--observed`` prefix, the output's timing and the prefix's mapping.

    Parameters
    ----------
    args : argparse.Namespace
    timing : Demonstration or ndarray
        The timing of ``--like`` or ``--duration``.

    Returns
    -------
    prefix : Demonstration or None
    timing : Demonstration or ndarray
        :func:`observed_timing` with a prefix, else as given.
    mapping : ColumnMapping or None
    """
    if args.observed is None:
        return None, timing, None
    # --episodes selects from the --like dataset, never from --observed (one
    # prefix, read whole); --feature applies to an --observed dataset too
    own = {**vars(args), "episodes": None}
    if not is_lerobot_dataset(args.observed):
        own["feature"] = None
    prefix, mapping = read_one(argparse.Namespace(**own), args.observed, "--observed")
    return prefix, observed_timing(prefix, timing), mapping


def output_mapping(model, like, observed):
    """The mapping the output is written with.

    As the ``--like`` file was read, else as the ``--observed`` file, else as
    the model's training files (its ``input_mapping_``; ``None`` for a model
    that did not record them, and the output keeps the model's names).
    """
    for mapping in (like, observed):
        if mapping is not None:
            return mapping
    return model.input_mapping_


def observed_timing(prefix: Demonstration, timing) -> np.ndarray:
    """The output's time stamps: the prefix's, then the timing's after them.

    A stamp of the timing within half its median step after the prefix's
    last is left out (two stamps a hair apart would make the derived
    velocity spike).

    Parameters
    ----------
    prefix : Demonstration
        What was executed, from the start of the timing.
    timing : Demonstration or ndarray of shape (n_samples,)
        The whole execution's timing (``--like`` or the uniform grid).

    Returns
    -------
    times : ndarray
        Starting with ``prefix.t``; at least one time stamp after it.

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> prefix = Demonstration([0.0, 0.3], [[0.0], [1.0]], ("x",), ("position",))
    >>> observed_timing(prefix, np.linspace(0.0, 1.0, 5))
    array([0.  , 0.3 , 0.5 , 0.75, 1.  ])
    >>> observed_timing(prefix, np.linspace(0.0, 1.0, 6))  # not 0.4 (0.1 after)
    array([0. , 0.3, 0.6, 0.8, 1. ])
    """
    t = timing.t if isinstance(timing, Demonstration) else np.asarray(timing)
    tol = 1e-9 * (t[-1] - t[0])
    if abs(prefix.t[0] - t[0]) > tol:
        raise ValidationError(
            f"--observed starts at {prefix.t[0]:g} s, the timing at {t[0]:g} s;"
            " expected the samples executed from the start of the motion, on"
            " the timing's clock"
        )
    rest = t[t > prefix.t[-1] + max(tol, 0.5 * float(np.median(np.diff(t))))]
    if rest.size == 0:
        raise ValidationError(
            f"--observed ends at {prefix.t[-1]:g} s, not before the timing's end"
            f" {t[-1]:g} s: nothing is left to generate"
        )
    return np.concatenate([prefix.t, rest])
