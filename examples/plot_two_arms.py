"""
Two arms: ALOHA Transfer Cube
=============================

ALOHA's two ViperX arms pass a cube: the right hand picks it from the table
and lifts it to the middle, the left hand takes it there, the right lets go.
Where the cube lies changes from episode to episode; the handover happens in
the same place. Each hand is a *pose group* of its own (``left_position``,
``left_orientation``, ``right_position``, ``right_orientation``; both grippers
one group ``gripper``) and the cube is a *task frame*: a new cube pose moves
each hand from its own view, each phase as the demonstrations agree, so the
right hand follows the cube down to the grasp and the world up to the
handover, and the left hand stays in the world.

The demonstrations are recorded here in the ALOHA simulator (gym-aloha's
bimanual scene, :mod:`ndlfd.sim`) from the package's scripted expert, so the
example needs the extra ``sim``: ``pip install "ndlfd[sim]"``. Without it the
example prints a note and stops.
"""

import time

import matplotlib.pyplot as plt
import numpy as np

import ndlfd
from ndlfd import sim

try:
    sim.require_sim()
    HAVE_SIM = True
except ndlfd.MissingExtraError as exc:
    HAVE_SIM = False
    print(f"This example runs the ALOHA simulator and is skipped here: {exc}")

TASK = "transfer-cube"

# %%
# Twenty demonstrations
# ---------------------
# The scripted expert (``ndlfd.sim.record_expert``) varies as people do:
# its timing, approach heights, grasp points and the meeting point, with a
# hand tremor. Each episode places the cube anew over gym-aloha's range
# (x 0-0.2 m, y 0.4-0.6 m) and records both hands' poses and grippers at
# 50 Hz (``ee_action``: per hand x, y, z, qw, qx, qy, qz, gripper) and the
# joints commanded through inverse kinematics (``joint_action``). As a person
# would, only the successful recordings are kept.
if HAVE_SIM:
    t0 = time.perf_counter()
    scene = sim.Scene(TASK, "joint")
    recordings, tried = [], 0
    while len(recordings) < 20:
        rng = np.random.default_rng([0, tried])
        tried += 1
        objects = sim.sample_objects(TASK, rng)
        scene.reset(objects)
        plan = sim.expert_episode(TASK, objects, rng, start=scene.hands())
        rec = sim.record_expert(scene, plan, objects)
        if rec.success:
            recordings.append(rec)
    print(
        f"{len(recordings)} successful recordings of {tried}"
        f" ({time.perf_counter() - t0:.1f} s)"
    )

# %%
# Both hands as pose groups, the cube as a task frame
# ---------------------------------------------------
# ``left_position`` and ``right_position`` are 3 columns each, their
# orientations unit quaternions (w, x, y, z); each hand's velocity is derived
# from its positions. The cube's position is the frame ``cube``.


def hands_demo(rec):
    """One recording's hands as a demonstration, the cube's position a frame."""
    ee = rec.ee_action
    return ndlfd.Demonstration.from_arrays(
        rec.t,
        left_position=ee[:, 0:3],
        left_orientation=ee[:, 3:7],
        right_position=ee[:, 8:11],
        right_orientation=ee[:, 11:15],
        gripper=ee[:, [7, 15]],
        frames={"cube": rec.objects[0]},
    )


if HAVE_SIM:
    model = ndlfd.KeypointHMM().fit([hands_demo(r) for r in recordings])
    print("groups:", ", ".join(model.groups_))
    print("task frames:", ", ".join(model.task_frames_))

# %%
# Three new cube poses, run in the simulator
# ------------------------------------------
# The path is generated from where the hands start, with the cube's new pose
# as the frame, and run open loop: each row's two hand poses are turned into
# joints by inverse kinematics (``ndlfd.sim.run_hands``) and commanded.
# Success is the task's own reward at its maximum (gym-aloha's "successful
# transfer"): the left hand's fingers on the cube, the cube off the table.
if HAVE_SIM:
    cubes = np.array([[0.02, 0.43, 0.05], [0.10, 0.56, 0.05], [0.18, 0.45, 0.05]])
    times = np.arange(round(np.mean([r.t[-1] for r in recordings]) / 0.02) + 1) * 0.02
    start = {"left_position": sim.START_HANDS[0, :3],
             "right_position": sim.START_HANDS[1, :3]}  # fmt: skip
    paths = []
    for cube in cubes:
        path = model.generate(times, dense=True, start=start, frames={"cube": cube})
        grip = path.get("gripper")
        rows = np.column_stack(
            [
                path.get("left_position"),
                path.get("left_orientation"),
                grip[:, 0],
                path.get("right_position"),
                path.get("right_orientation"),
                grip[:, 1],
            ]
        )
        _, reward = sim.run_hands(scene, rows, [cube])
        ok = reward.max() >= sim.MAX_REWARD
        print(f"cube at {cube[:2]}: {'success' if ok else 'failed'}")
        paths.append(path)

