"""The generator interface every peer shares, its conditioning, and ndlfd behind it.

:class:`Generator` writes the fit and generate of every generator once (the
checks, the conditions, the exact pins of :func:`pass_through`);
:class:`KeypointHMMGenerator` puts :class:`~ndlfd.KeypointHMM` behind the same
interface. The peers are in :mod:`ndlfd.baselines._peers`.
"""

from __future__ import annotations

import importlib
import inspect
from collections.abc import Sequence

import numpy as np

from .._errors import MissingExtraError, NotFittedError, ValidationError
from .._validation import as_float_array, check_times
from ..demonstration import Demonstration, unit_time
from ..learner import KeypointHMM, minimum_jerk, pin_offset

__all__ = [
    "EXTRA_HINT",
    "GROUP",
    "POINT_NOISE",
    "PREFIX_POINTS",
    "Generator",
    "KeypointHMMGenerator",
    "check_demos",
    "check_generate_times",
    "pass_through",
    "prefix_pins",
    "require",
    "resampled",
    "start_pin",
]

GROUP = "position"
#: Prefix samples a conditioning generator is given (:func:`prefix_pins`).
PREFIX_POINTS = 10
#: ProMP's observation noise at a via or prefix point, a fraction of the range.
POINT_NOISE = 1e-3
EXTRA_HINT = 'pip install "ndlfd[eval]"'


# ---------------------------------------------------------------------- helpers
def check_generate_times(times) -> np.ndarray:
    t = check_times(times, name="times")
    if t.shape[0] < 2:
        raise ValidationError(
            f"times must hold at least 2 time stamps (a start and an end); got"
            f" {t.shape[0]}"
        )
    return t


def check_demos(demos) -> list[Demonstration]:
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


def resampled(demos: Sequence[Demonstration], n: int) -> np.ndarray:
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


def pass_through(path: np.ndarray, tau: np.ndarray, pins) -> np.ndarray:
    """Shift ``path`` through each pinned row, offsets faded by minimum-jerk ramps.

    Pin by pin, the offset from the path's row to the pin's target is added
    to every row, weighted by a tent that is 1 at the pin's time and falls
    along a minimum-jerk ramp (:func:`minimum_jerk`) to 0 at the neighbouring
    pins' times (the path's ends where there is no neighbour), and the row is
    then set to the target exactly (:func:`~ndlfd.learner.pin_offset`). A pin
    at ``tau = 0`` (a start) holds its offset until there and fades it out to
    the next pin or the end. Each tent is 0 at every other pin, so every pin
    holds at the end.

    Parameters
    ----------
    path : ndarray of shape (n_samples, n_dims)
        The path (not changed).
    tau : ndarray of shape (n_samples,)
        Normalized times of its rows, increasing from 0 to 1.
    pins : sequence of (int, array-like of shape (n_dims,))
        Rows and the positions they must take, rows increasing.

    Returns
    -------
    path : ndarray of shape (n_samples, n_dims)
        A shifted copy.

    Examples
    --------
    >>> tau = np.linspace(0.0, 1.0, 5)
    >>> pass_through(np.zeros((5, 1)), tau, [(0, [1.0]), (2, [2.0])])[:, 0]
    array([1. , 1.5, 2. , 1. , 0. ])
    """
    out = np.array(path, dtype=np.float64)
    rows = [int(r) for r, _ in pins]
    for i, (row, target) in enumerate(pins):
        at = tau[row]
        lo = tau[rows[i - 1]] if i > 0 else 0.0
        hi = tau[rows[i + 1]] if i + 1 < len(rows) else 1.0
        rise = minimum_jerk((tau - lo) / (at - lo)) if at > lo else np.ones_like(tau)
        fall = minimum_jerk((tau - at) / (hi - at)) if hi > at else np.zeros_like(tau)
        pin_offset(out, np.where(tau <= at, rise, 1.0 - fall), row, target)
    return out


def prefix_pins(observed: np.ndarray) -> list:
    """Up to :data:`PREFIX_POINTS` samples of a prefix, spread evenly, both ends.

    Parameters
    ----------
    observed : ndarray of shape (n_observed, n_dims)

    Returns
    -------
    pins : list of (int, ndarray of shape (n_dims,))
        Rows and positions.

    Examples
    --------
    >>> [r for r, _ in prefix_pins(np.zeros((30, 2)))]
    [0, 3, 6, 10, 13, 16, 19, 23, 26, 29]
    """
    n = observed.shape[0]
    rows = np.unique(np.linspace(0, n - 1, min(n, PREFIX_POINTS)).round().astype(int))
    return [(int(r), observed[r]) for r in rows]


