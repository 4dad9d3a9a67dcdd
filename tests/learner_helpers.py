"""Shared data and checks of the learner tests (``tests/learner/``)."""

import numpy as np

from ndlfd.demonstration import Demonstration
from ndlfd.learner import minimum_jerk


# ------------------------------------------------------------ generation data
def two_routes(n=200, per_route=4, seed=0):
    """Demonstrations from (0, 1) over the top or from (0, -1) underneath to (2, 0)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2.0, n)
    s = t / 2.0
    demos = []
    for sign in (1.0, -1.0):
        for _ in range(per_route):
            x = 2.0 * s + rng.normal(0, 0.01)
            y = sign * (1.0 - s) * (1.0 + np.sin(np.pi * s)) + rng.normal(0, 0.01)
            demos.append(
                Demonstration.from_arrays(
                    t * rng.uniform(0.9, 1.1), position=np.column_stack([x, y])
                )
            )
    return demos


def reaches(n_demos=8, seed=2):
    """3-D minimum-jerk reaches with a turning orientation, 50-125 Hz, 2.6-3.1 s."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    demos = []
    for k in range(n_demos):
        duration = rng.uniform(2.6, 3.1)
        t = np.arange(0.0, duration, 1.0 / (50, 100, 125)[k % 3])
        s = minimum_jerk(t / t[-1])
        a = np.array([0.4, -0.2, 0.3]) + rng.normal(0, 0.01, 3)
        b = np.array([0.7, 0.25, 0.1]) + rng.normal(0, 0.01, 3)
        P = a + s[:, None] * (b - a)
        angles = np.column_stack([0.8 * s, 0.3 * s, np.zeros_like(s)])
        q = Rotation.from_euler("xyz", angles + rng.normal(0, 0.01, 3)).as_quat()
        demos.append(
            Demonstration.from_arrays(
                t, position=P, orientation=q, quaternion_order="xyzw"
            )
        )
    return demos


def resample(demo, grid):
    tau = (demo.t - demo.t[0]) / demo.duration
    at = (grid - grid[0]) / (grid[-1] - grid[0])
    P = demo.get("position")
    return np.column_stack([np.interp(at, tau, c) for c in P.T])


# ------------------------------------------------- map and reduce, out of core, Dask
def fixture_module(name):
    import importlib.util
    from pathlib import Path

    here = Path(__file__).parent / "data"
    spec = importlib.util.spec_from_file_location(name, here / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


class Reiterable:
    """Makes its demonstrations on demand; counts passes and live objects."""

    def __init__(self, demos, bad=None):
        self._demos = demos  # (t, P) pairs, not Demonstrations
        self.bad = bad
        self.passes = 0
        self.alive = 0
        self.most_alive = 0

    def _gone(self):
        self.alive -= 1

    def __iter__(self):
        import weakref

        self.passes += 1
        for i, (t, P) in enumerate(self._demos):
            if i == self.bad:
                yield Demonstration.from_arrays(t, force=P)  # no position
                continue
            d = Demonstration.from_arrays(t, position=P)
            self.alive += 1
            self.most_alive = max(self.most_alive, self.alive)
            weakref.finalize(d, self._gone)
            yield d


def waves(n, seed=0, m=120):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, m)
    out = []
    for _ in range(n):
        a = rng.uniform(0.8, 1.2)
        P = np.column_stack([t, a * np.sin(2 * np.pi * t)]) + rng.normal(0, 0.01, 2)
        out.append((t * rng.uniform(1.5, 2.5), P))
    return out


def fitted_arrays(model):
    """Everything a fit learns, as arrays."""
    arrays = model.fit_stats_.to_arrays()
    arrays.update(model.model_.to_arrays(prefix="hmm_"))
    arrays.update(model.segment_model_.to_arrays(prefix="seg_"))
    arrays.update(
        scaler_min=model.scaler_.data_min_,
        scaler_max=model.scaler_.data_max_,
        centroids=model.centroids_,
        templates=model.template_indices_,
    )
    return arrays


def assert_same_model(a, b, timing):
    fa, fb = fitted_arrays(a), fitted_arrays(b)
    assert fa.keys() == fb.keys()
    for k in fa:
        np.testing.assert_array_equal(fa[k], fb[k], err_msg=k)
    assert a.fit_stats_ == b.fit_stats_
    for kw in ({}, {"start": {"position": [0.0, 0.05]}}):
        pa, sa = a.generate(timing, dense=True, return_std=True, **kw)
        pb, sb = b.generate(timing, dense=True, return_std=True, **kw)
        np.testing.assert_array_equal(pa.X, pb.X)
        np.testing.assert_array_equal(sa, sb)


def run_in(where, request, monkeypatch):
    """(KeypointHMM parameters, fit arguments) that run a fit ``where``."""
    import ndlfd._parallel as _parallel
    import ndlfd.learner._passes as _passes

    seen = []
    for name in ("_run_threads", "_run_processes"):
        real = getattr(_parallel, name)

        def spy(*args, _real=real, _name=name):
            seen.append(_name)
            return _real(*args)

        monkeypatch.setitem(_parallel.BACKENDS._items, name[5:], spy)
    if where == "threads":  # short demonstrations go to processes otherwise
        monkeypatch.setattr(_passes, "_THREAD_MIN_SAMPLES", 1)
    params = {"serial": dict(n_jobs=1), "threads": dict(n_jobs=2),
              "processes": dict(n_jobs=2), "dask": {}}[where]  # fmt: skip
    fit = {"client": request.getfixturevalue("dask_client")} if where == "dask" else {}
    return params, fit, seen


def tight_starts(n=300, seed=0):
    """One smooth 2-D motion whose starts lie within 0.003 of each other."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 120)
    base = np.column_stack([2.0 * t, np.sin(np.pi * t)])
    demos = []
    for _ in range(n):
        P = base + rng.normal(0.0, 0.002, base.shape)
        P[0] = rng.uniform(-0.0015, 0.0015, 2)
        demos.append(Demonstration(t, P, ["x", "y"], ["position"] * 2))
    return demos