# %%
# Both hands from above
# ---------------------
# The demonstrations' right hands in grey; for each new cube (a square) the
# right hand (solid) goes down to it and carries it to the middle, where the
# left hand (dashed) takes it: nearly the same path for every cube, as the
# left hand's demonstrations are in the world, not in the cube's frame.
if HAVE_SIM:
    colors = ["tab:blue", "tab:orange", "tab:green"]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for rec in recordings:
        ax.plot(*rec.ee_action[:, 8:10].T, color="0.82", lw=0.7, zorder=1)
    for cube, path, c in zip(cubes, paths, colors, strict=True):
        ax.plot(*path.get("right_position")[:, :2].T, color=c, lw=2)
        ax.plot(*path.get("left_position")[:, :2].T, color=c, lw=1.5, ls="--")
        ax.plot(*cube[:2], "s", ms=9, mfc=c, mec="k", zorder=3)
    ax.plot([], [], color="0.3", lw=2, label="right hand")
    ax.plot([], [], color="0.3", lw=1.5, ls="--", label="left hand")
    ax.plot([], [], "s", color="0.3", label="cube")
    ax.plot([], [], color="0.82", label="demonstrations (right)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal")
    ax.set_title("Transfer Cube from above: both hands, three cube poses")
    ax.legend(fontsize=8, loc="upper left", ncol=2)
    fig.tight_layout()

# %%
# A joint-space model, given the cube's pose
# ------------------------------------------
# LeRobot's and ALOHA's native space is the joints: 12 arm joints and the two
# grippers, no hand at all. Such a model takes the same frames: its path moves
# along a regression on the frames' poses, as the demonstrations' joints
# co-vary with where the cube was (inverse kinematics is curved, so a
# quadratic regression is chosen when it predicts the left-out demonstrations
# better). The joints generated are commanded as they are; the hands' tool
# points are drawn where the robot put them. A regression learned from 20
# demonstrations is least sure near the edges of the range they cover: that
# is where the joint-space model misses first.
ARM = [0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]  # the 12 arm joints of 14


def joints_demo(rec):
    """One recording's joints as a demonstration, the cube's position a frame."""
    q = rec.joint_action
    return ndlfd.Demonstration.from_arrays(
        rec.t,
        joints=q[:, ARM],
        gripper=q[:, [6, 13]],
        frames={"cube": rec.objects[0]},
    )


if HAVE_SIM:
    joint_model = ndlfd.KeypointHMM().fit([joints_demo(r) for r in recordings])
    q0 = recordings[0].joint_action[0, ARM]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for cube, c in zip(cubes, colors, strict=True):
        path = joint_model.generate(
            times, dense=True, start={"joints": q0}, frames={"cube": cube}
        )
        q, grip = path.get("joints"), path.get("gripper")
        commands = np.column_stack([q[:, :6], grip[:, 0], q[:, 6:], grip[:, 1]])
        scene.reset([cube])
        reward, tool = [], []
        for command in commands:
            reward.append(scene.step(command))
            tool.append(scene.hands()[:, :3])
        ok = max(reward) >= sim.MAX_REWARD
        print(f"joint space, cube at {cube[:2]}: {'success' if ok else 'failed'}")
        tool = np.array(tool)
        ax.plot(*tool[:, 1, :2].T, color=c, lw=2)
        ax.plot(*tool[:, 0, :2].T, color=c, lw=1.5, ls="--")
        ax.plot(*cube[:2], "s", ms=9, mfc=c, mec="k", zorder=3)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal")
    ax.set_title("The joint-space model's hands (right solid, left dashed)")
    fig.tight_layout()
