"""Column mapping: which file column (or array) is the time, which a group.

Every reader maps the columns of a file (or the arrays of an ``.npz`` / HDF5
file) to a time vector and physical groups with :func:`map_arrays`, and says how
with a :class:`ColumnMapping`. Error messages name the settings through
``hints``: :data:`LIBRARY_HINTS` (parameters) or :data:`CLI_HINTS` (flags).

**Orientation of three columns.** Columns named ``roll``, ``pitch`` and
``yaw`` (any case) are the orientation as Euler angles in radians, about the
x, y and z axes, in the convention ``euler`` (default ``"xyz"``: extrinsic,
roll about the fixed x axis, then pitch about y, then yaw about z, as ROS's
``rpy``; ``"ZYX"`` is the intrinsic z-y'-x'' convention, the same rotation
for the same roll, pitch and yaw). Any other three orientation columns (an
orientation group of three mapped by ``groups``, or names such as
``rx, ry, rz``) need their representation named, never guessed: ``euler=``,
or ``representation=`` one of :data:`~ndlfd.orientation.REPRESENTATIONS`
(``"rotvec"``: a rotation vector, axis times angle, as Universal Robots log
``rx, ry, rz``; ``"euler-SEQ"``; ``"quat-wxyz"``/``"quat-xyzw"`` for four
columns); without one they are an error naming the choices (before issue
37, three mapped columns were read as Euler ``xyz``). On the command line
the representation follows the group: ``--group orientation=rx,ry,rz:rotvec``.
Every conversion is scipy's :class:`~scipy.spatial.transform.Rotation`. The
:class:`ColumnMapping` records the representation (``euler``: the
convention or ``"rotvec"``) and the names, and :func:`euler_columns` turns
an orientation group (a generated path's) back into those columns.

**Names labs export** (``current_pos_x``, ``goal_pos_x``, ``force_x``,
``torque_x``, ``joint_1``, ``q1``): :mod:`ndlfd.io._names`; a commanded set
beside a measured one is left out (``ColumnMapping.left_out``, a warning);
names that cannot be told give an error with a mapping to paste. ``groups``
and ``drop`` take glob patterns (``drop=["goal_*"]``, any case).

**Gripper.** A column named ``gripper`` (any case) is the group ``gripper``;
map another with ``groups={"gripper": ["NAME"]}``.

**Motor names** (LeRobot's SO-100/101, Koch, LeKiwi: ``shoulder_pan.pos``,
``x.vel``). A name ``NAME.pos`` is the joint ``NAME`` of the group ``joints``;
``NAME.vel`` and ``NAME.effort`` are the columns ``NAME.vel`` and
``NAME.effort`` of the groups ``joint_velocity`` and ``joint_effort``
(:data:`MOTOR_KINDS`; the suffix in any case). ``gripper.pos`` is the
exception: like a column named ``gripper`` it is the group ``gripper`` (its
column ``gripper``), learned as a gripper (kept on its two values when it
records two); its ``.vel`` and ``.effort`` go with the other motors'.

Older LeRobot datasets (v2.x, SO-100: ``lerobot/so100_*``) name the same
motors ``main_shoulder_pan``, ..., ``main_gripper`` (:data:`SO100_MAIN_NAMES`,
in any case): they are read alike, the joints ``main_shoulder_pan`` ... in the
group ``joints`` and ``main_gripper`` as the group ``gripper``, each column
keeping its name.
"""

from __future__ import annotations

import fnmatch
import glob
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .._errors import DataFileError, ValidationError
from .._pose_groups import hand_name
from .._pose_groups import kind as group_kind
from .._repairs import repaired
from ..demonstration import Demonstration, default_columns
from ..orientation import (
    QUATERNION_ORDERS,
    check_euler,
    check_representation,
)
from ._names import lab_groups, names_error, ready_line
from ._rotations import (
    EULER_NAMES,
    euler_columns,
    orientation_block,
    orientation_representation,
)
from ._rows import BAD_ROWS, check_bad_rows, drop_bad_rows

__all__ = [
    "ARRAY_NAMES",
    "BAD_ROWS",
    "CLI_HINTS",
    "EULER_NAMES",
    "LIBRARY_HINTS",
    "MAPPING_DEFAULTS",
    "MOTOR_KINDS",
    "NAMING_CONVENTION",
    "SO100_MAIN_NAMES",
    "SO_ARM_JOINTS",
    "TIME_NAMES",
    "ColumnMapping",
    "RateMapping",
    "check_bad_rows",
    "euler_columns",
    "group_of_column",
    "is_so_arm_joint",
    "map_arrays",
    "resolve_column",
    "wrap_error",
]

