"""Scripted experts for Transfer Cube and Insertion, varied as people vary.

Each expert is a sequence of *phases* shared by the two hands (reach, descend,
close, carry, ...), each ending at a key pose per hand: a tool point
(:func:`~ndlfd.sim._scene.tool_point`), an orientation and a gripper opening.
Between keys a hand moves by a minimum-jerk blend (positions and gripper) and
a spherical interpolation (orientation), sampled at 50 Hz, and runs in the
end-effector scene. The keys come from the tasks' geometry:

* **Transfer Cube.** The right hand comes down over the cube pitched steeply
  (40-55 degrees below horizontal, fingers closing on the cube's y faces),
  closes, lifts the cube to a meeting point above the middle of the table
  turning to 10-25 degrees below horizontal; the left hand comes in level from
  the other side rolled a quarter turn (its fingers close on the cube's top and
  bottom faces, clear of the right hand's), closes, and the right hand opens
  and leaves.
* **Insertion.** The right hand takes the peg near its outer (+x) end, the left
  the socket near its outer (-x) end, both from above; both lift to the
  meeting height, the peg's axis in line with the socket's, and the right hand
  pushes the peg into the socket until it meets the pin.

Human-like variation (:func:`expert_episode`, from a ``numpy.random.Generator``):
every phase's duration times a factor in [0.8, 1.2]; approach heights 5-10
cm; grasp points +-6 mm along the object and +-4 mm in height; the pitch at the
grasp and at the handover; the meeting point +-3 cm; and a smooth tremor
(three sines of 0.3-1.5 Hz, 1.5 mm in all) on every position.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._scene import CONTROL_DT, TOOL_DEPTH

__all__ = [
    "START_HANDS",
    "ExpertPlan",
    "Recording",
    "expert_episode",
    "quat_about",
    "record_expert",
    "render_plan",
]

# Where objects rest on the table (their centres' height), once settled.
_REST_Z = {"cube": 0.02, "peg": 0.01, "socket": 0.022}


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


def _pitch(side: str, below: float, roll: float = 0.0) -> np.ndarray:
    """A gripper pointing ``below`` radians under horizontal, rolled ``roll``.

    The left arm points along +x, the right along -x (its base turned half a
    turn about z); the fingers close along the gripper's y axis.
    """
    q = _mul(quat_about("y", below), quat_about("x", roll))
    return q if side == "left" else _mul(quat_about("z", np.pi), q)


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
    follow : list of (int, int, list of (int, ndarray, float))
        Where the expert watches an object: from phase ``k`` on, hand ``h``'s
        targets move by the sum of ``sign * (where object j is - where the
        plan expected it)``, measured as phase ``k`` begins (the left hand
        takes the cube where the right hand holds it, not where it should).
    """

    durations: np.ndarray
    keys: np.ndarray
    tremor: np.ndarray
    follow: list


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


def _transfer_cube(objects: np.ndarray, start, rng: np.random.Generator) -> list:
    cube = objects[0].copy()
    cube[2] = _REST_Z["cube"]
    u = rng.uniform
    grasp = cube + [u(-0.006, 0.006), u(-0.004, 0.004), u(-0.004, 0.004)]
    above = grasp + [0.0, 0.0, u(0.05, 0.10)]
    pick = _pitch("right", np.deg2rad(u(40, 55)))
    meet = np.array([u(-0.03, 0.03), 0.5 + u(-0.03, 0.03), u(0.22, 0.28)])
    hold = _pitch("right", np.deg2rad(u(10, 25)))
    level = _pitch("left", np.deg2rad(u(-5, 5)), roll=np.pi / 2)
    take = meet + [-u(0.012, 0.02), 0.0, 0.0]
    l0, r0 = (
        _key(start[0, :3], start[0, 3:], 1.0),
        _key(start[1, :3], start[1, 3:], 1.0),
    )
    lready = _key(take - [0.10, 0.0, 0.0], level, 1.0)
    # (nominal seconds, left key, right key) per phase; None keeps the last
    follow = [(6, 0, [(0, meet, 1.0)])]  # the left hand: where the cube is
    return follow, [
        (0.0, l0, r0),
        (1.0, None, _key(above, pick, 1.0)),
        (0.3, None, None),
        (0.6, None, _key(grasp, pick, 1.0)),
        (0.4, None, _key(grasp, pick, 0.0)),
        (1.2, lready, _key(meet, hold, 0.0)),
        (0.3, None, None),
        (0.6, _key(take, level, 1.0), None),
        (0.4, _key(take, level, 0.0), None),
        (0.3, None, _key(meet, hold, 1.0)),
        (
            0.8,
            _key(take - [0.03, 0, 0], level, 0.0),
            _key(meet + [0.1, 0, 0.05], hold, 1),
        ),
    ]


