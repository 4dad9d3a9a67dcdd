"""The ALOHA scenes of gym-aloha, stepped without rendering.

gym-aloha (extra ``sim``) ships the bimanual ViperX model and two tasks on
dm_control: Transfer Cube (the right hand picks a cube and hands it to the
left) and Insertion (the right hand picks a peg, the left a socket, and the
peg goes into the socket until it touches the pin inside). Each task comes in
two controls: joint positions (``bimanual_viperx_<task>.xml``: 12 arm joints
and 2 grippers, the action of ``AlohaTransferCube-v0``) and end effector
(``bimanual_viperx_end_effector_<task>.xml``: two mocap bodies welded to the
gripper links, moved to a pose each step; gym-aloha has the task classes but
no gym environment for them).

:class:`Scene` loads a task's model and steps it at 50 Hz (10 physics steps of
2 ms) with the package's own ``before_step`` (the action's units and order)
and ``get_reward`` (success is its maximum, 4), but never renders: gym's
``AlohaEnv.step`` draws three 640x480 images per step, and the episodes here
need none. Objects are placed by :func:`sample_objects`, over gym-aloha's own
ranges (its ``sample_box_pose`` and ``sample_insertion_pose``), from a numpy
``Generator``.

A hand's pose is its *tool point* (:func:`tool_point`: the middle of the two
fingers, where an object is held) and the orientation of its mocap body
(w, x, y, z), so an end-effector action is per hand ``x, y, z, qw, qx, qy,
qz, gripper`` (gripper 0 closed, 1 open) and :func:`mocap_action` turns it
into the mocap command.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from .._errors import MissingExtraError, ValidationError
from .._registry import Registry

__all__ = [
    "CONTROL_DT",
    "HAND_COLUMNS",
    "JOINT_NAMES",
    "MAX_REWARD",
    "TASKS",
    "TOOL_DEPTH",
    "VIPERX_LIMITS",
    "Scene",
    "TaskSpec",
    "mocap_action",
    "require_sim",
    "sample_objects",
]

#: The control period: 50 Hz, as gym-aloha's ``DT``.
CONTROL_DT = 0.02
#: The tasks' reward at success (``TransferCubeTask.max_reward``).
MAX_REWARD = 4
#: The joint-space action's components (gym-aloha's ``JOINTS``).
JOINT_NAMES = tuple(
    f"{side}_{j}"
    for side in ("left", "right")
    for j in (
        "waist",
        "shoulder",
        "elbow",
        "forearm_roll",
        "wrist_angle",
        "wrist_rotate",
        "gripper",
    )
)
#: One hand's end-effector components (tool point, mocap orientation, gripper).
HAND_COLUMNS = ("x", "y", "z", "qw", "qx", "qy", "qz", "gripper")
#: The ViperX 300 s joints' velocity limit (rad/s), from Interbotix's
#: ``vx300s.urdf.xacro`` (``velocity="${pi}"`` on every arm joint). The URDF
#: gives no acceleration limit and none is assumed here: accelerations are
#: reported as measured.
VIPERX_LIMITS = {"velocity": np.pi}

#: How far ahead of the gripper link (along its x axis) a hand's tool point
#: is: between the finger pads, 2-3 cm short of the tips (the finger meshes
#: reach 0.045-0.159 m ahead of the link).
TOOL_DEPTH = 0.13


@dataclass(frozen=True)
class TaskSpec:
    """A task: its models, its objects and where gym-aloha places them.

    Attributes
    ----------
    name : str
        The command line's name (``"transfer-cube"``, ``"insertion"``).
    model : str
        The gym-aloha model's stem (``transfer_cube``, ``insertion``).
    objects : tuple of str
        The objects' names, in the order of the model's free joints.
    ranges : tuple of ndarray of shape (2, 3)
        Per object, the low and high corners of its position (metres).
    """

    name: str
    model: str
    objects: tuple[str, ...]
    ranges: tuple[np.ndarray, ...]


TASKS: Registry[TaskSpec] = Registry("task")
TASKS.add(
    "transfer-cube",
    TaskSpec(
        "transfer-cube",
        "transfer_cube",
        ("cube",),
        (np.array([[0.0, 0.4, 0.05], [0.2, 0.6, 0.05]]),),
    ),
)
TASKS.add(
    "insertion",
    TaskSpec(
        "insertion",
        "insertion",
        ("peg", "socket"),
        (
            np.array([[0.1, 0.4, 0.05], [0.2, 0.6, 0.05]]),
            np.array([[-0.2, 0.4, 0.05], [-0.1, 0.6, 0.05]]),
        ),
    ),
)


def require_sim():
    """gym-aloha's modules (importing dm_control without a renderer).

    Returns
    -------
    modules : tuple
        ``(dm_control.mujoco, gym_aloha.constants, gym_aloha.tasks.sim,
        gym_aloha.tasks.sim_end_effector)``.

    Raises
    ------
    MissingExtraError
        mujoco, dm_control or gym-aloha is missing.
    """
    # dm_control picks an OpenGL backend at import; none is needed here, and
    # probing for one warns without a display. A choice the user made stands.
    os.environ.setdefault("MUJOCO_GL", "disable")
    try:
        from dm_control import mujoco as dm_mujoco
        from gym_aloha import constants
        from gym_aloha.tasks import sim, sim_end_effector
    except ImportError as exc:
        raise MissingExtraError(
            f"the simulated tasks need mujoco and gym-aloha ({exc}); install"
            ' them with: pip install "ndlfd[sim]"'
        ) from None
    return dm_mujoco, constants, sim, sim_end_effector


def sample_objects(task: str, rng: np.random.Generator) -> np.ndarray:
    """Object positions drawn uniformly over gym-aloha's ranges.

    Parameters
    ----------
    task : str
        A name from :data:`TASKS`.
    rng : numpy.random.Generator

    Returns
    -------
    positions : ndarray of shape (n_objects, 3)

    Examples
    --------
    >>> p = sample_objects("insertion", np.random.default_rng(0))
    >>> p.shape, bool(p[0, 0] > 0 > p[1, 0])
    ((2, 3), True)
    """
    spec = TASKS.get(task)
    return np.array([rng.uniform(lo, hi) for lo, hi in spec.ranges])


def _quat_matrix(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def mocap_action(hands) -> np.ndarray:
    """End-effector rows with each quaternion made unit: gym-aloha's action.

    Parameters
    ----------
    hands : array-like of shape (16,)
        Left then right: the mocap body's ``x, y, z, qw, qx, qy, qz`` and the
        gripper (0 closed, 1 open) each (:data:`HAND_COLUMNS`).

    Returns
    -------
    action : ndarray of shape (16,)

    Examples
    --------
    >>> mocap_action([0, 0.5, 0.3, 2, 0, 0, 0, 1] * 2)[:8]
    array([0. , 0.5, 0.3, 1. , 0. , 0. , 0. , 1. ])
    """
    out = np.array(hands, dtype=float)
    for k in (0, 8):
        out[k + 3 : k + 7] /= np.linalg.norm(out[k + 3 : k + 7])
    return out


class Scene:
    """One task's model, stepped at 50 Hz with gym-aloha's actions and reward.

    Parameters
    ----------
    task : str
        A name from :data:`TASKS`.
    control : {"joint", "ee"}
        Joint positions (14 per step: per arm 6 joints and a gripper, 0
        closed to 1 open) or end effector (16 per step, :func:`mocap_action`
        of :data:`HAND_COLUMNS` per hand).

    Examples
    --------
    >>> scene = Scene("transfer-cube", "joint")  # doctest: +SKIP
    >>> scene.reset([[0.1, 0.5, 0.05]])  # doctest: +SKIP
    """

    def __init__(self, task: str, control: str = "joint") -> None:
        spec = TASKS.get(task)
        if control not in ("joint", "ee"):
            raise ValidationError(f"control must be 'joint' or 'ee'; got {control!r}")
        dm_mujoco, constants, sim, sim_ee = require_sim()
        stem = spec.model if control == "joint" else f"end_effector_{spec.model}"
        path = constants.ASSETS_DIR / f"bimanual_viperx_{stem}.xml"
        self.spec = spec
        self.control = control
        self.physics = dm_mujoco.Physics.from_xml_path(str(path))
        reward_task = {
            "transfer-cube": sim.TransferCubeTask,
            "insertion": sim.InsertionTask,
        }[spec.name]()
        self._reward = reward_task.get_reward
        self._start = np.asarray(constants.START_ARM_POSE, dtype=float)
        if control == "joint":
            self._act = sim.BimanualViperXTask().before_step
        else:
            ee = sim_ee.BimanualViperXEndEffectorTask()
            self._act = ee.before_step
            self._init_robots = ee.initialize_robots
        self._get_qpos = sim.BimanualViperXTask.get_qpos
        self._n_sub = round(CONTROL_DT / self.physics.model.opt.timestep)
        self._object_qpos = [
            self.physics.model.jnt_qposadr[j]
            for j in range(self.physics.model.njnt)
            if self.physics.model.jnt_type[j] == 0  # free joints, in order
        ]

    def reset(self, objects) -> None:
        """The arms at gym-aloha's start pose, the objects at ``objects``.

        Parameters
        ----------
        objects : array-like of shape (n_objects, 3)
            Positions; orientations are the identity, as gym-aloha's.
        """
        objects = np.asarray(objects, dtype=float).reshape(-1, 3)
        p = self.physics
        with p.reset_context():
            if self.control == "joint":
                p.data.qpos[:16] = self._start
                p.data.ctrl[:] = self._start
            else:
                self._init_robots(p)
            for adr, xyz in zip(self._object_qpos, objects, strict=True):
                p.data.qpos[adr : adr + 7] = [*xyz, 1.0, 0.0, 0.0, 0.0]

    def step(self, action) -> int:
        """Apply one action for 20 ms; the task's reward after it.

        Parameters
        ----------
        action : array-like of shape (14,) or (16,)

        Returns
        -------
        reward : int
        """
        a = np.asarray(action, dtype=float)
        if self.control == "ee":
            a = mocap_action(a)
        self._act(a, self.physics)
        self.physics.step(self._n_sub)
        return int(self._reward(self.physics))

    def qpos(self) -> np.ndarray:
        """The 14 joint readings (grippers normalized, 0 closed to 1 open)."""
        return np.asarray(self._get_qpos(self.physics), dtype=float)

    def hands(self) -> np.ndarray:
        """Both hands' tool points and gripper-link orientations, left then right.

        Returns
        -------
        poses : ndarray of shape (2, 7)
            Per hand ``x, y, z, qw, qx, qy, qz``: :data:`TOOL_DEPTH` ahead of
            the gripper link, and the link's orientation.
        """
        d = self.physics.named.data
        out = np.empty((2, 7))
        for k, side in enumerate(("left", "right")):
            link = f"vx300s_{side}/gripper_link"
            R = d.xmat[link].reshape(3, 3)
            out[k, :3] = d.xpos[link] + TOOL_DEPTH * R[:, 0]
            out[k, 3:] = d.xquat[link]
        return out

    def mocap(self) -> np.ndarray:
        """The mocap bodies' poses, shape (2, 7) (end-effector scene)."""
        d = self.physics.data
        return np.concatenate([d.mocap_pos, d.mocap_quat], axis=1)

    def weld(self) -> np.ndarray:
        """Per hand the gripper link's pose in its mocap body's frame, (2, 7).

        The weld's ``relpose`` as compiled (from the model's reference pose).
        """
        return np.array(self.physics.model.eq_data[:2, 3:10], dtype=float)

    def objects(self) -> np.ndarray:
        """The objects' current positions, shape (n_objects, 3)."""
        q = self.physics.data.qpos
        return np.array([q[a : a + 3] for a in self._object_qpos])

    def object_poses(self) -> np.ndarray:
        """The objects' positions and orientations (w, x, y, z), (n_objects, 7)."""
        q = self.physics.data.qpos
        return np.array([q[a : a + 7] for a in self._object_qpos])
