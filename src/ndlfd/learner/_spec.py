"""The demonstration spec: what is learned of a demonstration, and how it is encoded.

Fit and generation see a demonstration the same way:

1. **groups** (:func:`resolve_groups`): the physical groups learned, from the
   parameter ``groups`` and the first demonstration;
2. **prepare** (:func:`prepare`): velocity derived when wanted, the groups
   selected;
3. **scaler** (:func:`scaler_from_ranges`): the group normalization, from the
   per-column ranges of pass 1 of the fit;
4. **levels** (:func:`levels_by_group`): the codebook levels of each group;
5. **reduce** (:meth:`DemoSpec.reduce`): normalize → :func:`ndlfd.simplify`
   (the key points) → time bins, for one demonstration; the paper's generation
   decodes the key points' time bins. **encode** (:meth:`DemoSpec.encode`)
   adds the key points' codebook cells, for the fit's second pass.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._errors import ValidationError
from .._pose_groups import hand_group, hands, kind, orientation_blocks
from .._registry import Registry
from .._validation import check_positive_int
from ..codebook import Codebook, TimeBins
from ..demonstration import Demonstration, unit_time, with_velocity
from ..dp import simplify
from ..normalize import SCALING_MODES, GroupScaler

__all__ = [
    "AUTO_GROUPS",
    "DEFAULT_LEVELS",
    "NORMALIZATIONS",
    "OTHER_LEVELS",
    "DemoSpec",
    "Reduced",
    "default_levels",
    "first_quaternion",
    "frame_spec",
    "levels_by_group",
    "negated_orientation",
    "prepare",
    "resolve_groups",
    "same_side",
    "scaler_from_ranges",
]

#: The groups ``groups="auto"`` learns first when a demonstration has them,
#: in this order (velocity also when it can be derived from position); every
#: other group of the demonstration follows, in its order.
AUTO_GROUPS = ("position", "velocity", "orientation", "force", "gripper")

#: Codebook levels per physical group when ``levels`` does not name the group
#: (the paper's 20 for position and 10 for velocity; joint angles are
#: positions, 20 levels).
DEFAULT_LEVELS = {
    "position": 20,
    "velocity": 10,
    "orientation": 10,
    "force": 10,
    "torque": 10,
    "gripper": 2,  # open or closed (a gripper of two recorded values stays so)
    "joints": 20,
    "joint_velocity": 10,
    "joint_effort": 10,
}

#: Codebook levels of a group :data:`DEFAULT_LEVELS` does not name (a user
#: group such as ``grip`` or ``tool``), when ``levels`` does not name it.
OTHER_LEVELS = 10

#: The scaler's range modes under the learner's parameter name (the errors
#: then say "normalization").
NORMALIZATIONS = Registry("normalization")
for _name in SCALING_MODES:
    NORMALIZATIONS.add(_name, SCALING_MODES.get(_name))


def resolve_groups(groups, first: Demonstration, *, derive_velocity=True):
    """The groups learned: the parameter ``groups`` resolved on a demonstration.

    Parameters
    ----------
    groups : "auto", str, sequence of str or None
        ``"auto"``: every group of the demonstration, those of
        :data:`AUTO_GROUPS` first in that order (velocity also when
        ``derive_velocity`` and it has position), then the others (joints, a
        user group) in the demonstration's order; ``None``: all of its
        groups as they are; a name or names: these.
    first : Demonstration
        The first training demonstration.
    derive_velocity : bool, default=True
        Whether a missing velocity group is derived from position.

    Returns
    -------
    groups : tuple of str

    Examples
    --------
    >>> import numpy as np
    >>> d = Demonstration.from_arrays(np.arange(3.0), position=np.zeros((3, 2)))
    >>> resolve_groups("auto", d)
    ('position', 'velocity')
    >>> resolve_groups("auto", d, derive_velocity=False)
    ('position',)
    """
    if groups is None:
        return tuple(first.group_names)
    if isinstance(groups, str) and groups == "auto":
        have = list(first.group_names)
        if derive_velocity:  # every hand's velocity (position: velocity)
            have += [
                hand_group(h.name, "velocity")
                for h in hands(first.groups)
                if hand_group(h.name, "velocity") not in have
            ]
        # the kinds in AUTO_GROUPS' order (each hand's in the order it came)
        auto = tuple(g for k in AUTO_GROUPS for g in have if kind(g) == k)
        return auto + tuple(g for g in first.group_names if g not in auto)
    if isinstance(groups, str):
        return (groups,)
    out = tuple(groups)
    if not out or not all(isinstance(g, str) for g in out):
        raise ValidationError(
            f"groups must be a non-empty sequence of group names; got {out!r}"
        )
    if len(set(out)) != len(out):
        raise ValidationError(f"groups must not repeat a name; got {out!r}")
    return out


def prepare(
    demo: Demonstration,
    groups: Sequence[str],
    *,
    derive_velocity: bool = True,
    cli: bool = False,
) -> Demonstration:
    """The demonstration's learned groups, velocity derived if wanted and missing.

    Parameters
    ----------
    demo : Demonstration
    groups : sequence of str
        The learned groups (:func:`resolve_groups`), in this order.
    derive_velocity : bool, default=True
    cli : bool, default=False
        Errors name the command line's ``--group`` and ``--groups`` flags.

    Returns
    -------
    demo : Demonstration
        With exactly ``groups``.
    """
    have = demo.group_names
    if derive_velocity:
        for h in hands(demo.groups):
            if hand_group(h.name, "velocity") in groups and not h.velocity:
                demo = with_velocity(demo, hand=h.name)
        have = demo.group_names
    if have == tuple(groups):
        return demo  # already these groups in this order: select would copy it
    missing = [g for g in groups if g not in have]
    if missing:
        hint = (
            f"; map its columns with --group {missing[0]}=NAME,... or leave it"
            " out of --groups"
            if cli
            else ""
        )
        raise ValidationError(
            f"a demonstration lacks group(s) {', '.join(missing)}; it has"
            f" {', '.join(demo.group_names)}{hint}"
        )
    return demo.select(*groups)


def levels_by_group(levels, groups: Sequence[str]) -> dict[str, int]:
    """Codebook levels of each learned group.

    Parameters
    ----------
    levels : int, mapping of str to int, or None
        One int for all groups, or per group; groups not named fall back to
        :data:`DEFAULT_LEVELS`, and groups it does not name either to
        :data:`OTHER_LEVELS` (10).
    groups : sequence of str

    Returns
    -------
    levels : dict of str to int

    Examples
    --------
    >>> levels_by_group({"velocity": 8}, ("position", "velocity"))
    {'position': 20, 'velocity': 8}
    >>> levels_by_group(None, ("joints", "gripper", "tool"))
    {'joints': 20, 'gripper': 2, 'tool': 10}
    """
    lv = {} if levels is None else levels
    if isinstance(lv, numbers.Integral) and not isinstance(lv, bool):
        return {g: check_positive_int(lv, "levels") for g in groups}
    if not isinstance(lv, Mapping):
        raise ValidationError(
            f"levels must be an int or a mapping of group to int; got {lv!r}"
        )
    unknown = [g for g in lv if g not in groups]
    if unknown:
        raise ValidationError(
            f"levels names group(s) {', '.join(map(repr, unknown))} that are not"
            f" learned; the learned groups are {', '.join(groups)}"
        )
    out = {}
    for g in groups:
        if g in lv:
            out[g] = check_positive_int(lv[g], f"levels[{g!r}]")
        else:
            out[g] = default_levels(g)
    return out


def default_levels(group: str) -> int:
    """A group's levels when ``levels`` does not name it (:data:`DEFAULT_LEVELS`).

    A hand's group by its kind (``left_position``: a position), a group
    named ``<prefix>_<name>`` as ``<name>`` (``left_joints``: joints).

    Examples
    --------
    >>> default_levels("right_orientation"), default_levels("left_joints")
    (10, 20)
    """
    for name in (group, kind(group), group.rsplit("_", 1)[-1]):
        if name in DEFAULT_LEVELS:
            return DEFAULT_LEVELS[name]
    return OTHER_LEVELS


def scaler_from_ranges(ranges, columns, col_groups, *, normalization, weights):
    """Exactly ``GroupScaler(mode, weights).fit(prepared demos)``, from pass 1.

    Parameters
    ----------
    ranges : RangeStats
        Per-column extremes and the sample count of the demonstrations.
    columns, col_groups : sequence of str
        The learned columns and the group of each.
    normalization : str
        The scaler's mode.
    weights : mapping of str to float or None

    Returns
    -------
    scaler : GroupScaler
    """
    return GroupScaler.from_data_ranges(
        ranges.data_min,
        ranges.data_max,
        col_groups,
        n_samples=ranges.n_samples,
        columns=columns,
        mode=normalization,
        weights=weights,
    )


@dataclass(frozen=True)
class Reduced:
    """One demonstration normalized, reduced to its key points and time-binned.

    Attributes
    ----------
    values : ndarray of shape (n_samples, n_columns)
        Normalized (unweighted) values.
    times : ndarray of shape (n_samples,)
        Time stamps.
    keypoints : ndarray of shape (n_keys,), dtype int64
        Key-point indices.
    key_bins : ndarray of shape (n_keys,), dtype int64
        Time bin of each key point.
    key_cells : ndarray of shape (n_keys, n_columns), dtype int64 or None
        Codebook cell of each key point: its level index in every column
        (:meth:`DemoSpec.encode` only).
    n_clipped : int
        Values the codebook clipped (:meth:`DemoSpec.encode` only).
    tau : ndarray of shape (n_samples,)
        Normalized times (0 to 1), computed when first read (a fit reads it
        for its templates only).
    """

    values: np.ndarray
    times: np.ndarray
    keypoints: np.ndarray
    key_bins: np.ndarray
    key_cells: np.ndarray | None = None
    n_clipped: int = 0

    @cached_property
    def tau(self) -> np.ndarray:
        """Normalized times, ``unit_time(times)``."""
        return unit_time(self.times)


def frame_spec(demo: Demonstration) -> tuple[tuple[str, int], ...]:
    """A demonstration's task frames: each one's name and pose size."""
    return tuple((name, int(p.size)) for name, p in demo.frames.items())


def _frames_text(spec) -> str:
    if not spec:
        return "none"
    return ", ".join(f"{name!r} ({size} values)" for name, size in spec)


def first_quaternion(d: Demonstration) -> tuple[float, ...]:
    """A demonstration's first orientations (w, x, y, z), or ``()`` without one.

    One quaternion per orientation group (every hand's), one after another.
    """
    return tuple(float(v) for b in orientation_blocks(d.groups) for v in d.X[0, b])


def same_side(d: Demonstration, ref: tuple[float, ...]) -> Demonstration:
    """``d`` with its quaternions negated if its first one points away from ``ref``.

    ``q`` and ``-q`` are one rotation; a recorded stream (a ROS 2 ``/tf`` bag,
    say) may give either, and demonstrations on both sides would be averaged
    into rotations none of them made. A demonstration's quaternions are
    continuous (:func:`~ndlfd.orientation.make_continuous`), so one sign
    decides for all of them: the first sample's, against ``ref`` (its
    rotation from ``ref`` is below 180 degrees exactly when they point the
    same way). Each orientation group (hand) is decided on its own.

    Examples
    --------
    >>> d = Demonstration.from_arrays([0.0, 1.0], orientation=[[0, 1, 0, 0]] * 2)
    >>> same_side(d, (0.0, -1.0, 0.0, 0.0)).get("orientation")[0]
    array([-0., -1., -0., -0.])
    """
    q = first_quaternion(d)
    if not ref or len(q) != len(ref):
        return d
    blocks = orientation_blocks(d.groups)
    away = [
        d.groups[b[0]]
        for k, b in enumerate(blocks)
        if float(np.dot(q[4 * k : 4 * k + 4], ref[4 * k : 4 * k + 4])) < 0.0
    ]
    return negated_orientation(d, away) if away else d


def negated_orientation(d: Demonstration, groups=("orientation",)) -> Demonstration:
    """``d`` with the quaternions of ``groups`` negated (``-q``: the same rotations)."""
    X = d.X.copy()
    for g in groups:
        cols = d.columns_of(g)
        X[:, cols] = -X[:, cols]
    return Demonstration(d.t, X, d.columns, d.groups, d.frames)


@dataclass(frozen=True)
class DemoSpec:
    """What is learned of a demonstration and how it is encoded (fit and generate).

    The fit's first pass knows the groups and columns only; its second pass
    and a fitted model also the scaler, codebook and time bins.

    Attributes
    ----------
    groups : tuple of str
        The learned groups.
    columns, col_groups : tuple of str
        The learned columns and the group of each.
    derive_velocity : bool
    epsilon : float
    n_points : int or None
    distance : str
        The reduction's parameters (see :func:`ndlfd.simplify`).
    scaler : GroupScaler or None
    codebook : Codebook or None
    time_bins : TimeBins or None
    cli : bool
        Errors name the command line's flags.
    frames : tuple of (str, int)
        The task frames every demonstration carries: name and pose size
        (:mod:`ndlfd._poses`), as the first one has them.
    quat_ref : tuple of float
        The first demonstration's first orientation (w, x, y, z), or empty:
        ``q`` and ``-q`` are one rotation, and every demonstration's
        quaternions are put on its side (:meth:`prepared`).
    """

    groups: tuple[str, ...] = ()
    columns: tuple[str, ...] = ()
    col_groups: tuple[str, ...] = ()
    derive_velocity: bool = True
    epsilon: float = 0.05
    n_points: int | None = None
    distance: str = "line"
    scaler: GroupScaler | None = None
    codebook: Codebook | None = None
    time_bins: TimeBins | None = None
    cli: bool = False
    frames: tuple[tuple[str, int], ...] = ()
    quat_ref: tuple[float, ...] = ()

    @classmethod
    def fitted(cls, params: Mapping, ranges, groups, columns, col_groups, **kw):
        """The spec of a fit's second pass: the scaler from the ranges of pass 1.

        Parameters
        ----------
        params : mapping
            The estimator's parameters (``KeypointHMM.get_params()``).
        ranges : RangeStats
            What pass 1 found.
        groups, columns, col_groups : tuple of str
        **kw
            Other fields (``cli``).

        Returns
        -------
        spec : DemoSpec
        """
        return cls(
            groups=groups,
            columns=columns,
            col_groups=col_groups,
            derive_velocity=params["derive_velocity"],
            epsilon=params["epsilon"],
            n_points=params["n_points"],
            distance=params["distance"],
            scaler=scaler_from_ranges(
                ranges,
                columns,
                col_groups,
                normalization=params["normalization"],
                weights=params["weights"],
            ),
            codebook=Codebook.from_groups(
                levels_by_group(params["levels"], groups), col_groups
            ),
            time_bins=TimeBins(params["n_time_bins"]),
            **kw,
        )

    @classmethod
    def of_model(cls, est) -> DemoSpec:
        """The spec of a fitted KeypointHMM (its parameters and learned stages)."""
        return cls(
            groups=est.groups_,
            columns=est.columns_,
            col_groups=est.column_groups_,
            derive_velocity=est.derive_velocity,
            epsilon=est.epsilon,
            n_points=est.n_points,
            distance=est.distance,
            scaler=est.scaler_,
            codebook=est.codebook_,
            time_bins=est.time_bins_,
            frames=tuple((k, int(v.shape[1])) for k, v in est.task_frames_.items()),
        )

    def prepared(self, demo: Demonstration) -> Demonstration:
        """:func:`prepare` of a training demonstration, checked against the first."""
        d = prepare(
            demo, self.groups, derive_velocity=self.derive_velocity, cli=self.cli
        )
        if d.columns != self.columns or d.groups != self.col_groups:
            raise ValidationError(
                "all demonstrations must have the same columns; the first has"
                f" {self.columns} and this one has {d.columns}"
            )
        have = frame_spec(d)
        if have != self.frames:
            raise ValidationError(
                "all demonstrations must carry the same task frames (name and"
                f" pose size); the first has {_frames_text(self.frames)} and this"
                f" one has {_frames_text(have)}"
            )
        return same_side(d, self.quat_ref)

    def frame_values(self, d: Demonstration) -> np.ndarray:
        """A prepared demonstration's frame poses, one after another (F,)."""
        if not self.frames:
            return np.zeros(0)
        return np.concatenate([d.frames[name] for name, _ in self.frames])

    @cached_property
    def column_weights(self) -> np.ndarray | None:
        """The scaler's per-column weights for the reduction (None if all 1)."""
        w = self.scaler.column_weights_
        return None if np.all(w == 1.0) else w

    def reduce(self, d: Demonstration, *, n_jobs=None) -> Reduced:
        """Normalize a prepared demonstration, find its key points, bin their times.

        Parameters
        ----------
        d : Demonstration
            Prepared (:meth:`prepared`), with the learned columns.
        n_jobs : int, optional
            Threads of the reduction (see :func:`ndlfd.simplify`).

        Returns
        -------
        reduced : Reduced
        """
        return Reduced(*self._key_points(d, n_jobs))

    def encode(self, d: Demonstration, *, n_jobs=None) -> Reduced:
        """:meth:`reduce`, and the key points' codebook cells (the fit's pass 2).

        Parameters
        ----------
        d : Demonstration
            Prepared (:meth:`prepared`), with the learned columns.
        n_jobs : int, optional
            Threads of the reduction.

        Returns
        -------
        reduced : Reduced
            With ``key_cells`` and ``n_clipped``.
        """
        u, t, idx, bins = self._key_points(d, n_jobs)
        # the key points' normalized values, float64 of n columns, which
        # simplify checked finite: the codebook need not check them again
        cells, clipped = self.codebook.cells_checked(u[idx])
        return Reduced(u, t, idx, bins, cells, clipped)

    def _key_points(self, d: Demonstration, n_jobs):
        """Normalized values, times, key points and their time bins."""
        u = self.scaler.transform(d, weighted=False)
        idx = simplify(
            u,
            None if self.n_points is not None else self.epsilon,
            distance=self.distance,
            weights=self.column_weights,
            times=d.t if self.distance == "sed" else None,
            n_points=self.n_points,
            n_jobs=n_jobs,
        )
        # the key points keep both ends, so their unit time is the
        # demonstration's at the key points (bit for bit): TimeBins.normalize;
        # d.t is checked already
        return u, d.t, idx, self.time_bins.symbols(unit_time(d.t[idx]))
