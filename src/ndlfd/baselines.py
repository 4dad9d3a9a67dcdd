"""Peer generators for the evaluation: the mean, ProMP, GMR, DMP, and ndlfd itself.

Every generator has the same small interface, so :func:`ndlfd.evaluate` treats
them alike:

``fit(demos) -> self``
    Learn from a list of :class:`~ndlfd.Demonstration` (their ``"position"``
    group and time stamps ``demo.t``).
``generate(times, *, start=None) -> ndarray of shape (n_samples, n_dims)``
    Positions at the given time stamps. Time is normalized: ``times`` are mapped
    to ``[0, 1]`` (first to last stamp), and so is every demonstration, so the
    generated motion lasts exactly as long as ``times`` span. With ``start``
    (a position), the path must begin there.

The baselines are deliberately plain, each the textbook use of a well-known
library:

============  =============================================================
``"mean"``    :class:`MeanBaseline`, the time-aligned mean of the demos
``"promp"``   :class:`ProMPBaseline`, ``movement_primitives.promp.ProMP``
``"gmr"``     :class:`GMRBaseline`, ``gmr.GMM`` on ``(time, position)``
``"dmp"``     :class:`DMPBaseline`, ``movement_primitives.dmp.DMP``
============  =============================================================

ProMP, GMR and DMP need the optional ``eval`` extra
(``pip install "ndlfd[eval]"``); without it, :func:`make_baseline` and ``fit``
raise :class:`~ndlfd.MissingExtraError`. :class:`KeypointHMMGenerator` puts
:class:`~ndlfd.KeypointHMM` behind the same interface.

Examples
--------
>>> import numpy as np
>>> from ndlfd import Demonstration
>>> t = np.linspace(0.0, 1.0, 5)
>>> demos = [
...     Demonstration.from_arrays(t, position=np.column_stack([t, t + y0]))
...     for y0 in (0.0, 1.0)
... ]
>>> MeanBaseline().fit(demos).generate([0.0, 2.0])
array([[0. , 0.5],
       [1. , 1.5]])
>>> MeanBaseline().fit(demos).generate([0.0, 2.0], start=[0.0, 0.0])
array([[0. , 0. ],
       [1. , 1.5]])
"""

from __future__ import annotations

import importlib
import inspect
from collections.abc import Sequence

import numpy as np

from ._errors import MissingExtraError, NotFittedError, ValidationError
from ._registry import Registry
from ._validation import (
    as_float_array,
    check_positive_int,
    check_random_state,
    check_times,
)
from .demonstration import Demonstration, unit_time
from .learner import KeypointHMM, minimum_jerk, pin_offset
from .metrics import mean_demo_baseline

__all__ = [
    "BASELINES",
    "DMPBaseline",
    "GMRBaseline",
    "KeypointHMMGenerator",
    "MeanBaseline",
    "ProMPBaseline",
    "make_baseline",
    "minimum_jerk",
]

GROUP = "position"
EXTRA_HINT = 'pip install "ndlfd[eval]"'


# ---------------------------------------------------------------------- helpers
def _check_times(times) -> np.ndarray:
    t = check_times(times, name="times")
    if t.shape[0] < 2:
        raise ValidationError(
            f"times must hold at least 2 time stamps (a start and an end); got"
            f" {t.shape[0]}"
        )
    return t


def _check_demos(demos) -> list[Demonstration]:
    if isinstance(demos, Demonstration):
        demos = [demos]
    if not isinstance(demos, Sequence) or isinstance(demos, (str, bytes)):
        raise ValidationError(
            f"demos must be a list of Demonstration; got {type(demos).__name__}"
        )
    out = list(demos)
    if not out:
        raise ValidationError("demos must hold at least one demonstration; got none")
    dims = None
    for i, d in enumerate(out):
        if not isinstance(d, Demonstration):
            raise ValidationError(
                f"demos[{i}] must be a Demonstration; got {type(d).__name__}"
            )
        if not d.has_group(GROUP):
            raise ValidationError(
                f"demos[{i}] has no {GROUP!r} group; its groups are"
                f" {', '.join(d.group_names)}"
            )
        if d.n_samples < 2:
            raise ValidationError(
                f"demos[{i}] must have at least 2 samples; got {d.n_samples}"
            )
        k = d.get(GROUP).shape[1]
        if dims is None:
            dims = k
        elif k != dims:
            raise ValidationError(
                f"every demonstration must have {dims} {GROUP} columns like"
                f" demos[0]; demos[{i}] has {k}"
            )
    return out


