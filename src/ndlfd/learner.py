"""KeypointHMM: the whole method as one scikit-learn style estimator.

It composes the stages and holds no algorithm of its own::

    demos → GroupScaler → simplify (key points) → Codebook + TimeBins → hmm.estimate
    new timing → TimeBins → hmm.viterbi → Codebook.decode → inverse_transform
"""

from __future__ import annotations

import numbers
import os
from collections.abc import Mapping, Sequence

import numpy as np

from . import hmm
from ._errors import DecodeError, NotFittedError, ValidationError
from ._fileformat import load_npz, save_npz
from ._registry import Registry
from ._simplify import DISTANCES, simplify, simplify_many
from ._validation import (
    check_nonnegative_scalar,
    check_positive_int,
    check_times,
)
from .codebook import Codebook, TimeBins
from .demo import Demonstration, with_velocity
from .normalize import GroupScaler

__all__ = ["DEFAULT_LEVELS", "KeypointHMM"]

#: Codebook levels per physical group when ``levels`` does not name the group
#: (the paper's 20 for position and 10 for velocity).
DEFAULT_LEVELS = {"position": 20, "velocity": 10, "orientation": 10, "force": 10}

_FORMAT_KIND = "KeypointHMM"
_FORMAT_VERSION = 1

NORMALIZATIONS = Registry("normalization")
for _name in ("group", "per-dimension", "none"):
    NORMALIZATIONS.add(_name, _name)
STARTS = Registry("start")
for _name in ("learned", "state1"):
    STARTS.add(_name, _name)


def _as_demo_list(demos) -> list[Demonstration]:
    if isinstance(demos, Demonstration):
        return [demos]
    if isinstance(demos, (str, bytes, os.PathLike)) or not isinstance(demos, Sequence):
        raise ValidationError(
            "demos must be a Demonstration or a list of them; got"
            f" {type(demos).__name__}. Load files with ndlfd.io.read_demos."
        )
    out = list(demos)
    if not out:
        raise ValidationError("demos must hold at least one demonstration; got none")
    for i, d in enumerate(out):
        if not isinstance(d, Demonstration):
            raise ValidationError(
                f"demos[{i}] must be a Demonstration; got {type(d).__name__}"
            )
    return out


