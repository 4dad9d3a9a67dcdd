"""Column names as labs export them: the groups of a whole header at once.

:func:`~ndlfd.io._mapping.group_of_column` reads one name by the naming
convention (``x``, ``qw``, ``fx``, ``NAME.pos``, ``group.column``). Logs
exported by robot labs name their columns otherwise: a kind, its component,
and often a prefix that says whose values they are, e.g. a Franka task log's
``current_pos_x``, ``current_orientation_w``, ``goal_pos_x``, ``force_x``,
``torque_x`` and ``joint_1`` ... ``joint_7``. :func:`lab_groups` reads such a
header as a whole:

* **Kinds** (:data:`LAB_KINDS`): a stem, then a component after an optional
  ``_`` or ``.``: ``pos``/``position``/``translation`` (x, y, z: group
  ``position``), ``vel``/``velocity`` (``velocity``), ``orientation``/
  ``quat``/``q``/``rot`` ... (w, x, y, z: ``orientation``, a quaternion),
  ``rotvec``/``axis_angle`` (x, y, z: ``orientation`` as a rotation vector),
  ``force``/``f`` (``force``), ``torque``/``tau``/``moment`` (``torque``),
  ``joint``/``q``/``j``/``joint_pos`` with a number (``joint_1``, ``joint1``,
  ``q1``: group ``joints``), ``joint_vel``/``dq``/``qd`` with a number
  (``joint_velocity``), ``joint_torque``/``tau``/``effort`` with a number
  (``joint_effort``). Any case.
* **Prefixes**: whatever stands before the stem (``current_``, ``ee_``,
  ``goal_``). One set of a kind is that kind's group whatever its prefix.
* **Measured and commanded sets.** Where a log holds two sets of one kind,
  the set whose prefix says it was measured (:data:`MEASURED`: ``current``,
  ``actual``, ``measured`` ...) or has no such word is learned, and the sets
  whose prefix says they were commanded (:data:`COMMANDED`: ``goal``,
  ``desired``, ``cmd``, ``target`` ...) are left out, with a note. Sets that
  cannot be told apart so are an error with a mapping to paste.
* **Three orientation columns** whose name does not say the representation
  (``rx, ry, rz``, ``rot_x, rot_y, rot_z``) are an error naming the choices
  (a rotation vector or Euler angles in some convention): never a guess.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from .._errors import DataFileError

__all__ = [
    "COMMANDED",
    "LAB_KINDS",
    "MEASURED",
    "LabGroups",
    "lab_groups",
    "lab_name",
    "names_error",
    "ready_line",
]

#: Prefix words of a measured set of values (learned when a commanded one
#: stands beside it).
MEASURED = ("current", "actual", "measured", "meas", "act", "cur", "observed", "obs")
#: Prefix words of a commanded set (left out beside a measured one).
COMMANDED = (
    "goal",
    "desired",
    "des",
    "cmd",
    "command",
    "commanded",
    "target",
    "ref",
    "reference",
    "setpoint",
)

_XYZ = ("x", "y", "z")
_WXYZ = ("w", "x", "y", "z")
#: What a name's stem says, by the kind of its component (a letter of
#: ``xyz``/``wxyz`` or a number): (stems, group, representation or None).
LAB_KINDS: dict[str, tuple[tuple[tuple[str, ...], str, str | None], ...]] = {
    "axis": (
        (("pos", "position", "translation", "trans"), "position", None),
        (("vel", "velocity", "lin_vel", "linear_velocity"), "velocity", None),
        (("ang_vel", "angular_velocity", "omega"), "angular_velocity", None),
        (
            ("orientation", "orient", "ori", "quat", "quaternion", "q", "rot"),
            "orientation",
            None,
        ),
        (("rotation", "r"), "orientation", None),
        (
            ("rotvec", "rot_vec", "rotation_vector", "axis_angle", "axisangle"),
            "orientation",
            "rotvec",
        ),
        (("force", "forces", "f"), "force", None),
        (("torque", "torques", "tau", "moment"), "torque", None),
    ),
    "number": (
        (
            ("joint", "joints", "q", "j", "joint_pos", "joint_position", "qpos"),
            "joints",
            None,
        ),
        (
            ("joint_vel", "joint_velocity", "dq", "qd", "qvel", "qdot"),
            "joint_velocity",
            None,
        ),
        (
            ("joint_torque", "joint_effort", "tau", "effort", "torque"),
            "joint_effort",
            None,
        ),
    ),
}


def _stem_pattern(kind: str) -> str:
    stems = sorted(
        {s for stems, _, _ in LAB_KINDS[kind] for s in stems}, key=len, reverse=True
    )
    return "|".join(re.escape(s) for s in stems)


def _patterns(kind: str, comp: str) -> tuple[re.Pattern, re.Pattern]:
    """A name without a prefix, and one with (the shortest prefix: the longest stem)."""
    stem = _stem_pattern(kind)
    tail = rf"(?P<stem>{stem})[_.]?(?P<comp>{comp})$"
    return (
        re.compile(rf"^(?P<prefix>){tail}", re.IGNORECASE),
        re.compile(rf"^(?P<prefix>.+?)[_.]{tail}", re.IGNORECASE),
    )


_PATTERNS = (
    ("axis", _patterns("axis", "[wxyz]")),
    ("number", _patterns("number", r"\d+")),
)


@dataclass(frozen=True)
class _Part:
    """What one name says: its group, set (prefix), component, representation."""

    name: str
    group: str
    prefix: str
    comp: str
    representation: str | None


def lab_name(name: str) -> tuple[str, str, str] | None:
    """The group, prefix and component a lab's column name gives, or None.

    Parameters
    ----------
    name : str
        A column name.

    Returns
    -------
    (group, prefix, component) : tuple of str, or None
        The prefix in lower case (``""`` without one), the component a letter
        of ``wxyz`` or a number.

    Examples
    --------
    >>> lab_name("current_pos_x")
    ('position', 'current', 'x')
    >>> lab_name("joint_3"), lab_name("q7"), lab_name("torque_z")
    (('joints', '', '3'), ('joints', '', '7'), ('torque', '', 'z'))
    >>> lab_name("Goal_Orientation_W")
    ('orientation', 'goal', 'w')
    >>> lab_name("speed") is None
    True
    """
    part = _parse(name)
    return None if part is None else (part.group, part.prefix, part.comp)


def _parse(name: str) -> _Part | None:
    for kind, (bare, prefixed) in _PATTERNS:
        m = bare.match(name) or prefixed.match(name)
        if m is None:
            continue
        stem = m["stem"].casefold()
        for stems, group, rep in LAB_KINDS[kind]:
            if stem in stems:
                if kind == "axis" and m["comp"].casefold() == "w":
                    if group != "orientation" or rep is not None:
                        return None  # only a quaternion has a w
                prefix = (m["prefix"] or "").casefold()
                return _Part(name, group, prefix, m["comp"].casefold(), rep)
    return None


def _role(prefix: str) -> str:
    words = set(re.split(r"[_.\-]+", prefix)) if prefix else set()
    if words & set(COMMANDED):
        return "commanded"
    if words & set(MEASURED):
        return "measured"
    return "neutral"


@dataclass
class LabGroups:
    """What :func:`lab_groups` made of a header.

    Attributes
    ----------
    groups : dict of str to list of str
        Each group told with its columns, in the file's order of groups and
        each group's components in order (``w, x, y, z``; ``x, y, z``; numbers).
    representation : dict of str to str
        The representation a group's names give (``"rotvec"``).
    quaternions : set of str
        The groups of four columns whose names give the order ``w, x, y, z``.
    left_out : list of str
        Columns of commanded sets left out beside a measured set.
    kept_for : dict of str to list of str
        For each column left out, the measured columns learned instead.
    ambiguous : list of (str, list of list of str)
        Groups with several sets that cannot be told apart: the sets.
    unsure : list of (str, list of str)
        Three orientation columns whose names do not say the representation.
    unknown : list of str
        Names that say no group.
    """

    groups: dict[str, list[str]] = field(default_factory=dict)
    representation: dict[str, str] = field(default_factory=dict)
    quaternions: set[str] = field(default_factory=set)
    left_out: list[str] = field(default_factory=list)
    kept_for: dict[str, list[str]] = field(default_factory=dict)
    ambiguous: list = field(default_factory=list)
    unsure: list = field(default_factory=list)
    unknown: list[str] = field(default_factory=list)


def _sorted_set(parts: list[_Part]) -> list[_Part]:
    def key(p: _Part):
        if p.comp.isdigit():
            return (0, int(p.comp), "")
        return (0, _WXYZ.index(p.comp), "")

    return sorted(parts, key=key)


def lab_groups(names, known=None) -> LabGroups:
    """The groups of the column names ``names`` as labs export them.

    Parameters
    ----------
    names : sequence of str
        The columns to place (neither the time nor mapped nor dropped).
    known : callable, optional
        ``known(name) -> (group, column) or None``: a name rule tried first
        (the naming convention); its groups form the set without a prefix.

    Returns
    -------
    found : LabGroups

    Examples
    --------
    >>> names = ["current_pos_x", "current_pos_y", "goal_pos_x", "goal_pos_y",
    ...          "joint_1", "joint_2"]
    >>> found = lab_groups(names)
    >>> found.groups
    {'position': ['current_pos_x', 'current_pos_y'], 'joints': ['joint_1', 'joint_2']}
    >>> found.left_out
    ['goal_pos_x', 'goal_pos_y']
    """
    found = LabGroups()
    sets: dict[str, dict[str, list[_Part]]] = {}  # group -> prefix -> parts
    for name in names:
        hit = known(name) if known is not None else None
        if hit is not None:
            part = _Part(name, hit[0], "", "", None)
        else:
            part = _parse(name)
        if part is None:
            found.unknown.append(name)
            continue
        sets.setdefault(part.group, {}).setdefault(part.prefix, []).append(part)
    for group, by_prefix in sets.items():
        chosen = list(by_prefix)
        if len(chosen) > 1:
            kept = [p for p in chosen if _role(p) != "commanded"]
            if len(kept) != 1:
                found.ambiguous.append(
                    (group, [[q.name for q in by_prefix[p]] for p in chosen])
                )
                continue
            keep = [q.name for q in by_prefix[kept[0]]]
            for p in chosen:
                if p != kept[0]:
                    for q in by_prefix[p]:
                        found.left_out.append(q.name)
                        found.kept_for[q.name] = keep
            chosen = kept
        parts = by_prefix[chosen[0]]
        if any(q.comp == "" for q in parts):  # a name rule's: as the file has them
            found.groups[group] = [q.name for q in parts]
            continue
        parts = _sorted_set(parts)
        cols = [q.name for q in parts]
        comps = tuple(q.comp for q in parts)
        reps = {q.representation for q in parts}
        if group == "orientation" and None in reps:
            if comps == _WXYZ:
                found.quaternions.add(group)
            elif comps == _XYZ:
                found.unsure.append((group, cols))
                continue
        elif group == "orientation" and reps == {"rotvec"} and comps == _XYZ:
            found.representation[group] = "rotvec"
        found.groups[group] = cols
    return found


def _quoted(name: str) -> str:
    """A name as a shell word (quoted when it holds anything but plain text)."""
    return name if re.fullmatch(r"[\w.,:=+\-/]+", name) else f"'{name}'"


def ready_line(cli: bool, groups: dict, drop=(), representation=None) -> str:
    """A mapping to paste: ``--group G=A,B --drop C`` or ``groups={...}, drop=[...]``.

    Parameters
    ----------
    cli : bool
        The command line's flags, else the library's parameters.
    groups : dict of str to list of str
        Each group's columns.
    drop : sequence of str, default=()
        Columns to leave out.
    representation : str, optional
        The orientation's representation (``"rotvec"``), or a placeholder.

    Returns
    -------
    line : str

    Examples
    --------
    >>> ready_line(True, {"orientation": ["rx", "ry", "rz"]}, ["id"], "rotvec")
    '--group orientation=rx,ry,rz:rotvec --drop id'
    >>> ready_line(False, {"position": ["a"]}, ["b"])
    "groups={'position': ['a']}, drop=['b']"
    """
    if cli:
        parts = []
        for g, cols in groups.items():
            rep = f":{representation}" if g == "orientation" and representation else ""
            parts.append(f"--group {_quoted(g + '=' + ','.join(cols) + rep)}")
        if drop:
            parts.append(f"--drop {_quoted(','.join(drop))}")
        return " ".join(parts)
    parts = [f"groups={dict(groups)!r}"] if groups else []
    if drop:
        parts.append(f"drop={list(drop)!r}")
    if representation:
        parts.append(f"representation={representation!r}")
    return ", ".join(parts)


def names_error(p, layout_of, placed, dropped, lab: LabGroups, how, noun):
    """The error for names that cannot be told, with a mapping to paste.

    ``layout_of`` holds the groups mapped by hand, ``placed`` those told by
    the names, ``lab`` what :func:`lab_groups` made of the names (its
    unknown names, ambiguous sets or orientation without a representation),
    ``how`` the hints (:data:`~ndlfd.io._mapping.CLI_HINTS` ...) and
    ``noun`` ``"column"`` or ``"array"``.
    """
    cli = how["groups"].startswith("--")
    groups = {**{g: list(c) for g, c in layout_of.items()}}
    for g, cols in placed.items():
        groups.setdefault(g, list(cols))
    drop = [*dropped, *lab.left_out]
    if lab.unknown:
        drop += lab.unknown
        head = (
            f"{p}: cannot tell the group of {noun}(s) {lab.unknown} from their"
            " names; name them x, y, z / vx, vy, vz / qw, qx, qy, qz / roll, pitch,"
            f" yaw / fx, fy, fz / gripper / group.column, or {how['group_hint']},"
            f" or leave them out with {how['drop_hint']}"
        )
    elif lab.ambiguous:
        g, sets = lab.ambiguous[0]
        head = (
            f"{p}: {len(sets)} sets of {noun}s name the group {g!r}"
            f" ({'; '.join(','.join(s) for s in sets)}), and their names do not"
            " say which one was measured; map the one to learn with"
            f" {how['groups']} and leave the others out (or give them groups"
            " of their own)"
        )
    else:
        g, cols = lab.unsure[0]
        head = (
            f"{p}: the {noun}s {', '.join(cols)} hold an orientation of three"
            " numbers, and their names do not say how: name its representation,"
            " rotvec (a rotation vector: axis times angle, as Universal Robots'"
            " rx, ry, rz) or euler-SEQ (Euler angles in radians, SEQ any scipy"
            " convention, e.g. euler-xyz or euler-ZYX)"
        )
    for g, sets in lab.ambiguous:
        groups.setdefault(g, sets[0])
        for s in sets[1:]:
            part = _parse(s[0])
            prefix = part.prefix if part is not None else ""
            prefix = re.sub(r"[^A-Za-z0-9_]+", "_", prefix).strip("_")
            groups.setdefault(f"{prefix or 'other'}_{g}", s)
    rep = None
    for g, cols in lab.unsure:
        groups.setdefault(g, cols)
        rep = "rotvec"
    line = ready_line(cli, groups, drop, rep)
    also = " (or another representation in place of rotvec)" if rep is not None else ""
    raise DataFileError(f"{head}; e.g., in place of your {how['groups']}/"
                        f"{how['drop']}: {line}{also}")  # fmt: skip