def _resampled(demos: Sequence[Demonstration], n: int) -> np.ndarray:
    """Positions of every demonstration at ``n`` evenly spaced normalized times.

    Returns an array of shape ``(n_demos, n, n_dims)``.
    """
    grid = np.linspace(0.0, 1.0, n)
    out = []
    for d in demos:
        s = unit_time(d.t)
        P = d.get(GROUP)
        out.append(
            np.column_stack([np.interp(grid, s, P[:, c]) for c in range(P.shape[1])])
        )
    return np.stack(out)


def _faded_offset(path: np.ndarray, tau: np.ndarray, start) -> np.ndarray:
    """Shift ``path`` to begin at ``start``, fading the shift out by the end.

    ``path`` is returned unchanged when ``start`` is None.
    """
    if start is None:
        return path
    return pin_offset(path.copy(), 1.0 - minimum_jerk(tau), 0, start)


def _require(module: str, what: str):
    """Import an optional module or raise :class:`MissingExtraError`."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingExtraError(
            f"the {what} baseline needs the optional package"
            f" {module.split('.')[0]}; install it with: {EXTRA_HINT} ({exc})"
        ) from None


class _Generator:
    """The fit and generate every generator shares, written once.

    :meth:`fit` imports the optional package, checks the parameters
    (:meth:`_params`) and the demonstrations, then calls :meth:`_learn`;
    :meth:`generate` checks that the generator is fitted, the time stamps and
    the start, then calls :meth:`_path`. A generator writes only those three
    hooks.
    """

    #: Whether ``generate(..., return_std=True)`` can return a standard deviation.
    has_std = False
    #: Optional modules the generator imports (checked by :meth:`check_extra`).
    _requires: tuple[str, ...] = ()
    _name = "generator"

    @classmethod
    def check_extra(cls) -> None:
        """Raise :class:`MissingExtraError` when an optional package is missing."""
        for module in cls._requires:
            _require(module, cls._name)

    def fit(self, demos, y=None):
        """Learn from the demonstrations (the class says how).

        Parameters
        ----------
        demos : list of Demonstration
            Training demonstrations with a ``"position"`` group.
        y : None
            Ignored.

        Returns
        -------
        self : the generator

        Raises
        ------
        MissingExtraError
            The generator's optional package is not installed.
        ValidationError
            A parameter or a demonstration is not valid.
        """
        extra = _require(self._requires[0], self._name) if self._requires else None
        params = self._params()
        demos = _check_demos(demos)
        self._learn(demos, extra, **params)
        self.n_dims_ = demos[0].get(GROUP).shape[1]
        return self

    def generate(self, times, *, start=None) -> np.ndarray:
        """Positions at the given time stamps, optionally from ``start``.

        Parameters
        ----------
        times : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least two).
        start : array-like of shape (n_dims,), optional
            The position to start at (the class says how it is reached).

        Returns
        -------
        path : ndarray of shape (n_samples, n_dims)
        """
        return self._path(*self._checked(times, start))

    def _params(self) -> dict:
        """The checked parameters :meth:`_learn` takes (none by default)."""
        return {}

    def _learn(self, demos: list[Demonstration], extra, **params) -> None:
        """Set the fitted attributes from checked demonstrations and parameters.

        ``extra`` is the optional module of ``_requires[0]`` (None without one).
        """
        raise NotImplementedError

    def _path(self, t: np.ndarray, start: np.ndarray | None) -> np.ndarray:
        """The path of shape ``(len(t), n_dims)`` at checked time stamps."""
        raise NotImplementedError

    def _checked(self, times, start) -> tuple[np.ndarray, np.ndarray | None]:
        """The checked time stamps and start position of a fitted generator."""
        self._check_fitted()
        return _check_times(times), self._check_start(start)

    def _check_fitted(self) -> None:
        if not hasattr(self, "n_dims_"):
            raise NotFittedError(
                f"this {type(self).__name__} is not fitted yet; call fit(demos) first"
            )

    def _check_start(self, start) -> np.ndarray | None:
        if start is None:
            return None
        s = as_float_array(start, "start")
        if s.shape != (self.n_dims_,) or not np.isfinite(s).all():
            raise ValidationError(
                f"start must be a finite position of shape ({self.n_dims_},); got"
                f" {s.tolist()!r}"
            )
        return s

    def __repr__(self) -> str:
        params = inspect.signature(type(self).__init__).parameters
        inner = ", ".join(
            f"{k}={getattr(self, k)!r}" for k in params if hasattr(self, k)
        )
        return f"{type(self).__name__}({inner})"


# -------------------------------------------------------------------- baselines
BASELINES: Registry[type] = Registry("baseline")


@BASELINES.register("mean")
class MeanBaseline(_Generator):
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
        return _faded_offset(path, unit_time(t), start)


@BASELINES.register("promp")
class ProMPBaseline(_Generator):
    """Probabilistic movement primitive (``movement_primitives.promp.ProMP``).

    The demonstrations are resampled at ``n_grid`` evenly spaced normalized
    times and the ProMP's weight distribution is learned from them
    (``ProMP.imitate``). Generation returns the ProMP's mean trajectory; with
    ``start``, the ProMP is first conditioned on the start position at
    normalized time 0 (``ProMP.condition_position``, exact: no observation
    noise) and the conditioned mean is returned.

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
        Y = _resampled(demos, n)
        model = promp.ProMP(n_dims=Y.shape[2], n_weights_per_dim=n_w)
        # ProMP normalizes its time arrays in place: hand it its own copy
        model.imitate(np.tile(np.linspace(0.0, 1.0, n), (len(demos), 1)), Y)
        self.promp_ = model

    def _path(self, t, start):
        model = self.promp_
        if start is not None:
            model = model.condition_position(start, t=0.0, t_max=1.0)
        return np.asarray(model.mean_trajectory(unit_time(t).copy()), dtype=float)


