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
* **Two arms** (:data:`HANDS`). Where names of both a ``left_`` and a
  ``right_`` hand say a group once their hand is taken off (``left_x``,
  ``left_pos_x``, ``right_ee_x``, ``left_qw``, ``left_rotvec_x``,
  ``left_roll``, ``left_joint_1``, ALOHA's ``left_waist`` ...
  (:data:`ALOHA_JOINTS`), ``left_shoulder_pan.pos``), each hand's values are
  its own groups: ``left_position`` (3 columns), ``left_orientation`` (a
  quaternion, or three columns converted as one hand's are),
  ``left_joints``, ``left_velocity`` ..., and the grippers one group
  ``gripper`` of both columns (``left_gripper``, ``right_gripper``). A word
  between the hand and the values (:data:`HAND_WORDS`: ``ee``, ``arm``,
  ``tcp`` ...) is a set's prefix, as ``current_`` is. Names of one hand alone
  are read as one arm's (``right_pos_x`` is ``position``), as before.
* **Short hands** (:data:`SHORT_HANDS`): ``l_`` and ``r_`` (any case), as
  some bimanual logs write them (``l_x, l_y, l_z, l_qw, ..., r_x, ...``,
  ``l_joint1``, ``r_gripper``), are the ``left`` and ``right`` hands, read
  into the same groups (``left_position`` ...), by this rule: a name
  ``l_REST`` is the left hand's when ``REST`` alone (or after a word of
  :data:`HAND_WORDS`) says a group as above, and the short names are hands
  only when ``l_`` and ``r_`` names say at least one group in common
  (mirrored: ``l_x`` and ``r_x``, ``l_joint1`` and ``r_joint1``). So a name
  whose rest says no group (``r_squared``, ``l_time``) is never a hand's (it
  is an unknown name, as any other), and ``r_x, r_y, r_z`` beside ``x, y, z``
  (no ``l_`` set like them) keep their meaning without hands (``r`` is a
  rotation's stem: three orientation columns). The short spelling is part of
  a set's prefix: a hand spelt both ways (``l_x`` and ``left_x``) is two sets
  of one group, an error with a mapping to paste.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from .._errors import DataFileError
from .._pose_groups import hand_name
from .._pose_groups import kind as group_kind

__all__ = [
    "ALOHA_JOINTS",
    "ALOHA_NAMES",
    "COMMANDED",
    "HANDS",
    "HAND_WORDS",
    "LAB_KINDS",
    "MEASURED",
    "SHORT_HANDS",
    "LabGroups",
    "aloha_groups",
    "bare_name",
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

#: The prefixes that name a hand (an arm) in a log of two arms.
HANDS = ("left", "right")
#: The short prefixes of the hands (``l_x``, ``r_gripper``): hand -> prefix.
SHORT_HANDS = {"left": "l", "right": "r"}
#: Words between a hand and its values that name no group (``right_ee_x``,
#: ``left_arm_joint_1``): read as a set's prefix.
HAND_WORDS = ("arm", "ee", "eef", "tcp", "tool", "hand")
#: ALOHA's arm joints (a ViperX 300 s) as LeRobot's aloha datasets name them
#: after the arm (``left_waist`` ... ``right_wrist_rotate``); a real ALOHA
#: records the shadow motors too.
ALOHA_JOINTS = (
    "waist",
    "shoulder",
    "shoulder_shadow",
    "elbow",
    "elbow_shadow",
    "forearm_roll",
    "wrist_angle",
    "wrist_rotate",
)
#: The 14 values of LeRobot's ALOHA ``observation.state`` and ``action``
#: (``lerobot/aloha_sim_*``): per arm, left then right, 6 joints and the gripper.
ALOHA_NAMES = tuple(
    f"{side}_{m}"
    for side in HANDS
    for m in (*(j for j in ALOHA_JOINTS if not j.endswith("_shadow")), "gripper")
)
_KINDS = ("position", "velocity", "orientation")
_HAND_NAME = re.compile(rf"^({'|'.join(HANDS)})_(.+)$", re.IGNORECASE)
_SHORT_HAND = re.compile(rf"^({'|'.join(SHORT_HANDS.values())})_(.+)$", re.IGNORECASE)
_LONG_HAND = {v: k for k, v in SHORT_HANDS.items()}
_HAND_WORD = re.compile(rf"^({'|'.join(HAND_WORDS)})[_.](.+)$", re.IGNORECASE)
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


def bare_name(name: str, hand: str) -> str:
    """A column's name without its hand's prefix (``left_roll`` -> ``roll``).

    Examples
    --------
    >>> bare_name("Left_Roll", "left"), bare_name("roll", "")
    ('Roll', 'roll')
    >>> bare_name("l_yaw", "left"), bare_name("r_squared", "left")
    ('yaw', 'r_squared')
    """
    for prefix in (hand, SHORT_HANDS.get(hand)):
        if prefix and name.casefold().startswith(prefix + "_"):
            return name[len(prefix) + 1 :]
    return name


def _convention_part(name, rest, group, prefix) -> _Part:
    """A hand's name the naming convention places, with its component.

    ``x``, ``vx``, ``fx``, ``p0``, ``qw``: the letter or number after the
    group's letter (so the set is put in order as a lab's is); ``roll``,
    ``pitch``, ``yaw``: ``x``, ``y``, ``z`` of Euler angles ``xyz``; any
    other name (a gripper, a motor) keeps the file's order.
    """
    low = rest.casefold()
    if low in ("roll", "pitch", "yaw"):
        return _Part(
            name, group, prefix, "xyz"[("roll", "pitch", "yaw").index(low)], "rpy"
        )
    m = re.fullmatch(r"[pvfq]?([wxyz]|\d+)", low)
    if m is not None and group in ("position", "velocity", "force", "orientation"):
        return _Part(name, group, prefix, m[1], None)
    return _Part(name, group, prefix, "", None)


def _rest_part(name, rest, rule, prefix="") -> _Part | None:
    """What a hand's name says once its hand is off (``rest``), or None."""
    hit = rule(rest)
    if hit is not None:
        return _convention_part(name, rest, hit[0], prefix)
    if rest.casefold() in ALOHA_JOINTS:
        return _Part(name, "joints", prefix, "", None)
    part = _parse(rest)
    if part is None:
        return None
    joined = "_".join(w for w in (prefix, part.prefix) if w)
    return _Part(name, part.group, joined, part.comp, part.representation)


def _hand_part(name, rule, short=False) -> tuple[str, _Part] | None:
    """The hand of a name (``left_x``) and the part of its hand's group, or None.

    With ``short``, the hand spelt ``l_``/``r_`` (:data:`SHORT_HANDS`); the
    spelling joins the set's prefix (``l_goal_pos_x``: ``l_goal``).
    """
    m = (_SHORT_HAND if short else _HAND_NAME).match(name)
    full = rule(name)
    if m is None or (full is not None and full[0] == name.split(".", 1)[0]):
        return None  # no hand, or a group.column name (left_joints.left_waist)
    hand, rest = m[1].casefold(), m[2]
    spelt = hand if short else ""
    hand = _LONG_HAND[hand] if short else hand
    part = _rest_part(name, rest, rule, spelt)
    if part is None:
        w = _HAND_WORD.match(rest)
        if w is None:
            return None
        word = "_".join(p for p in (spelt, w[1].casefold()) if p)
        part = _rest_part(name, w[2], rule, word)
        if part is None:
            return None
    prefix = part.prefix
    if part.group == "gripper" and spelt:  # both hands' group: no spelling
        prefix = prefix[len(spelt) :].lstrip("_")
    group = "gripper" if part.group == "gripper" else f"{hand}_{part.group}"
    return hand, _Part(name, group, prefix, part.comp, part.representation)


def _hand_parts(names, rule) -> dict[str, _Part]:
    """The parts of the names of two or more hands (empty for one hand or none).

    Short names (``l_x``) count only when both hands' short names say a
    group in common (the module's rule); the long ones as before.
    """
    if rule is None:
        return {}
    found = {n: hit for n in names if (hit := _hand_part(n, rule)) is not None}
    short = {
        n: hit
        for n in names
        if n not in found and (hit := _hand_part(n, rule, short=True)) is not None
    }
    said = {h: {bare_name(p.group, h) for g, p in short.values() if g == h}
            for h in HANDS}  # fmt: skip
    if set.intersection(*said.values()):
        found.update(short)
    if len({hand for hand, _ in found.values()}) < 2:
        return {}
    return {n: part for n, (_, part) in found.items()}


def aloha_groups(names) -> dict[str, list[str]]:
    """ALOHA's groups of 14 values named ``names`` in its order (left arm first).

    Per arm 6 joints and a gripper (:data:`ALOHA_NAMES`): ``left_joints``,
    ``gripper`` (both grippers) and ``right_joints``.

    Examples
    --------
    >>> g = aloha_groups([f"state_{i}" for i in range(14)])
    >>> g["gripper"], g["right_joints"][0]
    (['state_6', 'state_13'], 'state_7')
    """
    names = list(names)
    return {
        "left_joints": names[0:6],
        "gripper": [names[6], names[13]],
        "right_joints": names[7:13],
    }


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
    prefixes : dict of str to str
        The prefix of each ambiguous set, by its first column.
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
    prefixes: dict[str, str] = field(default_factory=dict)
    unsure: list = field(default_factory=list)
    unknown: list[str] = field(default_factory=list)


def _sorted_set(parts: list[_Part]) -> list[_Part]:
    def key(p: _Part):
        if p.comp.isdigit():
            return (0, int(p.comp), "")
        return (0, _WXYZ.index(p.comp), "")

    return sorted(parts, key=key)


def lab_groups(names, known=None, rule=None) -> LabGroups:
    """The groups of the column names ``names`` as labs export them.

    Parameters
    ----------
    names : sequence of str
        The columns to place (neither the time nor mapped nor dropped).
    known : callable, optional
        ``known(name) -> (group, column) or None``: a name rule tried first
        (the naming convention); its groups form the set without a prefix.
    rule : callable, optional
        ``rule(name) -> (group, column) or None``: the naming convention
        without side effects, tried on a name with its hand taken off
        (``left_x`` -> ``x``); without it no name is a hand's.

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
    >>> from ndlfd.io import group_of_column
    >>> arms = ["left_x", "left_y", "left_z", "left_gripper", "right_ee_x",
    ...         "right_ee_y", "right_ee_z", "right_gripper"]
    >>> lab_groups(arms, rule=group_of_column).groups  # doctest: +NORMALIZE_WHITESPACE
    {'left_position': ['left_x', 'left_y', 'left_z'],
     'gripper': ['left_gripper', 'right_gripper'],
     'right_position': ['right_ee_x', 'right_ee_y', 'right_ee_z']}
    """
    found = LabGroups()
    sets: dict[str, dict[str, list[_Part]]] = {}  # group -> prefix -> parts
    hands = _hand_parts(names, rule)
    for name in names:
        hit = known(name) if known is not None and name not in hands else None
        if name in hands:
            part = hands[name]
        elif hit is not None:
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
                found.prefixes.update((by_prefix[p][0].name, p) for p in chosen)
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
        if group_kind(group) == "orientation" and None in reps:
            if comps == _WXYZ:
                found.quaternions.add(group)
            elif comps == _XYZ:
                found.unsure.append((group, cols))
                continue
        elif group_kind(group) == "orientation" and comps == _XYZ:
            if reps == {"rotvec"}:
                found.representation[group] = "rotvec"
            elif reps == {"rpy"}:  # a hand's roll, pitch, yaw
                found.representation[group] = "euler-xyz"
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
        The representation of the orientations of three columns
        (``"rotvec"``), or a placeholder.

    Returns
    -------
    line : str

    Examples
    --------
    >>> ready_line(True, {"orientation": ["rx", "ry", "rz"]}, ["id"], "rotvec")
    '--group orientation=rx,ry,rz:rotvec --drop id'
    >>> ready_line(False, {"position": ["a"]}, ["b"])
    "groups={'position': ['a']}, drop=['b']"
    >>> ready_line(True, {"left_orientation": ["l1", "l2", "l3"]}, (), "rotvec")
    '--group left_orientation=l1,l2,l3:rotvec'
    """
    if cli:
        parts = []
        for g, cols in groups.items():
            three = group_kind(g) == "orientation" and len(cols) == 3
            rep = (
                f":{representation}"
                if representation and (g == "orientation" or three)
                else ""
            )
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
    aloha = ""
    if lab.unknown and len(lab.unknown) == len(ALOHA_NAMES) and not groups:
        shown = ready_line(cli, aloha_groups(lab.unknown), dropped)
        aloha = (
            f". If they are ALOHA's {len(ALOHA_NAMES)} values as LeRobot records"
            " them (per arm, left then right, 6 joints and the gripper:"
            f" {', '.join(ALOHA_NAMES[:7])}, right_...), pass: {shown}"
        )
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
        cols = [c for _, cs in lab.unsure for c in cs]
        head = (
            f"{p}: the {noun}s {', '.join(cols)} hold"
            f" {'an orientation' if len(lab.unsure) == 1 else 'orientations'} of"
            " three numbers, and their names do not say how: name the representation,"
            " rotvec (a rotation vector: axis times angle, as Universal Robots'"
            " rx, ry, rz) or euler-SEQ (Euler angles in radians, SEQ any scipy"
            " convention, e.g. euler-xyz or euler-ZYX)"
        )
    for g, sets in lab.ambiguous:
        groups.setdefault(g, sets[0])
        for s in sets[1:]:
            prefix = lab.prefixes.get(s[0], "")
            prefix = re.sub(r"[^A-Za-z0-9_]+", "_", prefix).strip("_") or "other"
            name = f"{g}_{prefix}" if hand_name(g) else f"{prefix}_{g}"
            if g == "position" and len(s) != 3:  # a hand's position is 3-D
                name = f"{prefix}_{'xyz'[: len(s)] if len(s) <= 3 else 'p'}"
            groups.setdefault(name, s)
    rep = None
    for g, cols in lab.unsure:
        groups.setdefault(g, cols)
        rep = "rotvec"
    line = ready_line(cli, groups, drop, rep)
    also = " (or another representation in place of rotvec)" if rep is not None else ""
    raise DataFileError(f"{head}; e.g., in place of your {how['groups']}/"
                        f"{how['drop']}: {line}{also}{aloha}")  # fmt: skip
