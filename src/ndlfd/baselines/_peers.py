"""The peers: the time-aligned mean, ProMP, GMR and DMP (see :mod:`ndlfd.baselines`)."""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from .._registry import Registry
from .._validation import check_positive_int, check_random_state
from ..demonstration import unit_time
from ..metrics import mean_demo_baseline
from ._generator import (
    GROUP,
    POINT_NOISE,
    Generator,
    pass_through,
    require,
    resampled,
    start_pin,
)

__all__ = [
    "BASELINES",
    "DMPBaseline",
    "GMRBaseline",
    "MeanBaseline",
    "ProMPBaseline",
    "make_baseline",
]


# -------------------------------------------------------------------- baselines
BASELINES: Registry[type] = Registry("baseline")


@BASELINES.register("mean")
class MeanBaseline(Generator):
    """The time-aligned mean of the demonstrations.

    At each normalized time, the average of every demonstration's position at
    that normalized time (linear interpolation,
    :func:`ndlfd.metrics.mean_demo_baseline`). With ``start``, the offset
    ``start - mean[0]`` is added and faded out over the motion with the
    minimum-jerk ramp (:func:`minimum_jerk`), so the path starts exactly at
    ``start`` and still ends at the mean's end.

    Attributes
    ----------
    demos_ : list of Demonstration
        The training demonstrations.
    n_dims_ : int
        Number of position columns.
    """

    _name = "mean"

    def _learn(self, demos, extra) -> None:
        self.demos_ = demos

    def _path(self, t, start):
        path = mean_demo_baseline(self.demos_, t, GROUP)
        return pass_through(path, unit_time(t), start_pin(start))


@BASELINES.register("promp")
class ProMPBaseline(Generator):
    """Probabilistic movement primitive (``movement_primitives.promp.ProMP``).

    The demonstrations are resampled at ``n_grid`` evenly spaced normalized
    times and the ProMP's weight distribution is learned from them
    (``ProMP.imitate``). Generation returns the ProMP's mean trajectory; with
    ``start``, the ProMP is first conditioned on the start position at
    normalized time 0 (``ProMP.condition_position``, exact: no observation
    noise) and the conditioned mean is returned. Via points and the prefix's
    points (:func:`prefix_pins`) are conditioned on in turn, each with an
    observation noise of :data:`POINT_NOISE` times the demonstrations' range
    (exact updates in a chain lose their positive definiteness), and the
    path then passes through them exactly (:func:`pass_through`).

    Parameters
    ----------
    n_weights_per_dim : int, default=25
        Radial basis functions per dimension.
    n_grid : int, default=100
        Samples per demonstration for learning (the EM works on matrices of
        ``n_grid * n_dims`` rows, so this is kept modest).

    Attributes
    ----------
    promp_ : movement_primitives.promp.ProMP
        The learned primitive.
    range_ : float
        The diagonal of the demonstrations' bounding box.
    n_dims_ : int
        Number of position columns.
    """

    _name = "promp"
    _requires = ("movement_primitives.promp",)

    def __init__(self, n_weights_per_dim: int = 25, n_grid: int = 100):
        self.n_weights_per_dim = n_weights_per_dim
        self.n_grid = n_grid

    def _params(self) -> dict:
        return {
            "n_w": check_positive_int(self.n_weights_per_dim, "n_weights_per_dim"),
            "n": check_positive_int(self.n_grid, "n_grid", minimum=2),
        }

    def _learn(self, demos, promp, *, n_w: int, n: int) -> None:
        Y = resampled(demos, n)
        model = promp.ProMP(n_dims=Y.shape[2], n_weights_per_dim=n_w)
        # ProMP normalizes its time arrays in place: hand it its own copy
        model.imitate(np.tile(np.linspace(0.0, 1.0, n), (len(demos), 1)), Y)
        self.promp_ = model
        self.range_ = float(np.linalg.norm(np.ptp(Y.reshape(-1, Y.shape[2]), axis=0)))

    def _path(self, t, start):
        return self._path_given(t, start, [])

    def _path_given(self, t, start, pins):
        tau = unit_time(t)
        model = self.promp_
        if start is not None:
            model = model.condition_position(start, t=0.0, t_max=1.0)
        # a little observation noise keeps the chain of updates well conditioned
        cov = np.eye(self.n_dims_) * (POINT_NOISE * self.range_) ** 2
        for row, p in pins:
            model = model.condition_position(p, cov, t=float(tau[row]), t_max=1.0)
        return np.asarray(model.mean_trajectory(tau.copy()), dtype=float)


