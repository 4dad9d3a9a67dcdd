"""Pose groups: which groups are a hand's position, velocity and orientation.

One hand is the groups ``position`` (2 or 3 columns), ``velocity`` (derived
from it) and ``orientation`` (a unit quaternion ``w, x, y, z``), as always.
Further hands are named: ``<hand>_position``, ``<hand>_velocity`` and
``<hand>_orientation`` (for example ``left_position``, ``left_orientation``;
a lowercase name, not ``joint`` or ``joints``). Every orientation group is a
quaternion (checked unit, made sign-continuous, blended and limited as a
rotation), every position group a hand that task frames may move.

Examples
--------
>>> groups = ("left_position",) * 3 + ("left_orientation",) * 4 + ("gripper",)
>>> [(h.name, h.position, h.orientation) for h in hands(groups)]
[('left', [0, 1, 2], [3, 4, 5, 6])]
>>> kind("right_orientation"), kind("position"), kind("joints")
('orientation', 'position', 'joints')
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ._errors import ValidationError

__all__ = [
    "Hand",
    "default_columns",
    "frame_hands_problem",
    "hand_group",
    "hand_label",
    "hand_labels",
    "hand_name",
    "hands",
    "is_orientation",
    "is_position",
    "kind",
    "orientation_blocks",
    "pose_dims",
    "position_columns",
]

_KINDS = ("position", "velocity", "orientation")
_NAMED = re.compile(
    r"^([a-z][a-z0-9]*(?:_[a-z0-9]+)*)_(position|velocity|orientation)$"
)
_NOT_HANDS = ("joint", "joints")


def _split(group: str) -> tuple[str, str] | None:
    if group in _KINDS:
        return "", group
    m = _NAMED.match(group)
    if m is None or m.group(1) in _NOT_HANDS:
        return None
    return m.group(1), m.group(2)


def kind(group: str) -> str:
    """``"position"``, ``"velocity"`` or ``"orientation"`` for a hand's group.

    Any other group is its own kind (``"joints"``, ``"gripper"``, ...).
    """
    s = _split(group)
    return group if s is None else s[1]


def hand_name(group: str) -> str | None:
    """The hand a group belongs to (``""``: the unnamed one; ``None``: no hand)."""
    s = _split(group)
    return None if s is None else s[0]


def hand_group(hand: str, what: str) -> str:
    """The name of a hand's group (``hand_group("left", "position")``).

    Examples
    --------
    >>> hand_group("", "orientation"), hand_group("left", "velocity")
    ('orientation', 'left_velocity')
    """
    return what if not hand else f"{hand}_{what}"


def is_position(group: str) -> bool:
    """Whether ``group`` is a hand's position (``position``, ``left_position``)."""
    return kind(group) == "position"


def is_orientation(group: str) -> bool:
    """Whether ``group`` is a hand's orientation, a unit quaternion."""
    return kind(group) == "orientation"


@dataclass(frozen=True)
class Hand:
    """One hand's columns in a model's or demonstration's column groups.

    Attributes
    ----------
    name : str
        ``""`` for the unnamed hand (``position``), else its prefix.
    position : list of int
    velocity : list of int
        Empty unless the hand's velocity group has as many columns as its
        position.
    orientation : list of int
        Four columns, or empty.
    """

    name: str
    position: list
    velocity: list
    orientation: list

    @property
    def moved(self) -> list:
        """The columns a frame moves: position, velocity, orientation."""
        return self.position + self.velocity + self.orientation


def _columns(groups, name: str) -> list:
    return [j for j, g in enumerate(groups) if g == name]


def hands(groups) -> list[Hand]:
    """Every hand with a position group, in the order of its position columns."""
    out, seen = [], []
    for g in groups:
        if is_position(g) and g not in seen:
            seen.append(g)
    for g in seen:
        name = hand_name(g)
        pos = _columns(groups, g)
        vel = _columns(groups, hand_group(name, "velocity"))
        quat = _columns(groups, hand_group(name, "orientation"))
        out.append(
            Hand(
                name,
                pos,
                vel if len(vel) == len(pos) else [],
                quat if len(quat) == 4 else [],
            )
        )
    return out


def position_columns(groups) -> list:
    """Every hand's position columns, in order (the first hand's first)."""
    return [j for h in hands(groups) for j in h.position]


