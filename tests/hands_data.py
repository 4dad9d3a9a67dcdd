"""Synthetic tasks with a known answer for several hands and joint-space frames.

``two_hands``: the right hand starts at a fixed home, goes to an object
(rigid in the object's frame while it grasps and holds), carries it to a
fixed handover point in the world and holds it there; the left hand's whole
motion is in the world (it waits, then comes to the handover point). So a
generated path for a new object must put the right hand on the new object at
the grasp, and both hands where they always were at the handover.

``planar_arm``: a planar 2-link arm (links 0.5 and 0.5, reach 1) moves its
joints from home to the joints that put its tip on a target (the elbow-down
solution); the target is the demonstration's task frame.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from ndlfd import Demonstration

HOME_R = np.array([0.35, -0.25, 0.30])
HOME_L = np.array([-0.35, -0.25, 0.30])
HANDOVER = np.array([0.0, 0.05, 0.35])
GRASP = np.array([0.0, 0.0, 0.02])  # the grasp point in the object's frame
LINKS = (0.5, 0.5)


def _ease(s):
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10 - 15 * s + 6 * s**2)


def _pieces(tau, knots, points):
    """Minimum-jerk pieces through ``points`` at normalized times ``knots``."""
    out = np.empty((tau.size, points.shape[1]))
    for a in range(len(knots) - 1):
        m = (tau >= knots[a]) & (tau <= knots[a + 1])
        s = _ease((tau[m] - knots[a]) / (knots[a + 1] - knots[a]))[:, None]
        out[m] = points[a] + s * (points[a + 1] - points[a])
    return out


def object_pose(rng, spread=0.08):
    """An object's position on the table (z = 0) and its yaw quaternion."""
    xy = rng.uniform(-spread, spread, 2) + np.array([0.1, 0.25])
    yaw = rng.uniform(-0.4, 0.4)
    q = Rotation.from_euler("z", yaw).as_quat()[[3, 0, 1, 2]]
    return np.array([*xy, 0.0]), q


def two_hands(n, seed=0, *, noise=5e-4, n_samples=200, flip_signs=False):
    """Demonstrations of the handover task and each one's object position.

    Returns
    -------
    demos : list of Demonstration
        Groups ``left_position``, ``left_orientation``, ``right_position``,
        ``right_orientation``, ``gripper`` (2 columns); the frame
        ``object`` (x, y, z).
    objects : list of ndarray of shape (3,)
    """
    rng = np.random.default_rng(seed)
    demos, objects = [], []
    for _ in range(n):
        obj, _q = object_pose(rng)
        grasp = obj + GRASP
        t = np.linspace(0.0, 4.0, n_samples)
        tau = t / t[-1]
        j = rng.uniform(-0.03, 0.03, 3)
        knots = np.array([0.0, 0.30 + j[0], 0.45 + j[1], 0.75 + j[2], 1.0])
        above = grasp + np.array([0.0, 0.0, 0.08])
        right = _pieces(
            tau, knots, np.array([HOME_R, grasp, grasp, HANDOVER, HANDOVER])
        )
        # the approach from above: the last part of the first piece lifted
        lift = np.interp(tau, [0.0, knots[1] * 0.6, knots[1]], [0.0, 1.0, 0.0])
        right = right + lift[:, None] * (above - grasp) * 0.5
        left_at = HANDOVER + np.array([-0.06, 0.0, 0.0])
        left = _pieces(
            tau,
            np.array([0.0, 0.5, 0.8, 1.0]),
            np.array([HOME_L, HOME_L, left_at, left_at]),
        )
        right += rng.normal(0.0, noise, right.shape)
        left += rng.normal(0.0, noise, left.shape)
        down = Rotation.from_euler("x", np.pi)
        turn = Rotation.from_euler("z", 0.6 * tau[:, None]) * down
        qr = turn.as_quat()[:, [3, 0, 1, 2]]
        ql = Rotation.from_euler("y", 0.3 * tau[:, None]).as_quat()[:, [3, 0, 1, 2]]
        if flip_signs:  # a recorder's sign flips: q and -q alternate
            qr[1::7] *= -1.0
            ql[2::5] *= -1.0
        grip = np.column_stack([tau > knots[2] + 0.02, tau > 0.85]).astype(float)
        demos.append(
            Demonstration.from_arrays(
                t,
                left_position=left,
                left_orientation=ql,
                right_position=right,
                right_orientation=qr,
                gripper=grip,
                frames={"object": obj},
            )
        )
        objects.append(obj)
    return demos, objects


def forward(q):
    """The planar arm's tip for joints ``q`` of shape (..., 2)."""
    a, b = q[..., 0], q[..., 0] + q[..., 1]
    return np.stack(
        [LINKS[0] * np.cos(a) + LINKS[1] * np.cos(b),
         LINKS[0] * np.sin(a) + LINKS[1] * np.sin(b)], axis=-1
    )  # fmt: skip


def inverse(p):
    """The elbow-down joints putting the tip at ``p`` (shape (2,))."""
    l1, l2 = LINKS
    c2 = (p @ p - l1 * l1 - l2 * l2) / (2 * l1 * l2)
    q2 = -np.arccos(np.clip(c2, -1.0, 1.0))
    q1 = np.arctan2(p[1], p[0]) - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    return np.array([q1, q2])


def planar_target(rng, spread=0.12):
    """A target in front of the arm, within ``spread`` of (0.55, 0.35)."""
    return np.array([0.55, 0.35]) + rng.uniform(-spread, spread, 2)


def planar_arm(n, seed=0, *, noise=2e-4, n_samples=150):
    """Joint-space demonstrations of reaching a target, the target as frame."""
    rng = np.random.default_rng(seed)
    home = np.array([0.3, -2.2])
    demos, targets = [], []
    for _ in range(n):
        p = planar_target(rng)
        goal = inverse(p)
        t = np.linspace(0.0, 2.0, n_samples)
        tau = t / t[-1]
        k = 0.7 + rng.uniform(-0.08, 0.08)
        q = _pieces(tau, np.array([0.0, k, 1.0]), np.array([home, goal, goal]))
        q += rng.normal(0.0, noise, q.shape)
        demos.append(Demonstration.from_arrays(t, joints=q, frames={"target": p}))
        targets.append(p)
    return demos, targets
