"""Sample demonstrations shared by the io tests."""

import numpy as np

from ndlfd.demonstration import Demonstration


def rich_demo(n=6, seed=0):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.01, 1.0, n))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return Demonstration.from_arrays(
        t,
        position=rng.normal(size=(n, 3)) * 1e3,
        velocity=rng.normal(size=(n, 3)),
        orientation=q,
        force=rng.normal(size=(n, 2)),
        grip=rng.normal(size=n),
    )


def reach(n=40, seed=0):
    """A 3-D reach with orientation at irregular time stamps."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.005, 0.02, n))
    s = np.linspace(0, 1, n)
    pos = np.column_stack([s, s**2, np.sin(s)]) + rng.normal(0, 1e-3, (n, 3))
    half = 0.5 * s  # rotation about z by s radians, exact unit quaternions
    quat = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
    return t, pos, quat