@BASELINES.register("gmr")
class GMRBaseline(_Generator):
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
        Y = _resampled(demos, n)
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
        return _faded_offset(np.asarray(path, dtype=float), tau, start)


@BASELINES.register("dmp")
class DMPBaseline(_Generator):
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
        dmp = _require("movement_primitives.dmp", self._name)
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


# ------------------------------------------------------------------------ ndlfd
def _keypoint_hmm_accepts(name: str) -> bool:
    return name in inspect.signature(KeypointHMM.generate).parameters


class KeypointHMMGenerator(_Generator):
    """:class:`~ndlfd.KeypointHMM` behind the generator interface.

    Parameters
    ----------
    model : KeypointHMM, optional
        Copy this learner's parameters (it is not fitted or changed itself).
    **params
        :class:`~ndlfd.KeypointHMM` parameters (override those of ``model``).

    Attributes
    ----------
    model_ : KeypointHMM
        The fitted learner.
    n_dims_ : int
        Number of position columns.

    Examples
    --------
    >>> from ndlfd import KeypointHMM
    >>> KeypointHMMGenerator(KeypointHMM(epsilon=0.01), n_time_bins=20).params
    {'epsilon': 0.01, 'n_time_bins': 20}
    """

    _name = "ndlfd"

    def __init__(self, model: KeypointHMM | None = None, /, **params):
        if model is not None:
            if not isinstance(model, KeypointHMM):
                raise ValidationError(
                    f"model must be a KeypointHMM; got {type(model).__name__}"
                )
            defaults = KeypointHMM().get_params()
            own = {
                k: v
                for k, v in model.get_params().items()
                if v is not defaults[k] and not _equal(v, defaults[k])
            }
            params = {**own, **params}
        KeypointHMM().set_params(**params)  # unknown names fail here, not later
        self.params = params

    @property
    def has_std(self) -> bool:  # type: ignore[override]
        """Whether this version of KeypointHMM returns a standard deviation."""
        return _keypoint_hmm_accepts("return_std")

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"KeypointHMMGenerator({inner})"

    def _learn(self, demos, extra) -> None:
        self.model_ = KeypointHMM(**self.params).fit(demos)

    def generate(self, times, *, start=None, return_std: bool = False):
        """Dense generated positions at each time stamp.

        Parameters
        ----------
        times : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least two).
        start : array-like of shape (n_dims,), optional
            Passed as ``start={"position": start}``.
        return_std : bool, default=False
            Also return the learner's standard deviation of the position
            (needs a KeypointHMM whose ``generate`` offers ``return_std``).

        Returns
        -------
        path : ndarray of shape (n_samples, n_dims)
        std : ndarray of shape (n_samples, n_dims)
            Only with ``return_std=True``.
        """
        t, start = self._checked(times, start)
        kw = {}
        if start is not None:
            if not _keypoint_hmm_accepts("start"):
                raise ValidationError(
                    "this version of KeypointHMM.generate takes no start position"
                )
            kw["start"] = {GROUP: start}
        if return_std:
            if not self.has_std:
                raise ValidationError(
                    "this version of KeypointHMM.generate offers no return_std"
                )
            kw["return_std"] = True
        out = self.model_.generate(t, dense=True, **kw)
        if not return_std:
            return out.get(GROUP)
        path, std = out
        cols = path.columns_of(GROUP)
        std = np.asarray(std, dtype=float)
        if std.shape[1] != path.X.shape[1]:  # std of the position group only
            return path.get(GROUP), std
        return path.get(GROUP), std[:, cols]


def _equal(a, b) -> bool:
    try:
        return bool(a == b)
    except (TypeError, ValueError):
        return False


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