#: The time column's names tried, in this order, when none is named
#: (``timestamp``: LeRobot's, which ``ndlfd generate`` keeps in its output).
TIME_NAMES = ("t", "time", "timestamp")

#: Names of 2-D arrays (``.npz`` keys, HDF5 datasets) that give their group.
ARRAY_NAMES: tuple[tuple[str, str], ...] = (
    ("position", "position"),
    ("pos", "position"),
    ("velocity", "velocity"),
    ("vel", "velocity"),
    ("orientation", "orientation"),
    ("quat", "orientation"),
    ("force", "force"),
)

#: How error messages name the settings: library parameters ...
LIBRARY_HINTS = {
    "time": "time_column=",
    "time_hint": "pass time_column='NAME' (or None to use the row number), or"
    " rate=HZ for a log without time stamps (read_demos, DemoFiles)",
    "groups": "groups",
    "group_hint": "pass groups={'position': [...], ...}",
    "drop": "drop",
    "drop_hint": "drop=[...]",
}
#: ... or the command line's flags (``ndlfd fit``, ``ndlfd plot``, ...).
CLI_HINTS = {
    "time": "--time-column",
    "time_hint": "name it with --time-column NAME, or give the sample rate of a"
    " log without time stamps with --rate HZ",
    "groups": "--group",
    "group_hint": "map them with --group GROUP=NAME[,NAME...]",
    "drop": "--drop",
    "drop_hint": "--drop NAME[,NAME...]",
}


#: How :func:`read_csv` tells a column's group from its name when no ``groups=``
#: mapping names it (case-insensitively). A name ``group.column`` puts
#: ``column`` in group ``group``.
NAMING_CONVENTION: tuple[tuple[str, str], ...] = (
    (r"x|y|z|p\d+", "position"),
    (r"vx|vy|vz|v\d+", "velocity"),
    (r"qw|qx|qy|qz", "orientation"),
    (r"fx|fy|fz|f\d+", "force"),
    (r"roll|pitch|yaw", "orientation"),
    (r"gripper", "gripper"),
)
#: Motor names ``NAME.KIND`` (LeRobot's robots): the group of each kind.
MOTOR_KINDS = {"pos": "joints", "vel": "joint_velocity", "effort": "joint_effort"}

#: The SO-100 arm's motor names in older LeRobot datasets (v2.x): the joints,
#: then the gripper (read as ``NAME.pos`` names are, without a suffix).
SO100_MAIN_NAMES = (
    "main_shoulder_pan",
    "main_shoulder_lift",
    "main_elbow_flex",
    "main_wrist_flex",
    "main_wrist_roll",
    "main_gripper",
)
_SO100_MAIN = {n.casefold(): n for n in SO100_MAIN_NAMES}
#: The SO-100/101 arm's joints (the gripper aside), by motor name.
SO_ARM_JOINTS = (
    "shoulder_pan",
    "shoulder_lift",
    "elbow_flex",
    "wrist_flex",
    "wrist_roll",
)


def is_so_arm_joint(name: str) -> bool:
    """Whether ``name`` is an SO-100/101 joint as LeRobot names it.

    ``NAME.pos`` (SO-101 and current LeRobot) or ``main_NAME`` (older SO-100
    datasets) for ``NAME`` in :data:`SO_ARM_JOINTS`, in any case.

    Examples
    --------
    >>> is_so_arm_joint("elbow_flex.pos"), is_so_arm_joint("main_wrist_roll")
    (True, True)
    >>> is_so_arm_joint("gripper.pos"), is_so_arm_joint("elbow_flex")
    (False, False)
    """
    low = name.casefold()
    if low.endswith(".pos"):
        return low[: -len(".pos")] in SO_ARM_JOINTS
    return low.startswith("main_") and low[len("main_") :] in SO_ARM_JOINTS


_CONVENTION = tuple(
    (re.compile(rf"^(?:{pat})$", re.IGNORECASE), g) for pat, g in NAMING_CONVENTION
)


