"""Scripted experts for Transfer Cube and Insertion, varied as people vary.

Each expert is a sequence of *phases* shared by the two hands (reach, descend,
close, carry, ...), each ending at a key pose per hand: a tool point
(:meth:`~ndlfd.sim._scene.Scene.hands`), the gripper link's orientation and
a gripper opening. Between keys a hand moves by a minimum-jerk blend
(positions and gripper) and a spherical interpolation (orientation), sampled
at 50 Hz. :func:`record_expert` runs a plan in the joint-position scene: at
every step each hand's pose is turned into the arm's six joints by inverse
kinematics (:class:`~ndlfd.sim._ik.ArmIK`, warm-started from the step
before) and those joints are commanded, so the joint paths recorded are what
the robot did. Like a person the expert watches the objects at a few moments
and plans the rest from where they actually are (:attr:`ExpertPlan.replan`):

* **Transfer Cube.** The right hand comes down over the cube pitched steeply
  (45-60 degrees below horizontal, fingers closing on the cube's y faces),
  closes and lifts the cube to a meeting point above the middle of the
  table, keeping its pitch. Once there, the expert looks where the cube
  actually is and brings the left hand in level from the other side, rolled
  a quarter turn (its fingers close on the cube's top and bottom faces, clear
  of the right hand's, on the cube's left half); it closes, and the right
  hand opens and backs away along its own axis.
* **Insertion.** The right hand takes the peg near its outer (+x) end, the
  left the socket near its outer (-x) end, both from above; both lift to the
  meeting height. The expert then looks at both held objects (their poses
  after the grasp: each has turned a little in its hand) and moves the right
  hand so that the peg's axis lies on the socket's, 2.5 cm outside its mouth;
  looks again, corrects, and pushes the peg along the socket's axis until it
  meets the pin.

Human-like variation (:func:`expert_episode`, from a ``numpy.random.Generator``):
every phase's duration times a factor in [0.8, 1.2]; approach heights 5-10
cm; grasp points (+-4 to +-8 mm along the object, +-3 mm across and in
height); the pitch at the grasp; how far from the cube's middle the left
hand takes it; the meeting point +-3 cm and its height; and a smooth tremor
(three sines of 0.3-1.5 Hz, 1.5 mm in all) on every position.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._ik import ArmIK
from ._scene import CONTROL_DT

__all__ = [
    "START_HANDS",
    "ExpertPlan",
    "Recording",
    "expert_episode",
    "quat_about",
    "record_expert",
    "render_plan",
    "run_hands",
]

# Where objects rest on the table (their centres' height), once settled.
_REST_Z = {"cube": 0.02, "peg": 0.01, "socket": 0.022}
_PEG_HALF = 0.06  # the peg's and the socket's half-length (metres)
_PIN_END = 0.04  # the pin's end, from the socket's centre along its axis


def quat_about(axis: str, angle: float) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a turn by ``angle`` radians.

    Examples
    --------
    >>> quat_about("y", np.pi).round(6)
    array([0., 0., 1., 0.])
    """
    q = np.zeros(4)
    q[0] = np.cos(angle / 2)
    q["xyz".index(axis) + 1] = np.sin(angle / 2)
    return q


def _mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


#: Where the arms' bases stand (their waists' axes cross the table there).
BASES = {"left": np.array([-0.469, 0.5]), "right": np.array([0.469, 0.5])}


def _pitch(side: str, below: float, roll: float = 0.0, toward=None) -> np.ndarray:
    """A gripper pointing ``below`` radians under horizontal, rolled ``roll``.

    Headed from its arm's base toward ``toward`` (x, y, ...), as the waist
    turns: by default straight across the table (the left arm along +x, the
    right along -x). A heading off the arm's own would take the wrist's two
    rolls (the ViperX's wrist is roll-pitch-roll), up to their limits when
    the wrist is nearly straight. The fingers close along the gripper's y
    axis.
    """
    base = BASES[side]
    aim = base + ([1.0, 0.0] if side == "left" else [-1.0, 0.0])
    if toward is not None:
        aim = np.asarray(toward, dtype=float)[:2]
    heading = np.arctan2(aim[1] - base[1], aim[0] - base[0])
    return _mul(
        quat_about("z", heading),
        _mul(quat_about("y", below), quat_about("x", roll)),
    )