def _insertion(objects: np.ndarray, start, rng: np.random.Generator) -> list:
    peg, socket = objects[0].copy(), objects[1].copy()
    peg[2], socket[2] = _REST_Z["peg"], _REST_Z["socket"]
    u = rng.uniform
    peg_at = u(0.02, 0.035)  # how far from the peg's centre, toward +x
    sock_at = u(0.02, 0.035)  # how far from the socket's centre, toward -x
    rgrasp = peg + [peg_at, u(-0.003, 0.003), u(-0.003, 0.003)]
    lgrasp = socket + [-sock_at, u(-0.003, 0.003), 0.02 + u(-0.003, 0.003)]
    rpick = _pitch("right", np.deg2rad(u(40, 55)))
    lpick = _pitch("left", np.deg2rad(u(40, 55)))
    height = u(0.06, 0.10)
    meet = np.array([u(-0.03, 0.03), 0.5 + u(-0.03, 0.03), u(0.2, 0.26)])
    # held objects' centres where the peg's end faces the socket's mouth
    sock_c = meet + [-0.08, 0.0, 0.0]
    lift_l = sock_c + [-sock_at, 0.0, lgrasp[2] - socket[2]]
    peg_ready = sock_c + [0.06 + 0.04 + 0.06 + 0.03, 0.0, 0.0]
    peg_in = sock_c + [0.06 + 0.04 - 0.012, 0.0, 0.0]
    lift_r = peg_ready + [peg_at, 0.0, rgrasp[2] - peg[2]]
    push_r = peg_in + [peg_at, 0.0, rgrasp[2] - peg[2]]
    l0 = _key(start[0, :3], start[0, 3:], 1.0)
    r0 = _key(start[1, :3], start[1, 3:], 1.0)
    up = [0.0, 0.0, height]
    # the right hand pushes the peg to where the socket is, from where it is
    follow = [(6, 1, [(1, sock_c, 1.0), (0, peg_ready, -1.0)])]
    return follow, [
        (0.0, l0, r0),
        (1.1, _key(lgrasp + up, lpick, 1.0), _key(rgrasp + up, rpick, 1.0)),
        (0.3, None, None),
        (0.6, _key(lgrasp, lpick, 1.0), _key(rgrasp, rpick, 1.0)),
        (0.4, _key(lgrasp, lpick, 0.0), _key(rgrasp, rpick, 0.0)),
        (1.2, _key(lift_l, lpick, 0.0), _key(lift_r, rpick, 0.0)),
        (0.3, None, None),
        (1.0, None, _key(push_r, rpick, 0.0)),
        (0.5, None, None),
    ]