def group_of_column(name: str) -> tuple[str, str] | None:
    """Group and column name that the CSV naming convention gives a header name.

    ``x, y, z, p0, p1, ...`` → position; ``vx, vy, vz, v0, ...`` → velocity;
    ``qw, qx, qy, qz`` and the Euler angles ``roll, pitch, yaw`` → orientation;
    ``fx, fy, fz, f0, ...`` → force; ``gripper`` → gripper (in any case);
    motor names: ``NAME.pos`` → ``NAME`` in ``joints`` (but ``gripper.pos``
    → ``gripper`` in ``gripper``), ``NAME.vel`` → ``NAME.vel`` in
    ``joint_velocity``, ``NAME.effort`` → ``NAME.effort`` in
    ``joint_effort``; the SO-100 names of older LeRobot datasets
    (:data:`SO100_MAIN_NAMES`): ``main_shoulder_pan`` ... in ``joints``,
    ``main_gripper`` in ``gripper``, as they are; ``group.column`` →
    ``column`` in the user group ``group``; anything else → ``None``.

    Parameters
    ----------
    name : str
        A header name.

    Returns
    -------
    (group, column) : tuple of str, or None

    Examples
    --------
    >>> group_of_column("vy")
    ('velocity', 'vy')
    >>> group_of_column("X")
    ('position', 'X')
    >>> group_of_column("grip.width")
    ('grip', 'width')
    >>> group_of_column("Yaw")
    ('orientation', 'Yaw')
    >>> group_of_column("shoulder_pan.pos")
    ('joints', 'shoulder_pan')
    >>> group_of_column("gripper.pos")
    ('gripper', 'gripper')
    >>> group_of_column("elbow_flex.vel")
    ('joint_velocity', 'elbow_flex.vel')
    >>> group_of_column("main_elbow_flex")
    ('joints', 'main_elbow_flex')
    >>> group_of_column("main_gripper")
    ('gripper', 'main_gripper')
    >>> group_of_column("speed") is None
    True
    """
    if "." in name:
        motor, kind = name.rsplit(".", 1)
        group = MOTOR_KINDS.get(kind.casefold())
        if motor and group is not None:
            if group == "joints" and motor.casefold() == "gripper":
                return "gripper", motor
            return group, (motor if group == "joints" else name)
        group, column = name.split(".", 1)
        if group and column:
            return group, column
        return None
    main = _SO100_MAIN.get(name.casefold())
    if main is not None:
        return ("gripper" if main == "main_gripper" else "joints"), name
    for pattern, group in _CONVENTION:
        if pattern.match(name):
            return group, name
    return None


def _group_of_array(name: str) -> str | None:
    low = name.casefold()
    for alias, group in ARRAY_NAMES:
        if low == alias:
            return group
    return None


