"""The orientation columns of a file as quaternions: by names or a representation.

Four columns are a quaternion (their names or the order option say which
component is which); three are Euler angles or a rotation vector, told by
the representation given (:data:`~ndlfd.orientation.REPRESENTATIONS`), the
Euler convention, the names ``roll, pitch, yaw`` or a lab's name that says
it (``rotvec_x``): never guessed. Every conversion is scipy's
:class:`~scipy.spatial.transform.Rotation` (:func:`~ndlfd.orientation.to_quaternions`).
"""

from __future__ import annotations

import numpy as np

from .._errors import DataFileError
from .._pose_groups import hand_name, kind
from ..demonstration import default_columns
from ..orientation import (
    QUATERNION_ORDERS,
    euler_to_quaternions,
    from_quaternions,
    representation_size,
    to_quaternions,
)
from ._names import bare_name, ready_line

__all__ = [
    "EULER_NAMES",
    "QUAT_NAMES",
    "euler_columns",
    "orientation_block",
    "orientation_representation",
    "quaternion_columns",
]

#: The quaternion columns known by name, scalar first.
QUAT_NAMES = ("qw", "qx", "qy", "qz")
#: The Euler angle columns known by name, about the x, y and z axes.
EULER_NAMES = ("roll", "pitch", "yaw")


def orientation_representation(
    p, ks, block, representation, euler, lab, explicit, how, group="orientation"
):
    """How the orientation columns ``ks`` hold it, or an error naming the choices.

    Returns a representation (``"rotvec"``, ``"euler-SEQ"``, ``"quat-..."``)
    or ``None`` for four columns read by their names or the order option.
    ``lab`` is what :func:`~ndlfd.io._names.lab_groups` told of the names,
    ``explicit`` whether the group was mapped by hand, ``group`` the
    orientation group (``orientation``, a hand's ``left_orientation``).
    """
    hand = hand_name(group) or ""
    what = "orientation" if not hand else group
    if representation is not None:
        if representation_size(representation) != block.shape[1]:
            raise DataFileError(
                f"{p}: the {what} {ks} has {block.shape[1]} columns; the"
                f" representation {representation} takes"
                f" {representation_size(representation)}"
            )
        return representation
    if block.shape[1] == 4:
        return None
    if block.shape[1] == 3:
        if euler is not None:
            return f"euler-{euler}"
        bare = sorted(bare_name(k, hand).casefold() for k in ks)
        if bare == sorted(EULER_NAMES):
            return "euler-xyz"
        if lab.representation.get(group) and not explicit:
            return lab.representation[group]
        cli = how["groups"].startswith("--")
        line = ready_line(cli, {group: list(ks)}, (), "rotvec")
        raise DataFileError(
            f"{p}: the {what} {list(ks)} has three columns, which hold"
            " rotation vectors or Euler angles: name which, never guessed, as"
            " rotvec (axis times angle, as Universal Robots' rx, ry, rz) or"
            " euler-SEQ (radians, SEQ any scipy convention, e.g. euler-xyz or"
            f" euler-ZYX); e.g. {line}"
        )
    raise DataFileError(
        f"{p}: the {what} must be four quaternion columns (qw, qx, qy,"
        " qz) or three Euler angles (roll, pitch, yaw) or a rotation vector; got"
        f" {block.shape[1]} columns from {ks}"
    )


def quaternion_columns(group: str) -> list[str]:
    """The names of an orientation's quaternion columns read from three.

    Examples
    --------
    >>> quaternion_columns("orientation"), quaternion_columns("left_orientation")[0]
    (['qw', 'qx', 'qy', 'qz'], 'left_qw')
    """
    hand = hand_name(group) or ""
    return [f"{hand}_{c}" if hand else c for c in default_columns("orientation", 4)]


