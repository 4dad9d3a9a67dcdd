"""Logs written the way robot labs export them (issue 37), for io and CLI tests.

A Franka task log: 27 columns at full float precision, no time column, 20 Hz:
``current_pos_x..z``, ``current_orientation_w..z`` (unit quaternions),
``goal_pos_x..z``, ``goal_orientation_w..z``, ``force_x..z``, ``torque_x..z``,
``joint_1..7``. A UR
kinesthetic log: ``t, x, y, z, rx, ry, rz`` with the orientation as scipy's
``Rotation.as_rotvec`` (axis-angle), tool pointing down (angles near pi).
"""

import numpy as np
from scipy.spatial.transform import Rotation

FRANKA_COLUMNS = (
    [f"current_pos_{a}" for a in "xyz"]
    + [f"current_orientation_{a}" for a in "wxyz"]
    + [f"goal_pos_{a}" for a in "xyz"]
    + [f"goal_orientation_{a}" for a in "wxyz"]
    + [f"force_{a}" for a in "xyz"]
    + [f"torque_{a}" for a in "xyz"]
    + [f"joint_{k}" for k in range(1, 8)]
)
RATE = 20.0


def franka_arrays(n=60, seed=0, norm_off=0.0):
    """The 27 columns of one task: position, quaternions, goal, wrench, joints.

    ``norm_off`` scales the quaternions by ``1 + norm_off`` (a logger's float32
    arithmetic leaves them off by a few 1e-6).
    """
    rng = np.random.default_rng(seed)
    s = np.linspace(0.0, 1.0, n)
    pos = np.column_stack([0.4 + 0.2 * s, 0.1 * np.sin(np.pi * s), 0.3 - 0.1 * s**2])
    pos += rng.normal(0.0, 1e-3, pos.shape)
    rot = Rotation.from_rotvec(
        np.column_stack([np.pi - 0.2 * s, 0.1 * s, 0.3 * s + 0.05 * seed])
    )
    q = rot.as_quat(scalar_first=True) * (1.0 + norm_off)
    goal = np.tile(np.r_[pos[-1] + [0.0, 0.0, 0.01], q[-1]], (n, 1))
    force = rng.normal(0.0, 0.5, (n, 3)) + [0.0, 0.0, -5.0 * s[-1]]
    torque = rng.normal(0.0, 0.05, (n, 3))
    joints = np.cumsum(rng.normal(0.0, 0.01, (n, 7)), axis=0) + np.linspace(-1, 1, 7)
    return np.column_stack([pos, q, goal, force, torque, joints])


def write_franka(folder, n_demos=4, n=60, norm_off=0.0):
    """A folder of Franka task logs without time (CSV, full precision)."""
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for i in range(n_demos):
        data = franka_arrays(n + 5 * i, seed=i, norm_off=norm_off)
        rows = [",".join(FRANKA_COLUMNS)]
        rows += [",".join(repr(float(v)) for v in row) for row in data]
        (folder / f"task{i}.csv").write_text("\n".join(rows) + "\n")
        out.append(data)
    return out


def ur_arrays(n=50, seed=0):
    """Time, position and rotation vectors of a UR reach (tool down, near pi)."""
    rng = np.random.default_rng(seed)
    s = np.linspace(0.0, 1.0, n)
    t = np.arange(n) / 125.0
    pos = np.column_stack([0.3 + 0.2 * s, -0.1 + 0.05 * s, 0.4 - 0.2 * s])
    pos += rng.normal(0.0, 1e-4, pos.shape)
    # about x by nearly pi, turning about z: scipy's rotvec flips its sign
    # where the angle passes pi, as UR's logs do
    rot = Rotation.from_euler(
        "zx", np.column_stack([0.6 * s + 0.1 * seed, 0 * s + 3.1])
    )
    return t, pos, rot.as_rotvec()


def write_ur(folder, n_demos=3, n=50):
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for i in range(n_demos):
        t, pos, rv = ur_arrays(n + 4 * i, seed=i)
        rows = ["t,x,y,z,rx,ry,rz"]
        rows += [",".join(repr(float(v)) for v in row)
                 for row in np.column_stack([t, pos, rv])]  # fmt: skip
        (folder / f"reach{i}.csv").write_text("\n".join(rows) + "\n")
        out.append((t, pos, rv))
    return out