def start_pin(start) -> list:
    return [] if start is None else [(0, start)]


def require(module: str, what: str):
    """Import an optional module or raise :class:`MissingExtraError`."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingExtraError(
            f"the {what} baseline needs the optional package"
            f" {module.split('.')[0]}; install it with: {EXTRA_HINT} ({exc})"
        ) from None


class Generator:
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
            require(module, cls._name)

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
        extra = require(self._requires[0], self._name) if self._requires else None
        params = self._params()
        demos = check_demos(demos)
        self._learn(demos, extra, **params)
        self.n_dims_ = demos[0].get(GROUP).shape[1]
        return self

    def generate(self, times, *, start=None, via=None, observed=None) -> np.ndarray:
        """Positions at the given time stamps, optionally conditioned.

        Parameters
        ----------
        times : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least two).
        start : array-like of shape (n_dims,), optional
            The position to start at (the class says how it is reached).
        via : sequence of (float, array-like of shape (n_dims,)), optional
            Via points: each time (one of ``times``) and the position the path
            must pass through then.
        observed : array-like of shape (n_observed, n_dims), optional
            The positions executed so far, at ``times[:n_observed]`` (fewer
            than ``times``); not with ``start`` or ``via``.

        Returns
        -------
        path : ndarray of shape (n_samples, n_dims)
            With ``observed``, its rows first, then the path continued from
            the last of them, the offset there faded out by a minimum-jerk
            ramp (:func:`pass_through`).
        """
        t, start, pins, observed = self._conditions(times, start, via, observed)
        tau = unit_time(t)
        if observed is None:
            return pass_through(self._path_given(t, start, pins), tau, pins)
        n = observed.shape[0]
        path = self._path_given(t, None, prefix_pins(observed))
        out = pass_through(path, tau, [(n - 1, observed[-1])])
        out[:n] = observed
        return out

    def _conditions(self, times, start, via, observed):
        """Checked times, start, via points as ``(row, position)`` and prefix."""
        t, start = self._checked(times, start)
        pins = self._check_via(via, t)
        observed = self._check_observed(observed, t)
        if observed is not None and (start is not None or pins):
            raise ValidationError(
                "observed already fixes where the path is: pass no start or via with it"
            )
        return t, start, pins, observed

    def _path_given(self, t, start, pins) -> np.ndarray:
        """The path before the exact pins: :meth:`_path` unless a class conditions.

        ``pins`` are ``(row, position)``: via points, or prefix samples.
        """
        return self._path(t, start)

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
        return check_generate_times(times), self._check_start(start)

    def _check_fitted(self) -> None:
        if not hasattr(self, "n_dims_"):
            raise NotFittedError(
                f"this {type(self).__name__} is not fitted yet; call fit(demos) first"
            )

    def _check_start(self, start) -> np.ndarray | None:
        return None if start is None else self._check_position(start, "start")

    def _check_position(self, value, name: str) -> np.ndarray:
        s = as_float_array(value, name)
        if s.shape != (self.n_dims_,) or not np.isfinite(s).all():
            raise ValidationError(
                f"{name} must be a finite position of shape ({self.n_dims_},); got"
                f" {s.tolist()!r}"
            )
        return s

    def _check_via(self, via, t: np.ndarray) -> list:
        if via is None:
            return []
        if isinstance(via, (str, bytes)) or not isinstance(via, Sequence):
            raise ValidationError(
                f"via must be a list of (time, position) pairs; got {via!r}"
            )
        pins = []
        for i, item in enumerate(via):
            if not (isinstance(item, Sequence) and len(item) == 2):
                raise ValidationError(
                    f"via[{i}] must be a (time, position) pair; got {item!r}"
                )
            time, p = item
            row = int(np.searchsorted(t, float(time)))
            if row == t.size or t[row] != float(time):
                raise ValidationError(
                    f"via[{i}]'s time must be one of the time stamps; got {time!r}"
                )
            if pins and row <= pins[-1][0]:
                raise ValidationError(
                    f"via times must increase; via[{i}] at {time!r} does not"
                )
            pins.append((row, self._check_position(p, f"via[{i}]'s position")))
        return pins

    def _check_observed(self, observed, t: np.ndarray) -> np.ndarray | None:
        if observed is None:
            return None
        obs = as_float_array(observed, "observed")
        ok = obs.ndim == 2 and obs.shape[1] == self.n_dims_
        if not ok or not 1 <= obs.shape[0] < t.size or not np.isfinite(obs).all():
            raise ValidationError(
                f"observed must be finite positions of shape (n_observed,"
                f" {self.n_dims_}) with 1 <= n_observed < {t.size} (the time"
                f" stamps); got an array of shape {obs.shape}"
            )
        return obs

    def __repr__(self) -> str:
        params = inspect.signature(type(self).__init__).parameters
        inner = ", ".join(
            f"{k}={getattr(self, k)!r}" for k in params if hasattr(self, k)
        )
        return f"{type(self).__name__}({inner})"


# ------------------------------------------------------------------------ ndlfd
def _keypoint_hmm_accepts(name: str) -> bool:
    return name in inspect.signature(KeypointHMM.generate).parameters


class KeypointHMMGenerator(Generator):
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
    #: :meth:`generate` takes task frames (the evaluation's ``"frames"``).
    takes_frames = True

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

    def generate(
        self,
        times,
        *,
        start=None,
        via=None,
        observed=None,
        return_std: bool = False,
        frames=None,
    ):
        """Dense generated positions at each time stamp.

        Parameters
        ----------
        times : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least two).
        start : array-like of shape (n_dims,), optional
            Passed as ``start={"position": start}``.
        via : sequence of (float, array-like of shape (n_dims,)), optional
            Passed as ``via=[(time, {"position": position})]``.
        observed : array-like of shape (n_observed, n_dims), optional
            Passed as ``observed``, a :class:`~ndlfd.Demonstration` of these
            positions at ``times[:n_observed]``.
        return_std : bool, default=False
            Also return the learner's standard deviation of the position
            (needs a KeypointHMM whose ``generate`` offers ``return_std``).
        frames : mapping of str to array-like, optional
            Passed as ``frames`` (new poses of the task frames the training
            demonstrations carried).

        Returns
        -------
        path : ndarray of shape (n_samples, n_dims)
        std : ndarray of shape (n_samples, n_dims)
            Only with ``return_std=True``.
        """
        t, start, pins, observed = self._conditions(times, start, via, observed)
        kw = {}
        if start is not None:
            kw["start"] = {GROUP: start}
        if pins:
            kw["via"] = [(t[row], {GROUP: p}) for row, p in pins]
        if observed is not None:
            n = observed.shape[0]
            kw["observed"] = Demonstration.from_arrays(t[:n], **{GROUP: observed})
        if return_std:
            kw["return_std"] = True
        if frames is not None:
            kw["frames"] = frames
        for name in kw:
            if not _keypoint_hmm_accepts(name):
                raise ValidationError(
                    f"this version of KeypointHMM.generate takes no {name}"
                )
        out = self.model_.generate(t, dense=True, **kw)
        if not return_std:
            return out.get(GROUP)
        path, std = out
        cols = path.columns_of(GROUP)
        std = np.asarray(std, dtype=float)
        if std.shape[1] != path.X.shape[1]:  # std of the position group only
            return path.get(GROUP), std
        return path.get(GROUP), std[:, cols]

    def sample(self, times, n_samples: int = 1, *, random_state=None) -> list:
        """Paths drawn from the learner (:meth:`~ndlfd.KeypointHMM.sample`).

        Parameters
        ----------
        times : array-like of shape (n_samples,)
            Strictly increasing time stamps (at least two).
        n_samples : int, default=1
        random_state : None, int or Generator, default=None

        Returns
        -------
        paths : list of ndarray of shape (n_times, n_dims)
        """
        t, _ = self._checked(times, None)
        draws = self.model_.sample(t, n_samples, random_state=random_state)
        return [d.get(GROUP) for d in draws]


def _equal(a, b) -> bool:
    try:
        return bool(a == b)
    except (TypeError, ValueError):
        return False