@BASELINES.register("gmr")
class GMRBaseline(Generator):
    """Gaussian mixture regression (``gmr.GMM``) of position on normalized time.

    A Gaussian mixture is fitted by EM (k-means++ initialization, covariances
    shrunk by the oracle approximating shrinkage) to the samples
    ``[tau, x, y, ...]`` of every demonstration resampled at ``n_grid`` evenly
    spaced normalized times ``tau``, each column standardized. Generation
    predicts the conditional mean of the position given ``tau``. With
    ``start``, the offset ``start - path[0]`` is faded out over the motion with
    the minimum-jerk ramp, as in :class:`MeanBaseline` (GMR has no way to
    condition on a start position: its only input is time).

    Parameters
    ----------
    n_components : int, default=8
        Number of Gaussians.
    n_grid : int, default=100
        Samples per demonstration for learning.
    random_state : None, int or Generator, default=0
        Seeds the EM's initialization.

    Attributes
    ----------
    gmm_ : gmr.GMM
        The mixture on the standardized columns.
    n_dims_ : int
        Number of position columns.
    """

    _name = "gmr"
    _requires = ("gmr",)

    def __init__(self, n_components: int = 8, n_grid: int = 100, random_state=0):
        self.n_components = n_components
        self.n_grid = n_grid
        self.random_state = random_state

    def _params(self) -> dict:
        return {
            "k": check_positive_int(self.n_components, "n_components"),
            "n": check_positive_int(self.n_grid, "n_grid", minimum=2),
            "seed": int(check_random_state(self.random_state).integers(2**31 - 1)),
        }

    def _learn(self, demos, gmr, *, k: int, n: int, seed: int) -> None:
        Y = resampled(demos, n)
        X = np.column_stack(
            [np.tile(np.linspace(0.0, 1.0, n), len(demos)), Y.reshape(-1, Y.shape[2])]
        )
        if X.shape[0] < k:
            raise ValidationError(
                f"n_components={k} needs at least {k} samples; got {X.shape[0]}"
                " (raise n_grid)"
            )
        self.center_ = X.mean(axis=0)
        scale = X.std(axis=0)
        self.scale_ = np.where(scale > 0, scale, 1.0)
        gmm = gmr.GMM(n_components=k, random_state=np.random.RandomState(seed))
        gmm.from_samples(
            (X - self.center_) / self.scale_,
            init_params="kmeans++",
            oracle_approximating_shrinkage=True,
        )
        self.gmm_ = gmm

    def _path(self, t, start):
        tau = unit_time(t)
        q = ((tau - self.center_[0]) / self.scale_[0])[:, None]
        path = self.gmm_.predict(np.array([0]), q) * self.scale_[1:] + self.center_[1:]
        return pass_through(np.asarray(path, dtype=float), tau, start_pin(start))


@BASELINES.register("dmp")
class DMPBaseline(Generator):
    """Dynamical movement primitive (``movement_primitives.dmp.DMP``).

    A DMP reproduces one demonstration, so it imitates the time-aligned mean of
    the demonstrations (:func:`ndlfd.metrics.mean_demo_baseline` sampled at
    ``n_grid`` normalized times over the mean duration): the usual way to
    teach a DMP from several demonstrations, and the one that makes it
    comparable to the other generators. Generation runs the DMP open loop from
    ``start`` (the mean's start when not given) to the mean's end as goal, with
    the execution time set to the requested duration, integrated with
    ``n_steps`` steps and interpolated linearly at the requested time stamps.

    Parameters
    ----------
    n_weights_per_dim : int, default=40
        Basis functions of the forcing term per dimension.
    n_grid : int, default=1000
        Samples of the mean the DMP imitates.
    n_steps : int, default=1000
        Integration steps over the motion.

    Attributes
    ----------
    dmp_ : movement_primitives.dmp.DMP
        The DMP fitted to the mean.
    start_, goal_ : ndarray of shape (n_dims,)
        The mean's first and last positions.
    n_dims_ : int
        Number of position columns.
    """

    _name = "dmp"
    _requires = ("movement_primitives.dmp",)

    def __init__(
        self, n_weights_per_dim: int = 40, n_grid: int = 1000, n_steps: int = 1000
    ):
        self.n_weights_per_dim = n_weights_per_dim
        self.n_grid = n_grid
        self.n_steps = n_steps

    def _params(self) -> dict:
        params = {
            "n_w": check_positive_int(self.n_weights_per_dim, "n_weights_per_dim"),
            "n": check_positive_int(self.n_grid, "n_grid", minimum=3),
        }
        check_positive_int(self.n_steps, "n_steps", minimum=2)
        return params

    def _learn(self, demos, dmp, *, n_w: int, n: int) -> None:
        duration = float(np.mean([d.t[-1] - d.t[0] for d in demos]))
        grid = np.linspace(0.0, 1.0, n)
        mean = mean_demo_baseline(demos, grid, GROUP)
        model = dmp.DMP(
            n_dims=mean.shape[1],
            execution_time=duration,
            dt=duration / (n - 1),
            n_weights_per_dim=n_w,
        )
        model.imitate(grid * duration, mean)
        self.dmp_ = model
        self.start_ = mean[0].copy()
        self.goal_ = mean[-1].copy()

    def _path(self, t, start):
        dmp = require("movement_primitives.dmp", self._name)
        duration = float(t[-1] - t[0])
        n_steps = check_positive_int(self.n_steps, "n_steps", minimum=2)
        # a fresh DMP with the learned weights, so generate leaves dmp_ untouched
        model = dmp.DMP(
            n_dims=self.n_dims_,
            execution_time=duration,
            dt=duration / n_steps,
            n_weights_per_dim=self.dmp_.n_weights_per_dim,
        )
        model.set_weights(self.dmp_.get_weights().copy())
        model.configure(
            start_y=self.start_ if start is None else start, goal_y=self.goal_
        )
        T, Y = model.open_loop()
        rel = t - t[0]
        return np.column_stack(
            [np.interp(rel, T, Y[:, c]) for c in range(self.n_dims_)]
        )


def make_baseline(name: str, **params):
    """A new, unfitted baseline by registry name.

    Parameters
    ----------
    name : {"mean", "promp", "gmr", "dmp"}
        The baseline (see :data:`BASELINES`).
    **params
        Passed to the baseline's constructor.

    Returns
    -------
    baseline : MeanBaseline, ProMPBaseline, GMRBaseline or DMPBaseline

    Raises
    ------
    OptionError
        An unknown name (the message lists the valid ones).
    MissingExtraError
        The baseline's optional package is not installed.

    Examples
    --------
    >>> make_baseline("promp", n_weights_per_dim=20)
    ProMPBaseline(n_weights_per_dim=20, n_grid=100)
    """
    cls = BASELINES.get(name)
    cls.check_extra()
    return cls(**params)