@dataclass
class ExpertPlan:
    """Key poses per phase: the expert's plan before it is sampled.

    Attributes
    ----------
    durations : ndarray of shape (n_phases,)
        Seconds per phase.
    keys : ndarray of shape (n_phases + 1, 2, 8)
        Per phase boundary (the start first), per hand (left, right), the
        tool point, orientation (w, x, y, z) and gripper (0 closed, 1 open).
    tremor : ndarray of shape (2, 3, 3, 3)
        Per hand and axis, three (amplitude, frequency, phase) sines.
    replan : list of (int, callable)
        Where the expert looks: as phase ``k`` begins, ``f(scene, keys)``
        rewrites the keys after boundary ``k`` from what the scene shows
        (the left hand takes the cube where the right hand holds it, the
        peg is aligned with the socket as they are held).
    """

    durations: np.ndarray
    keys: np.ndarray
    tremor: np.ndarray
    replan: list


def _key(pos, quat, grip) -> np.ndarray:
    quat = np.asarray(quat, dtype=float)
    return np.concatenate(
        [np.asarray(pos, dtype=float), quat / np.linalg.norm(quat), [grip]]
    )


def _tremor(rng: np.random.Generator) -> np.ndarray:
    amp = rng.uniform(0.2, 1.0, size=(2, 3, 3))
    amp *= 0.0015 / amp.sum(axis=2, keepdims=True)
    freq = rng.uniform(0.3, 1.5, size=(2, 3, 3))
    phase = rng.uniform(0.0, 2 * np.pi, size=(2, 3, 3))
    return np.stack([amp, freq, phase], axis=-1)