def orientation_block(
    p, ks, block, cols, rep, quaternion_order, named, how, group="orientation"
):
    """The orientation as quaternion columns, their names, and how it was given.

    Returns the file's names in the order read, the ``(n, 4)`` quaternions,
    the demonstration's column names (a hand's from three columns:
    ``left_qw`` ...) and what the mapping records (``ColumnMapping.euler``:
    an Euler convention, ``"rotvec"`` or ``None``).
    """
    if rep is not None and rep.startswith("euler-"):
        seq = rep[len("euler-") :]
        ks, Q = _euler_block(p, ks, block, seq, how, group)
        return ks, Q, quaternion_columns(group), seq
    if rep == "rotvec":
        Q = _rows_to_quaternions(block, "rotvec")
        return ks, Q, quaternion_columns(group), "rotvec"
    # four named columns qw, qx, qy, qz (or a lab's w, x, y, z) say their
    # order; else the representation or the option
    low = [bare_name(c, (hand_name(group) or "")).casefold() for c in ks]
    if named:
        order = [0, 1, 2, 3]
    elif len(ks) == 4 and sorted(low) == sorted(QUAT_NAMES):
        order = [low.index(q) for q in QUAT_NAMES]
    else:
        given = quaternion_order if rep is None else rep[len("quat-") :]
        order = list(QUATERNION_ORDERS.get(given))
    if len(ks) == 4:
        ks = [ks[i] for i in order]
        cols = [cols[i] for i in order]
    return ks, block[:, order], cols, None


def _rows_to_quaternions(block, rep):
    """Rows of ``block`` in ``rep`` as quaternions; rows with NaN or inf stay NaN."""
    ok = np.isfinite(block).all(axis=1)
    Q = np.full((block.shape[0], 4), np.nan)
    if ok.any():
        Q[ok] = to_quaternions(block[ok], rep)
    return Q


def _euler_block(p, ks, block, seq, how, group="orientation"):
    """Three Euler angle columns as quaternions, the names in ``seq``'s order.

    Columns named roll, pitch and yaw (a hand's: ``left_roll`` ...) are the
    angles about x, y and z and are put in the convention's order; other
    names are taken as listed.
    """
    low = [bare_name(k, (hand_name(group) or "")).casefold() for k in ks]
    if sorted(low) == sorted(EULER_NAMES):
        axes = seq.lower()
        if len(set(axes)) != 3:
            raise DataFileError(
                f"{p}: {ks} are the angles about x, y and z, but the Euler"
                f" convention {seq!r} turns about {seq[0]} twice; list the angles in"
                f" its order with {how['groups']} {group}=..."
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


def euler_columns(demo, mapping) -> tuple[list[str], list[str], np.ndarray]:
    """A demonstration's columns with its orientation back as it was recorded.

    The inverse of the Euler and rotation-vector mappings of
    :func:`~ndlfd.io._mapping.map_arrays`: the four quaternion columns of
    each of ``demo``'s orientation groups (``orientation``, a hand's
    ``left_orientation``; a generated path, say) that ``mapping`` read from
    three columns become those three columns again, with their names:
    Euler angles in the recorded convention (see
    :func:`~ndlfd.orientation.quaternions_to_euler` for the angles' ranges),
    or a rotation vector (``mapping.euler == "rotvec"``, continuous past an
    angle of pi: :func:`~ndlfd.orientation.quaternions_to_rotvec`). A
    mapping of quaternions leaves the columns as they are. Every writer that
    keeps the input's names (:func:`~ndlfd.io.write_csv`, the Parquet
    writer) calls it, so a rotation-vector input is written back as one.

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
    >>> from ndlfd import Demonstration
    >>> from ndlfd.io import ColumnMapping
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
    if mapping.euler is None:
        return columns, groups, demo.X
    names_of = dict(mapping.groups)
    X = demo.X
    for g in dict.fromkeys(groups):
        idx = [j for j, h in enumerate(groups) if h == g]
        names = names_of.get(g, ())
        if kind(g) != "orientation" or len(names) != 3 or len(idx) != 4:
            continue
        angles = from_quaternions(X[:, idx], mapping.representation)
        keep = [j for j in range(len(columns)) if j not in idx]
        before = [j for j in keep if j < idx[0]]
        after = [j for j in keep if j > idx[0]]
        X = np.hstack([X[:, before], angles, X[:, after]])
        columns = [*(columns[j] for j in before), *names, *(columns[j] for j in after)]
        groups = [groups[j] for j in before] + [g] * 3 + [groups[j] for j in after]
    return columns, groups, X
