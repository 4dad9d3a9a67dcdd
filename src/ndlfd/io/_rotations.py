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
from ..demonstration import default_columns
from ..orientation import (
    QUATERNION_ORDERS,
    euler_to_quaternions,
    representation_size,
    to_quaternions,
)
from ._names import ready_line

__all__ = [
    "EULER_NAMES",
    "QUAT_NAMES",
    "orientation_block",
    "orientation_representation",
]

#: The quaternion columns known by name, scalar first.
QUAT_NAMES = ("qw", "qx", "qy", "qz")
#: The Euler angle columns known by name, about the x, y and z axes.
EULER_NAMES = ("roll", "pitch", "yaw")


def orientation_representation(p, ks, block, representation, euler, lab, explicit, how):
    """How the orientation columns ``ks`` hold it, or an error naming the choices.

    Returns a representation (``"rotvec"``, ``"euler-SEQ"``, ``"quat-..."``)
    or ``None`` for four columns read by their names or the order option.
    ``lab`` is what :func:`~ndlfd.io._names.lab_groups` told of the names,
    ``explicit`` whether the group was mapped by hand.
    """
    if representation is not None:
        if representation_size(representation) != block.shape[1]:
            raise DataFileError(
                f"{p}: the orientation {ks} has {block.shape[1]} columns; the"
                f" representation {representation} takes"
                f" {representation_size(representation)}"
            )
        return representation
    if block.shape[1] == 4:
        return None
    if block.shape[1] == 3:
        if euler is not None:
            return f"euler-{euler}"
        if sorted(k.casefold() for k in ks) == sorted(EULER_NAMES):
            return "euler-xyz"
        if lab.representation.get("orientation") and not explicit:
            return lab.representation["orientation"]
        cli = how["groups"].startswith("--")
        line = ready_line(cli, {"orientation": list(ks)}, (), "rotvec")
        raise DataFileError(
            f"{p}: the orientation {list(ks)} has three columns, which hold"
            " rotation vectors or Euler angles: name which, never guessed, as"
            " rotvec (axis times angle, as Universal Robots' rx, ry, rz) or"
            " euler-SEQ (radians, SEQ any scipy convention, e.g. euler-xyz or"
            f" euler-ZYX); e.g. {line}"
        )
    raise DataFileError(
        f"{p}: the orientation must be four quaternion columns (qw, qx, qy,"
        " qz) or three Euler angles (roll, pitch, yaw) or a rotation vector; got"
        f" {block.shape[1]} columns from {ks}"
    )


def orientation_block(p, ks, block, cols, rep, quaternion_order, named, how):
    """The orientation as quaternion columns, their names, and how it was given.

    Returns the file's names in the order read, the ``(n, 4)`` quaternions,
    the demonstration's column names and what the mapping records
    (``ColumnMapping.euler``: an Euler convention, ``"rotvec"`` or ``None``).
    """
    if rep is not None and rep.startswith("euler-"):
        seq = rep[len("euler-") :]
        ks, Q = _euler_block(p, ks, block, seq, how)
        return ks, Q, list(default_columns("orientation", 4)), seq
    if rep == "rotvec":
        Q = _rows_to_quaternions(block, "rotvec")
        return ks, Q, list(default_columns("orientation", 4)), "rotvec"
    # four named columns qw, qx, qy, qz (or a lab's w, x, y, z) say their
    # order; else the representation or the option
    low = [c.casefold() for c in ks]
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