_EXPERTS = {"transfer-cube": _transfer_cube, "insertion": _insertion}
#: The hands' tool points and orientations after a reset of the end-effector
#: scene (:meth:`~ndlfd.sim._scene.Scene.hands`), left then right.
START_HANDS = np.array(
    [
        [-0.18795, 0.5, 0.30848, 0.99875, 0.0, -0.04998, 0.0],
        [0.18795, 0.5, 0.30848, 0.0, 0.04998, 0.0, 0.99875],
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
        end-effector scene's, :data:`START_HANDS`).

    Returns
    -------
    plan : ExpertPlan
        Sample it with :func:`render_plan`.

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
    follow, phases = _EXPERTS[task](objects, start, rng)
    keys = np.empty((len(phases), 2, 8))
    for k, (_, left, right) in enumerate(phases):
        for h, key in enumerate((left, right)):
            keys[k, h] = keys[k - 1, h] if key is None else key
    nominal = np.array([d for d, *_ in phases[1:]])
    durations = nominal * rng.uniform(0.8, 1.2, size=nominal.size)
    return ExpertPlan(durations, keys, _tremor(rng), follow)


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
    amp, freq, phase0 = np.moveaxis(plan.tremor, -1, 0)
    wave = amp * np.sin(2 * np.pi * freq * t[:, None, None, None] + phase0)
    ramp = np.minimum(1.0, t / 0.5)[:, None, None]  # still at the start pose
    tremor = wave.sum(axis=-1) * ramp
    out[:, 0:3] += tremor[:, 0]
    out[:, 8:11] += tremor[:, 1]
    return t, out


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


def _small_turn(q: np.ndarray, gain: float) -> np.ndarray:
    """``gain`` times the turn of quaternion ``q`` (its rotation vector scaled)."""
    q = q if q[0] >= 0 else -q
    angle = 2 * np.arccos(np.clip(q[0], -1.0, 1.0))
    if angle < 1e-12:
        return np.array([1.0, 0.0, 0.0, 0.0])
    axis = q[1:] / np.linalg.norm(q[1:])
    half = gain * angle / 2
    return np.concatenate([[np.cos(half)], np.sin(half) * axis])


@dataclass
class Recording:
    """One expert episode as it ran, at 50 Hz.

    Attributes
    ----------
    t : ndarray of shape (n,)
    objects : ndarray of shape (n_objects, 3)
        Where the objects were placed.
    ee_action : ndarray of shape (n, 16)
        The end-effector commands sent (per hand the mocap pose and gripper).
    joint_action : ndarray of shape (n, 14)
        The same motion as joint positions: per arm the 6 joints reached
        after each step and the gripper command (0 closed, 1 open).
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


#: How much of the tool point's error the expert corrects per step (an
#: integral correction of its command, as a person steers their hand).
CORRECTION = 0.1
_MAX_BIAS = 0.15  # metres


def record_expert(scene, plan: ExpertPlan, objects, *, settle: float = 0.5):
    """Run an expert's plan in the end-effector scene, steering as it goes.

    The plan gives where each hand's tool point and gripper should be; the
    mocap command that would put them there (through the weld's relative
    pose) is corrected by :data:`CORRECTION` times the remaining error on
    each step where the hand pauses (the plan's hover phases) with its
    gripper open: an integral term, capped at 15 cm, left alone while the
    hand moves (a lag, not an offset) or holds something (it would push into
    it). The weld is soft and the arms' joint friction large, so a welded
    gripper rests centimetres and degrees from its mocap body. Where the plan
    says so (:attr:`ExpertPlan.follow`) the expert looks at an object and
    moves a hand's remaining targets by how far it is from where the plan
    expected it. The commands sent are recorded: they are the demonstration
    in end-effector space; the joints reached are the one in joint space.

    Parameters
    ----------
    scene : Scene
        An end-effector scene (``Scene(task, "ee")``).
    plan : ExpertPlan
    objects : array-like of shape (n_objects, 3)
    settle : float, default=0.5
        Seconds the last command is held after the plan.

    Returns
    -------
    recording : Recording
    """
    objects = np.asarray(objects, dtype=float).reshape(-1, 3)
    scene.reset(objects)
    t, target = render_plan(plan)
    n_hold = round(settle / CONTROL_DT)
    target = np.concatenate([target, np.repeat(target[-1:], n_hold, axis=0)])
    t = np.arange(len(target)) * CONTROL_DT
    speed = np.linalg.norm(np.diff(target[:, [[0, 1, 2], [8, 9, 10]]], axis=0), axis=2)
    still = np.concatenate([speed, speed[-1:]]) < 0.2 * CONTROL_DT
    rel = scene.weld()
    bias_p = np.zeros((2, 3))
    bias_q = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    n = len(target)
    ee = np.empty((n, 16))
    state = np.empty((n, 14))
    hands = np.empty((n, 2, 7))
    reward = np.empty(n, dtype=np.int64)
    ends = np.concatenate([[0.0], np.cumsum(plan.durations)])
    starts = {round(ends[k] / CONTROL_DT): (k, h, rule) for k, h, rule in plan.follow}
    for k in range(n):
        if k in starts:
            _, h, rule = starts[k]
            now = scene.objects()
            shift = sum(sign * (now[j] - at) for j, at, sign in rule)
            target[k:, 8 * h : 8 * h + 3] += shift
        row = np.empty(16)
        for h in range(2):
            tcp, qg, grip = (
                target[k, 8 * h : 8 * h + 3],
                target[k, 8 * h + 3 : 8 * h + 7],
                target[k, 8 * h + 7],
            )
            qg = qg / np.linalg.norm(qg)
            qm = _mul(qg, _conj(rel[h, 3:]))
            link = tcp - TOOL_DEPTH * _matrix(qg)[:, 0]
            pm = link - _matrix(qm) @ rel[h, :3]
            row[8 * h : 8 * h + 3] = pm + bias_p[h]
            row[8 * h + 3 : 8 * h + 7] = _mul(bias_q[h], qm)
            row[8 * h + 7] = grip
        ee[k] = row
        reward[k] = scene.step(row)
        hands[k] = scene.hands()
        state[k] = scene.qpos()
        for h in range(2):
            if target[k, 8 * h + 7] < 0.999 or not still[k, h]:
                continue  # moving (a lag, not an offset), holding or closing
            err = target[k, 8 * h : 8 * h + 3] - hands[k, h, :3]
            bias_p[h] = np.clip(bias_p[h] + CORRECTION * err, -_MAX_BIAS, _MAX_BIAS)
            qg = target[k, 8 * h + 3 : 8 * h + 7]
            turn = _mul(qg / np.linalg.norm(qg), _conj(hands[k, h, 3:]))
            bias_q[h] = _mul(_small_turn(turn, CORRECTION), bias_q[h])
    joint = state.copy()
    joint[:, 6] = ee[:, 7]
    joint[:, 13] = ee[:, 15]
    return Recording(t, objects, ee, joint, state, hands, reward)