def orientation_blocks(groups) -> list:
    """The columns of every 4-column orientation group, one list per group.

    Examples
    --------
    >>> orientation_blocks(("orientation",) * 4 + ("right_orientation",) * 4)
    [[0, 1, 2, 3], [4, 5, 6, 7]]
    """
    seen = []
    for g in groups:
        if is_orientation(g) and g not in seen:
            seen.append(g)
    blocks = [_columns(groups, g) for g in seen]
    return [b for b in blocks if len(b) == 4]


def pose_dims(groups) -> int | None:
    """The dimension of the hands' positions (``None``: no hand), checked.

    A named hand (``left_position``) is a 3-D position, and with several
    hands every one is; the unnamed ``position`` alone may have any number of
    columns (a planar path).

    Raises
    ------
    ValidationError
        A named hand's position without 3 columns, or hands of different
        dimensions.

    Examples
    --------
    >>> pose_dims(("left_position",) * 3 + ("right_position",) * 3)
    3
    >>> pose_dims(("joints",) * 6) is None
    True
    """
    found = hands(groups)
    if not found:
        return None
    for h in found:
        if (h.name or len(found) > 1) and len(h.position) != 3:
            name = hand_group(h.name, "position")
            raise ValidationError(
                f"the pose group {name!r} must have 3 columns (x, y, z), as every"
                f" hand's position when there are named or several hands; got"
                f" {len(h.position)}"
            )
    return len(found[0].position)


def default_columns(group: str, k: int) -> tuple[str, ...]:
    """Default column names of a group with ``k`` columns.

    ``position``: ``x, y, z`` (k <= 3) else ``p0, p1, ...``; ``velocity``:
    ``vx, vy, vz`` else ``v0, ...``; ``orientation``: ``qw, qx, qy, qz``;
    ``force``: ``fx, fy, fz`` else ``f0, ...``; any other group ``<group>0, ...``.

    Parameters
    ----------
    group : str
        The group's name.
    k : int
        Its number of columns.

    Returns
    -------
    columns : tuple of str of length k

    Examples
    --------
    >>> default_columns("velocity", 2)
    ('vx', 'vy')
    >>> default_columns("position", 4)
    ('p0', 'p1', 'p2', 'p3')
    >>> default_columns("grip", 1)
    ('grip0',)
    >>> default_columns("left_orientation", 4)
    ('left_qw', 'left_qx', 'left_qy', 'left_qz')
    """
    hand = hand_name(group)
    if hand:  # a named hand's group: its prefix on the unnamed hand's names
        return tuple(f"{hand}_{c}" for c in default_columns(kind(group), k))
    axes = ("x", "y", "z")
    if group == "orientation" and k == 4:
        return ("qw", "qx", "qy", "qz")
    prefix = {"position": ("", "p"), "velocity": ("v", "v"), "force": ("f", "f")}
    if group in prefix:
        short, long = prefix[group]
        if k <= 3:
            return tuple(short + a for a in axes[:k])
        return tuple(f"{long}{i}" for i in range(k))
    return tuple(f"{group}{i}" for i in range(k))


def hand_label(name: str) -> str:
    """A hand as ``frame_hands`` names it: ``left`` (``left_position``), ``position``.

    Examples
    --------
    >>> hand_label("left_position"), hand_label("left"), hand_label("")
    ('left', 'left', 'position')
    """
    if name in ("", "position"):
        return "position"
    return name.removesuffix("_position")


def hand_labels(groups) -> list[str]:
    """Every hand of ``groups`` as ``frame_hands`` names it (:func:`hand_label`)."""
    return [hand_label(h.name) for h in hands(groups)]


def frame_hands_problem(frame_hands, frames, groups) -> tuple | None:
    """The first entry of ``frame_hands`` that names what is not there.

    Returns
    -------
    problem : tuple or None
        ``(frame, None)``: a frame not among ``frames``; ``(frame, hand)``: a
        hand (as given) not among the hands of ``groups``; ``None``: neither.

    Examples
    --------
    >>> g = ("left_position",) * 3
    >>> frame_hands_problem({"cube": ["left_position"]}, ["cube"], g) is None
    True
    >>> frame_hands_problem({"cube": ["right"]}, ["cube"], g)
    ('cube', 'right')
    """
    labels = hand_labels(groups)
    for frame, named in (frame_hands or {}).items():
        if frame not in frames:
            return frame, None
        for h in named:
            if not h or hand_label(h) not in labels:  # "" names no hand
                return frame, h
    return None