def _conj(q: np.ndarray) -> np.ndarray:
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def _matrix(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _quat(R: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(R).as_quat()
    return np.array([w, x, y, z])


def _align(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The smallest rotation (a matrix) turning unit vector ``u`` onto ``v``."""
    axis = np.cross(u, v)
    s, c = np.linalg.norm(axis), float(u @ v)
    if s < 1e-12:
        return np.eye(3)
    k = axis / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * K + (1 - c) * K @ K


def _tips_clear(down: float, centre_z: float, u) -> float:
    """The tool point's height over an object's centre, finger tips clear.

    The tips are 3 cm past the tool point along the gripper, pitched
    ``down`` radians: they end 4-7 mm above the table.
    """
    return 0.03 * np.sin(down) + u(0.004, 0.007) - centre_z


def _transfer_cube(objects: np.ndarray, start, rng: np.random.Generator):
    cube = objects[0].copy()
    cube[2] = _REST_Z["cube"]
    u = rng.uniform
    down = np.deg2rad(u(45, 60))
    grasp = cube + [u(-0.004, 0.004), u(-0.003, 0.003), _tips_clear(down, cube[2], u)]
    above = grasp + [0.0, 0.0, u(0.05, 0.10)]
    pick = _pitch("right", down, toward=cube)
    meet = np.array([u(-0.03, 0.03), 0.5 + u(-0.03, 0.03), u(0.22, 0.28)])
    hold = _pitch("right", down, toward=meet)
    level = _pitch("left", np.deg2rad(u(-5, 5)), roll=np.pi / 2, toward=meet)
    depth = u(0.010, 0.016)  # the left tool point, short of the cube's middle
    away = -0.08 * _matrix(hold)[:, 0] + [0.0, 0.0, 0.02]
    l0 = _key(start[0, :3], start[0, 3:], 1.0)
    r0 = _key(start[1, :3], start[1, 3:], 1.0)
    # the cube's centre as planned at the meeting point (the grasp's offset)
    planned = meet - (grasp - cube)

    def take_where_it_is(scene, keys):
        cube_now = scene.objects()[0]
        take = cube_now - [depth, 0.0, 0.0]
        keys[7, 0] = _key(take, level, 1.0)
        keys[8, 0] = _key(take, level, 0.0)
        keys[9, 0] = keys[8, 0]
        keys[10, 0] = _key(take - [0.03, 0.0, 0.0], level, 0.0)

    ready = planned - [depth + 0.10, 0.0, 0.0]
    phases = [
        (0.0, l0, r0),
        (1.0, None, _key(above, pick, 1.0)),
        (0.3, None, None),
        (0.6, None, _key(grasp, pick, 1.0)),
        (0.4, None, _key(grasp, pick, 0.0)),
        (1.2, _key(ready, level, 1.0), _key(meet, hold, 0.0)),
        (0.3, None, None),
        (0.6, None, None),  # the left hand to the cube (planned on the way)
        (0.4, None, None),  # the left hand closes
        (0.3, None, _key(meet, hold, 1.0)),
        (0.8, None, _key(meet + away, hold, 1.0)),
    ]
    return [(6, take_where_it_is)], phases


def _held_axis(pose: np.ndarray) -> np.ndarray:
    """A held object's long axis (its x), pointing to +x in the world."""
    a = _matrix(pose[3:])[:, 0]
    return a if a[0] >= 0 else -a


def _peg_onto_socket(depth: float):
    """A replanning step: the right hand moving the peg onto the socket's axis.

    The peg's centre goes to ``depth`` along the socket's axis from the
    socket's centre, the peg's axis turned onto the socket's by the smallest
    rotation, carried with the hand as it holds the peg now.
    """

    def hand_target(scene):
        peg, socket = scene.object_poses()
        axis = _held_axis(socket)
        turn = _align(_held_axis(peg), axis)
        hand = scene.hands()[1]
        goal = socket[:3] + depth * axis
        point = goal + turn @ (hand[:3] - peg[:3])
        return point, _quat(turn @ _matrix(hand[3:]))

    return hand_target


def _insertion(objects: np.ndarray, start, rng: np.random.Generator):
    peg, socket = objects[0].copy(), objects[1].copy()
    peg[2], socket[2] = _REST_Z["peg"], _REST_Z["socket"]
    u = rng.uniform
    # near the middles: held off-centre they pivot in the fingers (the pads'
    # torsional friction, 0.005, holds little against gravity's torque)
    peg_at = u(0.0, 0.012)  # how far from the peg's centre, toward +x
    sock_at = u(0.0, 0.012)  # how far from the socket's centre, toward -x
    rdown, ldown = np.deg2rad(u(40, 55)), np.deg2rad(u(40, 55))
    # the finger tips (3 cm past the tool point) 4-7 mm over the table
    rgrasp = peg + [peg_at, u(-0.002, 0.002), _tips_clear(rdown, peg[2], u)]
    lgrasp = socket + [-sock_at, u(-0.002, 0.002), _tips_clear(ldown, socket[2], u)]
    rpick = _pitch("right", rdown, toward=peg)
    lpick = _pitch("left", ldown, toward=socket)
    up_l, up_r = [0.0, 0.0, u(0.05, 0.10)], [0.0, 0.0, u(0.05, 0.10)]
    # on the line between the bases: both hands there head along it
    meet = np.array([u(-0.03, 0.03), 0.5 + u(-0.005, 0.005), u(0.2, 0.26)])
    sock_c = meet + [-0.08, 0.0, 0.0]
    rhold = _pitch("right", rdown, toward=meet)
    lhold = _pitch("left", ldown, toward=meet)
    lift_l = sock_c + (lgrasp - socket)
    ready = 2 * _PEG_HALF + 0.025  # the peg's end 2.5 cm outside the mouth
    lift_r = sock_c + [ready, 0.0, 0.0] + (rgrasp - peg)
    push = _PIN_END + _PEG_HALF - u(0.008, 0.012)  # against the pin, pressed
    l0 = _key(start[0, :3], start[0, 3:], 1.0)
    r0 = _key(start[1, :3], start[1, 3:], 1.0)
    align, press = _peg_onto_socket(ready), _peg_onto_socket(push)

    def aim(scene, keys):
        point, quat = align(scene)
        keys[7:, 1] = _key(point, quat, 0.0)

    def aim_again(scene, keys):
        point, quat = align(scene)
        keys[9, 1] = _key(point, quat, 0.0)
        point, quat = press(scene)
        keys[10:, 1] = _key(point, quat, 0.0)

    phases = [
        (0.0, l0, r0),
        (1.1, _key(lgrasp + up_l, lpick, 1.0), _key(rgrasp + up_r, rpick, 1.0)),
        (0.3, None, None),
        (0.6, _key(lgrasp, lpick, 1.0), _key(rgrasp, rpick, 1.0)),
        (0.4, _key(lgrasp, lpick, 0.0), _key(rgrasp, rpick, 0.0)),
        (1.2, _key(lift_l, lhold, 0.0), _key(lift_r, rhold, 0.0)),
        (0.3, None, None),
        (0.8, None, None),  # the peg onto the socket's axis (planned then)
        (0.3, None, None),
        (0.3, None, None),  # looked again: corrected
        (1.0, None, None),  # pushed in
        (0.4, None, None),
    ]
    return [(6, aim), (8, aim_again)], phases


_EXPERTS = {"transfer-cube": _transfer_cube, "insertion": _insertion}
#: The hands' tool points and gripper-link orientations after a reset of the
#: joint-position scene (:meth:`~ndlfd.sim._scene.Scene.hands`), left then
#: right.
START_HANDS = np.array(
    [
        [-0.18784, 0.5, 0.30823, 0.99875, 0.0, -0.04998, 0.0],
        [0.18784, 0.5, 0.30823, 0.0, 0.04998, 0.0, 0.99875],
    ]
)


def expert_episode(
    task: str, objects, rng: np.random.Generator, start=None
) -> ExpertPlan:
    """The expert's plan for objects at ``objects``, varied by ``rng``.

    Parameters
    ----------
    task : {"transfer-cube", "insertion"}
    objects : array-like of shape (n_objects, 3)
        Where the objects are (:func:`~ndlfd.sim._scene.sample_objects`).
    rng : numpy.random.Generator
    start : array-like of shape (2, 7), optional
        The hands' tool points and orientations at the start
        (:meth:`~ndlfd.sim._scene.Scene.hands` after a reset; by default the
        joint scene's, :data:`START_HANDS`).

    Returns
    -------
    plan : ExpertPlan
        Sample it with :func:`render_plan`, run it with :func:`record_expert`.

    Examples
    --------
    >>> plan = expert_episode(
    ...     "transfer-cube", [[0.1, 0.5, 0.05]], np.random.default_rng(0)
    ... )
    >>> plan.keys.shape, bool(0.8 * 5.9 <= plan.durations.sum() <= 1.2 * 5.9)
    ((11, 2, 8), True)
    """
    start = START_HANDS if start is None else np.asarray(start, dtype=float)
    objects = np.asarray(objects, dtype=float).reshape(-1, 3)
    replan, phases = _EXPERTS[task](objects, start, rng)
    keys = np.empty((len(phases), 2, 8))
    for k, (_, left, right) in enumerate(phases):
        for h, key in enumerate((left, right)):
            keys[k, h] = keys[k - 1, h] if key is None else key
    nominal = np.array([d for d, *_ in phases[1:]])
    durations = nominal * rng.uniform(0.8, 1.2, size=nominal.size)
    return ExpertPlan(durations, keys, _tremor(rng), replan)


def _slerp(a: np.ndarray, b: np.ndarray, s: np.ndarray) -> np.ndarray:
    if a @ b < 0:
        b = -b
    cos = np.clip(a @ b, -1.0, 1.0)
    angle = np.arccos(cos)
    if angle < 1e-9:
        return np.repeat(a[None], s.size, axis=0)
    wa = np.sin((1 - s) * angle) / np.sin(angle)
    wb = np.sin(s * angle) / np.sin(angle)
    return wa[:, None] * a + wb[:, None] * b


def render_plan(plan: ExpertPlan) -> tuple[np.ndarray, np.ndarray]:
    """The plan sampled at 50 Hz: time stamps and both hands' rows.

    Parameters
    ----------
    plan : ExpertPlan

    Returns
    -------
    t : ndarray of shape (n,)
        ``0, 0.02, ...`` up to the plan's end.
    hands : ndarray of shape (n, 16)
        Left then right, :data:`~ndlfd.sim._scene.HAND_COLUMNS` each.

    Examples
    --------
    >>> plan = expert_episode("insertion", [[0.15, 0.5, 0.05], [-0.15, 0.5, 0.05]],
    ...                       np.random.default_rng(1))
    >>> t, hands = render_plan(plan)
    >>> hands.shape[1], bool(np.allclose(np.diff(t), 0.02))
    (16, True)
    """
    ends = np.concatenate([[0.0], np.cumsum(plan.durations)])
    t = np.arange(int(np.floor(ends[-1] / CONTROL_DT)) + 1) * CONTROL_DT
    phase = np.clip(
        np.searchsorted(ends, t, side="right") - 1, 0, len(plan.durations) - 1
    )
    out = np.empty((t.size, 16))
    for k in range(len(plan.durations)):
        rows = np.flatnonzero(phase == k)
        tau = np.clip((t[rows] - ends[k]) / plan.durations[k], 0.0, 1.0)
        s = tau**3 * (10 - 15 * tau + 6 * tau**2)
        for h in range(2):
            a, b = plan.keys[k, h], plan.keys[k + 1, h]
            block = out[rows, 8 * h : 8 * h + 8]
            block[:, :3] = a[:3] + s[:, None] * (b[:3] - a[:3])
            block[:, 3:7] = _slerp(a[3:7], b[3:7], s)
            block[:, 7] = a[7] + s * (b[7] - a[7])
            out[rows, 8 * h : 8 * h + 8] = block
    for h in range(2):  # one sign along the path (slerp may pick either)
        q = out[:, 8 * h + 3 : 8 * h + 7]
        flip = np.cumprod(np.where(np.sum(q[1:] * q[:-1], axis=1) < 0, -1.0, 1.0))
        q[1:] *= flip[:, None]
    amp, freq, phase0 = np.moveaxis(plan.tremor, -1, 0)
    wave = amp * np.sin(2 * np.pi * freq * t[:, None, None, None] + phase0)
    ramp = np.minimum(1.0, t / 0.5)[:, None, None]  # still at the start pose
    tremor = wave.sum(axis=-1) * ramp
    out[:, 0:3] += tremor[:, 0]
    out[:, 8:11] += tremor[:, 1]
    return t, out


@dataclass
class Recording:
    """One expert episode as it ran, at 50 Hz.

    Attributes
    ----------
    t : ndarray of shape (n,)
    objects : ndarray of shape (n_objects, 3)
        Where the objects were placed.
    ee_action : ndarray of shape (n, 16)
        The hands' poses asked for: per hand the tool point, the gripper
        link's orientation (w, x, y, z) and the gripper (0 closed, 1 open),
        :data:`~ndlfd.sim._scene.HAND_COLUMNS`.
    joint_action : ndarray of shape (n, 14)
        The joint positions commanded (per arm the 6 joints from inverse
        kinematics and the gripper command): what the robot was told to do,
        replayed exactly by the joint-position scene.
    state : ndarray of shape (n, 14)
        The joint readings (grippers as measured).
    hands : ndarray of shape (n, 2, 7)
        Each hand's tool point and orientation reached.
    reward : ndarray of shape (n,), dtype int
    """

    t: np.ndarray
    objects: np.ndarray
    ee_action: np.ndarray
    joint_action: np.ndarray
    state: np.ndarray
    hands: np.ndarray
    reward: np.ndarray

    @property
    def success(self) -> bool:
        """Whether the task's reward reached its maximum."""
        return bool(self.reward.max() >= 4)


#: The wrist rolls' largest move per step: the ViperX's velocity limit
#: (:data:`~ndlfd.sim._scene.VIPERX_LIMITS`) times the control period.
_ROLL_STEP = np.pi * CONTROL_DT


def _ik_for(scene) -> ArmIK:
    ik = getattr(scene, "_ndlfd_ik", None)
    if ik is None:
        ik = ArmIK(scene.physics)
        scene._ndlfd_ik = ik
    return ik


def _joints_for(ik: ArmIK, row: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The joint action (14,) for one row of hand poses (16,), from joints q."""
    out = np.empty(14)
    for h, side in enumerate(("left", "right")):
        r = row[8 * h : 8 * h + 8]
        out[7 * h : 7 * h + 6], _ = ik.solve(
            side, r[:3], r[3:7], q[7 * h : 7 * h + 6], roll_step=_ROLL_STEP
        )
        out[7 * h + 6] = r[7]
    return out


def run_hands(scene, hands, objects) -> tuple[np.ndarray, np.ndarray]:
    """Run rows of hand poses in the joint scene through inverse kinematics.

    The tasks' end-effector control as this package runs it: each row's two
    hand poses are turned into joint positions (:class:`~ndlfd.sim._ik.ArmIK`,
    warm-started from the row before) and commanded.

    Parameters
    ----------
    scene : Scene
        A joint-position scene (``Scene(task, "joint")``).
    hands : array-like of shape (n, 16)
        Per row and hand the tool point, gripper-link orientation (w, x, y, z;
        made unit here) and gripper, :data:`~ndlfd.sim._scene.HAND_COLUMNS`.
    objects : array-like of shape (n_objects, 3)

    Returns
    -------
    joints : ndarray of shape (n, 14)
        The joint actions commanded.
    reward : ndarray of shape (n,), dtype int
    """
    hands = np.asarray(hands, dtype=float)
    scene.reset(objects)
    ik = _ik_for(scene)
    q = scene.qpos()
    joints = np.empty((len(hands), 14))
    reward = np.empty(len(hands), dtype=np.int64)
    for k, row in enumerate(hands):
        q = joints[k] = _joints_for(ik, row, q)
        reward[k] = scene.step(q)
    return joints, reward


def record_expert(scene, plan: ExpertPlan, objects, *, settle: float = 0.5):
    """Run an expert's plan in the joint scene through inverse kinematics.

    Every step each hand's pose in the plan becomes the arm's joints
    (:class:`~ndlfd.sim._ik.ArmIK`, from the last step's), which are
    commanded with the gripper. As a replanning phase begins
    (:attr:`ExpertPlan.replan`) the expert looks at the scene and rewrites
    the keys still ahead; the rest of the plan is sampled again from there
    (the keys behind are unchanged, so the path stays smooth).

    Parameters
    ----------
    scene : Scene
        A joint-position scene (``Scene(task, "joint")``).
    plan : ExpertPlan
        Its keys are rewritten by the replanning steps (a copy is not made).
    objects : array-like of shape (n_objects, 3)
    settle : float, default=0.5
        Seconds the last pose is held after the plan.

    Returns
    -------
    recording : Recording
    """
    objects = np.asarray(objects, dtype=float).reshape(-1, 3)
    scene.reset(objects)
    ik = _ik_for(scene)
    n_hold = round(settle / CONTROL_DT)

    def sampled():
        _, rows = render_plan(plan)
        return np.concatenate([rows, np.repeat(rows[-1:], n_hold, axis=0)])

    target = sampled()
    n = len(target)
    ends = np.concatenate([[0.0], np.cumsum(plan.durations)])
    looks = {round(ends[k] / CONTROL_DT): f for k, f in plan.replan}
    joints = np.empty((n, 14))
    state = np.empty((n, 14))
    hands = np.empty((n, 2, 7))
    reward = np.empty(n, dtype=np.int64)
    q = scene.qpos()
    for k in range(n):
        if k in looks:
            looks[k](scene, plan.keys)
            target[k:] = sampled()[k:]
        q = joints[k] = _joints_for(ik, target[k], q)
        reward[k] = scene.step(q)
        hands[k] = scene.hands()
        state[k] = scene.qpos()
    t = np.arange(n) * CONTROL_DT
    return Recording(t, objects, target, joints, state, hands, reward)
