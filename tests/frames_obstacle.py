"""A pick-and-place around a fixed obstacle, recorded with an object frame.

The demonstrations a task-frame model must learn both frames from
(:func:`pick_around`): the hand starts at a fixed home, passes on the left
of a fixed vertical post (the obstacle, world frame), comes down on an
object whose pose varies (moved by up to 10 cm, turned by up to 30 deg;
the approach is rigid in the object's frame), grasps it (a short rest while
the gripper closes), lifts, passes on the right of the post, and puts it
down at a fixed place. The post stands between the two routes. Each piece's
duration varies by up to 15 %, the world waypoints by a few mm, and the
samples carry noise, as a person's demonstrations would.

:func:`clearance` is the smallest horizontal distance of a path to the
post's centre line, the quantity a collision check against the post needs.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.spatial.transform import Rotation

from ndlfd import Demonstration

#: The post's centre line (x, y in m; vertical).
POST = np.array([0.35, 0.0])
#: Fixed home and place of the hand (m).
HOME = np.array([0.0, 0.0, 0.30])
PLACE = np.array([0.05, -0.30, 0.06])
#: Where the hand passes the post going out (left, two waypoints before and
#: after it) and coming back (right): the route keeps its distance to the
#: post whatever the object's pose.
OUT_BY = (np.array([0.25, 0.12, 0.26]), np.array([0.45, 0.12, 0.22]))
BACK_BY = (np.array([0.45, -0.12, 0.25]), np.array([0.25, -0.12, 0.27]))
#: The object's nominal position (m).
OBJECT = np.array([0.70, 0.0, 0.02])
#: Above and behind the object, in its frame (m): the approach is rigid in it.
APPROACH = np.array([-0.08, 0.0, 0.10])
#: Above the object after the grasp, in its frame (m).
LIFT = np.array([0.0, 0.0, 0.15])
#: Nominal durations (s): home to the left of the post, past it, to above
#: the object, down to it, the rest while the gripper closes, up, to the
#: right of the post, past it, to the place.
DURATIONS = (0.9, 0.6, 0.7, 0.6, 0.3, 0.5, 0.8, 0.6, 0.9)
RATE = 50.0


def _down(yaw: float) -> Rotation:
    """A hand pointing down, turned by ``yaw`` about z."""
    return Rotation.from_euler("z", yaw) * Rotation.from_euler("x", np.pi)


def _quat(r: Rotation) -> np.ndarray:
    """``(w, x, y, z)`` of ``r``."""
    return np.roll(r.as_quat(), 1, axis=-1)


def pick_around(
    n_demos: int = 14,
    *,
    shift: float = 0.10,
    yaw: float = np.radians(30.0),
    timing: float = 0.15,
    jitter: float = 0.004,
    noise: float = 5e-4,
    n_right: int = 0,
    random_state: int = 0,
):
    """Pick-and-place demonstrations around a fixed post (see the module).

    Parameters
    ----------
    n_demos : int
    shift : float
        Largest move of the object in x and y (m).
    yaw : float
        Largest turn of the object about z (radians).
    timing : float
        Largest relative change of each piece's duration.
    jitter : float
        Standard deviation of each demonstration's waypoints (m).
    noise : float
        Standard deviation of the samples' noise (m).
    n_right : int
        How many demonstrations (the last ones) go out on the right of the
        post and come back on its left: two routes, the post between them.
    random_state : int

    Returns
    -------
    demos : list of Demonstration
        Groups position (3), orientation (unit quaternions) and gripper (1
        open, 0 closed), at :data:`RATE` Hz; frame ``"object"`` (position and
        quaternion of the grasp).
    grasps : list of float
        The time each demonstration reaches the object (s).

    Examples
    --------
    >>> demos, grasps = pick_around(2)
    >>> bool(clearance(demos[0].get("position")) > 0.09)
    True
    """
    rng = np.random.default_rng(random_state)
    demos, grasps = [], []
    for i in range(n_demos):
        o = OBJECT.copy()
        o[:2] += rng.uniform(-shift, shift, 2)
        turn = float(rng.uniform(-yaw, yaw))
        R = Rotation.from_euler("z", turn)
        near = jitter / 2  # object-frame waypoints: the hand is guided by it
        side = np.array([1.0, -1.0 if i >= n_demos - n_right else 1.0, 1.0])
        grasp = o + rng.normal(0.0, near / 2, 3)
        pts = [
            HOME + rng.normal(0.0, jitter, 3),
            *(side * p + rng.normal(0.0, jitter, 3) for p in OUT_BY),
            o + R.apply(APPROACH + rng.normal(0.0, near, 3)),
            grasp,
            grasp,  # the rest at the object
            o + R.apply(LIFT + rng.normal(0.0, near, 3)),
            *(side * p + rng.normal(0.0, jitter, 3) for p in BACK_BY),
            PLACE + rng.normal(0.0, jitter, 3),
        ]
        yaws = [0.0, 0.0, 0.0, turn, turn, turn, turn, 0.0, 0.0, 0.0]
        d = np.asarray(DURATIONS) * rng.uniform(1 - timing, 1 + timing, len(DURATIONS))
        knots = np.concatenate([[0.0], np.cumsum(d)])
        t = np.arange(0.0, knots[-1] + 0.5 / RATE, 1.0 / RATE)
        t[-1] = knots[-1]
        P = np.empty((t.size, 3))
        Y = np.empty(t.size)
        # two smooth sweeps at rest at their ends: out to the object, and back
        for rows, sl in (
            (t <= knots[4], slice(0, 5)),
            (t >= knots[5], slice(5, 10)),
        ):
            P[rows] = CubicSpline(knots[sl], np.array(pts[sl]), bc_type="clamped")(
                t[rows]
            )
            Y[rows] = CubicSpline(knots[sl], yaws[sl], bc_type="clamped")(t[rows])
        rest = (t > knots[4]) & (t < knots[5])
        P[rest], Y[rest] = grasp, turn
        P += rng.normal(0.0, noise, P.shape)
        q = _quat(Rotation.from_euler("z", Y[:, None]) * _down(0.0))
        grip = np.where(t < knots[4] + 0.5 * d[4], 1.0, 0.0)
        frames = {"object": np.concatenate([o, _quat(_down(turn))])}
        demos.append(
            Demonstration.from_arrays(
                t, position=P, orientation=q, gripper=grip, frames=frames
            )
        )
        grasps.append(float(knots[4]))
    return demos, grasps


def clearance(P: np.ndarray) -> float:
    """Smallest horizontal distance of positions ``P`` (n, 3) to the post's line.

    Examples
    --------
    >>> clearance(np.array([[0.35, 0.2, 0.0], [0.45, 0.0, 1.0]]))
    0.1
    """
    return float(np.min(np.linalg.norm(P[:, :2] - POST, axis=1)).round(12))


def grasp_error(P: np.ndarray, obj: np.ndarray) -> float:
    """Closest approach of positions ``P`` (n, 3) to the object's position (m)."""
    return float(np.min(np.linalg.norm(P - obj[:3], axis=1)))


def object_frame_mean(train, pose, t) -> np.ndarray:
    """The training demonstrations carried rigidly to ``pose``, on one clock.

    Each demonstration's positions seen from its object frame, put in the
    frame at ``pose`` (position and quaternion ``(w, x, y, z)``), resampled
    at the same share of its duration as ``t`` of its, and averaged: what
    following the object's frame alone gives.

    Returns
    -------
    P : ndarray of shape (len(t), 3)
    """
    s = (t - t[0]) / (t[-1] - t[0])
    new = Rotation.from_quat(np.roll(pose[3:], -1))
    out = []
    for d in train:
        f = d.frames["object"]
        old = Rotation.from_quat(np.roll(f[3:], -1))
        u = (d.t - d.t[0]) / (d.t[-1] - d.t[0])
        P = d.get("position")
        Pi = np.column_stack([np.interp(s, u, P[:, c]) for c in range(3)])
        out.append((new * old.inv()).apply(Pi - f[:3]) + pose[:3])
    return np.mean(out, axis=0)