@dataclass(frozen=True)
class ColumnMapping:
    """How one demonstration was read: its source, time column and groups.

    Attributes
    ----------
    source : str
        The file (``file.h5:/episode`` for an HDF5 episode).
    time : str or None
        The file's name of the time column (``None``: the row number).
    groups : tuple of (str, tuple of str)
        Each group with the file's names of its columns (or arrays), in the
        demonstration's column order.
    dropped : tuple of str
        Columns left out on request.
    ignored : tuple of str
        Arrays that are not data (scalars, text), left out by themselves.
    layout : str
        ``"comma-separated"`` (or semicolon, tab, whitespace) for a CSV file,
        ``"arrays"`` for plain ``.npz`` / HDF5 arrays, ``"ndlfd"`` for an ndlfd
        demonstration file (self-described, no mapping).
    euler : str or None
        How the file gave the orientation when not as four quaternion
        columns: its Euler convention (``"xyz"``, ``"ZYX"``: three Euler
        angles, the group's names those three in the convention's order), or
        ``"rotvec"`` (three columns of a rotation vector); else ``None``. The
        orientation is written back so (:func:`euler_columns`).
    order : tuple of str
        The file's names of the mapped columns (or arrays) in the file's
        order, which outputs keep (empty: the order of ``groups``).
    span : tuple of (float, float) or None
        For a piece of a split recording (a bag read with ``split_gap`` or
        ``split_still``): its first and last time stamps in seconds from the
        recording's first (the piece's own time starts at 0); else ``None``.
        Not part of :meth:`__str__` (pieces of one recording read alike).
    left_out : tuple of str
        Commanded columns (``goal_pos_x`` ...) left out beside the measured
        ones of the same kind (:mod:`ndlfd.io._names`).

    Examples
    --------
    >>> m = ColumnMapping("a.csv", "time", (("position", ("X", "Y")),), ("id",))
    >>> str(m)
    'time=time; position=X,Y; dropped id'
    """

    source: str
    time: str | None
    groups: tuple[tuple[str, tuple[str, ...]], ...]
    dropped: tuple[str, ...] = ()
    ignored: tuple[str, ...] = ()
    layout: str = "comma-separated"
    euler: str | None = None
    order: tuple[str, ...] = ()
    span: tuple[float, float] | None = None
    left_out: tuple[str, ...] = ()

    def __str__(self) -> str:
        """The mapping in one line, as the command line reports it."""
        if self.layout == "ndlfd":
            return "ndlfd demonstration file"
        parts = [f"time={self.time if self.time is not None else '(row number)'}"]
        how = {None: "", "rotvec": " (rotation vector)"}.get(
            self.euler, f" (Euler {self.euler})"
        )
        parts += [
            f"{g}={','.join(cols)}"
            + (how if g == "orientation" or _three_angles(g, cols) else "")
            for g, cols in self.groups
        ]
        if self.dropped:
            parts.append("dropped " + ",".join(self.dropped))
        if self.left_out:
            parts.append("left out " + ",".join(self.left_out) + " (commanded)")
        if self.ignored:
            parts.append("ignored " + ",".join(self.ignored))
        text = "; ".join(parts)
        if self.layout not in ("comma-separated", "arrays"):
            text += f" ({self.layout})"
        return text

    @property
    def representation(self) -> str | None:
        """The orientation's representation when not four quaternion columns.

        ``"rotvec"`` or ``"euler-SEQ"`` (see
        :data:`~ndlfd.orientation.REPRESENTATIONS`), else ``None``.
        """
        if self.euler is None:
            return None
        return self.euler if self.euler == "rotvec" else f"euler-{self.euler}"

    @property
    def group_names(self) -> tuple[str, ...]:
        """The groups read, in column order."""
        return tuple(g for g, _ in self.groups)


@dataclass(frozen=True)
class RateMapping(ColumnMapping):
    """The mapping of a file read at a fixed rate: time is row / ``rate``.

    Attributes
    ----------
    rate : float
        The sample rate in Hz.
    """

    rate: float = 1.0

    def __str__(self) -> str:
        return (
            super()
            .__str__()
            .replace("time=(row number)", f"time=(row number) / {self.rate:g} Hz", 1)
        )


def _three_angles(group: str, cols) -> bool:
    """Whether a hand's orientation was read from three columns."""
    return group_kind(group) == "orientation" and len(cols) == 3


def resolve_column(p, name: str, keys: Sequence[str], what: str) -> str:
    """The key ``name`` names: an exact match, else the one equal up to case."""
    if name in keys:
        return name
    hits = [k for k in keys if k.casefold() == name.casefold()]
    if len(hits) == 1:
        return hits[0]
    if hits:
        raise DataFileError(
            f"{p}: {what} {name!r} matches {hits}, which differ only in case; name"
            " one of them exactly"
        )
    raise DataFileError(
        f"{p}: {what} {name!r}, but there is no such column; got columns {list(keys)}"
    )


def _find_time(p, keys, time_column, how) -> str | None:
    if time_column is None:
        return None
    if isinstance(time_column, str):
        return resolve_column(p, time_column, keys, f"{how['time']} names")
    candidates = list(time_column)
    for name in candidates:
        hits = [k for k in keys if k == name] or [
            k for k in keys if k.casefold() == name.casefold()
        ]
        if len(hits) == 1:
            return hits[0]
    names = " or ".join(repr(c) for c in candidates)
    raise DataFileError(
        f"{p}: expected a time column named {names} (any case); got columns"
        f" {list(keys)}; {how['time_hint']}"
    )


def _time_error(p, name, t, i, lines, layout) -> DataFileError:
    if lines is not None:
        return DataFileError(
            f"{p}, line {lines[i]}: time column {name!r} must be strictly"
            f" increasing; got {float(t[i])!r} after {float(t[i - 1])!r} on line"
            f" {lines[i - 1]}"
        )
    return DataFileError(
        f"{p}: time {layout} {name!r} must be strictly increasing; got"
        f" {float(t[i])!r} at row {i} after {float(t[i - 1])!r} at row {i - 1}"
    )


