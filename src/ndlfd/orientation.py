"""Unit quaternions for the orientation group.

ndlfd stores orientation as unit quaternions in scalar-first order
``(w, x, y, z)``. scipy's :class:`~scipy.spatial.transform.Rotation` uses the
scalar-last order ``(x, y, z, w)``; every function here that reads quaternions
takes an explicit ``order`` so the two cannot be mixed up silently.

``q`` and ``-q`` are the same rotation. Before orientations are normalized,
reduced or interpolated, consecutive quaternions are sign-aligned
(:func:`make_continuous`) so that a stream does not jump across the sphere.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from ._errors import ValidationError
from ._registry import Registry
from ._repairs import repaired
from ._validation import check_points

__all__ = [
    "EULER_AXES",
    "QUATERNION_ORDERS",
    "RENORMALIZE_TOL",
    "REPRESENTATIONS",
    "check_euler",
    "check_quaternions",
    "check_representation",
    "euler_to_quaternions",
    "from_quaternions",
    "make_continuous",
    "normalize_quaternions",
    "quaternions_to_euler",
    "quaternions_to_rotvec",
    "representation_size",
    "rotvec_to_quaternions",
    "to_order",
    "to_quaternions",
]

QUATERNION_ORDERS: Registry[tuple[int, ...]] = Registry("quaternion_order")
# column permutation that takes a quaternion of the named order to (w, x, y, z)
QUATERNION_ORDERS.add("wxyz", (0, 1, 2, 3))
QUATERNION_ORDERS.add("xyzw", (3, 0, 1, 2))


def _as_quaternion_array(Q, name: str) -> np.ndarray:
    A = check_points(Q, name)
    if A.shape[1] != 4:
        raise ValidationError(
            f"{name} must have shape (n_samples, 4) (one unit quaternion per row);"
            f" got an array of shape {A.shape}"
        )
    return A


#: Quaternions whose norm is off by at most this are renormalized (with one
#: warning that gives the count): logging four decimals gives up to ~2e-4.
RENORMALIZE_TOL = 1e-3


def check_quaternions(
    Q,
    order: str = "wxyz",
    *,
    atol: float = 1e-6,
    renormalize_tol: float = RENORMALIZE_TOL,
    name: str = "quaternions",
) -> np.ndarray:
    """Check a stream of unit quaternions and return it scalar-first.

    Rows whose norm is within ``atol`` of 1 are kept as they are; rows within
    ``renormalize_tol`` (quaternions logged with a few decimals) are divided
    by their norm, with one :class:`~ndlfd.NdlfdWarning` that gives the count;
    a row further off is an error.

    Parameters
    ----------
    Q : array-like of shape (n_samples, 4)
        One quaternion per row, in the given ``order``.
    order : {"wxyz", "xyzw"}, default="wxyz"
        ``"wxyz"`` is scalar-first (ndlfd's order); ``"xyzw"`` is scalar-last
        (scipy's :class:`~scipy.spatial.transform.Rotation`).
    atol : float, default=1e-6
        Largest deviation of a row's norm from 1 accepted without a change.
    renormalize_tol : float, default=1e-3
        Largest deviation of a row's norm from 1 that is repaired by
        renormalizing (:data:`RENORMALIZE_TOL`).
    name : str, default="quaternions"
        The argument's name, used in messages.

    Returns
    -------
    Q_wxyz : ndarray of shape (n_samples, 4), dtype float64
        The same quaternions in scalar-first order, rows off by more than
        ``atol`` renormalized (not sign-aligned: see :func:`make_continuous`).

    Raises
    ------
    ValidationError
        Wrong shape, NaN/inf, or a row whose norm is off by more than
        ``renormalize_tol`` (the message names the first such row).
    OptionError
        An unknown ``order``.

    Examples
    --------
    >>> check_quaternions([[0.0, 0.0, 0.0, 1.0]], order="xyzw")
    array([[1., 0., 0., 0.]])
    >>> check_quaternions([[1.0, 0.0, 0.0, 0.1]])
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: quaternions must have unit norm ... at row 0: ...

    Four logged decimals are repaired, with a warning:

    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     q = check_quaternions([[0.7071, 0.7071, 0.0, 0.0]])
    >>> float(np.linalg.norm(q)), len(caught)
    (1.0, 1)
    """
    perm = QUATERNION_ORDERS.get(order)
    A = _as_quaternion_array(Q, name)
    norms = np.sqrt(np.einsum("ij,ij->i", A, A))
    dev = np.abs(norms - 1.0)
    bad = np.flatnonzero(dev > max(atol, renormalize_tol))
    if bad.size:
        i = int(bad[0])
        raise ValidationError(
            f"{name} must have unit norm (rows within {renormalize_tol:g} of it"
            f" are renormalized); got norm {norms[i]:.6g} at row {i}:"
            f" {A[i].tolist()}"
        )
    fix = dev > atol
    if np.any(fix):
        A = A.copy()
        A[fix] /= norms[fix, None]
        repaired(
            "quaternions",
            int(fix.sum()),
            f"{name}: renormalized {int(fix.sum())} of {A.shape[0]} quaternions"
            f" whose norm was off by more than {atol:g} (at most"
            f" {float(dev.max()):.2g}; up to {renormalize_tol:g} is repaired)",
            worst=float(dev.max()),
        )
    return np.ascontiguousarray(A[:, list(perm)])


def to_order(Q_wxyz, order: str) -> np.ndarray:
    """Reorder scalar-first quaternions to ``order`` (the inverse of the check).

    Parameters
    ----------
    Q_wxyz : array-like of shape (n_samples, 4)
        Scalar-first quaternions.
    order : {"wxyz", "xyzw"}
        The wanted order.

    Returns
    -------
    Q : ndarray of shape (n_samples, 4)

    Examples
    --------
    >>> to_order([[1.0, 0.0, 0.0, 0.0]], "xyzw")
    array([[0., 0., 0., 1.]])
    """
    perm = QUATERNION_ORDERS.get(order)
    A = _as_quaternion_array(Q_wxyz, "quaternions")
    inverse = np.argsort(perm)
    return np.ascontiguousarray(A[:, inverse])


#: Tie tolerance of :func:`make_continuous`, in units of the float64 machine
#: epsilon times ``sum_k |q_k p_k|``: about twice the bound on the rounding
#: error of a 4-term dot product summed in any order (gamma_4 = 2 eps / (1 - 2 eps)).
CONTINUITY_TIE_EPS = 4.0


def _signed_dots(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Dot product of each row with the previous one, and its tie tolerance.

    Both are summed in one stated order, left to right over the columns, so any
    other code that follows the same order gets bit-identical values.
    """
    P = A[1:] * A[:-1]
    raw = ((P[:, 0] + P[:, 1]) + P[:, 2]) + P[:, 3]
    M = np.abs(P)
    magnitude = ((M[:, 0] + M[:, 1]) + M[:, 2]) + M[:, 3]
    return raw, CONTINUITY_TIE_EPS * np.finfo(np.float64).eps * magnitude


def make_continuous(Q) -> np.ndarray:
    """Flip signs so that no two consecutive quaternions point apart.

    The first row is kept as given; each following row ``q`` is negated when its
    dot product with the (already aligned) previous row ``p`` is below ``-tol``,
    and kept as given otherwise. The rotations are unchanged, since ``q`` and
    ``-q`` are the same rotation. The order of the four components does not
    matter.

    Ties are defined, so the result does not depend on rounding: the dot
    product is summed left to right, ``((q0 p0 + q1 p1) + q2 p2) + q3 p3``, and
    ``tol = 4 * eps * (|q0 p0| + |q1 p1| + |q2 p2| + |q3 p3|)`` (``eps`` the
    float64 machine epsilon; the same left-to-right sum), about twice the bound
    on the rounding error of a 4-term dot product. A dot product within ``tol``
    of zero is a tie: zero up to rounding, so ``q`` and ``-q`` are equally close
    to ``p`` (a half-turn apart), and the row is kept as given. A dot product
    that is exactly zero is thus a tie whatever order it is summed in (as long
    as no product underflows); the stated order settles the rest.

    Parameters
    ----------
    Q : array-like of shape (n_samples, 4)
        Quaternions (any order, any norm).

    Returns
    -------
    Q_continuous : ndarray of shape (n_samples, 4), dtype float64
        Consecutive rows have a dot product ``>= -tol``.

    Examples
    --------
    >>> Q = [[0.6, 0.8, 0, 0], [-0.6, -0.8, 0, 0], [-0.8, -0.6, 0, 0]]
    >>> make_continuous(Q)[:, :2]
    array([[0.6, 0.8],
           [0.6, 0.8],
           [0.8, 0.6]])

    A dot product of zero up to rounding is a tie, and the row is kept:

    >>> make_continuous([[0.5, 0.5, 0.5, 0.5], [-1.0, 0.5, 0.5, -1e-17]])[1, :3]
    array([-1. ,  0.5,  0.5])
    """
    A = _as_quaternion_array(Q, "quaternions")
    if A.shape[0] < 2:
        return A.copy()
    # Row i is compared with the already aligned row i-1, whose sign is s[i-1]:
    # dot(q_i, s[i-1] q_{i-1}) = s[i-1] * raw[i] exactly (negation is exact and
    # the tolerance does not depend on the sign), so s[i] = s[i-1] * sign(raw[i])
    # and s[i] = +1 when raw[i] is a tie (nothing to align to). Hence s[i] is -1
    # to the number of negative raw dots since the last tie (or row 0).
    raw, tol = _signed_dots(A)
    negatives = np.concatenate([[0], np.cumsum(raw < -tol)])
    n = A.shape[0]
    reset = np.concatenate([[True], np.abs(raw) <= tol])
    last_reset = np.maximum.accumulate(np.where(reset, np.arange(n), 0))
    odd = (negatives - negatives[last_reset]) % 2 == 1
    sign = np.where(odd, -1.0, 1.0)
    return A * sign[:, None]


def normalize_quaternions(Q, *, zero="error") -> np.ndarray:
    """Scale quaternions to unit norm (for example after interpolation).

    Parameters
    ----------
    Q : array-like of shape (n_samples, 4)
        Quaternions of any non-zero norm.
    zero : {"error", "identity"}, default="error"
        What to do with a row of (numerically) zero norm, which has no
        direction: refuse it, naming the row, or replace it by the identity
        rotation ``(1, 0, 0, 0)`` (scalar-first).

    Returns
    -------
    Q_unit : ndarray of shape (n_samples, 4), dtype float64

    Examples
    --------
    >>> normalize_quaternions([[2.0, 0.0, 0.0, 0.0], [0.0, 3.0, 4.0, 0.0]])
    array([[1. , 0. , 0. , 0. ],
           [0. , 0.6, 0.8, 0. ]])
    >>> normalize_quaternions([[0.0, 0.0, 0.0, 0.0]], zero="identity")
    array([[1., 0., 0., 0.]])
    """
    if zero not in ("error", "identity"):
        raise ValidationError(f"zero must be 'error' or 'identity'; got {zero!r}")
    A = _as_quaternion_array(Q, "quaternions")
    norms = np.sqrt(np.einsum("ij,ij->i", A, A))
    tiny = norms <= 1e-12
    if np.any(tiny):
        if zero == "error":
            i = int(np.flatnonzero(tiny)[0])
            raise ValidationError(
                "quaternions must have a non-zero norm to be normalized; got norm"
                f" {norms[i]:.3g} at row {i} (pass zero='identity' to replace such"
                " rows by the identity rotation)"
            )
        A = A.copy()
        A[tiny] = (1.0, 0.0, 0.0, 0.0)
        norms = np.where(tiny, 1.0, norms)
    return A / norms[:, None]


# ------------------------------------------------------------------ Euler angles
#: What an Euler convention looks like: three axes, all lower case (extrinsic:
#: rotations about the fixed frame's axes) or all upper case (intrinsic: about
#: the rotating frame's), no axis twice in a row (scipy's rule).
EULER_AXES = re.compile(r"^(?:[xyz]{3}|[XYZ]{3})$")


def check_euler(seq) -> str:
    """``seq`` if it is an Euler convention scipy takes, else a clear error.

    Parameters
    ----------
    seq : str
        Three axes, e.g. ``"xyz"`` (extrinsic: roll about x, then pitch about
        y, then yaw about z, all about the fixed axes: the ROS convention) or
        ``"ZYX"`` (intrinsic z-y'-x'', the same rotation for the same angles
        listed yaw, pitch, roll).

    Returns
    -------
    seq : str

    Examples
    --------
    >>> check_euler("ZYX")
    'ZYX'
    """
    if (
        not isinstance(seq, str)
        or not EULER_AXES.match(seq)
        or seq[0] == seq[1]
        or seq[1] == seq[2]
    ):
        raise ValidationError(
            "euler must be three axes from xyz (extrinsic) or XYZ (intrinsic), no"
            f" axis twice in a row, e.g. 'xyz' or 'ZYX'; got {seq!r}"
        )
    return seq


def euler_to_quaternions(angles, seq: str = "xyz") -> np.ndarray:
    """Unit quaternions ``(w, x, y, z)`` of Euler angles (radians).

    Parameters
    ----------
    angles : array-like of shape (n_samples, 3)
        The angles about the axes of ``seq``, in its order.
    seq : str, default="xyz"
        The convention (see :func:`check_euler`).

    Returns
    -------
    Q : ndarray of shape (n_samples, 4)
        Scalar-first unit quaternions, sign-aligned from one sample to the
        next (:func:`make_continuous`).

    Examples
    --------
    >>> euler_to_quaternions([[0.0, 0.0, np.pi / 2]]).round(4)
    array([[0.7071, 0.    , 0.    , 0.7071]])
    """
    from scipy.spatial.transform import Rotation

    seq = check_euler(seq)
    A = check_points(angles, "Euler angles")
    if A.shape[1] != 3:
        raise ValidationError(
            "Euler angles must have shape (n_samples, 3); got an array of shape"
            f" {A.shape}"
        )
    xyzw = Rotation.from_euler(seq, A).as_quat()
    return make_continuous(np.ascontiguousarray(xyzw[:, [3, 0, 1, 2]]))


def quaternions_to_euler(Q, seq: str = "xyz") -> np.ndarray:
    """Euler angles (radians) of unit quaternions ``(w, x, y, z)``.

    The inverse of :func:`euler_to_quaternions` up to the angles' ranges: each
    column is unwrapped along the samples (no jump of 2 pi from one sample to
    the next), starting in scipy's range (the first and last angle in
    ``[-pi, pi]``, the middle one in ``[-pi/2, pi/2]`` for three distinct
    axes). Near gimbal lock (middle angle at +-pi/2) only the sum or
    difference of the other two is defined; scipy then sets the third to 0
    and warns, which is kept quiet here.

    Parameters
    ----------
    Q : array-like of shape (n_samples, 4)
        Scalar-first unit quaternions.
    seq : str, default="xyz"
        The convention (see :func:`check_euler`).

    Returns
    -------
    angles : ndarray of shape (n_samples, 3)
        The angles about the axes of ``seq``, in its order.

    Examples
    --------
    >>> Q = euler_to_quaternions([[0.1, -0.2, 0.3]], "xyz")
    >>> quaternions_to_euler(Q, "xyz").round(6)
    array([[ 0.1, -0.2,  0.3]])
    """
    from scipy.spatial.transform import Rotation

    seq = check_euler(seq)
    A = _as_quaternion_array(Q, "quaternions")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Gg]imbal.*")
        angles = Rotation.from_quat(A[:, [1, 2, 3, 0]]).as_euler(seq)
    return np.unwrap(angles, axis=0)


# ------------------------------------------------- rotation vectors, representations
def rotvec_to_quaternions(rotvec) -> np.ndarray:
    """Unit quaternions ``(w, x, y, z)`` of rotation vectors (axis times angle).

    A rotation vector is the rotation's axis scaled by its angle in radians
    (Universal Robots' ``rx, ry, rz``; scipy's ``as_rotvec``). Converted by
    :meth:`scipy.spatial.transform.Rotation.from_rotvec`.

    Parameters
    ----------
    rotvec : array-like of shape (n_samples, 3)

    Returns
    -------
    Q : ndarray of shape (n_samples, 4)
        Scalar-first unit quaternions, sign-aligned from one sample to the
        next (:func:`make_continuous`): a logged vector that flips to its
        equivalent at an angle of pi gives no jump.

    Examples
    --------
    >>> rotvec_to_quaternions([[0.0, 0.0, np.pi / 2]]).round(4)
    array([[0.7071, 0.    , 0.    , 0.7071]])
    """
    from scipy.spatial.transform import Rotation

    A = check_points(rotvec, "rotation vectors")
    if A.shape[1] != 3:
        raise ValidationError(
            "rotation vectors must have shape (n_samples, 3); got an array of shape"
            f" {A.shape}"
        )
    xyzw = Rotation.from_rotvec(A).as_quat()
    return make_continuous(np.ascontiguousarray(xyzw[:, [3, 0, 1, 2]]))


def quaternions_to_rotvec(Q) -> np.ndarray:
    """Rotation vectors of unit quaternions ``(w, x, y, z)``, continuous in time.

    The inverse of :func:`rotvec_to_quaternions`:
    :meth:`scipy.spatial.transform.Rotation.as_rotvec` gives each vector with
    an angle in ``[0, pi]``; where the stream turns through an angle of pi,
    the vectors continue past it (angle up to ``2 pi``, the same rotation)
    instead of flipping to the opposite side. The stream is taken on the side
    of its first quaternion with ``w >= 0``, so a path that stays within an
    angle of pi gives exactly scipy's vectors.

    Parameters
    ----------
    Q : array-like of shape (n_samples, 4)
        Scalar-first unit quaternions.

    Returns
    -------
    rotvec : ndarray of shape (n_samples, 3)

    Examples
    --------
    >>> quaternions_to_rotvec([[np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)]]).round(4)
    array([[0.    , 0.    , 1.5708]])
    """
    from scipy.spatial.transform import Rotation

    A = make_continuous(_as_quaternion_array(Q, "quaternions"))
    if A[0, 0] < 0:
        A = -A
    r = Rotation.from_quat(A[:, [1, 2, 3, 0]]).as_rotvec()
    # rows past an angle of pi (w < 0 on the continuous stream): the same
    # rotation as r - 2 pi r / |r|, which continues the stream
    angle = np.linalg.norm(r, axis=1)
    past = (A[:, 0] < 0) & (angle > 0)
    r[past] -= (2.0 * np.pi / angle[past])[:, None] * r[past]
    return r


#: The representations an orientation may be read from and written back to:
#: ``"quat-wxyz"``, ``"quat-xyzw"`` (four columns), ``"rotvec"`` (three: a
#: rotation vector) and ``"euler-SEQ"`` for any Euler convention ``SEQ`` that
#: :func:`check_euler` takes (three angles in radians, e.g. ``"euler-xyz"``,
#: ``"euler-ZYX"``). Every conversion goes through scipy's
#: :class:`~scipy.spatial.transform.Rotation`.
REPRESENTATIONS = ("quat-wxyz", "quat-xyzw", "rotvec", "euler-SEQ")


def check_representation(rep) -> str:
    """``rep`` if it names an orientation representation, else a clear error.

    Parameters
    ----------
    rep : str
        One of :data:`REPRESENTATIONS` (``"euler-SEQ"`` with a convention).

    Returns
    -------
    rep : str

    Examples
    --------
    >>> check_representation("euler-ZYX")
    'euler-ZYX'
    >>> check_representation("axis")
    Traceback (most recent call last):
    ...
    ndlfd._errors.ValidationError: an orientation representation must be ...
    """
    ok = isinstance(rep, str) and (
        rep in ("quat-wxyz", "quat-xyzw", "rotvec")
        or (rep.startswith("euler-") and _is_euler(rep[len("euler-") :]))
    )
    if not ok:
        raise ValidationError(
            "an orientation representation must be one of quat-wxyz, quat-xyzw"
            " (four columns), rotvec (a rotation vector: axis times angle, three"
            " columns) or euler-SEQ (three Euler angles in radians, SEQ any"
            f" convention scipy takes, e.g. euler-xyz or euler-ZYX); got {rep!r}"
        )
    return rep


def _is_euler(seq: str) -> bool:
    try:
        check_euler(seq)
    except ValidationError:
        return False
    return True


def representation_size(rep: str) -> int:
    """How many columns a representation takes: 4 for a quaternion, else 3.

    Examples
    --------
    >>> representation_size("rotvec"), representation_size("quat-xyzw")
    (3, 4)
    """
    return 4 if check_representation(rep).startswith("quat-") else 3


def to_quaternions(values, rep: str) -> np.ndarray:
    """Scalar-first unit quaternions of orientations given in ``rep``.

    Parameters
    ----------
    values : array-like of shape (n_samples, 3) or (n_samples, 4)
        The orientations, as many columns as :func:`representation_size`.
    rep : str
        The representation (:data:`REPRESENTATIONS`).

    Returns
    -------
    Q : ndarray of shape (n_samples, 4)
        Sign-aligned from one sample to the next. Quaternions are only put in
        scalar-first order (their unit norm is checked where a demonstration
        is made, :func:`check_quaternions`).

    Examples
    --------
    >>> to_quaternions([[0.0, 0.0, np.pi]], "euler-xyz").round(4)
    array([[0., 0., 0., 1.]])
    >>> to_quaternions([[0.0, 0.0, 0.0, 1.0]], "quat-xyzw")
    array([[1., 0., 0., 0.]])
    """
    rep = check_representation(rep)
    if rep == "rotvec":
        return rotvec_to_quaternions(values)
    if rep.startswith("euler-"):
        return euler_to_quaternions(values, rep[len("euler-") :])
    A = _as_quaternion_array(values, "quaternions")
    perm = QUATERNION_ORDERS.get(rep[len("quat-") :])
    return make_continuous(np.ascontiguousarray(A[:, list(perm)]))


def from_quaternions(Q, rep: str) -> np.ndarray:
    """Orientations in ``rep`` of scalar-first unit quaternions.

    The inverse of :func:`to_quaternions`: rotation vectors continue past an
    angle of pi (:func:`quaternions_to_rotvec`), Euler angles are unwrapped
    along the samples (:func:`quaternions_to_euler`).

    Parameters
    ----------
    Q : array-like of shape (n_samples, 4)
    rep : str
        The representation (:data:`REPRESENTATIONS`).

    Returns
    -------
    values : ndarray of shape (n_samples, 3) or (n_samples, 4)

    Examples
    --------
    >>> from_quaternions([[0.0, 0.0, 0.0, 1.0]], "rotvec").round(4)
    array([[0.    , 0.    , 3.1416]])
    """
    rep = check_representation(rep)
    if rep == "rotvec":
        return quaternions_to_rotvec(Q)
    if rep.startswith("euler-"):
        return quaternions_to_euler(Q, rep[len("euler-") :])
    return to_order(Q, rep[len("quat-") :])
