"""Column mapping: which file column (or array) is the time, which a group.

Every reader maps the columns of a file (or the arrays of an ``.npz`` / HDF5
file) to a time vector and physical groups with :func:`map_arrays`, and says how
with a :class:`ColumnMapping`. Error messages name the settings through
``hints``: :data:`LIBRARY_HINTS` (parameters) or :data:`CLI_HINTS` (flags).

**Euler angles.** Columns named ``roll``, ``pitch`` and ``yaw`` (any case) are
the orientation as Euler angles in radians, about the x, y and z axes; so is
an orientation group of three columns mapped by ``groups`` (its columns listed
in the order of the convention's axes). They become unit quaternions
``(w, x, y, z)`` with :func:`~ndlfd.orientation.euler_to_quaternions` in the
convention ``euler`` (default ``"xyz"``: extrinsic, roll about the fixed x
axis, then pitch about y, then yaw about z, as ROS's ``rpy``; ``"ZYX"`` is the
intrinsic z-y'-x'' convention, the same rotation for the same roll, pitch and
yaw). The :class:`ColumnMapping` records the convention and the names, and
:func:`euler_columns` turns an orientation group (a generated path's) back
into those columns. ``rx, ry, rz`` are not taken for Euler angles by their
names: many robots (Universal Robots' TCP pose) log a rotation vector under
them; map them with ``groups={"orientation": ["rx", "ry", "rz"]}`` when they
are Euler angles.

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

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .._errors import DataFileError, ValidationError
from .._repairs import repaired
from ..demonstration import Demonstration, default_columns
from ..orientation import (
    QUATERNION_ORDERS,
    check_euler,
    euler_to_quaternions,
    quaternions_to_euler,
)

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
    "time_hint": "pass time_column='NAME' (or None to use the row number)",
    "groups": "groups",
    "group_hint": "pass groups={'position': [...], ...}",
    "drop": "drop",
    "drop_hint": "drop=[...]",
}
#: ... or the command line's flags (``ndlfd fit``, ``ndlfd plot``, ...).
CLI_HINTS = {
    "time": "--time-column",
    "time_hint": "name it with --time-column NAME",
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
_QUAT_NAMES = ("qw", "qx", "qy", "qz")
#: The Euler angle columns known by name, about the x, y and z axes.
EULER_NAMES = ("roll", "pitch", "yaw")


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
        The Euler convention of the orientation when the file gave it as three
        Euler angles (the group's names are then those three, in the
        convention's order), else ``None``.
    order : tuple of str
        The file's names of the mapped columns (or arrays) in the file's
        order, which outputs keep (empty: the order of ``groups``).
    span : tuple of (float, float) or None
        For a piece of a split recording (a bag read with ``split_gap`` or
        ``split_still``): its first and last time stamps in seconds from the
        recording's first (the piece's own time starts at 0); else ``None``.
        Not part of :meth:`__str__` (pieces of one recording read alike).

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

    def __str__(self) -> str:
        """The mapping in one line, as the command line reports it."""
        if self.layout == "ndlfd":
            return "ndlfd demonstration file"
        parts = [f"time={self.time if self.time is not None else '(row number)'}"]
        parts += [
            f"{g}={','.join(cols)}"
            + (f" (Euler {self.euler})" if g == "orientation" and self.euler else "")
            for g, cols in self.groups
        ]
        if self.dropped:
            parts.append("dropped " + ",".join(self.dropped))
        if self.ignored:
            parts.append("ignored " + ",".join(self.ignored))
        text = "; ".join(parts)
        if self.layout not in ("comma-separated", "arrays"):
            text += f" ({self.layout})"
        return text

    @property
    def group_names(self) -> tuple[str, ...]:
        """The groups read, in column order."""
        return tuple(g for g, _ in self.groups)


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


def map_arrays(
    p,
    arrays: Mapping[str, np.ndarray],
    *,
    time_column,
    groups,
    drop,
    quaternion_order: str,
    how: Mapping[str, str],
    euler: str = "xyz",
    lines: np.ndarray | None = None,
    layout: str = "arrays",
    source: str | None = None,
    bad_rows: str = "error",
) -> tuple[Demonstration, ColumnMapping]:
    """Map named 1-D and 2-D arrays (CSV columns, npz keys) to a demonstration.

    ``bad_rows="drop"`` drops the rows with NaN or inf in the time or a mapped
    column (a repair: see :mod:`ndlfd._repairs`); at least 2 rows must remain.
    """
    check_bad_rows(bad_rows)
    QUATERNION_ORDERS.get(quaternion_order)
    check_euler(euler)
    keys = list(arrays)
    table = lines is not None
    noun = "column" if table else "array"
    drop = [drop] if isinstance(drop, str) else list(drop)
    dropped = []
    unknown = []
    for c in drop:
        try:
            dropped.append(resolve_column(p, c, keys, f"{how['drop']} names"))
        except DataFileError:
            unknown.append(c)
    if unknown:
        raise DataFileError(
            f"{p}: {how['drop']} names unknown column(s) {unknown}; the columns are"
            f" {keys}"
        )
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
    # explicit groups
    layout_of: dict[str, list[str]] = {}
    owner: dict[str, str] = {}
    if groups is not None:
        if not isinstance(groups, Mapping):
            raise ValidationError(
                f"groups must be a mapping group -> column names; got {groups!r}"
            )
        for g, cols in groups.items():
            cols = [cols] if isinstance(cols, str) else list(cols)
            if not cols:
                raise DataFileError(f"{p}: {how['groups']} {g} names no column")
            for c in cols:
                k = resolve_column(p, c, keys, f"{how['groups']} {g} names")
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
    explicit = set(layout_of)
    # every other key by its name
    ignored, unassigned, conflicts = [], [], []
    by_name: dict[str, str] = {}  # key -> column name, for keys the convention put
    for k in keys:
        if k == tname or k in dropped or k in owner:
            continue
        a = np.asarray(arrays[k])
        if not _is_data(a):
            ignored.append(k)
            continue
        g = _group_of_array(k) if a.ndim >= 2 else None
        if g is None and a.ndim == 1:
            hit = group_of_column(k)
            if hit is not None:
                g, by_name[k] = hit
        if g is None:
            unassigned.append(k)
        elif g in explicit:
            conflicts.append((k, g))
        else:
            owner[k] = g
            layout_of.setdefault(g, []).append(k)
    if unassigned:
        raise DataFileError(
            f"{p}: cannot tell the group of {noun}(s) {unassigned} from their"
            " names; name them x, y, z / vx, vy, vz / qw, qx, qy, qz / roll, pitch,"
            f" yaw / fx, fy, fz / gripper / group.column, or {how['group_hint']},"
            " or leave them out with"
            f" {how['drop_hint']}"
        )
    if conflicts:
        k, g = conflicts[0]
        raise DataFileError(
            f"{p}: {noun} {k!r} belongs to group {g!r} by its name, but"
            f" {how['groups']} {g} does not list it; add it there or leave it out"
            f" with {how['drop_hint']}"
        )
    if not layout_of:
        raise DataFileError(
            f"{p}: expected value columns besides the time column; got none"
        )
    # shapes
    blocks, names, gnames, mapped = [], [], [], []
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
        if g == "orientation" and block.shape[1] not in (3, 4):
            raise DataFileError(
                f"{p}: the orientation must be four quaternion {noun}s (qw, qx, qy,"
                " qz) or three Euler angles (roll, pitch, yaw); got"
                f" {block.shape[1]} columns from {ks}"
            )
        if g == "orientation" and block.shape[1] == 3:
            ks, block = _euler_block(p, ks, block, euler, how)
            cols = list(default_columns("orientation", 4))
            from_euler = euler
        elif g == "orientation" and block.shape[1] == 4:
            # four named columns qw, qx, qy, qz say their order; else the option
            low = [c.casefold() for c in ks]
            if len(ks) == 4 and sorted(low) == sorted(_QUAT_NAMES):
                order = [low.index(q) for q in _QUAT_NAMES]
            else:
                order = list(QUATERNION_ORDERS.get(quaternion_order))
            if len(ks) == 4:
                ks = [ks[i] for i in order]
                cols = [cols[i] for i in order]
            block = block[:, order]
        blocks.append(block)
        names.extend(cols)
        gnames.extend([g] * block.shape[1])
        mapped.append((g, tuple(ks)))
    if bad_rows == "drop":
        t, blocks, lines = _drop_bad_rows(p, t, blocks, lines)
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
    )
    try:
        demo = Demonstration(t, np.hstack(blocks), tuple(names), tuple(gnames))
    except ValidationError as exc:
        raise wrap_error(p, exc, lines) from None
    return demo, mapping


def check_bad_rows(bad_rows) -> str:
    """``bad_rows`` if it is ``"error"`` or ``"drop"``, else a clear error."""
    if bad_rows not in BAD_ROWS:
        raise ValidationError(
            f"bad_rows must be one of {', '.join(map(repr, BAD_ROWS))}; got"
            f" {bad_rows!r}"
        )
    return bad_rows


def _drop_bad_rows(p, t, blocks, lines):
    """Rows with NaN or inf dropped from ``t``, ``blocks`` and ``lines``."""
    ok = np.all([np.isfinite(b).all(axis=1) for b in blocks], axis=0)
    if t is not None:
        ok &= np.isfinite(t)
    n_bad = int(ok.size - ok.sum())
    if n_bad == 0:
        return t, blocks, lines
    if ok.sum() < 2:
        raise DataFileError(
            f"{p}: expected at least 2 rows without NaN or inf; got"
            f" {int(ok.sum())} after dropping {n_bad} of {ok.size}"
        )
    repaired(
        "rows",
        n_bad,
        f"{p}: dropped {n_bad} of {ok.size} row(s) with NaN or inf",
        stacklevel=3,
    )
    t = None if t is None else t[ok]
    lines = None if lines is None else lines[ok]
    return t, [b[ok] for b in blocks], lines


def _euler_block(p, ks, block, seq, how):
    """Three Euler angle columns as quaternions, the names in ``seq``'s order.

    Columns named roll, pitch and yaw are the angles about x, y and z and are
    put in the convention's order; other names are taken as listed.
    """
    low = [k.casefold() for k in ks]
    if sorted(low) == sorted(EULER_NAMES):
        axes = seq.lower()
        if len(set(axes)) != 3:
            raise DataFileError(
                f"{p}: {ks} are the angles about x, y and z, but the Euler"
                f" convention {seq!r} turns about {seq[0]} twice; list the angles in"
                f" its order with {how['groups']} orientation=..."
            )
        order = [low.index(EULER_NAMES["xyz".index(a)]) for a in axes]
        ks = [ks[i] for i in order]
        block = block[:, order]
    # rows with NaN or inf stay NaN: the demonstration's check names the row
    ok = np.isfinite(block).all(axis=1)
    Q = np.full((block.shape[0], 4), np.nan)
    if ok.any():
        Q[ok] = euler_to_quaternions(block[ok], seq)
    return ks, Q


def euler_columns(
    demo: Demonstration, mapping: ColumnMapping
) -> tuple[list[str], list[str], np.ndarray]:
    """A demonstration's columns with its orientation back as recorded Euler angles.

    The inverse of the Euler mapping of :func:`map_arrays`: the four
    quaternion columns of ``demo``'s orientation group (a generated path, say)
    become the three Euler angle columns ``mapping`` recorded, with their
    names, in the recorded convention (see
    :func:`~ndlfd.orientation.quaternions_to_euler` for the angles' ranges).
    A mapping without Euler angles leaves the columns as they are.

    Parameters
    ----------
    demo : Demonstration
    mapping : ColumnMapping
        How the input was read.

    Returns
    -------
    columns, groups : list of str
        The column names and their groups (orientation: the three names).
    X : ndarray of shape (n_samples, n_columns)

    Examples
    --------
    >>> import numpy as np
    >>> q = [[1.0, 0.0, 0.0, 0.0], [np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)]]
    >>> d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]],
    ...                               orientation=q)
    >>> m = ColumnMapping("a.csv", "t", (("position", ("x", "y")),
    ...                   ("orientation", ("roll", "pitch", "yaw"))), euler="xyz")
    >>> cols, groups, X = euler_columns(d, m)
    >>> cols, X[:, 2:].round(4).tolist()
    (['x', 'y', 'roll', 'pitch', 'yaw'], [[0.0, 0.0, 0.0], [0.0, 0.0, 1.5708]])
    """
    columns, groups = list(demo.columns), list(demo.groups)
    if mapping.euler is None or not demo.has_group("orientation"):
        return columns, groups, demo.X
    names = dict(mapping.groups)["orientation"]
    idx = [j for j, g in enumerate(groups) if g == "orientation"]
    angles = quaternions_to_euler(demo.X[:, idx], mapping.euler)
    first = idx[0]
    keep = [j for j in range(len(columns)) if j not in idx]
    before = [j for j in keep if j < first]
    after = [j for j in keep if j > first]
    X = np.hstack([demo.X[:, before], angles, demo.X[:, after]])
    columns = [columns[j] for j in before] + list(names)
    columns += [demo.columns[j] for j in after]
    groups = [groups[j] for j in before] + ["orientation"] * 3
    groups += [demo.groups[j] for j in after]
    return columns, groups, X


def wrap_error(p, exc: ValidationError, lines: np.ndarray | None = None):
    msg = str(exc)
    m = re.search(r"at row (\d+)", msg)
    if m and lines is not None and int(m.group(1)) < lines.size:
        msg += f" (line {lines[int(m.group(1))]})"
    return DataFileError(f"{p}: {msg}")


#: What ``bad_rows`` may be: ``"error"`` (a row with NaN or inf is an error
#: naming it) or ``"drop"`` (such rows are dropped, with a summary warning).
BAD_ROWS = ("error", "drop")

#: The column mapping options of every reader, with their defaults.
MAPPING_DEFAULTS = {
    "time_column": TIME_NAMES,
    "groups": None,
    "quaternion_order": "wxyz",
    "drop": (),
    "euler": "xyz",
    "bad_rows": "error",
}