def _is_data(a: np.ndarray) -> bool:
    return a.dtype.kind in "biuf" and a.ndim >= 1


def _matches(p, name: str, keys: Sequence[str], what: str) -> list[str]:
    """The keys ``name`` names: a glob pattern's matches (any case), else one."""
    if not glob.has_magic(name):
        return [resolve_column(p, name, keys, what)]
    pat = name.casefold()
    hits = [k for k in keys if fnmatch.fnmatchcase(k.casefold(), pat)]
    if not hits:
        raise DataFileError(
            f"{p}: {what} the pattern {name!r}, which matches no column; got columns"
            f" {list(keys)}"
        )
    return hits


def _dropped(p, drop, keys, how) -> list[str]:
    drop = [drop] if isinstance(drop, str) else list(drop)
    dropped: list[str] = []
    unknown = []
    for c in drop:
        try:
            hits = _matches(p, c, keys, f"{how['drop']} names")
        except DataFileError:
            unknown.append(c)
            continue
        dropped.extend(k for k in hits if k not in dropped)
    if unknown:
        raise DataFileError(
            f"{p}: {how['drop']} names unknown column(s) {unknown}; the columns are"
            f" {keys}"
        )
    return dropped


def _explicit(p, groups, keys, tname, dropped, how, noun):
    """``groups`` resolved to the file's keys (glob patterns expanded)."""
    layout_of: dict[str, list[str]] = {}
    owner: dict[str, str] = {}
    if groups is None:
        return layout_of, owner
    if not isinstance(groups, Mapping):
        raise ValidationError(
            f"groups must be a mapping group -> column names; got {groups!r}"
        )
    free = [k for k in keys if k != tname and k not in dropped]
    for g, cols in groups.items():
        cols = [cols] if isinstance(cols, str) else list(cols)
        if not cols:
            raise DataFileError(f"{p}: {how['groups']} {g} names no column")
        for c in cols:
            what = f"{how['groups']} {g} names"
            for k in _matches(p, c, keys if not glob.has_magic(c) else free, what):
                if k == tname or k in dropped:
                    raise DataFileError(
                        f"{p}: {how['groups']} {g} names {noun} {k!r}, which is the"
                        " time column or dropped"
                    )
                if k in owner:
                    raise DataFileError(
                        f"{p}: {how['groups']} maps {noun} {k!r} to both"
                        f" {owner[k]!r} and {g!r}"
                    )
                owner[k] = g
                layout_of.setdefault(g, []).append(k)
    return layout_of, owner


