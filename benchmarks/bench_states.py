"""States for any number of channels: cost per visited cell, wide against narrow.

A whole robot log (a Franka-like export: position, orientation, force,
torque, 7 joints, a gripper, and the derived velocity: 24 columns, about
1e23 possible cells) against the same demonstrations' position group alone
(3 columns, 8,000 cells), both at the default levels. States are the visited
cells, interned (issue 37), so the cost should follow the cells visited and
the samples read, not the number of possible cells. Printed per model:
visited cells, fit time, generate time (median of 15 calls after a warm-up),
the peak of Python-traced memory during the fit, and each per visited cell;
then the wide model's ratios to the narrow one.

Run: ``.venv/bin/python benchmarks/bench_states.py [n_demos]`` (default 40;
about half a minute).
"""

from __future__ import annotations

import sys
import time
import tracemalloc

import numpy as np
from scipy.spatial.transform import Rotation

from ndlfd import Demonstration, KeypointHMM


def robot_log(k: int, n: int = 600) -> Demonstration:
    """A reach logged whole at 20 Hz: 21 columns (velocity derived: 24)."""
    rng = np.random.default_rng(k)
    t = np.arange(n) / 20.0
    s = 0.5 - 0.5 * np.cos(np.pi * np.linspace(0, 1, n))
    start = np.array([0.4, -0.2, 0.3]) + rng.normal(0, 0.02, 3)
    goal = np.array([0.7, 0.25, 0.1]) + rng.normal(0, 0.02, 3)
    position = start + s[:, None] * (goal - start)
    position += rng.normal(0, 0.0005, position.shape)
    turn = Rotation.from_rotvec(np.outer(s, [0.0, 0.0, 0.8 + 0.05 * rng.normal()]))
    quat = (turn * Rotation.from_euler("x", np.pi)).as_quat(scalar_first=True)
    contact = np.clip((s - 0.8) / 0.2, 0, 1)
    force = np.column_stack([0.2 * contact, -0.1 * contact, 5.0 * contact])
    force += rng.normal(0, 0.05, force.shape)
    torque = 0.01 * force + rng.normal(0, 0.002, force.shape)
    joints = np.linspace(
        [0, -0.8, 0, -2.3, 0, 1.6, 0.8], [0.6, -0.2, 0.1, -1.7, 0.1, 1.9, 1.4], n
    )
    joints = joints + rng.normal(0, 0.002, joints.shape)
    return Demonstration.from_arrays(
        t, position=position, orientation=quat, force=force, torque=torque,
        joints=joints, gripper=(s > 0.9).astype(float),
    )  # fmt: skip


def measure(demos, groups) -> dict:
    model = KeypointHMM(groups=groups)
    model.fit(demos)  # compile and warm caches
    tracemalloc.start()
    t0 = time.perf_counter()
    model = KeypointHMM(groups=groups).fit(demos)
    fit = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    t = demos[0].t
    model.generate(t, dense=True)
    gen = []
    for _ in range(15):
        t0 = time.perf_counter()
        model.generate(t, dense=True)
        gen.append(time.perf_counter() - t0)
    return {
        "columns": model.codebook_.n_dims,
        "possible": model.codebook_.n_states,
        "cells": model.n_states_used_,
        "fit_s": fit,
        "gen_ms": 1000 * float(np.median(gen)),
        "peak_mb": peak / 2**20,
    }


def main() -> None:
    n_demos = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    demos = [robot_log(k) for k in range(n_demos)]
    wide = measure(demos, "auto")
    narrow = measure(demos, ("position",))
    print(f"{n_demos} demonstrations of {demos[0].n_samples} samples")
    head = (
        f"{'model':<10}{'cols':>5}{'possible':>11}{'visited':>9}{'fit s':>8}"
        f"{'gen ms':>8}{'peak MB':>9}{'fit us/cell':>13}{'gen us/cell':>13}"
        f"{'kB/cell':>9}"
    )
    print(head)
    for name, r in (("whole log", wide), ("position", narrow)):
        c = r["cells"]
        print(
            f"{name:<10}{r['columns']:>5}{float(r['possible']):>11.3g}{c:>9}"
            f"{r['fit_s']:>8.3f}{r['gen_ms']:>8.2f}{r['peak_mb']:>9.1f}"
            f"{1e6 * r['fit_s'] / c:>13.1f}{1e3 * r['gen_ms'] / c:>13.2f}"
            f"{1024 * r['peak_mb'] / c:>9.2f}"
        )
    ratio = {
        k: (wide[k] / wide["cells"]) / (narrow[k] / narrow["cells"])
        for k in ("fit_s", "gen_ms", "peak_mb")
    }
    whole = {k: wide[k] / narrow[k] for k in ("fit_s", "gen_ms", "peak_mb")}
    print(
        "whole log / position, as they are:"
        f" fit {whole['fit_s']:.2f}x, generate {whole['gen_ms']:.2f}x,"
        f" memory {whole['peak_mb']:.2f}x (the whole log keeps more key points)"
    )
    print(
        "whole log / position, per visited cell:"
        f" fit {ratio['fit_s']:.2f}x, generate {ratio['gen_ms']:.2f}x,"
        f" memory {ratio['peak_mb']:.2f}x"
    )


if __name__ == "__main__":
    main()