class KeypointHMM:
    """Learn a path from demonstrations and generate it for a new timing.

    Parameters
    ----------
    groups : sequence of str or None, default=("position", "velocity")
        The physical groups to learn from, in this order. ``None`` uses every
        group of the first demonstration. A ``"velocity"`` group missing from a
        demonstration is derived from its position and time stamps when
        ``derive_velocity`` is true.
    levels : int or mapping of str to int, optional
        Codebook levels per group (one int for all groups). Groups not named
        fall back to :data:`DEFAULT_LEVELS` (20 for position, 10 otherwise).
    epsilon : float, default=0.05
        Douglas–Peucker tolerance on the normalized (and weighted) values.
        Ignored when ``n_points`` is given.
    n_time_bins : int, default=50
        Number of time symbols ``N_t``.
    n_points : int, optional
        Key-point budget per demonstration instead of ``epsilon``.
    distance : {"line", "segment", "sed", "paper"}, default="line"
        Distance used by the reduction (see :func:`ndlfd.simplify`).
    normalization : {"group", "per-dimension", "none"}, default="group"
        How values are normalized before reduction and encoding.
    weights : mapping of str to float, optional
        Per-group weights multiplying the normalized values during reduction
        only (the codebook always sees the unweighted values in ``[0, 1]``).
    pseudo_transition : float, optional
        Transition pseudo-count; ``None`` means ``1 / n_states``.
    pseudo_emission : float, default=0.0
        Emission pseudo-count.
    start : {"learned", "state1"}, default="learned"
        Viterbi start mode (``"state1"`` reproduces MATLAB ``hmmviterbi``).
    derive_velocity : bool, default=True
        Derive a missing velocity group from position and time.
    n_jobs : int, optional
        Threads used to reduce many demonstrations.
    random_state : None, int or Generator, default=None
        Accepted for the estimator contract; fitting and generation are fully
        deterministic, so it changes nothing today.

    Attributes
    ----------
    columns_ : tuple of str
        Names of the learned columns.
    column_groups_ : tuple of str
        Group of each learned column.
    scaler_ : GroupScaler
        The fitted normalization.
    codebook_ : Codebook
        The discrete states.
    time_bins_ : TimeBins
        The time symbols.
    model_ : ndlfd.hmm.DiscreteHMM
        The supervised discrete HMM.
    keypoints_ : list of ndarray of int
        Key-point indices of each training demonstration.
    n_keypoints_ : ndarray of shape (n_demos,)
        Number of key points per demonstration.
    n_states_used_ : int
        Number of distinct codebook states seen in training.
    n_clipped_ : int
        Values clipped by the codebook while fitting (0 unless weights or
        normalization ``"none"`` push values outside ``[0, 1]``).

    Examples
    --------
    >>> from ndlfd import synth
    >>> train, test = synth.make_dataset("square", n_demos=20, random_state=0)
    >>> model = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
    >>> path = model.generate(test)
    >>> path.groups[:2]
    ('position', 'position')
    """

    def __init__(
        self,
        groups=("position", "velocity"),
        levels=None,
        epsilon=0.05,
        n_time_bins=50,
        *,
        n_points=None,
        distance="line",
        normalization="group",
        weights=None,
        pseudo_transition=None,
        pseudo_emission=0.0,
        start="learned",
        derive_velocity=True,
        n_jobs=None,
        random_state=None,
    ):
        self.groups = groups
        self.levels = levels
        self.epsilon = epsilon
        self.n_time_bins = n_time_bins
        self.n_points = n_points
        self.distance = distance
        self.normalization = normalization
        self.weights = weights
        self.pseudo_transition = pseudo_transition
        self.pseudo_emission = pseudo_emission
        self.start = start
        self.derive_velocity = derive_velocity
        self.n_jobs = n_jobs
        self.random_state = random_state

    # ------------------------------------------------------------------ params
    def get_params(self, deep: bool = True) -> dict:
        """Return the constructor parameters (scikit-learn convention)."""
        return {k: getattr(self, k) for k in _PARAM_NAMES}

    def set_params(self, **params) -> KeypointHMM:
        """Set constructor parameters (scikit-learn convention)."""
        for k, v in params.items():
            if k not in _PARAM_NAMES:
                raise ValidationError(
                    f"unknown parameter {k!r}; expected one of: "
                    + ", ".join(_PARAM_NAMES)
                )
            setattr(self, k, v)
        return self

    def __repr__(self) -> str:
        defaults = KeypointHMM().get_params()
        changed = {
            k: v for k, v in self.get_params().items() if not _same(v, defaults[k])
        }
        inner = ", ".join(f"{k}={v!r}" for k, v in changed.items())
        return f"KeypointHMM({inner})"

    # ----------------------------------------------------------------- helpers
    def _check_params(self) -> None:
        NORMALIZATIONS.get(self.normalization)
        STARTS.get(self.start)
        DISTANCES.get(self.distance)
        if self.n_points is None:
            check_nonnegative_scalar(self.epsilon, "epsilon")
        else:
            check_positive_int(self.n_points, "n_points", minimum=2)
        check_positive_int(self.n_time_bins, "n_time_bins")
        if self.pseudo_transition is not None:
            check_nonnegative_scalar(self.pseudo_transition, "pseudo_transition")
        check_nonnegative_scalar(self.pseudo_emission, "pseudo_emission")

    def _wanted_groups(self, first: Demonstration) -> tuple[str, ...]:
        if self.groups is None:
            return tuple(first.group_names)
        if isinstance(self.groups, str):
            return (self.groups,)
        groups = tuple(self.groups)
        if not groups or not all(isinstance(g, str) for g in groups):
            raise ValidationError(
                f"groups must be a non-empty sequence of group names; got {groups!r}"
            )
        if len(set(groups)) != len(groups):
            raise ValidationError(f"groups must not repeat a name; got {groups!r}")
        return groups

    def _prepare(self, demo: Demonstration, groups: Sequence[str]) -> Demonstration:
        if (
            "velocity" in groups
            and "velocity" not in demo.group_names
            and self.derive_velocity
        ):
            demo = with_velocity(demo)
        missing = [g for g in groups if g not in demo.group_names]
        if missing:
            raise ValidationError(
                f"a demonstration lacks group(s) {', '.join(missing)}; it has"
                f" {', '.join(demo.group_names)}"
            )
        return demo.select(*groups)

    def _levels_by_group(self, groups: Sequence[str]) -> dict[str, int]:
        lv = self.levels
        if lv is None:
            lv = {}
        if isinstance(lv, numbers.Integral) and not isinstance(lv, bool):
            return {g: check_positive_int(lv, "levels") for g in groups}
        if not isinstance(lv, Mapping):
            raise ValidationError(
                f"levels must be an int or a mapping of group to int; got {lv!r}"
            )
        unknown = [g for g in lv if g not in groups]
        if unknown:
            raise ValidationError(
                f"levels names group(s) {', '.join(map(repr, unknown))} that are not"
                f" learned; the learned groups are {', '.join(groups)}"
            )
        out = {}
        for g in groups:
            if g in lv:
                out[g] = check_positive_int(lv[g], f"levels[{g!r}]")
            elif g in DEFAULT_LEVELS:
                out[g] = DEFAULT_LEVELS[g]
            else:
                raise ValidationError(
                    f"no codebook levels for group {g!r}; pass levels={{{g!r}: N}}"
                )
        return out

    def _column_weights(self) -> np.ndarray | None:
        if self.weights is None:
            return None
        if not isinstance(self.weights, Mapping):
            raise ValidationError(
                f"weights must be a mapping of group to weight; got {self.weights!r}"
            )
        unknown = [g for g in self.weights if g not in self.column_groups_]
        if unknown:
            raise ValidationError(
                f"weights names group(s) {', '.join(map(repr, unknown))} that are"
                f" not learned; the learned groups are"
                f" {', '.join(dict.fromkeys(self.column_groups_))}"
            )
        w = np.array(
            [
                check_nonnegative_scalar(self.weights.get(g, 1.0), f"weights[{g!r}]")
                for g in self.column_groups_
            ]
        )
        return w

    def _check_fitted(self) -> None:
        if not hasattr(self, "model_"):
            raise NotFittedError(
                "this KeypointHMM is not fitted yet; call fit(demos) first"
            )

    def _reduce(self, U_list, t_list) -> list[np.ndarray]:
        times = t_list if self.distance == "sed" else None
        return simplify_many(
            U_list,
            None if self.n_points is not None else self.epsilon,
            distance=self.distance,
            weights=self._column_weights(),
            times=times,
            n_points=self.n_points,
            n_jobs=self.n_jobs,
        )

    # --------------------------------------------------------------------- fit
    def fit(self, demos, y=None) -> KeypointHMM:
        """Learn the key points, codebook states and HMM from demonstrations.

        Parameters
        ----------
        demos : Demonstration or sequence of Demonstration
            Training demonstrations (lengths may differ).
        y : None
            Ignored.

        Returns
        -------
        self : KeypointHMM
        """
        self._check_params()
        demo_list = _as_demo_list(demos)
        groups = self._wanted_groups(demo_list[0])
        prepared = [self._prepare(d, groups) for d in demo_list]
        columns, col_groups = prepared[0].columns, prepared[0].groups
        for i, d in enumerate(prepared[1:], start=1):
            if d.columns != columns or d.groups != col_groups:
                raise ValidationError(
                    f"all demonstrations must have the same columns; demos[0] has"
                    f" {columns} and demos[{i}] has {d.columns}"
                )
        self.columns_ = tuple(columns)
        self.column_groups_ = tuple(col_groups)
        self.groups_ = groups
        self.scaler_ = GroupScaler(mode=self.normalization).fit(prepared)
        U = [self.scaler_.transform(d) for d in prepared]
        self.keypoints_ = self._reduce(U, [d.t for d in prepared])
        self.codebook_ = Codebook.from_groups(
            self._levels_by_group(groups), self.column_groups_
        )
        self.time_bins_ = TimeBins(self.n_time_bins)
        states, symbols, clipped = [], [], 0
        for d, u, idx in zip(prepared, U, self.keypoints_, strict=True):
            s, c = self.codebook_.encode(u[idx], return_n_clipped=True)
            states.append(s)
            clipped += int(c)
            symbols.append(self.time_bins_.transform(d.t)[idx])
        self.model_ = hmm.estimate(
            states,
            symbols,
            self.codebook_.n_states,
            self.n_time_bins,
            pseudo_transition=self.pseudo_transition,
            pseudo_emission=self.pseudo_emission,
        )
        self.n_keypoints_ = np.array([k.size for k in self.keypoints_], np.int64)
        self.n_states_used_ = int(np.unique(np.concatenate(states)).size)
        self.n_clipped_ = clipped
        self.n_demos_ = len(prepared)
        seen = np.zeros(self.n_time_bins, dtype=bool)
        seen[np.concatenate(symbols)] = True
        self.symbols_seen_ = seen
        return self

    # ---------------------------------------------------------------- generate
    def timing(self, times_or_demo) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Observation times and symbols for a new execution.

        A :class:`Demonstration` is normalized and reduced like the training
        demonstrations; its key points' times are the observations (the paper's
        procedure with its "ideal" test demonstration). A plain time vector has
        no key points: it contributes one observation per time bin it touches,
        at the bin's first time stamp, keeping only bins that training key points
        fell into (unless ``pseudo_emission > 0``, where every bin can be
        emitted).

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            The new execution or its time stamps.

        Returns
        -------
        key_times : ndarray of shape (n_obs,)
            Time of each observation.
        symbols : ndarray of shape (n_obs,), dtype int64
            Time symbol of each observation.
        all_times : ndarray of shape (n_samples,)
            Every time stamp of the new execution (for dense generation).
        """
        self._check_fitted()
        if isinstance(times_or_demo, Demonstration):
            d = self._prepare(times_or_demo, self.groups_)
            if d.columns != self.columns_:
                raise ValidationError(
                    f"the demonstration's columns {d.columns} differ from the"
                    f" learned columns {self.columns_}"
                )
            u = self.scaler_.transform(d)
            idx = simplify(
                u,
                None if self.n_points is not None else self.epsilon,
                n_points=self.n_points,
                distance=self.distance,
                weights=self._column_weights(),
                times=d.t if self.distance == "sed" else None,
            )
            return d.t[idx], self.time_bins_.transform(d.t)[idx], d.t
        t = check_times(times_or_demo, name="times")
        sym = self.time_bins_.transform(t)
        first = np.flatnonzero(np.r_[True, sym[1:] != sym[:-1]])
        if self.pseudo_emission == 0:
            first = first[self.symbols_seen_[sym[first]]]
        if first.size == 0:
            raise DecodeError(
                "none of the time bins of this timing was seen in training; cannot"
                " generate a path"
            )
        return t[first], sym[first], t

    def decode(self, times_or_demo) -> tuple[np.ndarray, np.ndarray, float]:
        """Most likely codebook states for a new timing (Viterbi).

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            See :meth:`timing`.

        Returns
        -------
        key_times : ndarray of shape (n_obs,)
        states : ndarray of shape (n_obs,), dtype int64
        log_probability : float
        """
        key_t, states, logp, _ = self._decode(times_or_demo)
        return key_t, states, logp

    def _decode(self, times_or_demo):
        key_t, symbols, all_t = self.timing(times_or_demo)
        try:
            states, logp = hmm.viterbi(self.model_, symbols, start=self.start)
        except DecodeError as exc:
            raise DecodeError(
                f"cannot generate a path for this timing: {exc}. Use fewer time"
                " bins, more demonstrations, or pseudo_emission > 0."
            ) from None
        return key_t, states, logp, all_t

    def generate(self, times_or_demo, *, dense: bool = False) -> Demonstration:
        """Generate a path for a new timing.

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            A new execution (its key points' times are decoded) or its time
            stamps; see :meth:`timing`.
        dense : bool, default=False
            Interpolate the generated key points linearly to every time stamp of
            the new execution (quaternions are renormalized afterwards).

        Returns
        -------
        path : Demonstration
            The generated key points (codebook centres mapped back to physical
            units) at their times, or the dense path when ``dense=True``.
        """
        key_t, states, _, all_t = self._decode(times_or_demo)
        X = self.scaler_.inverse_transform(self.codebook_.decode(states))
        X = self._renormalize(X)
        path = Demonstration(key_t, X, self.columns_, self.column_groups_)
        if not dense:
            return path
        Xd = np.column_stack(
            [np.interp(all_t, key_t, X[:, c]) for c in range(X.shape[1])]
        )
        return Demonstration(all_t, self._renormalize(Xd), path.columns, path.groups)

    def _renormalize(self, X: np.ndarray) -> np.ndarray:
        cols = [i for i, g in enumerate(self.column_groups_) if g == "orientation"]
        if len(cols) == 4:
            q = X[:, cols]
            norm = np.linalg.norm(q, axis=1, keepdims=True)
            norm[norm == 0] = 1.0
            X = X.copy()
            X[:, cols] = q / norm
        return X

    # --------------------------------------------------------------- save/load
    def save(self, path: str | os.PathLike) -> None:
        """Save the fitted learner (``.npz`` + JSON metadata, never pickle).

        Parameters
        ----------
        path : str or path-like
            Destination file (conventionally ``*.ndlfd``).
        """
        self._check_fitted()
        arrays = {
            "scaler_min": self.scaler_.data_min_,
            "scaler_max": self.scaler_.data_max_,
            "levels": self.codebook_.levels,
            "keypoints": np.concatenate(self.keypoints_),
            "keypoint_counts": self.n_keypoints_,
            "symbols_seen": self.symbols_seen_,
        }
        arrays.update(self.model_.to_arrays(prefix="hmm_"))
        params = self.get_params()
        params["groups"] = list(self.groups_)
        meta = {
            "params": _jsonable(params),
            "columns": list(self.columns_),
            "column_groups": list(self.column_groups_),
            "n_states_used": self.n_states_used_,
            "n_clipped": self.n_clipped_,
        }
        save_npz(
            path, arrays, kind=_FORMAT_KIND, version=_FORMAT_VERSION, metadata=meta
        )

    @classmethod
    def load(cls, path: str | os.PathLike) -> KeypointHMM:
        """Load a learner written by :meth:`save`.

        Parameters
        ----------
        path : str or path-like
            The file.

        Returns
        -------
        model : KeypointHMM
        """
        from ._errors import ModelFormatError

        arrays, meta = load_npz(path, kind=_FORMAT_KIND, version=_FORMAT_VERSION)
        try:
            params = dict(meta["params"])
            columns = tuple(meta["columns"])
            col_groups = tuple(meta["column_groups"])
            if isinstance(params.get("groups"), list):
                params["groups"] = tuple(params["groups"])
            self = cls(**params)
            self._check_params()
            d = len(columns)
            mins = np.asarray(arrays["scaler_min"], np.float64)
            maxs = np.asarray(arrays["scaler_max"], np.float64)
            levels = np.asarray(arrays["levels"])
            counts = np.asarray(arrays["keypoint_counts"], np.int64)
            flat = np.asarray(arrays["keypoints"], np.int64)
            seen = np.asarray(arrays["symbols_seen"], bool)
            if (
                len(col_groups) != d
                or mins.shape != (d,)
                or maxs.shape != (d,)
                or levels.shape != (d,)
                or counts.sum() != flat.size
                or seen.shape != (self.n_time_bins,)
                or not (np.all(np.isfinite(mins)) and np.all(np.isfinite(maxs)))
            ):
                raise ModelFormatError(
                    f"{path}: inconsistent KeypointHMM arrays (tampered file?)"
                )
            self.columns_ = columns
            self.column_groups_ = col_groups
            self.groups_ = tuple(params["groups"])
            self.scaler_ = GroupScaler.from_ranges(
                mins, maxs, col_groups, columns=columns, mode=self.normalization
            )
            self.codebook_ = Codebook([int(x) for x in levels])
            self.time_bins_ = TimeBins(self.n_time_bins)
            self.model_ = hmm.DiscreteHMM.from_arrays(arrays, prefix="hmm_")
            if (
                self.model_.n_states != self.codebook_.n_states
                or self.model_.n_symbols != self.n_time_bins
            ):
                raise ModelFormatError(
                    f"{path}: the HMM does not match the codebook (tampered file?)"
                )
            self.keypoints_ = np.split(flat, np.cumsum(counts)[:-1])
            self.n_keypoints_ = counts
            self.n_states_used_ = int(meta["n_states_used"])
            self.n_clipped_ = int(meta["n_clipped"])
            self.n_demos_ = int(counts.size)
            self.symbols_seen_ = seen
        except ModelFormatError:
            raise
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelFormatError(
                f"{path}: not a valid KeypointHMM file ({type(exc).__name__}: {exc})"
            ) from None
        return self


_PARAM_NAMES = (
    "groups",
    "levels",
    "epsilon",
    "n_time_bins",
    "n_points",
    "distance",
    "normalization",
    "weights",
    "pseudo_transition",
    "pseudo_emission",
    "start",
    "derive_velocity",
    "n_jobs",
    "random_state",
)


def _same(a, b) -> bool:
    try:
        return bool(a == b)
    except (ValueError, TypeError):
        return a is b


def _jsonable(params: dict) -> dict:
    out = {}
    for k, v in params.items():
        if isinstance(v, np.generic):
            v = v.item()
        if isinstance(v, Mapping):
            v = {
                str(kk): (vv.item() if isinstance(vv, np.generic) else vv)
                for kk, vv in v.items()
            }
        if k == "random_state" and not (v is None or isinstance(v, int)):
            v = None  # a Generator is not stored; generation is deterministic
        out[k] = v
    return out