def map_arrays(
    p,
    arrays: Mapping[str, np.ndarray],
    *,
    time_column,
    groups,
    drop,
    quaternion_order: str,
    how: Mapping[str, str],
    euler: str | None = None,
    representation: str | None = None,
    lines: np.ndarray | None = None,
    layout: str = "arrays",
    source: str | None = None,
    bad_rows: str = "error",
) -> tuple[Demonstration, ColumnMapping]:
    """Map named 1-D and 2-D arrays (CSV columns, npz keys) to a demonstration.

    ``groups`` and ``drop`` take glob patterns (``"goal_*"``, any case);
    columns no group names go by their names (:func:`group_of_column`, then
    :func:`~ndlfd.io._names.lab_groups`). ``representation`` is the
    orientation's (:data:`~ndlfd.orientation.REPRESENTATIONS`); ``euler`` an
    Euler convention (the same as ``representation="euler-SEQ"``).
    ``bad_rows="drop"`` drops the rows with NaN or inf in the time or a mapped
    column (a repair: see :mod:`ndlfd._repairs`); at least 2 rows must remain.
    """
    check_bad_rows(bad_rows)
    QUATERNION_ORDERS.get(quaternion_order)
    if euler is not None:
        check_euler(euler)
    if representation is not None:
        check_representation(representation)
    keys = list(arrays)
    table = lines is not None
    noun = "column" if table else "array"
    dropped = _dropped(p, drop, keys, how)
    tname = _find_time(p, [k for k in keys if k not in dropped], time_column, how)
    if tname is None:
        n = None
        t = None
    else:
        t = np.asarray(arrays[tname])
        if not _is_data(t) or t.ndim > 2 or (t.ndim == 2 and t.shape[1] != 1):
            raise DataFileError(
                f"{p}: the time {noun} {tname!r} must hold one number per sample"
                f" (shape (n,)); got shape {t.shape} and dtype {t.dtype}"
            )
        t = t.reshape(-1).astype(np.float64)
        n = t.shape[0]
    layout_of, owner = _explicit(p, groups, keys, tname, dropped, how, noun)
    explicit = set(layout_of)
    found = _by_names(
        p, arrays, keys, (tname, dropped, representation), owner, layout_of, how, noun
    )
    ignored, by_name, lab, conflicts = found
    if conflicts:
        k, g = conflicts[0]
        same = [c for c, h in conflicts if h == g]
        line = ready_line(how["groups"].startswith("--"), {}, [*dropped, *same], None)
        raise DataFileError(
            f"{p}: {noun} {k!r} belongs to group {g!r} by its name, but"
            f" {how['groups']} {g} does not list it; add it there or leave it out"
            f" with {how['drop_hint']} (e.g. {line})"
        )
    if not layout_of:
        raise DataFileError(
            f"{p}: expected value columns besides the time column; got none"
        )
    if lab.left_out:
        kept = lab.kept_for[lab.left_out[0]]
        repaired(
            "left_out",
            len(lab.left_out),
            f"{p}: left out the commanded column(s) {', '.join(lab.left_out)}"
            f" beside the measured {', '.join(kept)}; map them with"
            f" {how['groups']} to learn them instead",
            detail=f"{p} ({','.join(lab.left_out)})",
            stacklevel=3,
        )
    # shapes
    blocks, names, gnames, mapped, flat = [], [], [], [], []
    from_euler = None
    for g, ks in layout_of.items():
        parts, cols = [], []
        for k in ks:
            a = np.asarray(arrays[k])
            if not _is_data(a) or a.ndim > 2:
                raise DataFileError(
                    f"{p}: {noun} {k!r} must hold numbers of shape (n,) or (n, k);"
                    f" got shape {a.shape} and dtype {a.dtype}"
                )
            if a.ndim == 0 or a.shape[0] == 0:
                raise DataFileError(
                    f"{p}: {noun} {k!r} must hold at least one sample; got shape"
                    f" {a.shape}"
                )
            a = a.astype(np.float64).reshape(a.shape[0], -1)
            if n is None:
                n = a.shape[0]
            if a.shape[0] != n:
                ref = f"the time {noun} {tname!r}" if tname else "the first array"
                hint = " (transposed?)" if a.shape[1] == n else ""
                raise DataFileError(
                    f"{p}: {noun} {k!r} has {a.shape[0]} rows{hint}; expected {n},"
                    f" like {ref}"
                )
            parts.append(a)
            if a.ndim == 2 and np.asarray(arrays[k]).ndim == 2:
                if len(ks) == 1:
                    cols.extend(default_columns(g, a.shape[1]))
                else:
                    cols.extend(f"{k}_{i}" for i in range(a.shape[1]))
            else:
                cols.append(by_name.get(k, k))
        block = np.hstack(parts)
        if group_kind(g) == "orientation":
            rep = orientation_representation(
                p, ks, block, representation, euler, lab, g in explicit, how, g
            )
            ks, block, cols, given = orientation_block(
                p, ks, block, cols, rep, quaternion_order, g in lab.quaternions, how, g
            )
            from_euler = _one_representation(p, from_euler, given, g, mapped)
        elif hand_name(g) and group_kind(g) == "position" and block.shape[1] != 3:
            flat.append((g, ks))
        blocks.append(block)
        names.extend(cols)
        gnames.extend([g] * block.shape[1])
        mapped.append((g, tuple(ks)))
    if flat:
        raise _hand_position_error(p, flat, how)
    if bad_rows == "drop":
        t, blocks, lines = drop_bad_rows(p, t, blocks, lines)
        n = blocks[0].shape[0]
    if t is None:
        t = np.arange(n, dtype=np.float64)
    else:
        bad = np.flatnonzero(~(np.diff(t) > 0))
        if bad.size:
            raise _time_error(p, tname, t, int(bad[0]) + 1, lines, noun)
    mapping = ColumnMapping(
        source if source is not None else str(p),
        tname,
        tuple(mapped),
        tuple(dropped),
        tuple(ignored),
        layout,
        from_euler,
        tuple(k for k in keys if k in owner),
        left_out=tuple(lab.left_out),
    )
    try:
        demo = Demonstration(t, np.hstack(blocks), tuple(names), tuple(gnames))
    except ValidationError as exc:
        raise wrap_error(p, exc, lines) from None
    return demo, mapping


