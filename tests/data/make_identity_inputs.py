"""Write tests/data/identity_inputs.npz, the inputs of test_learner_identity.py.

The identity tests check that what ndlfd computes from a fixed data set stays
bit for bit the same. Their data were first made inside the test from a seeded
generator with ``np.sin``/``np.cos``/``**``, whose last bits depend on the CPU
features numpy dispatches to (AVX-512 or not): on another machine the inputs,
and so every digest, differed (issue 25). The generator below is that code,
unchanged; it was run once, on the machine where the known digests of commit
8de859a were made (the fitted arrays match them bit for bit), and its output
is stored, so every machine now reads the same bits:

    .venv/bin/python tests/data/make_identity_inputs.py

Running it again on another CPU may write different last bits; do not, unless
the data set itself is meant to change (then the known digests must be made
anew and the change said in the commit).

The file holds, per data set (``arm``, ``loops``) and demonstration ``k``, the
arrays given to :meth:`ndlfd.Demonstration.from_arrays`, named
``<set>/<k:02d>/<keyword>`` (``t`` for the time stamps).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

FIXTURE = Path(__file__).with_name("identity_inputs.npz")


def arm(n_demos=14, seed=11):
    """3-D reaches with a turning orientation and a gripper closing mid-way.

    Lengths 300 to 1,000 samples; every third has jittery time stamps (the
    velocity is then derived by the window fit), one has a pause.
    """
    rng = np.random.default_rng(seed)
    demos = []
    for k in range(n_demos):
        n = int(rng.integers(300, 1001))
        dt = np.full(n - 1, rng.uniform(0.004, 0.012))
        if k % 3 == 2:
            dt *= rng.uniform(0.6, 1.4, n - 1)  # logging jitter
        t = np.concatenate([[rng.uniform(0.0, 5.0)], np.cumsum(dt)])
        t[1:] += t[0]
        s = (t - t[0]) / (t[-1] - t[0])
        s = s**3 * (10 - 15 * s + 6 * s**2)  # minimum jerk
        if k == 5:
            s = np.where(s > 0.5, np.maximum(s, 0.5), s)  # a pause
        a = np.array([0.4, -0.2, 0.3]) + rng.normal(0, 0.02, 3)
        b = np.array([0.9, 0.35, 0.1]) + rng.normal(0, 0.02, 3)
        bow = np.outer(np.sin(np.pi * s), [0.0, 0.0, rng.uniform(0.05, 0.2)])
        P = a + s[:, None] * (b - a) + bow + rng.normal(0, 0.002, (n, 3))
        half = 0.5 * (0.9 * s + rng.normal(0, 0.01, n))
        q = np.column_stack(
            [np.cos(half), np.sin(half) * 0.6, np.sin(half) * 0.8, 0 * half]
        )
        if k % 2:
            q = -q  # the same rotations, sign-aligned on construction
        grip = (s > rng.uniform(0.4, 0.6)).astype(float)
        demos.append(dict(t=t, position=P, orientation=q, gripper=grip))
    return demos


def loops(n_demos=10, seed=4):
    """2-D loops with given velocity, 120 to 200 samples, variable speed."""
    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n_demos):
        n = int(rng.integers(120, 201))
        t = np.linspace(0.0, rng.uniform(1.5, 2.5), n)
        s = t / t[-1]
        s = s + 0.1 * np.sin(2 * np.pi * s) / (2 * np.pi)
        r = 1.0 + rng.normal(0, 0.03)
        P = np.column_stack([r * np.cos(2 * np.pi * s), 0.5 * np.sin(4 * np.pi * s)])
        P += rng.normal(0, 0.01, P.shape)
        V = np.gradient(P, t, axis=0) + rng.normal(0, 0.05, P.shape)
        demos.append(dict(t=t, position=P, velocity=V))
    return demos


def main() -> None:
    arrays = {}
    for name, make in (("arm", arm), ("loops", loops)):
        for k, demo in enumerate(make()):
            for key, value in demo.items():
                arrays[f"{name}/{k:02d}/{key}"] = value
    np.savez_compressed(FIXTURE, **arrays)
    print(f"wrote {FIXTURE} ({FIXTURE.stat().st_size:,} bytes, {len(arrays)} arrays)")


if __name__ == "__main__":
    main()
