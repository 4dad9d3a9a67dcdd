"""
From a LeRobot dataset to a ROS 2 controller
============================================

A LeRobot dataset of an SO-101 arm (joints in degrees, a gripper 0-100),
learned, generated from where the arm is now within its joint limits, and
written as one ``trajectory_msgs/msg/JointTrajectory`` in radians for a
``joint_trajectory_controller``. The dataset is written here with pyarrow as
LeRobot lays out its 2.1 format (``meta/info.json``, one Parquet file per
episode), so the example needs no download; :func:`ndlfd.io.read_lerobot`
reads a real one the same way (``pip install "ndlfd[lerobot]"``: pyarrow, not
the ``lerobot`` package).
"""

import json
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

import ndlfd
from ndlfd.plot import plot_channels

# %%
# A small SO-101 dataset
# ----------------------
# Six pick episodes at 30 Hz: pan out and back, lift, the gripper closing
# (5) between 40 % and 80 % of the motion.
MOTORS = [
    "shoulder_pan",
    "shoulder_lift",
    "elbow_flex",
    "wrist_flex",
    "wrist_roll",
    "gripper",
]
NAMES = [f"{m}.pos" for m in MOTORS]
FPS = 30
rng = np.random.default_rng(0)
root = Path(tempfile.mkdtemp()) / "so101_pick"
(root / "meta").mkdir(parents=True)
episodes = []
for e in range(6):
    s = np.linspace(0.0, 1.0, 90 + 6 * e)
    state = np.column_stack(
        [
            40 * np.sin(np.pi * s),
            -60 + 50 * s,
            80 * s**2,
            10 * np.cos(2 * np.pi * s),
            5 * s,
            np.where((s > 0.4) & (s < 0.8), 5.0, 40.0),
        ]
    )
    state[:, :5] += rng.normal(0.0, 0.3, (s.size, 5))
    episodes.append(state.astype(np.float32))

start = 0
for e, state in enumerate(episodes):
    n = len(state)
    flat = pa.array(state.ravel())
    table = pa.table(
        {
            "observation.state": pa.FixedSizeListArray.from_arrays(flat, 6),
            "timestamp": pa.array((np.arange(n) / FPS).astype(np.float32)),
            "frame_index": pa.array(np.arange(n)),
            "episode_index": pa.array(np.full(n, e)),
            "index": pa.array(np.arange(start, start + n)),
            "task_index": pa.array(np.zeros(n, dtype=np.int64)),
        }
    )
    path = root / f"data/chunk-000/episode_{e:06d}.parquet"
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)
    start += n
scalar = {"dtype": "int64", "shape": [1], "names": None}
info = {
    "codebase_version": "v2.1",
    "robot_type": "so101_follower",
    "fps": FPS,
    "total_episodes": len(episodes),
    "total_frames": start,
    "chunks_size": 1000,
    "data_path": "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet",
    "features": {
        "observation.state": {"dtype": "float32", "shape": [6], "names": NAMES},
        "timestamp": {"dtype": "float32", "shape": [1], "names": None},
        **{k: scalar for k in ("frame_index", "episode_index", "index", "task_index")},
    },
}
(root / "meta" / "info.json").write_text(json.dumps(info))
with open(root / "meta" / "episodes.jsonl", "w") as f:
    for e, state in enumerate(episodes):
        f.write(
            json.dumps({"episode_index": e, "tasks": ["pick"], "length": len(state)})
            + "\n"
        )

# %%
# Read, fit, generate within limits
# ---------------------------------
# ``NAME.pos`` columns are the group ``joints``, ``gripper.pos`` the group
# ``gripper``. The path starts where the arm is, lasts 4 s at 100 Hz and is
# slowed to 30 deg/s and 200 deg/s² per joint where it would be faster.
demos = ndlfd.io.read_lerobot(root)
print(demos[0])
model = ndlfd.KeypointHMM().fit(demos)
t = np.arange(0.0, 4.0, 0.01)
here = {"joints": [3.0, -57.0, 2.0, 12.0, 1.0]}
limits = {"joints": {"velocity": 30.0, "acceleration": 200.0}}
path = model.generate(t, dense=True, start=here, limits=limits)
joint_velocity = np.gradient(path.get("joints"), path.t, axis=0)
print(
    f"{path.duration:.2f} s after the limits; peak joint velocity "
    f"{np.abs(joint_velocity).max():.1f} deg/s"
)

# %%
# The JointTrajectory
# -------------------
# Radians (``units="deg"`` says what the dataset recorded), the URDF's joint
# names (the gripper last), at rest at both ends. A name ending in ``.yaml``
# writes the message as YAML; a bag folder or ``.mcap`` writes a ROS 2 bag
# for ``ros2 bag play`` (``pip install "ndlfd[ros]"``).
out = ndlfd.io.write_joint_trajectory(
    path, root.parent / "traj.yaml", units="deg", joint_names=MOTORS
)
lines = out.read_text().splitlines()
print("\n".join(line[:110] for line in lines[:4]), f"\n... {len(lines) - 3} points")

# %%
# The demonstrations and the generated path, joint by joint
# ---------------------------------------------------------
fig = plt.figure(figsize=(8, 6))
plot_channels(demos, generated=path, fig=fig, title="SO-101 pick: joints (deg)")