def _one_representation(p, before, given, group, mapped):
    """The representation of every orientation read from three columns.

    A :class:`ColumnMapping` records one (``euler``): two hands' orientations
    given in two representations are an error.
    """
    if given is None or before is None or given == before:
        return given if given is not None else before
    first = next(
        g for g, ks in mapped if group_kind(g) == "orientation" and len(ks) == 3
    )
    raise DataFileError(
        f"{p}: {first} is read as {before} and {group} as {given}; expected the"
        " hands' orientations in one representation (name it with"
        " representation=, or --group HAND_orientation=A,B,C:REPR)"
    )


def _hand_position_error(p, flat, how) -> DataFileError:
    """Hands' positions (``left_position``) of other than 3 columns."""
    plain = {f"{hand_name(g)}_{'xyz'[: len(ks)]}": list(ks) for g, ks in flat}
    line = ready_line(how["groups"].startswith("--"), plain)
    got = "; ".join(f"{g} {len(ks)} ({', '.join(ks)})" for g, ks in flat)
    return DataFileError(
        f"{p}: a hand's position takes 3 columns (x, y, z); got {got}; give"
        " each hand all three, or learn the columns as groups that are no"
        f" hand's pose, e.g. {line}"
    )


def _by_names(p, arrays, keys, given, owner, layout_of, how, noun):
    """Every key no group names, placed by its name (``layout_of`` extended).

    ``given`` is the time key, the dropped keys and the representation (three
    orientation columns whose names do not say theirs need it).

    Returns the ignored keys, the column name of each key a name rule
    placed, what :func:`~ndlfd.io._names.lab_groups` made of the 1-D keys,
    and the conflicts with the explicit groups (key, group).
    """
    tname, dropped, representation = given
    explicit = set(layout_of)
    ignored, single, placed = [], [], {}
    by_name: dict[str, str] = {}  # key -> column name, for keys a name rule put
    for k in keys:
        if k == tname or k in dropped or k in owner:
            continue
        a = np.asarray(arrays[k])
        if not _is_data(a):
            ignored.append(k)
        elif a.ndim >= 2:
            g = _group_of_array(k)
            if g is None:
                single.append(k)  # named as nothing: said below
            else:
                placed.setdefault(g, []).append(k)
        else:
            single.append(k)

    def known(name):
        if np.asarray(arrays[name]).ndim >= 2:
            return None
        hit = group_of_column(name)
        if hit is not None:
            by_name[name] = hit[1]
        return hit

    lab = lab_groups(single, known, group_of_column)
    for g, cols in lab.groups.items():
        placed.setdefault(g, []).extend(cols)
    conflicts = [(k, g) for g, ks in placed.items() if g in explicit for k in ks]
    unsure = representation is None and any(g not in explicit for g, _ in lab.unsure)
    if lab.unknown or lab.ambiguous or unsure:
        names_error(p, layout_of, placed, dropped, lab, how, noun)
    for g, cols in lab.unsure:  # a hand's (with a representation) in its place
        if g != "orientation" and g not in explicit:
            placed[g] = cols
    rank = {k: i for i, k in enumerate(keys)}
    for g in sorted(placed, key=lambda g: min(rank[k] for k in placed[g])):
        if g not in explicit:
            layout_of[g] = placed[g]
            owner.update(dict.fromkeys(placed[g], g))
    for g, cols in lab.unsure:  # with a representation given (else an error)
        if g == "orientation" and g not in explicit:
            layout_of[g] = cols
            owner.update(dict.fromkeys(cols, g))
    return ignored, by_name, lab, conflicts


def wrap_error(p, exc: ValidationError, lines: np.ndarray | None = None):
    msg = str(exc)
    m = re.search(r"at row (\d+)", msg)
    if m and lines is not None and int(m.group(1)) < lines.size:
        msg += f" (line {lines[int(m.group(1))]})"
    return DataFileError(f"{p}: {msg}")


#: The column mapping options of every reader, with their defaults.
MAPPING_DEFAULTS = {
    "time_column": TIME_NAMES,
    "groups": None,
    "quaternion_order": "wxyz",
    "drop": (),
    "euler": None,
    "representation": None,
    "bad_rows": "error",
}
