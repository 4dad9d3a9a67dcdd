"""Inverse kinematics of the ViperX arms: damped least squares on mujoco's Jacobian.

A hand's pose is its tool point (:data:`~ndlfd.sim._scene.TOOL_DEPTH` ahead
of the gripper link along the link's x axis) and the gripper link's
orientation. :class:`ArmIK` finds the six arm joints that put a hand there:
Gauss-Newton steps damped as Levenberg-Marquardt's (``dq = J^T (J J^T +
lambda^2 I)^-1 e``, Wampler 1986; Buss 2004, "Introduction to inverse
kinematics with Jacobian transpose, pseudoinverse and damped least squares
methods"), with ``J`` mujoco's ``mj_jac`` at the tool point (translation, and
rotation weighted by :data:`ROTATION_WEIGHT` metres per radian) and ``e`` the
position error and the rotation vector from the pose reached to the one
asked. The steps run on a scratch copy of the model's data, never on the
simulation's own, and are clipped to the joints' ranges (the two rolls to
:data:`ROLL_RANGE`).
"""

from __future__ import annotations

import numpy as np

from ._scene import TOOL_DEPTH

__all__ = ["ARM_JOINTS", "ROLL_RANGE", "ROTATION_WEIGHT", "ArmIK"]

#: One arm's joints, in the action's order.
ARM_JOINTS = (
    "waist",
    "shoulder",
    "elbow",
    "forearm_roll",
    "wrist_angle",
    "wrist_rotate",
)
#: Metres of tool-point error worth one radian of orientation error.
ROTATION_WEIGHT = 0.1
_DAMPING = 0.02
#: The rolls' range the solutions keep to (radians): the forearm's roll and
#: the wrist's rotation undo each other when both turn half a turn (with the
#: wrist's angle negated), a branch that ends on their +-pi limits and cannot
#: follow a turn from there.
ROLL_RANGE = 2.0
_MAX_STEP = 0.2  # radians per joint per iteration


class ArmIK:
    """Joint positions that put a hand's tool point and orientation at a pose.

    Parameters
    ----------
    physics : dm_control.mujoco.Physics
        A scene's physics (:attr:`~ndlfd.sim._scene.Scene.physics`); only its
        model is read.

    Examples
    --------
    >>> from ndlfd.sim import Scene  # doctest: +SKIP
    >>> ik = ArmIK(Scene("transfer-cube", "joint").physics)  # doctest: +SKIP
    >>> q0 = [0, -0.96, 1.16, 0, -0.3, 0]  # gym-aloha's start
    >>> pose = [0.1, 0.5, 0.1], [0, 0, 0.38, 0.92]
    >>> q, err = ik.solve("right", *pose, q0)  # doctest: +SKIP
    """

    def __init__(self, physics) -> None:
        import mujoco

        self._mj = mujoco
        self.model = physics.model.ptr
        self.data = mujoco.MjData(self.model)
        m = self.model
        self._qadr, self._dadr, self._lo, self._hi, self._link = {}, {}, {}, {}, {}
        for side in ("left", "right"):
            ids = [
                mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"vx300s_{side}/{j}")
                for j in ARM_JOINTS
            ]
            self._qadr[side] = np.array([m.jnt_qposadr[i] for i in ids])
            self._dadr[side] = np.array([m.jnt_dofadr[i] for i in ids])
            self._lo[side] = np.array([m.jnt_range[i, 0] for i in ids])
            self._hi[side] = np.array([m.jnt_range[i, 1] for i in ids])
            for k in (3, 5):
                self._lo[side][k] = max(self._lo[side][k], -ROLL_RANGE)
                self._hi[side][k] = min(self._hi[side][k], ROLL_RANGE)
            self._link[side] = mujoco.mj_name2id(
                m, mujoco.mjtObj.mjOBJ_BODY, f"vx300s_{side}/gripper_link"
            )
        self.data.qpos[:] = m.qpos0
        self._jacp = np.zeros((3, m.nv))
        self._jacr = np.zeros((3, m.nv))

    def pose(self, side: str, q) -> tuple[np.ndarray, np.ndarray]:
        """The tool point and link rotation matrix at arm joints ``q`` (6,)."""
        d = self.data
        d.qpos[self._qadr[side]] = q
        self._mj.mj_kinematics(self.model, d)
        self._mj.mj_comPos(self.model, d)  # mj_jac reads cdof and subtree_com
        b = self._link[side]
        R = d.xmat[b].reshape(3, 3).copy()
        return d.xpos[b] + TOOL_DEPTH * R[:, 0], R

    def solve(
        self,
        side: str,
        point,
        quat,
        q0,
        *,
        iterations: int = 30,
        tol: float = 1e-4,
        roll_step: float | None = None,
    ) -> tuple[np.ndarray, float]:
        """The arm's joints putting its hand at ``point`` turned by ``quat``.

        Parameters
        ----------
        side : {"left", "right"}
        point : array-like of shape (3,)
            The tool point (metres, world frame).
        quat : array-like of shape (4,)
            The gripper link's orientation (w, x, y, z).
        q0 : array-like of shape (6,)
            Where the iterations start (the last solution, for a smooth path).
        iterations : int, default=30
        tol : float, default=1e-4
            Stop when the weighted error's norm is below this (metres).
        roll_step : float, optional
            How far the two rolls may move from ``q0`` (radians). Where the
            wrist passes straight the rolls undo each other and the exact
            solution swings them fast; a step bound (the velocity limit
            times the control period) lets the pose lag there instead.

        Returns
        -------
        q : ndarray of shape (6,)
        error : float
            The weighted pose error left (metres; radians times
            :data:`ROTATION_WEIGHT`).
        """
        mj = self._mj
        target = np.asarray(point, dtype=float)
        qd = np.asarray(quat, dtype=float)
        qd = qd / np.linalg.norm(qd)
        q = np.clip(np.asarray(q0, dtype=float), self._lo[side], self._hi[side])
        lo, hi = self._lo[side].copy(), self._hi[side].copy()
        if roll_step is not None:
            for k in (3, 5):
                lo[k] = max(lo[k], q[k] - roll_step)
                hi[k] = min(hi[k], q[k] + roll_step)
        dadr = self._dadr[side]
        cur = np.empty(4)
        rot = np.empty(3)
        err = np.inf
        for _ in range(iterations):
            tool, R = self.pose(side, q)
            mj.mju_mat2Quat(cur, R.ravel())
            mj.mju_subQuat(rot, qd, cur)  # in the current link's frame
            e = np.concatenate([target - tool, ROTATION_WEIGHT * (R @ rot)])
            err = float(np.linalg.norm(e))
            if err < tol:
                break
            mj.mj_jac(
                self.model, self.data, self._jacp, self._jacr, tool, self._link[side]
            )
            J = np.vstack([self._jacp[:, dadr], ROTATION_WEIGHT * self._jacr[:, dadr]])
            dq = J.T @ np.linalg.solve(J @ J.T + _DAMPING**2 * np.eye(6), e)
            dq = np.clip(dq, -_MAX_STEP, _MAX_STEP)
            q = np.clip(q + dq, lo, hi)
        return q, err
